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
#include <memory>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// Returns a narrow-band level set of the sphere of `radius` around `center` (world units):
/// background voxelSize * halfWidth, a linear transform of `voxelSize`, grid class level set.
/// A sphere whose radius is below 1.5 voxels gives an empty grid (as in OpenVDB).
/// @param halfWidth  half the width of the band, in voxels.
/// @throw ValueError when radius or voxelSize is not positive or halfWidth is not above 1.
/// @throw IndexError when a band voxel lies outside a bounded tree's domain.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createLevelSetSphere(float radius, const Vec3f& center, float voxelSize,
                                         float halfWidth = 3.0f, bool threaded = true);

/// The Enright sphere of the paper's section 5: radius 0.15 around (0.35, 0.35, 0.35) in the
/// unit box, voxel size 1 / resolution.
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

/// A sphere in index space (voxel units).
template <typename ValueT>
struct IndexSphere {
    math::Vec3<ValueT> center;
    ValueT radius;
};

/// Takes ownership of `leaf` and links it into `tree`, creating the internal nodes above it
/// from the tiles they replace. @pre no leaf exists at its origin
template <typename NodeT, typename LeafT>
void linkLeafBelow(NodeT& node, std::unique_ptr<LeafT>& leaf) {
    using ChildT = typename NodeT::ChildNodeType;
    const Coord ijk = leaf->origin();
    const Index n = NodeT::coordToOffset(ijk);
    if constexpr (ChildT::LEVEL == 0) {
        node.setChild(n, leaf.release());
    } else {
        ChildT* child = node.getChild(n);
        if (!child) {
            child = new ChildT(ijk, node.getTileValue(n), node.isTileOn(n));
            node.setChild(n, child);
        }
        linkLeafBelow(*child, leaf);
    }
}

template <typename TreeT, typename LeafT>
void linkLeaf(TreeT& tree, std::unique_ptr<LeafT> leaf) {
    using TopT = typename TreeT::TopNodeType;
    TreeT::checkDomain(leaf->origin());
    TopT& top = tree.topNode();
    if constexpr (tree::IS_ROOT_NODE<TopT>) {
        using ChildT = typename TopT::ChildNodeType;
        const Coord key = TopT::coordToKey(leaf->origin());
        const auto* e = top.findEntry(key);
        ChildT* child = e ? e->child : nullptr;
        if (!child) {
            child = new ChildT(key, e ? e->tile : top.background(), e ? e->active : false);
            top.setChild(child);
        }
        linkLeafBelow(*child, leaf);
    } else {
        linkLeafBelow(top, leaf);
    }
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
            const Int64 l = Int64(int(std::floor(spheres[s].center[a] - rmax)));
            const Int64 h = Int64(int(std::ceil(spheres[s].center[a] + rmax)));
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
                        const auto& c = spheres[s].center;
                        const ValueT x2 = pow2(ValueT(Int32(i)) - c[0]);
                        const ValueT x2y2 = pow2(ValueT(Int32(j)) - c[1]) + x2;
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
                        const ValueT cz = spheres[near[0].first].center[2];
                        const ValueT r0 = spheres[near[0].first].radius;
                        for (Int64 k = lo[2]; k <= hi[2];) {
                            const ValueT v = std::sqrt(x2y2 + pow2(ValueT(Int32(k)) - cz)) - r0;
                            const ValueT d = std::abs(v);
                            if (d < w) {
                                emit(k, v);
                                ++k;
                            } else {
                                k += 1 + Int64(int(std::floor(d - w)));
                            }
                        }
                        continue;
                    }
                    for (Int64 k = lo[2]; k <= hi[2];) {
                        ValueT v = 0;
                        for (size_t n = 0; n < near.size(); ++n) {
                            const auto& sphere = spheres[near[n].first];
                            const ValueT vs = std::sqrt(near[n].second +
                                                        pow2(ValueT(Int32(k)) - sphere.center[2])) -
                                              sphere.radius;
                            v = n == 0 ? vs : std::min(v, vs);
                        }
                        const ValueT d = std::abs(v);
                        if (d < w) {
                            emit(k, v);
                            ++k;
                        } else {
                            k += 1 + Int64(int(std::floor(d - w)));
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
            linkLeaf(tree, std::move(leaf));
    }
}

/// An empty level-set grid as OpenVDB's createLevelSet makes it: background
/// voxelSize * halfWidth (computed in double), a linear transform, class level set.
template <typename GridT>
typename GridT::Ptr makeLevelSetGrid(typename GridT::ValueType voxelSize,
                                     typename GridT::ValueType halfWidth) {
    using ValueT = typename GridT::ValueType;
    auto grid = GridT::create(ValueT(double(voxelSize) * double(halfWidth)));
    grid->setTransform(math::Transform::createLinearTransform(double(voxelSize)));
    grid->setGridClass(GRID_LEVEL_SET);
    return grid;
}

/// Rasterizes world-space spheres (radius, center) at `voxelSize` into a new level-set grid.
template <typename GridT>
typename GridT::Ptr createLevelSetSpheres(const std::vector<std::pair<float, Vec3f>>& spheres,
                                          float voxelSize, float halfWidth, bool threaded) {
    using ValueT = typename GridT::ValueType;
    for (const auto& sphere : spheres) {
        if (!(ValueT(sphere.first) > ValueT(0)))
            throw ValueError("createLevelSetSphere: the radius must be positive");
    }
    const ValueT dx = ValueT(voxelSize), w = ValueT(halfWidth);
    if (!(dx > ValueT(0)))
        throw ValueError("createLevelSetSphere: the voxel size must be positive");
    if (!(w > ValueT(1)))
        throw ValueError("createLevelSetSphere: the half width must be larger than one voxel");
    auto grid = makeLevelSetGrid<GridT>(dx, w);

    // Spheres below 1.5 voxels of radius are left out.
    std::vector<IndexSphere<ValueT>> indexSpheres;
    for (const auto& [radius, center] : spheres) {
        const ValueT r0 = ValueT(radius) / dx;
        if (r0 < 1.5f)
            continue;
        const math::Vec3<ValueT> c(center);
        indexSpheres.push_back({math::Vec3<ValueT>(c[0] / dx, c[1] / dx, c[2] / dx), r0});
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
    return detail::createLevelSetSpheres<GridT>({{radius, center}}, voxelSize, halfWidth, threaded);
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createEnrightSphere(int resolution, float halfWidth, bool threaded) {
    if (resolution <= 0)
        throw ValueError("createEnrightSphere: the resolution must be positive");
    return createLevelSetSphere<GridT>(0.15f, Vec3f(0.35f, 0.35f, 0.35f), 1.0f / float(resolution),
                                       halfWidth, threaded);
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr createEnrightEightSpheres(int resolution, float halfWidth, bool threaded) {
    if (resolution <= 0)
        throw ValueError("createEnrightEightSpheres: the resolution must be positive");
    const float r = 0.125f;
    const std::vector<std::pair<float, Vec3f>> spheres = {
        {r, Vec3f(0.35f, 0.35f, 0.35f)}, {r, Vec3f(0.15f, 0.15f, 0.85f)},
        {r, Vec3f(0.15f, 0.85f, 0.15f)}, {r, Vec3f(0.35f, 0.65f, 0.65f)},
        {r, Vec3f(0.85f, 0.15f, 0.15f)}, {r, Vec3f(0.65f, 0.35f, 0.65f)},
        {r, Vec3f(0.65f, 0.65f, 0.35f)}, {r, Vec3f(0.85f, 0.85f, 0.85f)}};
    return detail::createLevelSetSpheres<GridT>(spheres, 1.0f / float(resolution), halfWidth,
                                                threaded);
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/LevelSetSphere.cpp

namespace vdb::tools {

extern template FloatGrid::Ptr createLevelSetSphere<FloatGrid>(float, const Vec3f&, float, float,
                                                               bool);
extern template DoubleGrid::Ptr createLevelSetSphere<DoubleGrid>(float, const Vec3f&, float, float,
                                                                 bool);
extern template FloatGrid::Ptr createEnrightSphere<FloatGrid>(int, float, bool);
extern template DoubleGrid::Ptr createEnrightSphere<DoubleGrid>(int, float, bool);
extern template FloatGrid::Ptr createEnrightEightSpheres<FloatGrid>(int, float, bool);
extern template DoubleGrid::Ptr createEnrightEightSpheres<DoubleGrid>(int, float, bool);

}  // namespace vdb::tools
