// SPDX-License-Identifier: Apache-2.0
/// @file
/// Rasterization of spheres (particles with a position and a radius) into a narrow-band level
/// set: the CSG union of their signed distance fields (paper section 4.5, appendix B), and the
/// torus-knot-helix of the paper's Fig. 8 as a reusable list of spheres.
///
/// A voxel's value is the smallest signed distance to the spheres, min_i(|x - c_i| - r_i), in
/// world units; it is active when that distance lies within the half width of the band (the
/// grid's background over its voxel size). Deeper inside it is an inactive -background,
/// farther outside the background. Inside the union where spheres overlap, the value is the
/// union of the fields (the depth inside the deepest sphere), as with any CSG union.
///
/// Spheres are bucketed into blocks of 64^3 voxels; each block (one task) builds its own leaves,
/// each leaf from the spheres whose band can reach it, so tasks never share a leaf. The new
/// leaves are flood-filled (section 4.6) and merged into the grid by csgUnion (section 4.3), so
/// several calls accumulate, and the grid is the same for every thread count.
///
/// Small and large particles: a sphere whose radius is below getRmin() voxels (default 1.5) is
/// skipped, since the grid cannot resolve it (a level set of a sub-voxel sphere has no inside
/// voxel and an unreliable zero crossing); getMinCount() counts them. A radius above getRmax()
/// voxels (default unlimited) is clamped to it and counted by getMaxCount().
///
/// Cost: for each sphere, its band's voxels (about 4 pi r^2 * 2 * halfWidth distance
/// evaluations), plus a sort of (block, sphere) pairs.
///
/// @code
/// auto grid = vdb::FloatGrid::create(/*background=*/3 * 0.01f);
/// grid->setTransform(vdb::math::Transform::createLinearTransform(0.01));
/// grid->setGridClass(vdb::GRID_LEVEL_SET);
/// vdb::tools::ParticlesToLevelSet<vdb::FloatGrid> raster(*grid);
/// auto tkh = vdb::tools::torusKnotHelixSpheres(1'000'000);
/// raster.rasterizeSpheres(tkh.positions, tkh.radii);
/// raster.finalize();
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/detail/BlockRaster.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools {

/// Spheres in world space: positions[n] with radius radii[n].
struct SphereList {
    std::vector<Vec3s> positions;
    std::vector<float> radii;
};

/// Returns `count` spheres placed at random along the torus-knot-helix curve of the paper's
/// Fig. 8 in the unit box: a (2, 3) torus knot (major radius 0.25, minor 0.1, centred at
/// (0.5, 0.5, 0.5), axis z) with a helix of radius 0.03 wound 64 times around it. Radii are
/// drawn from [0.75, 1] * `radius`. The same seed gives the same spheres on every platform.
inline SphereList torusKnotHelixSpheres(size_t count, float radius = 0.005f,
                                        uint64_t seed = 20130601);

/// Rasterizes spheres into a narrow-band level set grid (see the file comment).
///
/// The grid must have a linear transform with a uniform scale and a positive background,
/// which sets the band's half width (background / voxel size voxels, at least 1); its tree
/// should hold a level set (or be empty).
/// Threads: one rasterizer per grid; calls run in parallel inside when `threaded`.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
class ParticlesToLevelSet {
public:
    using ValueType = typename GridT::ValueType;

    /// @throw ValueError when the background is not positive or not at least one voxel, or
    ///        the transform is not linear with a uniform scale.
    explicit ParticlesToLevelSet(GridT& grid, bool threaded = true);

    /// Radii below `rmin` voxels are skipped (default 1.5).
    void setRmin(double rmin) { mRmin = rmin; }
    double getRmin() const { return mRmin; }
    /// Radii above `rmax` voxels are clamped to it (default: no limit).
    void setRmax(double rmax) { mRmax = rmax; }
    double getRmax() const { return mRmax; }
    /// Particles skipped as too small, and clamped as too large, over all calls.
    size_t getMinCount() const { return mMinCount; }
    size_t getMaxCount() const { return mMaxCount; }
    bool ignoredParticles() const { return mMinCount > 0 || mMaxCount > 0; }

    /// Adds the union of the spheres (positions[n], radii[n]) to the grid.
    /// @throw ValueError when the sizes differ or a position is not finite or too far out.
    void rasterizeSpheres(const std::vector<Vec3s>& positions, const std::vector<float>& radii);
    /// Adds spheres of one radius.
    void rasterizeSpheres(const std::vector<Vec3s>& positions, float radius) {
        rasterizeSpheres(positions, std::vector<float>(positions.size(), radius));
    }
    /// Adds the spheres of an OpenVDB-style particle list: `list.size()` and
    /// `list.getPosRad(n, xyz, radius)`.
    template <typename ParticleListT>
    void rasterizeSpheres(const ParticleListT& list);

    /// Prunes the grid's tree (pruneLevelSet). The grid is a valid level set after every
    /// rasterizeSpheres() call already; this only compacts it.
    void finalize(bool prune = true) {
        if (prune)
            pruneLevelSet(mGrid->tree(), mThreaded);
    }

private:
    GridT* mGrid;
    bool mThreaded;
    double mRmin = 1.5;
    double mRmax = std::numeric_limits<double>::infinity();
    size_t mMinCount = 0, mMaxCount = 0;
};

// ---- Implementation ---------------------------------------------------------------------------

inline SphereList torusKnotHelixSpheres(size_t count, float radius, uint64_t seed) {
    // SplitMix64: the same stream on every platform, unlike <random>'s distributions.
    uint64_t state = seed;
    const auto uniform = [&state] {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
    };
    constexpr double P = 2.0, Q = 3.0, MAJOR = 0.25, MINOR = 0.1, HELIX = 0.03, TURNS = 64.0;
    const auto knot = [&](double t) {
        const double rr = MAJOR + MINOR * std::cos(Q * t);
        return Vec3d(rr * std::cos(P * t), rr * std::sin(P * t), MINOR * std::sin(Q * t));
    };
    SphereList out;
    out.positions.reserve(count);
    out.radii.reserve(count);
    for (size_t n = 0; n < count; ++n) {
        const double t = 2.0 * std::numbers::pi * uniform();
        // A frame around the knot: its tangent, and two normals from the z axis.
        const double h = 1e-5;
        const Vec3d tangent = (knot(t + h) - knot(t - h)).unitSafe();
        Vec3d normal = tangent.cross(Vec3d(0.0, 0.0, 1.0)).unitSafe();
        const Vec3d binormal = tangent.cross(normal);
        const double phase = TURNS * t;
        const Vec3d p =
            knot(t) + (normal * std::cos(phase) + binormal * std::sin(phase)) * HELIX + Vec3d(0.5);
        out.positions.emplace_back(p);
        out.radii.push_back(radius * float(0.75 + 0.25 * uniform()));
    }
    return out;
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
ParticlesToLevelSet<GridT>::ParticlesToLevelSet(GridT& grid, bool threaded)
    : mGrid(&grid), mThreaded(threaded) {
    const math::Transform& xform = grid.transform();
    if (!xform.isLinear() || !xform.hasUniformScale())
        throw ValueError("ParticlesToLevelSet: the transform must be linear with a uniform scale");
    const double halfWidth = double(grid.background()) / xform.voxelSize()[0];
    if (!(halfWidth >= 1.0) || !std::isfinite(halfWidth))
        throw ValueError("ParticlesToLevelSet: the background must be at least one voxel");
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
template <typename ParticleListT>
void ParticlesToLevelSet<GridT>::rasterizeSpheres(const ParticleListT& list) {
    std::vector<Vec3s> positions(list.size());
    std::vector<float> radii(list.size());
    for (size_t n = 0; n < list.size(); ++n) {
        typename ParticleListT::PosType xyz;
        double r = 0;
        list.getPosRad(n, xyz, r);
        positions[n] = Vec3s(float(xyz[0]), float(xyz[1]), float(xyz[2]));
        radii[n] = float(r);
    }
    rasterizeSpheres(positions, radii);
}

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
void ParticlesToLevelSet<GridT>::rasterizeSpheres(const std::vector<Vec3s>& positions,
                                                  const std::vector<float>& radii) {
    using TreeT = typename GridT::TreeType;
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = ValueType;
    // Distances are computed in the grid's precision: float for float grids (errors of a few
    // 1e-6 voxels for radii of tens of voxels), double otherwise.
    using DistT = std::conditional_t<(sizeof(ValueT) > sizeof(float)), double, float>;
    constexpr Int32 LEAF_DIM = Int32(LeafT::DIM);
    constexpr Index BLOCK_LOG2 = detail::blockLog2<TreeT>();
    using Leaves = detail::BlockLeaves<LeafT, BLOCK_LOG2>;
    if (positions.size() != radii.size())
        throw ValueError("ParticlesToLevelSet: one radius per position is needed");
    const math::Transform& xform = mGrid->transform();
    const double dx = xform.voxelSize()[0];
    const ValueT background = mGrid->background();
    const double w = double(background) / dx;

    // Index-space spheres, without the skipped ones.
    std::vector<Vec3d> centers;
    std::vector<double> rad;
    centers.reserve(positions.size());
    rad.reserve(positions.size());
    for (size_t n = 0; n < positions.size(); ++n) {
        double r = double(radii[n]) / dx;
        if (!(r >= mRmin)) {
            ++mMinCount;
            continue;
        }
        if (r > mRmax) {
            r = mRmax;
            ++mMaxCount;
        }
        centers.push_back(xform.worldToIndex(Vec3d(positions[n])));
        rad.push_back(r);
    }
    const auto reachOf = [&](size_t s) {
        return detail::voxelReach(centers[s], centers[s], rad[s] + w, "ParticlesToLevelSet");
    };
    const detail::BlockBuckets buckets = detail::bucketByBlock(
        centers.size(), BLOCK_LOG2,
        [&](size_t s, CoordBBox& box) {
            box = reachOf(s);
            return true;
        },
        mThreaded);

    // Each block's leaves: the smallest signed distance over the spheres that reach them.
    TreeT fresh(background);
    const double halfDiagonal = 0.5 * double(LEAF_DIM - 1) * std::sqrt(3.0);
    detail::buildLeavesByBlock(
        fresh, buckets.size(),
        [&](size_t b, std::vector<std::unique_ptr<LeafT>>& out) {
            const Coord origin = buckets.origins[b];
            // (leaf in block, sphere); sphere DEEP marks a leaf deep inside some sphere, where
            // the union has no band.
            constexpr uint32_t DEEP = ~uint32_t(0);
            std::vector<std::pair<uint32_t, uint32_t>> pairs;
            for (uint32_t s : buckets.primitives(b)) {
                Leaves::forEachTouched(origin, reachOf(s), [&](uint32_t leaf, const Vec3d& c) {
                    // Only leaves that the sphere's band (not its deep inside) reaches.
                    const double d = (c - centers[s]).length() - rad[s];
                    if (d < w + halfDiagonal + 1e-6)
                        pairs.emplace_back(leaf, d <= -(w + halfDiagonal + 1e-6) ? DEEP : s);
                });
            }
            std::sort(pairs.begin(), pairs.end());

            std::array<DistT, LeafT::NUM_VALUES> dist;
            for (size_t p = 0; p < pairs.size();) {
                const uint32_t leafIndex = pairs[p].first;
                const Coord leafOrigin = Leaves::leafOrigin(origin, leafIndex);
                size_t q = p;
                while (q < pairs.size() && pairs[q].first == leafIndex)
                    ++q;
                if (pairs[q - 1].second == DEEP) {
                    p = q;
                    continue;
                }
                dist.fill(std::numeric_limits<DistT>::infinity());
                for (; p < q; ++p) {
                    const Vec3d& c = centers[pairs[p].second];
                    const double r = rad[pairs[p].second];
                    const double outer = r + w;
                    // Offsets from the centre in double, the distances along a row in DistT.
                    const DistT rr = DistT(r), ez0 = DistT(double(leafOrigin[2]) - c[2]);
                    // The rows of the leaf within the sphere's bounding box.
                    const auto range = [&](int axis) {
                        return std::pair<Int32, Int32>(
                            std::max(Int32(0),
                                     Int32(std::ceil(c[axis] - outer)) - leafOrigin[axis]),
                            std::min(LEAF_DIM - 1,
                                     Int32(std::floor(c[axis] + outer)) - leafOrigin[axis]));
                    };
                    const auto [i0, i1] = range(0);
                    const auto [j0, j1] = range(1);
                    for (Int32 i = i0; i <= i1; ++i) {
                        const double ex = double(leafOrigin[0] + i) - c[0];
                        for (Int32 j = j0; j <= j1; ++j) {
                            const double ey = double(leafOrigin[1] + j) - c[1];
                            const double rest = outer * outer - ex * ex - ey * ey;
                            if (rest <= 0.0)
                                continue;
                            const double reach = std::sqrt(rest);
                            const Int32 k0 =
                                std::max(Int32(0), Int32(std::ceil(c[2] - reach)) - leafOrigin[2]);
                            const Int32 k1 = std::min(
                                LEAF_DIM - 1, Int32(std::floor(c[2] + reach)) - leafOrigin[2]);
                            const DistT exy = DistT(ex * ex + ey * ey);
                            DistT* row = dist.data() + LeafT::coordToOffset(Coord(i, j, 0));
                            for (Int32 k = k0; k <= k1; ++k) {
                                const DistT ez = ez0 + DistT(k);
                                row[k] = std::min(row[k], std::sqrt(exy + ez * ez) - rr);
                            }
                        }
                    }
                }
                auto leaf = std::make_unique<LeafT>(leafOrigin, background, false);
                bool active = false;
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                    if (std::abs(double(dist[n])) < w) {
                        leaf->setValueOn(n, ValueT(double(dist[n]) * dx));
                        active = true;
                    } else if (dist[n] < DistT(0)) {
                        leaf->setValueOff(n, ValueT(-background));
                    }
                }
                if (active)
                    out.push_back(std::move(leaf));
            }
        },
        mThreaded);

    // Signs beyond the band, then the union with what the grid holds.
    signedFloodFill(fresh, mThreaded);
    csgUnion(mGrid->tree(), fresh, /*prune=*/false, mThreaded);
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/ParticlesToLevelSet.cpp

namespace vdb::tools {

extern template class ParticlesToLevelSet<FloatGrid>;
extern template class ParticlesToLevelSet<DoubleGrid>;

}  // namespace vdb::tools
