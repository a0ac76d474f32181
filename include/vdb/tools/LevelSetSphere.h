// SPDX-License-Identifier: Apache-2.0
/// @file
/// Narrow-band level sets of spheres, and the Enright test shapes of the paper's section 5.
///
/// createLevelSetSphere() samples the signed distance to a sphere at every voxel centre and
/// keeps, as active voxels, those whose distance lies strictly within `halfWidth` voxels of the
/// surface; every other value is -background inside and +background outside (a signed flood
/// fill, see SignedFloodFill.h). The voxels, their values and the float arithmetic are those
/// of OpenVDB 10's tools::createLevelSetSphere, so both libraries produce the same grid:
/// in voxel units (ValueT arithmetic) c = center / voxelSize and r = radius / voxelSize; voxel
/// (i, j, k) has v = sqrt(((j - c.y)^2 + (i - c.x)^2) + (k - c.z)^2) - r and is active when
/// |v| < halfWidth, with value voxelSize * v. Each z-line is scanned from the bounding box's
/// low end, leaping over floor(|v| - halfWidth) voxels after every voxel outside the band, as
/// OpenVDB does; i runs over [floor(c.x - r - w), ceil(c.x + r + w)) and j, k over the closed
/// ranges of the same form.
///
/// Leaves are written directly, one column of leaves per task, and then linked into the tree,
/// so the cost is about one square root per band voxel plus a few per z-line; the result does
/// not depend on the thread count.
///
/// @code
/// auto sphere = vdb::tools::createLevelSetSphere<vdb::FloatGrid>(
///     /*radius=*/1.0f, vdb::Vec3f(0.0f), /*voxelSize=*/0.01f, /*halfWidth=*/3.0f);
/// auto enright = vdb::tools::createEnrightSphere<vdb::FloatGrid>(/*resolution=*/1024);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// Returns a narrow-band level set of the sphere of `radius` around `center` (world units):
/// background voxelSize * halfWidth, a linear transform of `voxelSize`, grid class level set.
/// A sphere whose radius is below 1.5 voxels gives an empty grid (as in OpenVDB).
/// @param halfWidth  half the width of the band, in voxels.
/// @throw ValueError when radius or voxelSize is not positive and finite, the center is not
///        finite, or halfWidth is not above 1.
/// @throw IndexError when a band voxel lies outside a bounded tree's domain or beyond the
///        32-bit index space.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createLevelSetSphere(float radius, const Vec3f& center, float voxelSize,
                                         float halfWidth = 3.0f, bool threaded = true);

/// As above, with the voxel size, radius, center and half width in double: the transform
/// keeps `voxelSize` exactly (the float form stores float(voxelSize), e.g. 0.012500000186 for
/// 0.0125), and the center's position is resolved to the voxel anywhere in the index space.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createLevelSetSphere(double radius, const Vec3d& center, double voxelSize,
                                         double halfWidth = 3.0, bool threaded = true);

/// The Enright sphere of the paper's section 5: radius 0.15 around (0.35, 0.35, 0.35) in the
/// unit box, voxel size 1 / resolution (in double in the transform; the values are those of
/// createLevelSetSphere(0.15f, Vec3f(0.35f), 1.0f / resolution)).
/// @throw ValueError when resolution is not positive.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createEnrightSphere(int resolution, float halfWidth = 5.0f,
                                        bool threaded = true);

/// The paper's "8x" Enright variant: the level set of the union of 8 spheres of radius 0.125
/// around (.35,.35,.35), (.15,.15,.85), (.15,.85,.15), (.35,.65,.65), (.85,.15,.15),
/// (.65,.35,.65), (.65,.65,.35) and (.85,.85,.85), voxel size 1 / resolution. A voxel's value is
/// voxelSize times the smallest of its signed distances to the spheres (computed as in
/// createLevelSetSphere), and it is active when that distance is within the band.
/// @throw ValueError when resolution is not positive.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createEnrightEightSpheres(int resolution, float halfWidth = 5.0f,
                                              bool threaded = true);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// A sphere in index space (voxel units): its center is `origin + center`, with `origin` an
/// integer voxel and `center` in ValueT, so that distances are computed from the exact integer
/// differences i - origin. Spheres near the index origin keep origin 0 and OpenVDB's ValueT
/// center (the arithmetic is then OpenVDB's, bit for bit); far ones keep only the fraction in
/// ValueT, so a float grid's sphere at 10^9 voxels is as round as one at the origin.
template <typename ValueT>
struct IndexSphere {
    std::array<Int64, 3> origin;
    math::Vec3<ValueT> center;
    ValueT radius;

    /// ValueT(i) - center[a] along axis `a`, exact in the integer part.
    ValueT offset(int a, Int64 i) const { return ValueT(i - origin[size_t(a)]) - center[a]; }
};

/// The index-space sphere of world `radius` and `center` at `voxelSize` (dx in ValueT): in ValueT
/// arithmetic (OpenVDB's) while the center and the band lie where ValueT holds every voxel
/// coordinate exactly with room to spare, else from the double-precision center.
/// @throw IndexError when the band reaches beyond the 32-bit index space.
template <typename ValueT>
IndexSphere<ValueT> makeIndexSphere(double radius, const Vec3d& center, double voxelSize, ValueT dx,
                                    ValueT w) {
    constexpr double exact = double(Int64(1) << (std::numeric_limits<ValueT>::digits - 2));
    IndexSphere<ValueT> sphere{};
    sphere.radius = ValueT(radius) / dx;
    const double reach = double(sphere.radius) + double(w) + 2.0;
    for (int a = 0; a < 3; ++a) {
        const ValueT fast = ValueT(center[a]) / dx;
        const double c = center[a] / voxelSize;
        if (!(std::abs(c) + reach < 2147483647.0))
            throw IndexError("createLevelSetSphere: the band of the sphere around " +
                             std::to_string(center[a]) + " (voxel " + std::to_string(c) +
                             ") reaches beyond the 32-bit index space of +-2^31 voxels");
        if (std::abs(double(fast)) + reach < exact) {
            sphere.origin[size_t(a)] = 0;
            sphere.center[a] = fast;
        } else {
            const double whole = std::floor(c);
            sphere.origin[size_t(a)] = Int64(whole);
            sphere.center[a] = ValueT(c - whole);
        }
    }
    return sphere;
}

template <typename ValueT>
ValueT pow2(ValueT x) {
    return x * x;
}

/// Writes the narrow band of the union of `spheres` (index space) into the empty `tree` and
/// flood-fills it. Values are `dx` times the smallest signed distance in voxels; a voxel is
/// active when that distance is within `w` voxels of the surface. For one sphere this is
/// OpenVDB's loop voxel for voxel and bit for bit (see the file comment).
template <typename TreeT, typename ValueT>
void rasterSpheres(TreeT& tree, const std::vector<IndexSphere<ValueT>>& spheres, ValueT dx,
                   ValueT w, bool threaded) {
    using LeafT = typename TreeT::LeafNodeType;
    constexpr Int64 DIM = LeafT::DIM;
    constexpr Index LOG2 = LeafT::LOG2DIM;
    if (spheres.empty())
        return;

    // Voxel bounds: i in [lo[0], hi[0]), j in [lo[1], hi[1]], k in [lo[2], hi[2]].
    std::array<Int64, 3> lo{}, hi{};
    for (size_t s = 0; s < spheres.size(); ++s) {
        const ValueT rmax = spheres[s].radius + w;
        for (int a = 0; a < 3; ++a) {
            const Int64 o = spheres[s].origin[size_t(a)];
            const Int64 l = o + Int64(std::floor(spheres[s].center[a] - rmax));
            const Int64 h = o + Int64(std::ceil(spheres[s].center[a] + rmax));
            lo[a] = s == 0 ? l : std::min(lo[a], l);
            hi[a] = s == 0 ? h : std::max(hi[a], h);
        }
    }
    if (hi[0] <= lo[0])
        return;
    // Leaf-aligned columns along z: blocks [bx0, bx1] x [by0, by1], each bz0..bz1 tall.
    const Int64 bx0 = lo[0] >> LOG2, bx1 = (hi[0] - 1) >> LOG2;
    const Int64 by0 = lo[1] >> LOG2, by1 = hi[1] >> LOG2;
    const Int64 bz0 = lo[2] >> LOG2, bz1 = hi[2] >> LOG2;
    const size_t ny = size_t(by1 - by0 + 1), nz = size_t(bz1 - bz0 + 1);
    const size_t columnCount = size_t(bx1 - bx0 + 1) * ny;
    const ValueT background = tree.background();

    std::vector<std::vector<std::unique_ptr<LeafT>>> columns(columnCount);
    util::parallelFor(
        columnCount,
        [&](size_t col) {
            const Int64 bx = bx0 + Int64(col / ny), by = by0 + Int64(col % ny);
            std::vector<std::unique_ptr<LeafT>> leaves(nz);
            std::vector<std::pair<size_t, ValueT>> near;  // sphere index, its x^2 + y^2
            near.reserve(spheres.size());
            const Int64 i0 = std::max(lo[0], bx * DIM), i1 = std::min(hi[0], (bx + 1) * DIM);
            const Int64 j0 = std::max(lo[1], by * DIM), j1 = std::min(hi[1] + 1, (by + 1) * DIM);
            for (Int64 i = i0; i < i1; ++i) {
                for (Int64 j = j0; j < j1; ++j) {
                    // The spheres whose band can reach this z-line (with a voxel of margin, so
                    // that rounding cannot matter).
                    near.clear();
                    for (size_t s = 0; s < spheres.size(); ++s) {
                        const ValueT x2 = pow2(spheres[s].offset(0, i));
                        const ValueT x2y2 = pow2(spheres[s].offset(1, j)) + x2;
                        const ValueT reach = spheres[s].radius + w + ValueT(1);
                        if (!(x2y2 > reach * reach))
                            near.emplace_back(s, x2y2);
                    }
                    if (near.empty())
                        continue;
                    const Index rowOffset =
                        Index((i & (DIM - 1)) << (2 * LOG2)) | Index((j & (DIM - 1)) << LOG2);
                    // Leapfrog along z from the low end of the box.
                    const auto emit = [&](Int64 k, ValueT v) {
                        auto& leaf = leaves[size_t((k >> LOG2) - bz0)];
                        if (!leaf) {
                            leaf = std::make_unique<LeafT>(
                                Coord(Int32(bx * DIM), Int32(by * DIM), Int32(k)), background,
                                false);
                        }
                        leaf->setValueOn(rowOffset | Index(k & (DIM - 1)), dx * v);
                    };
                    if (near.size() == 1) {
                        const ValueT x2y2 = near[0].second;
                        const auto& sphere = spheres[near[0].first];
                        const ValueT r0 = sphere.radius;
                        for (Int64 k = lo[2]; k <= hi[2];) {
                            const ValueT v = std::sqrt(x2y2 + pow2(sphere.offset(2, k))) - r0;
                            const ValueT d = std::abs(v);
                            if (d < w) {
                                emit(k, v);
                                ++k;
                            } else {
                                k += 1 + Int64(std::floor(d - w));
                            }
                        }
                        continue;
                    }
                    for (Int64 k = lo[2]; k <= hi[2];) {
                        ValueT v = 0;
                        for (size_t n = 0; n < near.size(); ++n) {
                            const auto& sphere = spheres[near[n].first];
                            const ValueT vs =
                                std::sqrt(near[n].second + pow2(sphere.offset(2, k))) -
                                sphere.radius;
                            v = n == 0 ? vs : std::min(v, vs);
                        }
                        const ValueT d = std::abs(v);
                        if (d < w) {
                            emit(k, v);
                            ++k;
                        } else {
                            k += 1 + Int64(std::floor(d - w));
                        }
                    }
                }
            }
            auto& out = columns[col];
            for (auto& leaf : leaves) {
                if (leaf)
                    out.push_back(std::move(leaf));
            }
        },
        threaded, 1);

    // Link the leaves in column order, so the tree's tables fill in the same order always.
    for (auto& column : columns) {
        for (auto& leaf : column)
            tree.addLeaf(std::move(leaf));
    }
}

/// An empty level-set grid as OpenVDB's createLevelSet makes it: background
/// voxelSize * halfWidth (computed in double), a linear transform of `voxelSize`, class level
/// set.
template <typename GridT>
typename GridT::Ptr makeLevelSetGrid(double voxelSize, double halfWidth) {
    using ValueT = typename GridT::ValueType;
    auto grid = GridT::create(ValueT(voxelSize * halfWidth));
    grid->setTransform(math::Transform::createLinearTransform(voxelSize));
    grid->setGridClass(GRID_LEVEL_SET);
    return grid;
}

/// Rasterizes world-space spheres (radius, center) at `voxelSize` into a new level-set grid.
/// Index-space arithmetic is in ValueT with ValueT(voxelSize), as OpenVDB's; the transform
/// keeps `voxelSize` itself.
template <typename GridT>
typename GridT::Ptr createLevelSetSpheres(const std::vector<std::pair<double, Vec3d>>& spheres,
                                          double voxelSize, double halfWidth, bool threaded) {
    using ValueT = typename GridT::ValueType;
    for (const auto& [radius, center] : spheres) {
        if (!(ValueT(radius) > ValueT(0)) || !std::isfinite(radius))
            throw ValueError("createLevelSetSphere: the radius must be positive and finite, not " +
                             std::to_string(radius));
        if (!std::isfinite(center[0]) || !std::isfinite(center[1]) || !std::isfinite(center[2]))
            throw ValueError("createLevelSetSphere: the center must be finite");
    }
    const ValueT dx = ValueT(voxelSize), w = ValueT(halfWidth);
    if (!(dx > ValueT(0)) || !std::isfinite(voxelSize))
        throw ValueError("createLevelSetSphere: the voxel size must be positive and finite, not " +
                         std::to_string(voxelSize));
    if (!(w > ValueT(1)) || !std::isfinite(halfWidth))
        throw ValueError("createLevelSetSphere: the half width must be larger than one voxel");
    auto grid = makeLevelSetGrid<GridT>(voxelSize, halfWidth);

    // Spheres below 1.5 voxels of radius are left out.
    std::vector<IndexSphere<ValueT>> indexSpheres;
    for (const auto& [radius, center] : spheres) {
        if (ValueT(radius) / dx < 1.5f)
            continue;
        indexSpheres.push_back(makeIndexSphere(radius, center, voxelSize, dx, w));
    }
    if (indexSpheres.empty())
        return grid;
    rasterSpheres(grid->tree(), indexSpheres, dx, w, threaded);
    signedFloodFill(grid->tree(), threaded);
    return grid;
}

}  // namespace detail

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createLevelSetSphere(float radius, const Vec3f& center, float voxelSize,
                                         float halfWidth, bool threaded) {
    return detail::createLevelSetSpheres<GridT>({{radius, Vec3d(center)}}, voxelSize, halfWidth,
                                                threaded);
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createLevelSetSphere(double radius, const Vec3d& center, double voxelSize,
                                         double halfWidth, bool threaded) {
    return detail::createLevelSetSpheres<GridT>({{radius, center}}, voxelSize, halfWidth, threaded);
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createEnrightSphere(int resolution, float halfWidth, bool threaded) {
    if (resolution <= 0)
        throw ValueError("createEnrightSphere: the resolution must be positive");
    return detail::createLevelSetSpheres<GridT>({{0.15f, Vec3d(Vec3f(0.35f))}},
                                                1.0 / double(resolution), halfWidth, threaded);
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createEnrightEightSpheres(int resolution, float halfWidth, bool threaded) {
    if (resolution <= 0)
        throw ValueError("createEnrightEightSpheres: the resolution must be positive");
    const double r = 0.125f;
    const auto at = [](float x, float y, float z) { return Vec3d(Vec3f(x, y, z)); };
    const std::vector<std::pair<double, Vec3d>> spheres = {
        {r, at(0.35f, 0.35f, 0.35f)}, {r, at(0.15f, 0.15f, 0.85f)}, {r, at(0.15f, 0.85f, 0.15f)},
        {r, at(0.35f, 0.65f, 0.65f)}, {r, at(0.85f, 0.15f, 0.15f)}, {r, at(0.65f, 0.35f, 0.65f)},
        {r, at(0.65f, 0.65f, 0.35f)}, {r, at(0.85f, 0.85f, 0.85f)}};
    return detail::createLevelSetSpheres<GridT>(spheres, 1.0 / double(resolution), halfWidth,
                                                threaded);
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/LevelSetSphere.cpp

namespace vdb::tools {

extern template FloatGrid::Ptr createLevelSetSphere<FloatGrid>(float, const Vec3f&, float, float,
                                                               bool);
extern template DoubleGrid::Ptr createLevelSetSphere<DoubleGrid>(float, const Vec3f&, float, float,
                                                                 bool);
extern template FloatGrid::Ptr createLevelSetSphere<FloatGrid>(double, const Vec3d&, double, double,
                                                               bool);
extern template DoubleGrid::Ptr createLevelSetSphere<DoubleGrid>(double, const Vec3d&, double,
                                                                 double, bool);
extern template FloatGrid::Ptr createEnrightSphere<FloatGrid>(int, float, bool);
extern template DoubleGrid::Ptr createEnrightSphere<DoubleGrid>(int, float, bool);
extern template FloatGrid::Ptr createEnrightEightSpheres<FloatGrid>(int, float, bool);
extern template DoubleGrid::Ptr createEnrightEightSpheres<DoubleGrid>(int, float, bool);

}  // namespace vdb::tools
