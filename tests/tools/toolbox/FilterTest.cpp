// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic answers. A constant field survives mean and Gaussian filters; a median
// filter restores a field linear in x where single voxels were spiked; mean-curvature flow
// shrinks a sphere as r^2 = r0^2 - 2t; an offset moves a sphere's surface by the offset
// (inwards for a positive offset, as phi + offset);
// masks leave the voxels of alpha 0 untouched. Radii are measured from the level set's values
// near the surface, not through the library's measures.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/Filter.h>
#include <vdb/tools/LevelSetFilter.h>
#include <vdb/tools/LevelSetSphere.h>

#include "ToolboxTestUtil.h"
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace vdb {
namespace {

using test::forEachVoxel;
using test::sampleField;

const CoordBBox kBox(Coord(-20), Coord(19));

TEST(Filter, MeanAndGaussianLeaveAConstantFieldUnchanged) {
    auto x = math::Transform::createLinearTransform(0.5);
    auto grid = sampleField<FloatGrid>(
        kBox, x, [](const Vec3d&) { return 2.5f; }, 2.5f);
    tools::Filter<FloatGrid> filter(*grid);
    filter.mean(2, 2);
    filter.gaussian(1);
    forEachVoxel(kBox, [&](const Coord& ijk) {
        ASSERT_NEAR(grid->tree().getValue(ijk), 2.5f, 1e-5f) << ijk;
    });
    auto vectors = sampleField<Vec3SGrid>(
        kBox, x, [](const Vec3d&) { return Vec3s(1, -2, 3); }, Vec3s(1, -2, 3));
    tools::Filter<Vec3SGrid> vfilter(*vectors);
    vfilter.gaussian(1, 2);
    forEachVoxel(kBox, [&](const Coord& ijk) {
        const Vec3s v = vectors->tree().getValue(ijk);
        ASSERT_NEAR(v[0], 1.0f, 1e-5f);
        ASSERT_NEAR(v[1], -2.0f, 1e-5f);
        ASSERT_NEAR(v[2], 3.0f, 1e-5f);
    });
}

TEST(Filter, MeanOfALinearFieldKeepsItAwayFromTheBorder) {
    // A box filter reproduces linear functions; the border sees the background.
    auto x = math::Transform::createLinearTransform(1.0);
    auto grid =
        sampleField<DoubleGrid>(kBox, x, [](const Vec3d& p) { return 3 * p[0] - p[1] + 2 * p[2]; });
    tools::Filter<DoubleGrid> filter(*grid);
    filter.mean(2);
    // The weights are float, as in OpenVDB: 1/5 to within 1e-8 relative.
    forEachVoxel(CoordBBox(kBox.min().offsetBy(2), kBox.max().offsetBy(-2)), [&](const Coord& ijk) {
        const double want = 3.0 * ijk[0] - ijk[1] + 2.0 * ijk[2];
        ASSERT_NEAR(grid->tree().getValue(ijk), want, 1e-7 * std::max(1.0, std::abs(want))) << ijk;
    });
    EXPECT_NE(grid->tree().getValue(kBox.min()),
              3.0 * kBox.min()[0] - kBox.min()[1] + 2.0 * kBox.min()[2]);
}

TEST(Filter, IntegerMeanIsTheTruncatedFloatAverageOfEachPass) {
    // Brute-force model: three passes along x, z, y over a dense copy with the background (0)
    // around it; each active voxel becomes int(float(sum of 2w + 1 values) / (2w + 1)).
    const CoordBBox box(Coord(-6), Coord(5));
    const int w = 2, pad = 3 * w, n = 12 + 2 * pad;
    std::vector<int> dense(size_t(n * n * n), 0);
    const auto at = [&](const Coord& ijk) -> int& {
        const Coord d = ijk - box.min() + Coord(pad);
        return dense[size_t((d[0] * n + d[1]) * n + d[2])];
    };
    auto grid = Int32Grid::create(0);
    forEachVoxel(box, [&](const Coord& ijk) {
        const int h = ijk[0] * 7919 + ijk[1] * 104729 + ijk[2] * 1299709;
        const int v = ((h % 201) + 201) % 201 - 100;  // scattered values in [-100, 100]
        grid->tree().setValue(ijk, v);
        at(ijk) = v;
    });
    const float frac = 1.0f / float(2 * w + 1);
    for (const int axis : {0, 2, 1}) {
        std::vector<int> next = dense;
        forEachVoxel(box, [&](const Coord& ijk) {
            int sum = 0;
            for (int d = -w; d <= w; ++d) {
                Coord q = ijk;
                q[size_t(axis)] += d;
                sum += at(q);
            }
            const Coord o = ijk - box.min() + Coord(pad);
            next[size_t((o[0] * n + o[1]) * n + o[2])] = int(float(sum) * frac);
        });
        dense.swap(next);
    }
    tools::Filter<Int32Grid>(*grid).mean(w);
    forEachVoxel(box,
                 [&](const Coord& ijk) { ASSERT_EQ(grid->tree().getValue(ijk), at(ijk)) << ijk; });
    EXPECT_EQ(grid->activeVoxelCount(), box.volume());
}

TEST(Filter, MedianRemovesSingleVoxelSpikes) {
    auto x = math::Transform::createLinearTransform(1.0);
    const auto f = [](const Vec3d& p) { return float(0.5 * p[0]); };
    auto grid = sampleField<FloatGrid>(kBox, x, f);
    const Coord spikes[] = {Coord(0), Coord(5, -3, 7), Coord(-9, 9, 2)};
    for (const Coord& s : spikes)
        grid->tree().setValue(s, 1000.0f);
    tools::Filter<FloatGrid> filter(*grid);
    filter.median(1);
    for (const Coord& s : spikes)
        EXPECT_EQ(grid->tree().getValue(s), f(Vec3d(s))) << s;
    forEachVoxel(CoordBBox(kBox.min().offsetBy(1), kBox.max().offsetBy(-1)), [&](const Coord& ijk) {
        ASSERT_EQ(grid->tree().getValue(ijk), f(Vec3d(ijk))) << ijk;
    });
}

TEST(Filter, MaskLimitsTheFilterToAlphaAboveZero) {
    auto x = math::Transform::createLinearTransform(1.0);
    auto grid = sampleField<FloatGrid>(kBox, x, [](const Vec3d& p) { return float(p[0] * p[0]); });
    auto before = grid->deepCopy();
    // Alpha 1 for z >= 0, 0 below; a mask on another transform is sampled in world space.
    auto mask =
        sampleField<FloatGrid>(kBox, x, [](const Vec3d& p) { return p[2] >= 0 ? 1.0f : 0.0f; });
    tools::Filter<FloatGrid> filter(*grid);
    filter.mean(1, 1, mask.get());
    filter.offset(1.0f, mask.get());
    auto acc = before->getConstAccessor();
    int changed = 0;
    forEachVoxel(kBox, [&](const Coord& ijk) {
        const float v = grid->tree().getValue(ijk), old = acc.getValue(ijk);
        if (ijk[2] < 0)
            ASSERT_EQ(v, old) << ijk;
        else if (v != old)
            ++changed;
    });
    EXPECT_EQ(changed, 40 * 40 * 20);
    // Inverted: the other half.
    auto again = before->deepCopy();
    tools::Filter<FloatGrid> inverted(*again);
    inverted.invertMask();
    inverted.offset(1.0f, mask.get());
    EXPECT_EQ(again->tree().getValue(Coord(3, 3, -3)), acc.getValue(Coord(3, 3, -3)) + 1.0f);
    EXPECT_EQ(again->tree().getValue(Coord(3, 3, 3)), acc.getValue(Coord(3, 3, 3)));
}

TEST(Filter, RefusesBadWidthsAndVectorMedians) {
    auto grid = FloatGrid::create();
    grid->tree().setValue(Coord(0), 1.0f);
    tools::Filter<FloatGrid> filter(*grid);
    EXPECT_THROW(filter.mean(0), ValueError);
    EXPECT_THROW(filter.gaussian(-1), ValueError);
    EXPECT_THROW(filter.mean(tools::FILTER_MAX_WIDTH + 1), ValueError);
    EXPECT_THROW(filter.median(tools::MEDIAN_FILTER_MAX_WIDTH + 1), ValueError);
    EXPECT_THROW(filter.offset(std::nanf("")), ValueError);
    EXPECT_THROW(filter.setMaskRange(1.0f, 1.0f), ValueError);
    EXPECT_EQ(grid->tree().getValue(Coord(0)), 1.0f);  // nothing ran
    auto vectors = Vec3SGrid::create();
    vectors->setName("v");
    tools::Filter<Vec3SGrid> vfilter(*vectors);
    try {
        vfilter.median(1);
        FAIL() << "expected TypeError";
    } catch (const TypeError& e) {
        EXPECT_NE(std::string(e.what()).find("vec3s"), std::string::npos) << e.what();
    }
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.1f);
    tools::LevelSetFilter<FloatGrid> lsf(*sphere);
    EXPECT_THROW(lsf.mean(0), ValueError);
    EXPECT_THROW(lsf.median(tools::MEDIAN_FILTER_MAX_WIDTH + 1), ValueError);
    EXPECT_THROW(lsf.offset(std::numeric_limits<float>::infinity()), ValueError);
}

// The radius of a sphere level set centred at `c`: the mean of |x - c| - phi(x) over the active
// voxels within half a voxel of the surface.
double radiusOf(const FloatGrid& grid, const Vec3d& c) {
    const double dx = grid.voxelSize()[0];
    double sum = 0;
    int n = 0;
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        if (std::abs(*it) > 0.5 * dx)
            continue;
        sum += (grid.indexToWorld(Vec3d(it.getCoord())) - c).length() - double(*it);
        ++n;
    }
    return sum / n;
}

TEST(LevelSetFilter, MeanCurvatureFlowShrinksASphereAtTheAnalyticRate) {
    const double dx = 0.05, r0 = 1.0;
    const Vec3d c(0.1, -0.05, 0.2);
    auto sphere = tools::createLevelSetSphere<FloatGrid>(r0, c, dx);
    const double start = radiusOf(*sphere, c);
    tools::LevelSetFilter<FloatGrid> filter(*sphere);
    const int steps = 100;
    for (int n = 0; n < steps; ++n)
        filter.meanCurvature();
    // H |grad phi| = 1/r on a sphere: dr/dt = -1/r, so r^2 = r0^2 - 2t, t = steps dx^2 / 3.
    const double t = steps * dx * dx / 3.0;
    const double expected = start * start - 2 * t;
    const double got = radiusOf(*sphere, c);
    EXPECT_NEAR(start * start - got * got, start * start - expected, 0.02 * 2 * t);
}

TEST(LevelSetFilter, OffsetMovesTheSurfaceByTheAmount) {
    const double dx = 0.05, r0 = 1.0;
    const Vec3d c(0.0);
    for (const double d : {0.123, -0.2}) {
        auto sphere = tools::createLevelSetSphere<FloatGrid>(r0, c, dx);
        const double start = radiusOf(*sphere, c);
        tools::LevelSetFilter<FloatGrid> filter(*sphere);
        filter.offset(float(d));
        // phi + d: the surface moves inwards by d (OpenVDB's sign).
        EXPECT_NEAR(radiusOf(*sphere, c), start - d, 0.01 * dx) << d;
        // Still a narrow band of the same width.
        EXPECT_EQ(sphere->background(), float(3 * dx));
    }
}

TEST(LevelSetFilter, SmoothingKeepsASphereASphere) {
    const double dx = 0.05, r0 = 1.0;
    const Vec3d c(0.0);
    auto sphere = tools::createLevelSetSphere<FloatGrid>(r0, c, dx);
    tools::LevelSetFilter<FloatGrid> filter(*sphere);
    filter.mean(1);
    filter.gaussian(1);
    filter.median(1);
    filter.laplacian();
    const double r = radiusOf(*sphere, c);
    EXPECT_LT(r, r0);
    EXPECT_GT(r, r0 - 0.5 * dx);
    // Every active value lies within the band.
    for (auto it = sphere->cbeginValueOn(); it; ++it)
        ASSERT_LT(std::abs(*it), sphere->background() + 1e-6f);
}

/// True when both trees have the same active voxels with the same values.
bool sameActiveValues(const FloatGrid& a, const FloatGrid& b) {
    if (a.activeVoxelCount() != b.activeVoxelCount())
        return false;
    auto acc = b.getConstAccessor();
    for (auto it = a.cbeginValueOn(); it; ++it) {
        if (!acc.isValueOn(it.getCoord()) || acc.getValue(it.getCoord()) != *it)
            return false;
    }
    return true;
}

TEST(Filter, EveryFilterIsOffUnderAZeroMaskAndWholeUnderAOneMask) {
    // Masks of constant alpha (empty grids whose background is the mask value): alpha 0 must
    // leave every value as it was, alpha 1 must give the unmasked result.
    auto zero = FloatGrid::create(0.0f), one = FloatGrid::create(1.0f);
    auto x = math::Transform::createLinearTransform(0.5);
    const auto input = sampleField<FloatGrid>(
        kBox, x, [](const Vec3d& p) { return float(std::sin(p[0]) * p[1] + p[2] * p[2]); });
    const std::function<void(tools::Filter<FloatGrid>&, const FloatGrid*)> ops[] = {
        [](auto& f, auto m) { f.mean(2, 2, m); },
        [](auto& f, auto m) { f.gaussian(1, 1, m); },
        [](auto& f, auto m) { f.median(1, 2, m); },
        [](auto& f, auto m) { f.offset(0.75f, m); },
    };
    for (size_t i = 0; i < std::size(ops); ++i) {
        auto off = input->deepCopy(), on = input->deepCopy(), plain = input->deepCopy();
        tools::Filter<FloatGrid> fOff(*off), fOn(*on), fPlain(*plain);
        ops[i](fOff, zero.get());
        ops[i](fOn, one.get());
        ops[i](fPlain, nullptr);
        EXPECT_TRUE(sameActiveValues(*off, *input)) << "filter " << i;
        EXPECT_TRUE(sameActiveValues(*on, *plain)) << "filter " << i;
        EXPECT_FALSE(sameActiveValues(*plain, *input)) << "filter " << i;
    }
}

TEST(LevelSetFilter, EveryFilterIsOffUnderAZeroMaskAndWholeUnderAOneMask) {
    // Under alpha 0 a level set filter only rebuilds the band (as LevelSetTracker::track()
    // does, once per pass: four times for the Gaussian); under alpha 1 it is the unmasked
    // filter.
    auto zero = FloatGrid::create(0.0f), one = FloatGrid::create(1.0f);
    auto input = tools::createLevelSetSphere<FloatGrid>(0.8f, Vec3f(0.02f, -0.03f, 0.01f), 0.05f);
    input->tree().setValue(Coord(16, 0, 0), 0.0f);  // a bump, so that smoothing changes it
    using LsFilter = tools::LevelSetFilter<FloatGrid>;
    struct Op {
        std::function<void(LsFilter&, const FloatGrid*)> run;
        int passes;
    };
    const Op ops[] = {
        {[](auto& f, auto m) { f.mean(1, m); }, 1},
        {[](auto& f, auto m) { f.gaussian(1, m); }, 4},
        {[](auto& f, auto m) { f.median(1, m); }, 1},
        {[](auto& f, auto m) { f.meanCurvature(m); }, 1},
        {[](auto& f, auto m) { f.laplacian(m); }, 1},
        {[](auto& f, auto m) { f.offset(0.02f, m); }, 1},  // under half a voxel: one step
    };
    for (size_t i = 0; i < std::size(ops); ++i) {
        auto tracked = input->deepCopy();
        tools::LevelSetTracker<FloatGrid> tracker(*tracked);
        for (int p = 0; p < ops[i].passes; ++p)
            tracker.track();
        auto off = input->deepCopy(), on = input->deepCopy(), plain = input->deepCopy();
        LsFilter fOff(*off), fOn(*on), fPlain(*plain);
        ops[i].run(fOff, zero.get());
        ops[i].run(fOn, one.get());
        ops[i].run(fPlain, nullptr);
        EXPECT_TRUE(sameActiveValues(*off, *tracked)) << "filter " << i;
        EXPECT_TRUE(sameActiveValues(*on, *plain)) << "filter " << i;
        EXPECT_FALSE(sameActiveValues(*plain, *tracked)) << "filter " << i;
    }
}

TEST(LevelSetFilter, MaskRestrictsTheOffsetToTheMaskedHalf) {
    const double dx = 0.05;
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0, Vec3d(0.0), dx);
    // Alpha 1 for x > 0.2, 0 for x < -0.2, a smooth ramp between.
    auto mask = sampleField<FloatGrid>(CoordBBox(Coord(-30), Coord(30)), sphere->transformPtr(),
                                       [](const Vec3d& p) { return float(p[0]); });
    tools::LevelSetFilter<FloatGrid> filter(*sphere);
    filter.setMaskRange(-0.2f, 0.2f);
    filter.offset(0.1f, mask.get());
    // Where x < -0.2 the surface stays at radius 1, where x > 0.2 it moves in to 0.9.
    const auto along = [&](int axisSign) {
        for (int i = 0; i < 40; ++i) {
            const Coord ijk(axisSign * i, 0, 0);
            if (sphere->tree().getValue(ijk) >= 0.0f)
                return double(i) * dx;
        }
        return 0.0;
    };
    EXPECT_NEAR(along(1), 0.9, 1.01 * dx);
    EXPECT_NEAR(along(-1), 1.0, 1.01 * dx);
}

}  // namespace
}  // namespace vdb
