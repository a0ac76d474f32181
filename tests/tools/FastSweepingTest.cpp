// SPDX-License-Identifier: Apache-2.0
// Oracle: the analytic distance to a sphere, |x - c| - R, and its gradient, of norm 1 away from
// the centre; for extension, a surface field that depends only on the direction from the
// centre, so its exact extension along the normals is known at every voxel.
//
// The error bound checked below, in voxels, for a voxel at distance d voxels from a sphere of
// radius 24 voxels:
//     |phi - d| <= e0 + 0.045 |d|
// The first term is the boundary condition's: e0 = 0.1 where the band's own values are the
// boundary (dilateSdf, maskSdf: the band voxels keep their exact values), e0 = 0.45 where the
// boundary voxels get their distance from the crossings of the isosurface along the three axes
// (fogToSdf, sdfToSdf: h / sqrt(sum 1 / t_a^2), OpenVDB's formula, which overestimates by up
// to sqrt(2) where a crossing falls just beyond a neighbour, about 0.4 voxel). The second is the
// first-order scheme's, which grows with the distance: measured 0.012 per voxel outside the
// sphere and up to 0.045 per voxel inside, where the characteristics converge on the centre
// (about one voxel at 20 voxels deep).

#include <vdb/Grid.h>
#include <vdb/tools/FastSweeping.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/LevelSetUtil.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

namespace vdb {
namespace {

using tools::FastSweepingDomain;

constexpr double RADIUS = 24.0;  // voxels
const Vec3d CENTER(1.3, -0.7, 2.2);

/// The signed distance, in voxels, from the centre of voxel `ijk` to the sphere.
double sphereDistance(const Coord& ijk, double radius = RADIUS) {
    return (Vec3d(ijk) - CENTER).length() - radius;
}

constexpr double BAND_BOUNDARY = 0.1, CROSSING_BOUNDARY = 0.45;  // e0 above, voxels

double firstOrderBound(double e0, double distanceVoxels) {
    return e0 + 0.045 * std::abs(distanceVoxels);
}

/// Largest error, in voxels, of the active values of `grid` (voxel size h) against the
/// sphere's distance, and how many active voxels break the bound with boundary term `e0`; the
/// voxels within 2 voxels of the centre (the medial axis, where the distance has a kink) are
/// left out.
template <typename GridT>
std::pair<double, size_t> sphereError(const GridT& grid, double h, double e0,
                                      double radius = RADIUS) {
    double worst = 0.0;
    size_t broken = 0;
    for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
        if ((Vec3d(it.getCoord()) - CENTER).length() < 2.0)
            continue;
        const double exact = sphereDistance(it.getCoord(), radius);
        const double err = std::abs(double(*it) / h - exact);
        worst = std::max(worst, err);
        if (err > firstOrderBound(e0, exact))
            ++broken;
    }
    return {worst, broken};
}

/// Fraction of the active voxels farther than `minRadius` voxels from the centre and 2 voxels
/// from the surface (beyond the boundary condition's voxels), whose six neighbours are active,
/// where the central-difference gradient norm is not 1 within 5%; and the number of voxels
/// checked.
template <typename GridT>
std::pair<double, size_t> gradientFailures(const GridT& grid, double h, double minRadius) {
    tree::ValueAccessor<const typename GridT::TreeType> acc(grid.tree());
    size_t checked = 0, failed = 0;
    for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
        const Coord ijk = it.getCoord();
        if ((Vec3d(ijk) - CENTER).length() < minRadius || std::abs(double(*it)) < 2.0 * h)
            continue;
        Vec3d g;
        bool inside = true;
        for (int a = 0; a < 3 && inside; ++a) {
            Coord lo = ijk, hi = ijk;
            lo[a] -= 1;
            hi[a] += 1;
            inside = acc.isValueOn(lo) && acc.isValueOn(hi);
            g[a] = (double(acc.getValue(hi)) - double(acc.getValue(lo))) / (2.0 * h);
        }
        if (!inside)
            continue;
        ++checked;
        if (std::abs(g.length() - 1.0) > 0.05)
            ++failed;
    }
    return {checked ? double(failed) / double(checked) : 1.0, checked};
}

/// A fog volume of the sphere: density 0.5 - d / (2w) clamped to [0, 1] (d the signed
/// distance, w = 2 voxels), active on every voxel of a box 10 voxels beyond the sphere.
template <typename GridT>
typename GridT::Ptr fogSphere(double h) {
    using ValueT = typename GridT::ValueType;
    auto fog = GridT::create(ValueT(0));
    fog->setTransform(math::Transform::createLinearTransform(h));
    fog->setGridClass(GRID_FOG_VOLUME);
    const Int32 r = Int32(RADIUS) + 10;
    auto acc = fog->getAccessor();
    for (Int32 i = -r; i <= r; ++i) {
        for (Int32 j = -r; j <= r; ++j) {
            for (Int32 k = -r; k <= r; ++k) {
                const double d = sphereDistance(Coord(i, j, k));
                acc.setValue(Coord(i, j, k), ValueT(std::clamp(0.5 - d / 4.0, 0.0, 1.0)));
            }
        }
    }
    return fog;
}

FloatGrid::Ptr sphereLevelSet(double h, double halfWidth) {
    return tools::createLevelSetSphere<FloatGrid>(RADIUS * h, CENTER * h, h, halfWidth);
}

TEST(FastSweeping, FogSphereToSdfIsWithinTheFirstOrderBound) {
    const double h = 0.5;
    const auto fog = fogSphere<FloatGrid>(h);
    const auto sdf = tools::fogToSdf(*fog, 0.5f);
    EXPECT_EQ(sdf->getGridClass(), GRID_LEVEL_SET);
    EXPECT_EQ(sdf->activeVoxelCount(), fog->activeVoxelCount());
    const auto [worst, broken] = sphereError(*sdf, h, CROSSING_BOUNDARY);
    EXPECT_EQ(broken, 0u) << "worst error " << worst << " voxels";
    const auto [fraction, checked] = gradientFailures(*sdf, h, 4.0);
    EXPECT_GT(checked, 100000u);
    EXPECT_LT(fraction, 0.01) << checked << " voxels checked";
    // Inactive values and the background are the extrema, with the sign of their side.
    EXPECT_GT(sdf->background(), float(20 * h));
    EXPECT_LT(sdf->tree().getValue(Coord(0, 0, 0)), 0.0f);
}

TEST(FastSweeping, DoubleFogSphereToSdfIsWithinTheFirstOrderBound) {
    const auto fog = fogSphere<DoubleGrid>(1.0);
    const auto sdf = tools::fogToSdf(*fog, 0.5);
    EXPECT_EQ(sphereError(*sdf, 1.0, CROSSING_BOUNDARY).second, 0u);
}

TEST(FastSweeping, DistortedBandIsRedistanced) {
    const double h = 0.25;
    auto band = sphereLevelSet(h, 8.0);
    // Scale the values by 0.5 to 1.5, varying along x: the surface stays, the distances do not.
    for (auto it = band->tree().beginValueAll(); it; ++it) {
        const double s = 1.0 + 0.5 * std::tanh(double(it.getCoord()[0]) / RADIUS);
        it.setValue(float(double(*it) * s));
    }
    const auto before = sphereError(*band, h, CROSSING_BOUNDARY);
    ASSERT_GT(before.second, 1000u) << "the distortion must break the bound";
    const auto sdf = tools::sdfToSdf(*band);
    EXPECT_EQ(sdf->activeVoxelCount(), band->activeVoxelCount());
    const auto [worst, broken] = sphereError(*sdf, h, CROSSING_BOUNDARY);
    EXPECT_EQ(broken, 0u) << "worst error " << worst << " voxels";
    EXPECT_LT(gradientFailures(*sdf, h, 4.0).first, 0.01);
}

TEST(FastSweeping, DilateSdfByTwentyVoxelsIsWithinTheFirstOrderBound) {
    const double h = 0.5;
    const auto band = sphereLevelSet(h, 3.0);
    const auto wide = tools::dilateSdf(*band, 20);
    // The band voxels keep their values; the new ones reach 20 voxels out along the axes.
    tree::ValueAccessor<const FloatTree> acc(wide->tree());
    for (auto it = band->tree().cbeginValueOn(); it; ++it)
        ASSERT_TRUE(test::sameBits(acc.getValue(it.getCoord()), *it)) << it.getCoord();
    const Coord out(Int32(std::lround(CENTER[0] + RADIUS + 22)), Int32(std::lround(CENTER[1])),
                    Int32(std::lround(CENTER[2])));
    EXPECT_TRUE(acc.isValueOn(out));
    EXPECT_GT(wide->activeVoxelCount(), 6 * band->activeVoxelCount());
    const auto [worst, broken] = sphereError(*wide, h, BAND_BOUNDARY);
    EXPECT_EQ(broken, 0u) << "worst error " << worst << " voxels";
    EXPECT_LT(gradientFailures(*wide, h, 4.0).first, 0.01);
    EXPECT_GT(wide->background(), float(20 * h));
}

TEST(FastSweeping, DilateSdfOutsideOnlyGrowsTheOutside) {
    const auto band = sphereLevelSet(1.0, 3.0);
    const auto wide = tools::dilateSdf(*band, 6, tools::NN_FACE_EDGE_VERTEX, 1,
                                       FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE);
    tree::ValueAccessor<const FloatTree> acc(band->tree());
    size_t added = 0;
    for (auto it = wide->tree().cbeginValueOn(); it; ++it) {
        if (acc.isValueOn(it.getCoord())) {
            ASSERT_TRUE(test::sameBits(*it, acc.getValue(it.getCoord())));
        } else {
            ASSERT_GT(*it, 0.0f) << it.getCoord();
            ++added;
        }
    }
    EXPECT_GT(added, 10000u);
    EXPECT_EQ(sphereError(*wide, 1.0, BAND_BOUNDARY).second, 0u);
}

TEST(FastSweeping, MaskSdfFillsTheMask) {
    const auto band = sphereLevelSet(1.0, 3.0);
    auto mask = MaskGrid::create();
    mask->tree().fill(CoordBBox(Coord(-40), Coord(40)), true, true);
    const auto filled = tools::maskSdf(*band, *mask);
    EXPECT_GE(filled->activeVoxelCount(), Index64(81 * 81 * 81));
    for (auto it = mask->tree().cbeginValueOn(); it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        EXPECT_TRUE(filled->tree().isValueOn(box.min()));
    }
    EXPECT_EQ(sphereError(*filled, 1.0, BAND_BOUNDARY).second, 0u);
    auto moved = MaskGrid::create();
    moved->setTransform(math::Transform::createLinearTransform(2.0));
    EXPECT_THROW(tools::maskSdf(*band, *moved), ValueError);
}

/// The scalar surface field cos(theta) of the direction from the centre (world positions).
struct CosTheta {
    double h;
    float operator()(const Vec3d& xyz) const {
        const Vec3d d = xyz / h - CENTER;
        return float(d[2] / d.length());
    }
};

/// The largest difference, over the active voxels at least 4 voxels from the centre and at
/// most `depth` voxels from the surface, between the extension of CosTheta in `ext` and its
/// exact value: the surface value at the foot of the normal through the voxel, cos(theta) of
/// the voxel's own direction.
double worstCosThetaError(const FloatGrid& ext, double depth = 1e9) {
    double worst = 0.0;
    for (auto it = ext.tree().cbeginValueOn(); it; ++it) {
        const Vec3d d = Vec3d(it.getCoord()) - CENTER;
        if (d.length() >= 4.0 && std::abs(d.length() - RADIUS) <= depth)
            worst = std::max(worst, std::abs(double(*it) - d[2] / d.length()));
    }
    return worst;
}

TEST(FastSweeping, ExtensionIsConstantAlongTheNormals) {
    const double h = 0.5;
    const auto band = tools::dilateSdf(*sphereLevelSet(h, 3.0), 5);
    const auto [sdf, ext] = tools::sdfToSdfAndExt(*band, CosTheta{h}, 7.0f, 0.0f);
    EXPECT_TRUE(ext->transform() == band->transform());
    EXPECT_EQ(ext->activeVoxelCount(), band->activeVoxelCount());
    EXPECT_LT(worstCosThetaError(*ext), 0.05);

    // A vector field (a rotation about z, scaled to unit speed on the surface) likewise.
    const auto vel = tools::sdfToExt(
        *band,
        [h](const Vec3d& xyz) {
            const Vec3d d = xyz / h - CENTER;
            const double rxy = std::sqrt(d[0] * d[0] + d[1] * d[1]) + 1e-12;
            return Vec3s(float(-d[1] / rxy), float(d[0] / rxy), 0.0f);
        },
        Vec3s(0.0f), 0.0f);
    double worstVec = 0.0;
    for (auto it = vel->tree().cbeginValueOn(); it; ++it) {
        const Vec3d d = Vec3d(it.getCoord()) - CENTER;
        const double rxy = std::sqrt(d[0] * d[0] + d[1] * d[1]);
        if (d.length() < 4.0 || rxy < 4.0)
            continue;
        const Vec3d exact(-d[1] / rxy, d[0] / rxy, 0.0);
        worstVec = std::max(worstVec, (Vec3d(*it) - exact).length());
    }
    EXPECT_LT(worstVec, 0.05);
}

TEST(FastSweeping, FogExtensionUsesTheFogSurface) {
    const auto fog = fogSphere<FloatGrid>(1.0);
    const auto ext = tools::fogToExt(*fog, CosTheta{1.0}, 0.0f, 0.5f);
    // Within 10 voxels of the surface; deeper, towards the centre where the normals meet, the
    // first-order extension drifts (0.05 at 15 voxels, 0.16 at 20).
    EXPECT_LT(worstCosThetaError(*ext, 10.0), 0.05);
}

TEST(FastSweeping, OneSidedExtensionKeepsTheOtherSide) {
    const auto band = sphereLevelSet(1.0, 4.0);
    auto input = FloatGrid::create(0.0f);
    input->tree().topologyUnion(band->tree());
    for (auto it = input->tree().beginValueOn(); it; ++it)
        it.setValue(-3.0f);
    const auto ext = tools::sdfToExt(*band, CosTheta{1.0}, 0.0f, 0.0f, 1,
                                     FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE,
                                     FloatGrid::ConstPtr(input));
    tree::ValueAccessor<const FloatTree> sdf(band->tree());
    size_t kept = 0;
    for (auto it = ext->tree().cbeginValueOn(); it; ++it) {
        if (sdf.getValue(it.getCoord()) < -1.0f) {
            EXPECT_EQ(*it, -3.0f) << it.getCoord();
            ++kept;
        }
    }
    EXPECT_GT(kept, 1000u);
    EXPECT_THROW(tools::sdfToExt(*band, CosTheta{1.0}, 0.0f, 0.0f, 1,
                                 FastSweepingDomain::SWEEP_LESS_THAN_ISOVALUE),
                 ValueError);
}

/// Success when both trees have the same leaves, in the same order, with the same masks and
/// bitwise equal values, the same tile counts and the same background.
template <typename TreeT>
::testing::AssertionResult identicalLeaves(const TreeT& a, const TreeT& b) {
    if (a.leafCount() != b.leafCount() || a.activeTileCount() != b.activeTileCount() ||
        !test::sameBits(a.background(), b.background()))
        return ::testing::AssertionFailure() << "leaf counts, tile counts or backgrounds differ";
    auto lb = b.cbeginLeaf();
    for (auto la = a.cbeginLeaf(); la; ++la, ++lb) {
        const auto& x = *la.getLeaf();
        const auto& y = *lb.getLeaf();
        if (!(x.origin() == y.origin()) || !(x.getValueMask() == y.getValueMask()) ||
            std::memcmp(x.buffer(0).data(), y.buffer(0).data(),
                        sizeof(typename TreeT::ValueType) * x.NUM_VALUES) != 0)
            return ::testing::AssertionFailure() << "the leaves at " << x.origin() << " differ";
    }
    return ::testing::AssertionSuccess();
}

TEST(FastSweeping, ResultsDoNotDependOnTheThreadCount) {
    const auto fog = fogSphere<FloatGrid>(1.0);
    const auto band = sphereLevelSet(1.0, 3.0);
    const auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return std::make_tuple(tools::fogToSdf(*fog, 0.5f), tools::dilateSdf(*band, 12),
                               tools::sdfToExt(*band, CosTheta{1.0}, 0.0f, 0.0f, 2));
    };
    const auto [sdf1, wide1, ext1] = run(1);
    const auto [sdf2, wide2, ext2] = run(2);
    EXPECT_TRUE(identicalLeaves(sdf1->tree(), sdf2->tree()));
    EXPECT_TRUE(identicalLeaves(wide1->tree(), wide2->tree()));
    EXPECT_TRUE(identicalLeaves(ext1->tree(), ext2->tree()));
}

TEST(FastSweeping, ActiveTilesBecomeVoxels) {
    // sdfToFogVolume makes the interior active tiles of 1.
    auto fog = sphereLevelSet(1.0, 3.0);
    tools::sdfToFogVolume(*fog);
    ASSERT_GT(fog->tree().activeTileCount(), 0u);
    const auto sdf = tools::fogToSdf(*fog, 0.5f);
    EXPECT_EQ(sdf->tree().activeTileCount(), 0u);
    EXPECT_EQ(sdf->activeVoxelCount(), fog->activeVoxelCount());
    // The fog's 0.5 surface lies 1.5 voxels inside the sphere (a ramp over the inner band).
    EXPECT_EQ(sphereError(*sdf, 1.0, CROSSING_BOUNDARY, RADIUS - 1.5).second, 0u);
}

TEST(FastSweeping, ReportsAnIsovalueThatMissesTheVolume) {
    const auto fog = fogSphere<FloatGrid>(1.0);
    tools::FastSweeping<FloatGrid> fs;
    EXPECT_FALSE(fs.initSdf(*fog, 2.0f, false));
    EXPECT_EQ(fs.boundaryVoxelCount(), 0u);
    EXPECT_THROW(fs.sweep(), ValueError);
    // OpenVDB's convention: every active value is +-max.
    const auto sdf = tools::fogToSdf(*fog, 2.0f);
    EXPECT_EQ(sdf->tree().getValue(Coord(0)), std::numeric_limits<float>::max());
    EXPECT_THROW(tools::dilateSdf(*sdf, -1), ValueError);
    tools::FastSweeping<FloatGrid> unused;
    EXPECT_THROW(unused.sweep(), ValueError);
}

}  // namespace
}  // namespace vdb
