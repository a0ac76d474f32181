// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10. The same inputs go through OpenVDB's createLevelSetSphere, signedFloodFill
// and prune family and through ours; the trees must then hold the same values, states and
// tiles everywhere: every voxel and every tile of every level, compared bit for bit, plus the
// background and the node counts.

#include <vdb/Grid.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tree/TreeConfigs.h>

#include "OpenVdbConvert.h"
#include <Oracles.h>
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <sstream>
#include <tuple>
#include <type_traits>
#include <vector>

namespace vdb {
namespace {

// ---- Converting between the libraries ---------------------------------------------------------

using test::fromOvdb;
using test::sameBits;
using test::toOvdb;

// ---- Whole-tree listings ----------------------------------------------------------------------

/// One stored value: a voxel (dim 1) or a tile (dim = its edge), with its value and state.
template <typename ValueT>
struct Item {
    Coord min;
    Int32 dim;
    ValueT value;
    bool on;
};

template <typename ValueT>
void sortItems(std::vector<Item<ValueT>>& items) {
    std::sort(items.begin(), items.end(), [](const Item<ValueT>& a, const Item<ValueT>& b) {
        return std::tie(a.min, a.dim) < std::tie(b.min, b.dim);
    });
}

/// Every voxel and tile of one of our trees, sorted.
template <typename TreeT>
std::vector<Item<typename TreeT::ValueType>> listOurs(const TreeT& tree) {
    std::vector<Item<typename TreeT::ValueType>> items;
    for (auto it = tree.cbeginValueAll(); it; ++it) {
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        items.push_back({bbox.min(), bbox.dim()[0], it.getValue(), it.isValueOn()});
    }
    sortItems(items);
    return items;
}

/// Every voxel and tile of an OpenVDB tree, sorted, with our value type.
template <typename ValueT, typename OvdbTreeT>
std::vector<Item<ValueT>> listOvdb(const OvdbTreeT& tree) {
    std::vector<Item<ValueT>> items;
    for (auto it = tree.cbeginValueAll(); it; ++it) {
        openvdb::CoordBBox bbox;
        it.getBoundingBox(bbox);
        items.push_back(
            {fromOvdb(bbox.min()), bbox.dim()[0], ValueT(fromOvdb(it.getValue())), it.isValueOn()});
    }
    sortItems(items);
    return items;
}

template <typename ValueT>
std::string describe(const Item<ValueT>& item) {
    std::ostringstream s;
    s << item.min << " dim " << item.dim << " value " << item.value << (item.on ? " on" : " off");
    return s.str();
}

/// Success when both listings hold the same regions with bit-identical values and states.
template <typename ValueT>
::testing::AssertionResult sameItems(const std::vector<Item<ValueT>>& ours,
                                     const std::vector<Item<ValueT>>& theirs) {
    const size_t n = std::min(ours.size(), theirs.size());
    for (size_t i = 0; i < n; ++i) {
        const Item<ValueT>& a = ours[i];
        const Item<ValueT>& b = theirs[i];
        if (a.min != b.min || a.dim != b.dim || a.on != b.on || !sameBits(a.value, b.value)) {
            return ::testing::AssertionFailure()
                   << "item " << i << ": ours " << describe(a) << ", OpenVDB " << describe(b);
        }
    }
    if (ours.size() != theirs.size()) {
        return ::testing::AssertionFailure()
               << "ours holds " << ours.size() << " values and tiles, OpenVDB " << theirs.size();
    }
    return ::testing::AssertionSuccess();
}

template <typename TreeT, typename OvdbTreeT>
::testing::AssertionResult sameTrees(const TreeT& ours, const OvdbTreeT& theirs) {
    using ValueT = typename TreeT::ValueType;
    if (!sameBits(ours.background(), ValueT(fromOvdb(theirs.background())))) {
        return ::testing::AssertionFailure() << "backgrounds differ: ours " << ours.background()
                                             << ", OpenVDB " << theirs.background();
    }
    if (ours.leafCount() != theirs.leafCount()) {
        return ::testing::AssertionFailure() << "leaf counts differ: ours " << ours.leafCount()
                                             << ", OpenVDB " << theirs.leafCount();
    }
    if (ours.activeTileCount() != theirs.activeTileCount()) {
        return ::testing::AssertionFailure()
               << "active tile counts differ: ours " << ours.activeTileCount() << ", OpenVDB "
               << theirs.activeTileCount();
    }
    if (ours.activeVoxelCount() != theirs.activeVoxelCount()) {
        return ::testing::AssertionFailure()
               << "active voxel counts differ: ours " << ours.activeVoxelCount() << ", OpenVDB "
               << theirs.activeVoxelCount();
    }
    return sameItems(listOurs(ours), listOvdb<ValueT>(theirs));
}

// ---- The same writes into both libraries ------------------------------------------------------

/// One write: a voxel value and state, or (dim > 1) a box fill.
template <typename ValueT>
struct Write {
    Coord ijk;
    ValueT value;
    bool on;
    Int32 dim = 1;
};

template <typename TreeT, typename OvdbTreeT>
void applyWrites(const std::vector<Write<typename TreeT::ValueType>>& writes, TreeT& ours,
                 OvdbTreeT& theirs) {
    for (const auto& w : writes) {
        if (w.dim > 1) {
            const CoordBBox box = CoordBBox::createCube(w.ijk, w.dim);
            ours.fill(box, w.value, w.on);
            theirs.fill(openvdb::CoordBBox(toOvdb(box.min()), toOvdb(box.max())), toOvdb(w.value),
                        w.on);
        } else if (w.on) {
            ours.setValueOn(w.ijk, w.value);
            theirs.setValueOn(toOvdb(w.ijk), toOvdb(w.value));
        } else {
            ours.setValueOff(w.ijk, w.value);
            theirs.setValueOff(toOvdb(w.ijk), toOvdb(w.value));
        }
    }
}

// ---- Narrow bands of analytic shapes (voxel units) --------------------------------------------

using Sdf = std::function<double(const Coord&)>;

Sdf sphereSdf(double cx, double cy, double cz, double r) {
    return [=](const Coord& p) {
        return std::sqrt((p[0] - cx) * (p[0] - cx) + (p[1] - cy) * (p[1] - cy) +
                         (p[2] - cz) * (p[2] - cz)) -
               r;
    };
}
Sdf torusSdf(double cx, double cy, double cz, double major, double minor) {
    return [=](const Coord& p) {
        const double x = p[0] - cx, y = p[1] - cy, z = p[2] - cz;
        const double q = std::sqrt(x * x + y * y) - major;
        return std::sqrt(q * q + z * z) - minor;
    };
}
Sdf boxSdf(double cx, double cy, double cz, double hx, double hy, double hz) {
    return [=](const Coord& p) {
        const double dx = std::abs(p[0] - cx) - hx, dy = std::abs(p[1] - cy) - hy,
                     dz = std::abs(p[2] - cz) - hz;
        const double ox = std::max(dx, 0.0), oy = std::max(dy, 0.0), oz = std::max(dz, 0.0);
        return std::sqrt(ox * ox + oy * oy + oz * oz) +
               std::min(std::max(dx, std::max(dy, dz)), 0.0);
    };
}

/// The active voxels of the band |sdf| < halfWidth inside `bounds`, values in voxel units.
std::vector<Write<float>> band(const Sdf& sdf, const CoordBBox& bounds, double halfWidth) {
    std::vector<Write<float>> writes;
    for (Int32 i = bounds.min()[0]; i <= bounds.max()[0]; ++i)
        for (Int32 j = bounds.min()[1]; j <= bounds.max()[1]; ++j)
            for (Int32 k = bounds.min()[2]; k <= bounds.max()[2]; ++k) {
                const double d = sdf(Coord(i, j, k));
                if (std::abs(d) < halfWidth)
                    writes.push_back({Coord(i, j, k), float(d), true});
            }
    return writes;
}

class LevelSetToolsCompat : public ::testing::Test {
protected:
    static void SetUpTestSuite() { openvdb::initialize(); }
};

// ---- createLevelSetSphere ---------------------------------------------------------------------

struct SphereCase {
    float radius;
    Vec3f center;
    float voxelSize;
    float halfWidth;
};

TEST_F(LevelSetToolsCompat, LevelSetSphereMatchesOpenVdbVoxelForVoxel) {
    const std::vector<SphereCase> cases = {
        {5.0f, Vec3f(0.0f, 0.0f, 0.0f), 0.1f, 3.0f},
        {1.3f, Vec3f(-0.7f, 2.1f, -3.3f), 0.05f, 3.0f},
        {10.0f, Vec3f(3.3f, -4.4f, 5.5f), 0.5f, 2.5f},
        {0.15f, Vec3f(0.35f, 0.35f, 0.35f), 1.0f / 256.0f, 5.0f},
        {2.0f, Vec3f(-40.25f, 17.5f, 0.125f), 0.0625f, 4.0f},
        {1.0f, Vec3f(0.0f, 0.0f, 0.0f), 1.0f, 3.0f},  // below 1.5 voxels: empty
    };
    for (const SphereCase& c : cases) {
        for (const bool threaded : {false, true}) {
            SCOPED_TRACE(::testing::Message() << "radius " << c.radius << " center " << c.center
                                              << " voxel " << c.voxelSize << " half width "
                                              << c.halfWidth << " threaded " << threaded);
            auto ours = tools::createLevelSetSphere<FloatGrid>(c.radius, c.center, c.voxelSize,
                                                               c.halfWidth, threaded);
            auto theirs = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
                c.radius, openvdb::Vec3f(c.center[0], c.center[1], c.center[2]), c.voxelSize,
                c.halfWidth, threaded);
            EXPECT_TRUE(sameTrees(ours->tree(), theirs->tree()));
            EXPECT_EQ(ours->getGridClass(), GRID_LEVEL_SET);
            EXPECT_EQ(ours->voxelSize()[0], theirs->voxelSize()[0]);
        }
    }
}

TEST_F(LevelSetToolsCompat, LevelSetSphereInDoubleMatchesOpenVdb) {
    auto ours = tools::createLevelSetSphere<DoubleGrid>(2.5f, Vec3f(0.3f, -1.7f, 0.9f), 0.1f);
    auto theirs = openvdb::tools::createLevelSetSphere<openvdb::DoubleGrid>(
        2.5f, openvdb::Vec3f(0.3f, -1.7f, 0.9f), 0.1f);
    EXPECT_TRUE(sameTrees(ours->tree(), theirs->tree()));
}

// ---- signedFloodFill --------------------------------------------------------------------------

TEST_F(LevelSetToolsCompat, SignedFloodFillOfAnalyticBandsMatchesOpenVdb) {
    struct Shape {
        const char* name;
        Sdf sdf;
        CoordBBox bounds;
    };
    const std::vector<Shape> shapes = {
        {"sphere", sphereSdf(3.3, -5.7, 1.2, 56.0), CoordBBox(Coord(-62), Coord(62))},
        {"torus", torusSdf(-2.5, 4.25, -1.5, 48.0, 16.0), CoordBBox(Coord(-70), Coord(70))},
        {"box", boxSdf(0.5, -10.5, 20.25, 40.0, 24.0, 50.0), CoordBBox(Coord(-50), Coord(75))},
    };
    const float background = 2.0f;
    for (const Shape& shape : shapes) {
        SCOPED_TRACE(shape.name);
        const auto writes = band(shape.sdf, shape.bounds, 2.0);
        FloatTree ours(background);
        openvdb::FloatTree theirs(background);
        applyWrites(writes, ours, theirs);
        ASSERT_TRUE(sameTrees(ours, theirs)) << "the inputs differ";
        tools::signedFloodFill(ours);
        openvdb::tools::signedFloodFill(theirs);
        EXPECT_TRUE(sameTrees(ours, theirs));

        FloatTree ours2(background);
        openvdb::FloatTree theirs2(background);
        applyWrites(writes, ours2, theirs2);
        tools::signedFloodFillWithValues(ours2, -7.0f, 3.0f, false);
        openvdb::tools::signedFloodFillWithValues(theirs2, -7.0f, 3.0f, false);
        EXPECT_TRUE(sameTrees(ours2, theirs2));
    }
}

TEST_F(LevelSetToolsCompat, SignedFloodFillOfArbitraryInputMatchesOpenVdb) {
    // Not a level set: random signs, inactive non-background values, leaves without active
    // voxels, inactive tiles of either sign and children spread over several root keys, so that
    // every rule of the fill (seeds, line starts, empty nodes, root gaps) decides something.
    std::mt19937 rng(4242);
    std::uniform_int_distribution<Int32> near(-100, 100);
    std::uniform_real_distribution<float> value(-3.0f, 3.0f);
    const int batches = test::scaledBatchCount(4);
    for (int batch = 0; batch < batches; ++batch) {
        SCOPED_TRACE(::testing::Message() << "batch " << batch);
        std::vector<Write<float>> writes;
        for (int n = 0; n < 1200; ++n) {
            const Coord ijk(near(rng), near(rng), near(rng));
            writes.push_back({ijk, value(rng), rng() % 3 != 0});
        }
        // Clusters near far-apart root keys along one z-line, and leaf- and node-sized tiles.
        for (int n = 0; n < 40; ++n) {
            const Coord ijk(Int32(rng() % 64), Int32(rng() % 64),
                            Int32(rng() % 5) * 4096 - 8192 + Int32(rng() % 4096));
            writes.push_back({ijk, value(rng), rng() % 2 == 0});
        }
        for (int n = 0; n < 30; ++n) {
            const Int32 dim = rng() % 4 == 0 ? 128 : 8;
            const Coord ijk = Coord(near(rng), near(rng), near(rng)).alignedDown(dim == 8 ? 3 : 7);
            writes.push_back({ijk, value(rng), false, dim});
        }
        FloatTree ours(1.5f);
        openvdb::FloatTree theirs(1.5f);
        applyWrites(writes, ours, theirs);
        ASSERT_TRUE(sameTrees(ours, theirs)) << "the inputs differ";
        const bool threaded = batch % 2 == 0;
        tools::signedFloodFill(ours, threaded);
        openvdb::tools::signedFloodFill(theirs, threaded);
        EXPECT_TRUE(sameTrees(ours, theirs));
    }
}

TEST_F(LevelSetToolsCompat, SignedFloodFillInsertsTheSameRootTiles) {
    // Children at z keys 0, 12288 (inside faces toward each other), 20480 (outside), 24576.
    std::vector<Write<float>> writes = {
        {Coord(4095, 4095, 4095), -1.0f, true},  {Coord(0, 0, 12288), -1.0f, true},
        {Coord(4095, 4095, 16383), -1.0f, true}, {Coord(0, 0, 20480), 1.0f, true},
        {Coord(4095, 4095, 24575), -1.0f, true}, {Coord(0, 0, 24576), -1.0f, true},
        {Coord(-4096, 0, 0), -2.0f, true},       {Coord(-1, 4095, 12287 + 4096 * 3), -2.0f, true},
    };
    FloatTree ours(3.0f);
    openvdb::FloatTree theirs(3.0f);
    applyWrites(writes, ours, theirs);
    tools::signedFloodFill(ours);
    openvdb::tools::signedFloodFill(theirs);
    EXPECT_TRUE(sameTrees(ours, theirs));
    EXPECT_EQ(ours.getValue(Coord(0, 0, 4096)), -3.0f);  // a gap tile
}

// ---- prune, pruneInactive, pruneLevelSet ------------------------------------------------------

/// Writes that leave constant and nearly constant leaves, level-1 nodes made of leaf-sized
/// tiles, inactive leaves and nodes within one level-2 node, and root-sized tiles on both
/// sides of the origin.
template <typename ValueT>
std::vector<Write<ValueT>> pruneWorkload(uint32_t seed, const std::vector<ValueT>& palette,
                                         const std::function<ValueT(std::mt19937&)>& jitter) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> leafCoord(1, 40);  // one level-2 node
    std::vector<Write<ValueT>> writes;
    auto pick = [&] { return palette[rng() % palette.size()]; };
    // Whole leaves written voxel by voxel: constant, jittered, or one odd voxel.
    for (int n = 0; n < 60; ++n) {
        const Coord origin(leafCoord(rng) * 8, leafCoord(rng) * 8, leafCoord(rng) * 8);
        const ValueT v = pick();
        const bool on = rng() % 2 == 0;
        const int kind = int(rng() % 3);
        for (Int32 i = 0; i < 8; ++i)
            for (Int32 j = 0; j < 8; ++j)
                for (Int32 k = 0; k < 8; ++k) {
                    const ValueT w = kind == 1 ? jitter(rng) : v;
                    writes.push_back({origin.offsetBy(i, j, k), w, on});
                }
        if (kind == 2)
            writes.push_back({origin.offsetBy(3, 4, 5), pick(), !on});
    }
    // Level-1 nodes tiled by leaf-sized boxes of one value (sometimes jittered).
    for (int n = 0; n < 3; ++n) {
        const Coord origin =
            Coord(leafCoord(rng) * 8, leafCoord(rng) * 8, leafCoord(rng) * 8).alignedDown(7);
        const ValueT v = pick();
        const bool on = rng() % 2 == 0;
        const bool jittered = n == 1;
        for (Int32 i = 0; i < 128; i += 8)
            for (Int32 j = 0; j < 128; j += 8)
                for (Int32 k = 0; k < 128; k += 8)
                    writes.push_back({origin.offsetBy(i, j, k), jittered ? jitter(rng) : v, on, 8});
    }
    // Scattered voxels, and root-sized tiles.
    for (int n = 0; n < 400; ++n) {
        writes.push_back({Coord(leafCoord(rng) * 4, leafCoord(rng) * 4, leafCoord(rng) * 4), pick(),
                          rng() % 3 != 0});
    }
    writes.push_back({Coord(8192, 0, 0), pick(), false, 4096});
    writes.push_back({Coord(-8192, 0, 0), pick(), true, 4096});
    return writes;
}

template <typename TreeT, typename OvdbTreeT, typename OpT, typename OvdbOpT>
void checkPrune(const std::vector<Write<typename TreeT::ValueType>>& writes,
                const typename TreeT::ValueType& background, const OpT& op, const OvdbOpT& ovdbOp) {
    // Threaded and serial runs agree bit for bit (tests/tools/levelset); each library runs
    // threaded.
    {
        const bool threaded = true;
        TreeT ours(background);
        OvdbTreeT theirs(toOvdb(background));
        applyWrites(writes, ours, theirs);
        ASSERT_TRUE(sameTrees(ours, theirs)) << "the inputs differ";
        const auto before = listOurs(ours);
        op(ours, threaded);
        ovdbOp(theirs, threaded);
        EXPECT_TRUE(sameTrees(ours, theirs));
        EXPECT_FALSE(sameItems(before, listOurs(ours))) << "the input had nothing to prune";
    }
}

TEST_F(LevelSetToolsCompat, PruneMatchesOpenVdbOnFloatTrees) {
    const std::vector<float> palette = {0.0f, 0.25f, -1.0f, 2.0f, 0.5f};
    const auto jitter = [](std::mt19937& rng) {
        return 0.25f + 0.01f * float(rng() % 5) - 0.02f;  // within 0.04 of each other
    };
    const auto writes = pruneWorkload<float>(7, palette, jitter);
    for (const float tolerance : {0.0f, 0.01f, 0.05f}) {
        SCOPED_TRACE(::testing::Message() << "tolerance " << tolerance);
        checkPrune<FloatTree, openvdb::FloatTree>(
            writes, 0.5f, [&](auto& t, bool th) { tools::prune(t, tolerance, th); },
            [&](auto& t, bool th) { openvdb::tools::prune(t, tolerance, th); });
    }
    checkPrune<FloatTree, openvdb::FloatTree>(
        writes, 0.5f, [](auto& t, bool th) { tools::pruneInactive(t, th); },
        [](auto& t, bool th) { openvdb::tools::pruneInactive(t, th); });
    checkPrune<FloatTree, openvdb::FloatTree>(
        writes, 0.5f, [](auto& t, bool th) { tools::pruneInactiveWithValue(t, -4.0f, th); },
        [](auto& t, bool th) { openvdb::tools::pruneInactiveWithValue(t, -4.0f, th); });
    checkPrune<FloatTree, openvdb::FloatTree>(
        writes, 0.5f, [](auto& t, bool th) { tools::pruneLevelSet(t, th); },
        [](auto& t, bool th) { openvdb::tools::pruneLevelSet(t, th); });
    checkPrune<FloatTree, openvdb::FloatTree>(
        writes, 0.5f, [](auto& t, bool th) { tools::pruneLevelSet(t, 9.0f, -8.0f, th); },
        [](auto& t, bool th) { openvdb::tools::pruneLevelSet(t, 9.0f, -8.0f, th); });
}

TEST_F(LevelSetToolsCompat, PruneDropsTheSameNearBackgroundRootTiles) {
    // 5e-9 is within OpenVDB's default float tolerance of a zero background; 1e-3 is not.
    const std::vector<Write<float>> writes = {{Coord(0), 5e-9f, false, 4096},
                                              {Coord(4096, 0, 0), 1e-3f, false, 4096},
                                              {Coord(-4096, 0, 0), 0.0f, false, 4096},
                                              {Coord(0, -4096, 0), 0.0f, true, 4096}};
    checkPrune<FloatTree, openvdb::FloatTree>(
        writes, 0.0f, [](auto& t, bool th) { tools::prune(t, 0.0f, th); },
        [](auto& t, bool th) { openvdb::tools::prune(t, 0.0f, th); });
}

TEST_F(LevelSetToolsCompat, PruneMatchesOpenVdbOnOtherValueTypes) {
    {
        SCOPED_TRACE("Int32");
        const auto writes = pruneWorkload<Int32>(
            11, {0, 3, -7, 12}, [](std::mt19937& rng) { return Int32(rng() % 3); });
        for (const Int32 tolerance : {0, 2}) {
            checkPrune<Int32Tree, openvdb::Int32Tree>(
                writes, 3, [&](auto& t, bool th) { tools::prune(t, tolerance, th); },
                [&](auto& t, bool th) { openvdb::tools::prune(t, tolerance, th); });
        }
    }
    {
        SCOPED_TRACE("Vec3s");
        const auto writes = pruneWorkload<Vec3s>(
            13, {Vec3s(0.0f), Vec3s(1.0f, 2.0f, 3.0f), Vec3s(-1.0f, 0.5f, 0.0f)},
            [](std::mt19937& rng) {
                return Vec3s(1.0f + 0.01f * float(rng() % 3), 2.0f - 0.01f * float(rng() % 3),
                             3.0f + 0.01f * float(rng() % 4));
            });
        for (const float t : {0.0f, 0.015f, 0.05f}) {
            checkPrune<Vec3STree, openvdb::Vec3STree>(
                writes, Vec3s(0.0f), [&](auto& tr, bool th) { tools::prune(tr, Vec3s(t), th); },
                [&](auto& tr, bool th) { openvdb::tools::prune(tr, openvdb::Vec3s(t), th); });
        }
    }
    {
        SCOPED_TRACE("bool");
        const auto writes = pruneWorkload<bool>(17, {false, true},
                                                [](std::mt19937& rng) { return rng() % 8 != 0; });
        checkPrune<BoolTree, openvdb::BoolTree>(
            writes, false, [](auto& t, bool th) { tools::prune(t, false, th); },
            [](auto& t, bool th) { openvdb::tools::prune(t, false, th); });
        checkPrune<BoolTree, openvdb::BoolTree>(
            writes, false, [](auto& t, bool th) { tools::pruneInactive(t, th); },
            [](auto& t, bool th) { openvdb::tools::pruneInactive(t, th); });
    }
}

TEST_F(LevelSetToolsCompat, PruneLevelSetOfASphereMatchesOpenVdb) {
    auto ours = tools::createLevelSetSphere<FloatGrid>(3.0f, Vec3f(0.5f, -0.25f, 1.0f), 0.05f);
    auto theirs = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        3.0f, openvdb::Vec3f(0.5f, -0.25f, 1.0f), 0.05f);
    tools::pruneLevelSet(ours->tree());
    openvdb::tools::pruneLevelSet(theirs->tree());
    EXPECT_TRUE(sameTrees(ours->tree(), theirs->tree()));
    tools::prune(ours->tree());
    openvdb::tools::prune(theirs->tree());
    EXPECT_TRUE(sameTrees(ours->tree(), theirs->tree()));
}

}  // namespace
}  // namespace vdb
