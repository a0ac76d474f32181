// SPDX-License-Identifier: Apache-2.0
// Oracle: the analytic CSG union of the spheres' signed distance fields,
// min_i(|x - c_i| - r_i), evaluated by brute force at every voxel of the spheres' box.

#include <vdb/tools/ParticlesToLevelSet.h>
#include <vdb/vdb.h>

#include "GridContents.h"
#include "Oracles.h"
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>

namespace vdb::tools {
namespace {

FloatGrid::Ptr makeLevelSetGrid(double voxelSize, double halfWidth) {
    auto grid = FloatGrid::create(float(voxelSize * halfWidth));
    grid->setTransform(math::Transform::createLinearTransform(voxelSize));
    grid->setGridClass(GRID_LEVEL_SET);
    return grid;
}

SphereList randomSpheres(int count, double boxSize, double rMin, double rMax, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(0.0, boxSize), rad(rMin, rMax);
    SphereList out;
    for (int n = 0; n < count; ++n) {
        out.positions.emplace_back(Vec3d(pos(rng), pos(rng), pos(rng)) - Vec3d(0.5 * boxSize));
        out.radii.push_back(float(rad(rng)));
    }
    return out;
}

/// Compares every voxel of the spheres' box grown by the band with the analytic union.
::testing::AssertionResult matchesUnion(const FloatGrid& grid, const SphereList& spheres, double dx,
                                        double w) {
    Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (size_t n = 0; n < spheres.positions.size(); ++n) {
        lo = Vec3d::minComponent(lo, Vec3d(spheres.positions[n]) - double(spheres.radii[n]));
        hi = Vec3d::maxComponent(hi, Vec3d(spheres.positions[n]) + double(spheres.radii[n]));
    }
    const Coord a = math::floorToCoord(lo / dx - (w + 2)), b = math::floorToCoord(hi / dx + w + 2);
    const auto acc = grid.getConstAccessor();
    int failures = 0;
    Index64 active = 0;
    std::ostringstream msg;
    for (Int32 i = a[0]; i <= b[0]; ++i) {
        for (Int32 j = a[1]; j <= b[1]; ++j) {
            for (Int32 k = a[2]; k <= b[2]; ++k) {
                const Vec3d p(Coord(i, j, k));
                double v = std::numeric_limits<double>::max();
                for (size_t n = 0; n < spheres.positions.size(); ++n) {
                    const Vec3d c = Vec3d(spheres.positions[n]) / dx;
                    v = std::min(v, (p - c).length() - double(spheres.radii[n]) / dx);
                }
                if (std::abs(std::abs(v) - w) < 1e-5 || std::abs(v) < 1e-5)
                    continue;  // on the band's edge or the surface, up to float rounding: either is
                               // right
                float value = 0;
                const bool on = acc.probeValue(Coord(i, j, k), value);
                bool ok = on == (std::abs(v) < w);
                if (ok && on) {
                    ++active;
                    ok = std::abs(double(value) / dx - v) < 1e-4;
                } else if (ok) {
                    ok = value == (v < 0 ? -grid.background() : grid.background());
                }
                if (!ok && ++failures <= 8) {
                    msg << "\n  " << Coord(i, j, k) << ": " << (on ? "active " : "inactive ")
                        << value / dx << ", expected " << v;
                }
            }
        }
    }
    if (active == 0)
        return ::testing::AssertionFailure() << "no active voxel";
    if (failures > 0)
        return ::testing::AssertionFailure() << failures << " voxels differ:" << msg.str();
    return ::testing::AssertionSuccess();
}

TEST(ParticlesToLevelSet, OverlappingSpheresGiveTheUnionOfTheirDistanceFields) {
    const double dx = 0.1, w = 3.0;
    const SphereList spheres = randomSpheres(40, 5.0, 0.2, 0.7, 7);
    auto grid = makeLevelSetGrid(dx, w);
    ParticlesToLevelSet<FloatGrid> raster(*grid);
    raster.rasterizeSpheres(spheres.positions, spheres.radii);
    raster.finalize();
    EXPECT_FALSE(raster.ignoredParticles());
    EXPECT_TRUE(matchesUnion(*grid, spheres, dx, w));
}

TEST(ParticlesToLevelSet, NestedSpheresLeaveNoBandInsideTheOuterOne) {
    // A small sphere deep inside a large one adds nothing.
    const double dx = 0.1, w = 3.0;
    SphereList spheres;
    spheres.positions = {Vec3s(0.0f, 0.0f, 0.0f), Vec3s(0.3f, -0.2f, 0.1f)};
    spheres.radii = {2.0f, 0.4f};
    auto grid = makeLevelSetGrid(dx, w);
    ParticlesToLevelSet<FloatGrid> raster(*grid);
    raster.rasterizeSpheres(spheres.positions, spheres.radii);
    EXPECT_TRUE(matchesUnion(*grid, spheres, dx, w));
}

TEST(ParticlesToLevelSet, SmallParticlesAreSkippedAndLargeOnesClamped) {
    const double dx = 0.1;
    auto grid = makeLevelSetGrid(dx, 3.0);
    ParticlesToLevelSet<FloatGrid> raster(*grid);
    raster.setRmax(10.0);
    // Radii of 0.5 and 1.2 voxels are skipped (below 1.5), 2 voxels kept, 30 clamped to 10.
    raster.rasterizeSpheres({Vec3s(0, 0, 0), Vec3s(5, 0, 0), Vec3s(-5, 0, 0), Vec3s(0, 5, 0)},
                            {0.05f, 0.12f, 0.2f, 3.0f});
    EXPECT_EQ(raster.getMinCount(), 2u);
    EXPECT_EQ(raster.getMaxCount(), 1u);
    EXPECT_TRUE(raster.ignoredParticles());
    SphereList expected;
    expected.positions = {Vec3s(-5, 0, 0), Vec3s(0, 5, 0)};
    expected.radii = {0.2f, 1.0f};
    EXPECT_TRUE(matchesUnion(*grid, expected, dx, 3.0));
}

TEST(ParticlesToLevelSet, ResultDoesNotDependOnTheThreadCount) {
    const auto spheres = torusKnotHelixSpheres(20000, 0.01f);
    const auto build = [&](bool threaded) {
        auto grid = makeLevelSetGrid(1.0 / 256, 3.0);
        ParticlesToLevelSet<FloatGrid> raster(*grid, threaded);
        raster.rasterizeSpheres(spheres.positions, spheres.radii);
        raster.finalize();
        return grid;
    };
    const auto threaded = build(true);
    ASSERT_GT(threaded->tree().leafCount(), 1000u);
    const auto sameContents = [](const FloatTree& a, const FloatTree& b) {
        const auto ca = test::treeContents(a), cb = test::treeContents(b);
        if (ca.size() != cb.size())
            return false;
        for (size_t n = 0; n < ca.size(); ++n) {
            if (!(ca[n].min == cb[n].min) || ca[n].level != cb[n].level ||
                ca[n].active != cb[n].active || !test::sameBits(ca[n].value, cb[n].value)) {
                return false;
            }
        }
        return true;
    };
    EXPECT_TRUE(sameContents(threaded->tree(), build(false)->tree()));
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_TRUE(sameContents(threaded->tree(), build(true)->tree()));
}

TEST(ParticlesToLevelSet, SeparateCallsAccumulateByUnion) {
    const double dx = 0.1, w = 2.0;
    const SphereList spheres = randomSpheres(30, 4.0, 0.2, 0.6, 11);
    auto grid = makeLevelSetGrid(dx, w);
    ParticlesToLevelSet<FloatGrid> raster(*grid);
    const size_t half = spheres.positions.size() / 2;
    raster.rasterizeSpheres(
        std::vector<Vec3s>(spheres.positions.begin(), spheres.positions.begin() + half),
        std::vector<float>(spheres.radii.begin(), spheres.radii.begin() + half));
    raster.rasterizeSpheres(
        std::vector<Vec3s>(spheres.positions.begin() + half, spheres.positions.end()),
        std::vector<float>(spheres.radii.begin() + half, spheres.radii.end()));
    EXPECT_TRUE(matchesUnion(*grid, spheres, dx, w));
}

/// Two spheres of radius 0.4, in the shape of OpenVDB's particle lists.
struct TwoParticles {
    using PosType = Vec3d;
    size_t size() const { return 2; }
    void getPosRad(size_t n, Vec3d& xyz, double& r) const {
        xyz = n == 0 ? Vec3d(0.0) : Vec3d(0.5, 0.0, 0.0);
        r = 0.4;
    }
};

TEST(ParticlesToLevelSet, AcceptsOpenVdbStyleParticleLists) {
    auto grid = makeLevelSetGrid(0.05, 3.0);
    ParticlesToLevelSet<FloatGrid> raster(*grid);
    raster.rasterizeSpheres(TwoParticles{});
    SphereList expected;
    expected.positions = {Vec3s(0, 0, 0), Vec3s(0.5f, 0, 0)};
    expected.radii = {0.4f, 0.4f};
    EXPECT_TRUE(matchesUnion(*grid, expected, 0.05, 3.0));
}

TEST(ParticlesToLevelSet, BadInputThrows) {
    auto grid = makeLevelSetGrid(0.1, 3.0);
    ParticlesToLevelSet<FloatGrid> raster(*grid);
    EXPECT_THROW(raster.rasterizeSpheres({Vec3s(0, 0, 0)}, std::vector<float>{}), ValueError);
    EXPECT_THROW(
        raster.rasterizeSpheres({Vec3s(std::numeric_limits<float>::quiet_NaN(), 0, 0)}, {1.0f}),
        ValueError);
    auto thin = makeLevelSetGrid(0.1, 0.5);
    EXPECT_THROW(ParticlesToLevelSet<FloatGrid>{*thin}, ValueError);
}

TEST(TorusKnotHelix, SpheresLieOnAHelixAroundTheKnotAndRepeat) {
    const auto a = torusKnotHelixSpheres(2000, 0.004f);
    const auto b = torusKnotHelixSpheres(2000, 0.004f);
    ASSERT_EQ(a.positions.size(), 2000u);
    ASSERT_EQ(a.radii.size(), 2000u);
    EXPECT_TRUE(a.positions == b.positions && a.radii == b.radii);
    EXPECT_FALSE(torusKnotHelixSpheres(2000, 0.004f, 1).positions == a.positions);
    // The (2, 3) torus knot of radii 0.25 and 0.1 about (0.5, 0.5, 0.5), densely sampled:
    // every sphere lies 0.03 (the helix radius) from it, up to the sampling's spacing.
    std::vector<Vec3d> knot;
    const int samples = 20000;
    for (int n = 0; n < samples; ++n) {
        const double t = 2.0 * std::numbers::pi * n / samples;
        const double rr = 0.25 + 0.1 * std::cos(3.0 * t);
        knot.emplace_back(0.5 + rr * std::cos(2.0 * t), 0.5 + rr * std::sin(2.0 * t),
                          0.5 + 0.1 * std::sin(3.0 * t));
    }
    double lo = 1.0, hi = 0.0;
    for (size_t n = 0; n < a.positions.size(); n += 4) {
        double d = std::numeric_limits<double>::max();
        for (const Vec3d& k : knot)
            d = std::min(d, (Vec3d(a.positions[n]) - k).length());
        lo = std::min(lo, d);
        hi = std::max(hi, d);
        ASSERT_GE(a.radii[n], 0.75f * 0.004f - 1e-9f);
        ASSERT_LE(a.radii[n], 0.004f);
    }
    EXPECT_NEAR(lo, 0.03, 2e-4);
    EXPECT_NEAR(hi, 0.03, 2e-4);
}

}  // namespace
}  // namespace vdb::tools
