// SPDX-License-Identifier: Apache-2.0
// Oracles: brute force. Statistics, histograms and min/max are recomputed from a plain list of
// (value, voxel count) pairs taken with the tree's own iterators; the background changes are
// checked value by value against the rules, on trees with voxels and tiles at every level.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/math/Stats.h>
#include <vdb/tools/ChangeBackground.h>
#include <vdb/tools/Count.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/Statistics.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace vdb {
namespace {

/// A float tree with random voxels, an active and an inactive tile in an internal node and an
/// active root tile.
FloatGrid::Ptr mixedGrid() {
    auto grid = FloatGrid::create(0.5f);
    std::mt19937 rng(20240518);
    std::uniform_real_distribution<float> value(-3.0f, 5.0f);
    std::uniform_int_distribution<int> coord(-60, 60);
    for (int n = 0; n < 5000; ++n) {
        const Coord ijk(coord(rng), coord(rng), coord(rng));
        if (n % 3 == 0)
            grid->tree().setValueOff(ijk, value(rng));
        else
            grid->tree().setValue(ijk, value(rng));
    }
    grid->tree().fill(CoordBBox::createCube(Coord(1024, 0, 0), 8), 2.0f, true);
    grid->tree().fill(CoordBBox::createCube(Coord(1024, 128, 0), 128), -1.0f, false);
    grid->tree().fill(CoordBBox::createCube(Coord(8192, 0, 0), 4096), 4.0f, true);
    return grid;
}

template <typename IterT>
math::Stats bruteStats(IterT it) {
    math::Stats s;
    for (; it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        s.add(double(*it), Index64(box.volume()));
    }
    return s;
}

TEST(Statistics, MatchTheIteratorsValuesOnOffAndAll) {
    auto grid = mixedGrid();
    const auto check = [](const math::Stats& got, const math::Stats& want) {
        EXPECT_EQ(got.size(), want.size());
        EXPECT_DOUBLE_EQ(got.min(), want.min());
        EXPECT_DOUBLE_EQ(got.max(), want.max());
        EXPECT_NEAR(got.mean(), want.mean(), 1e-9 * std::max(1.0, std::abs(want.mean())));
        EXPECT_NEAR(got.variance(), want.variance(), 1e-9 * want.variance());
    };
    check(tools::statistics(grid->cbeginValueOn()), bruteStats(grid->cbeginValueOn()));
    check(tools::statistics(grid->cbeginValueOff()), bruteStats(grid->cbeginValueOff()));
    check(tools::statistics(grid->cbeginValueAll()), bruteStats(grid->cbeginValueAll()));
    // Serial and threaded give identical results.
    const auto a = tools::statistics(grid->cbeginValueOn(), true);
    const auto b = tools::statistics(grid->cbeginValueOn(), false);
    EXPECT_EQ(a.mean(), b.mean());
    EXPECT_EQ(a.variance(), b.variance());
    // An iterator already under way: the rest of its walk.
    auto it = grid->cbeginValueOn();
    for (int n = 0; n < 100; ++n)
        ++it;
    check(tools::statistics(it), bruteStats(it));
}

TEST(Statistics, VectorGridsContributeLengths) {
    auto grid = Vec3SGrid::create();
    grid->tree().setValue(Coord(0), Vec3s(3, 4, 0));
    grid->tree().setValue(Coord(9, 0, 0), Vec3s(0, 0, -2));
    const auto s = tools::statistics(grid->cbeginValueOn());
    EXPECT_EQ(s.size(), 2u);
    EXPECT_DOUBLE_EQ(s.min(), 2.0);
    EXPECT_DOUBLE_EQ(s.max(), 5.0);
    EXPECT_DOUBLE_EQ(s.mean(), 3.5);
    EXPECT_DOUBLE_EQ(s.variance(), 2.25);
    const auto e = tools::extrema(grid->cbeginValueOn());
    EXPECT_EQ(e.size(), 2u);
    EXPECT_DOUBLE_EQ(e.range(), 3.0);
}

TEST(Statistics, HistogramCountsEveryValueInRange) {
    auto grid = mixedGrid();
    const auto h = tools::histogram(grid->cbeginValueOn(), -3.0, 5.0, 16);
    std::vector<uint64_t> want(16, 0);
    uint64_t total = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        const double v = *it;
        const size_t bin = std::min<size_t>(size_t((v + 3.0) * 2.0), 15);
        want[bin] += Index64(box.volume());
        total += Index64(box.volume());
    }
    for (int b = 0; b < 16; ++b)
        EXPECT_EQ(h.count(b), want[size_t(b)]) << "bin " << b;
    EXPECT_EQ(h.size(), total);
    EXPECT_THROW(tools::histogram(grid->cbeginValueOn(), 1.0, 1.0, 4), ValueError);
    EXPECT_THROW(tools::histogram(grid->cbeginValueOn(), 0.0, 1.0, 0), ValueError);
}

TEST(Stats, WelfordAndPairwiseMergesAgreeWithTheDefinition) {
    std::vector<double> v = {1.5, -2.0, 7.25, 3.0, 3.0, 0.125, 9.0};
    math::Stats all, left, right;
    for (size_t i = 0; i < v.size(); ++i) {
        all.add(v[i]);
        (i < 3 ? left : right).add(v[i]);
    }
    left.add(right);
    double mean = 0.0, var = 0.0;
    for (double x : v)
        mean += x / double(v.size());
    for (double x : v)
        var += (x - mean) * (x - mean) / double(v.size());
    EXPECT_NEAR(all.mean(), mean, 1e-12);
    EXPECT_NEAR(all.variance(), var, 1e-12);
    EXPECT_NEAR(left.mean(), mean, 1e-12);
    EXPECT_NEAR(left.variance(), var, 1e-12);
    EXPECT_NEAR(all.stdDev(), std::sqrt(var), 1e-12);
    math::Stats tiles;
    tiles.add(2.0, 3);
    tiles.add(4.0, 1);
    EXPECT_DOUBLE_EQ(tiles.mean(), 2.5);
    EXPECT_DOUBLE_EQ(tiles.variance(), 0.75);
    math::Histogram h(0.0, 1.0, 4);
    EXPECT_TRUE(h.add(1.0));  // the maximum falls in the last bin
    EXPECT_FALSE(h.add(1.5));
    EXPECT_EQ(h.count(3), 1u);
}

TEST(Count, MinMaxCoversActiveVoxelsAndTiles) {
    auto grid = mixedGrid();
    float lo = 1e30f, hi = -1e30f;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        lo = std::min(lo, *it);
        hi = std::max(hi, *it);
    }
    const auto mm = tools::minMax(grid->tree());
    EXPECT_EQ(mm.min(), lo);
    EXPECT_EQ(mm.max(), hi);
    const auto empty = tools::minMax(FloatTree(3.0f));
    EXPECT_EQ(empty.min(), 0.0f);
    EXPECT_EQ(empty.max(), 0.0f);
}

TEST(ChangeBackground, EveryInactiveBackgroundValueChanges) {
    auto sphere = tools::createLevelSetSphere<FloatGrid>(10.0f, Vec3f(0.0f), 1.0f, 3.0f);
    auto before = sphere->deepCopy();
    tools::changeBackground(sphere->tree(), 5.0f);
    EXPECT_EQ(sphere->background(), 5.0f);
    auto acc = before->getConstAccessor();
    for (auto it = sphere->cbeginValueAll(); it; ++it) {
        const float old = acc.getValue(it.getCoord());
        const float want = it.isValueOn() ? old : old == 3.0f ? 5.0f : old == -3.0f ? -5.0f : old;
        ASSERT_EQ(*it, want) << it.getCoord();
    }
    // Outside the root's entries the new background answers.
    EXPECT_EQ(sphere->tree().getValue(Coord(1000, 0, 0)), 5.0f);
    EXPECT_EQ(sphere->tree().getValue(Coord(0)), -5.0f);  // an inside tile
}

TEST(ChangeBackground, LevelSetBackgroundSetsInsideAndOutsideBySign) {
    auto sphere = tools::createLevelSetSphere<FloatGrid>(10.0f, Vec3f(0.0f), 1.0f, 3.0f);
    auto before = sphere->deepCopy();
    tools::changeLevelSetBackground(sphere->tree(), 2.0f);
    auto acc = before->getConstAccessor();
    for (auto it = sphere->cbeginValueAll(); it; ++it) {
        const float old = acc.getValue(it.getCoord());
        const float want = it.isValueOn() ? old : old < 0.0f ? -2.0f : 2.0f;
        ASSERT_EQ(*it, want) << it.getCoord();
    }
    tools::changeAsymmetricLevelSetBackground(sphere->tree(), 4.0f, -1.0f);
    EXPECT_EQ(sphere->tree().getValue(Coord(0)), -1.0f);
    EXPECT_EQ(sphere->background(), 4.0f);
    EXPECT_THROW(tools::changeLevelSetBackground(sphere->tree(), 0.0f), ValueError);
    EXPECT_THROW(tools::changeAsymmetricLevelSetBackground(sphere->tree(), 1.0f, 1.0f), ValueError);
    EXPECT_THROW(tools::changeAsymmetricLevelSetBackground(sphere->tree(), -1.0f, -1.0f),
                 ValueError);
}

TEST(Grid, VectorTypeLivesInTheMetadata) {
    auto grid = Vec3SGrid::create();
    EXPECT_EQ(grid->getVectorType(), VEC_INVARIANT);
    for (int t = 0; t < NUM_VEC_TYPES; ++t) {
        grid->setVectorType(VecType(t));
        EXPECT_EQ(grid->getVectorType(), VecType(t));
        EXPECT_EQ(grid->metaValue<std::string>("vector_type"), vecTypeToString(VecType(t)));
    }
    EXPECT_EQ(vecTypeToString(VEC_CONTRAVARIANT_RELATIVE), "contravariant relative");
    EXPECT_EQ(stringToVecType("covariant normalize"), VEC_COVARIANT_NORMALIZE);
    grid->clearVectorType();
    EXPECT_FALSE(grid->hasMeta("vector_type"));
}

}  // namespace
}  // namespace vdb
