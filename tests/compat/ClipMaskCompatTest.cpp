// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10. The same writes build the same grids in both libraries; then clip (by a
// world box, a frustum and a mask grid on the same or, resampled with OpenVDB's transforms,
// another transform), interiorMask,
// activate / deactivate, every compositing operation, foreach and transformValues (OpenVDB's
// serial definition, see below) run in both, and every voxel of a box around the contents must have
// the same value and active state (tiles are compared through their voxels).

#include <vdb/Grid.h>
#include <vdb/math/Transform.h>
#include <vdb/tools/Activate.h>
#include <vdb/tools/Clip.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/Mask.h>
#include <vdb/tools/ValueTransformer.h>
#include <vdb/tree/TreeConfigs.h>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Activate.h>
#include <openvdb/tools/Clip.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/Mask.h>
#include <openvdb/tools/ValueTransformer.h>  // foreach

#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace vdb {
namespace {

class ClipMaskCompat : public ::testing::Test {
protected:
    static void SetUpTestSuite() { openvdb::initialize(); }
};

inline openvdb::Coord ov(const Coord& c) {
    return openvdb::Coord(c[0], c[1], c[2]);
}

/// One write, applied identically to a tree of either library.
struct Write {
    enum Kind { On, Off, Fill } kind;
    Coord ijk;
    Int32 dim;  // Fill: the cube's edge
    float value;
    bool active;
};

/// Random voxels in [-44, 44]^3 (active and inactive), leaf-sized tiles and a level-2 tile;
/// with `activeTiles` false, every tile is inactive and non-negative.
std::vector<Write> randomWrites(uint32_t seed, bool activeTiles = true, int count = 1500) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> c(-44, 44);
    std::uniform_int_distribution<int> v(-40, 40);
    std::vector<Write> writes;
    for (int n = 0; n < count; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        writes.push_back({n % 3 ? Write::On : Write::Off, ijk, 1, float(v(rng)) / 8.0f, true});
    }
    for (int n = 0; n < 5; ++n) {
        const Coord origin = Coord(c(rng), c(rng), c(rng)).alignedDown(3);
        writes.push_back({Write::Fill, origin, 8, float(v(rng)) / 8.0f, rng() % 2 == 0});
    }
    writes.push_back({Write::Fill, Coord(seed % 2 ? -128 : 0, -128, 0), 128, float(v(rng)) / 8.0f,
                      seed % 3 != 0});
    if (!activeTiles) {
        for (Write& w : writes) {
            if (w.kind == Write::Fill) {
                w.active = false;
                w.value = std::abs(w.value);
            }
        }
    }
    return writes;
}

template <typename TreeT, typename CoordT, typename BBoxT>
void apply(TreeT& tree, const std::vector<Write>& writes, const CoordT& toCoord, const BBoxT&) {
    using ValueT = typename TreeT::ValueType;
    for (const Write& w : writes) {
        const auto ijk = toCoord(w.ijk);
        if (w.kind == Write::On) {
            tree.setValueOn(ijk, ValueT(w.value));
        } else if (w.kind == Write::Off) {
            tree.setValueOff(ijk, ValueT(w.value));
        } else {
            const auto hi = toCoord(w.ijk.offsetBy(w.dim - 1, w.dim - 1, w.dim - 1));
            tree.fill(BBoxT(ijk, hi), ValueT(w.value), w.active);
        }
    }
}

void applyOurs(FloatTree& tree, const std::vector<Write>& writes) {
    apply(
        tree, writes, [](const Coord& c) { return c; }, CoordBBox());
}
void applyTheirs(openvdb::FloatTree& tree, const std::vector<Write>& writes) {
    apply(
        tree, writes, [](const Coord& c) { return ov(c); }, openvdb::CoordBBox());
}

/// Every voxel of `region` has the same value and state in both trees.
template <typename TreeT, typename OvdbTreeT>
void expectSame(const TreeT& ours, const OvdbTreeT& theirs, const CoordBBox& region) {
    tree::ValueAccessor<const TreeT> a(ours);
    openvdb::tree::ValueAccessor<const OvdbTreeT> b(theirs);
    int failures = 0;
    Index64 active = 0;
    for (Int32 x = region.min()[0]; x <= region.max()[0]; ++x) {
        for (Int32 y = region.min()[1]; y <= region.max()[1]; ++y) {
            for (Int32 z = region.min()[2]; z <= region.max()[2]; ++z) {
                const Coord ijk(x, y, z);
                const auto va = a.getValue(ijk);
                const auto vb = b.getValue(ov(ijk));
                const bool same = [&] {
                    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(va)>>) {
                        return va == vb;
                    } else {
                        return va[0] == vb[0] && va[1] == vb[1] && va[2] == vb[2];
                    }
                }();
                active += a.isValueOn(ijk);
                if (!same || a.isValueOn(ijk) != b.isValueOn(ov(ijk))) {
                    ADD_FAILURE() << "at " << ijk << ": states " << a.isValueOn(ijk) << " vs "
                                  << b.isValueOn(ov(ijk));
                    if (++failures > 5)
                        return;
                }
            }
        }
    }
    EXPECT_GT(active, 0u) << "the comparison saw no active voxel";
}

const CoordBBox kRegion(Coord(-60, -60, -40), Coord(60, 60, 60));

struct GridPair {
    FloatGrid::Ptr ours;
    openvdb::FloatGrid::Ptr theirs;
};

GridPair makeGrids(uint32_t seed, float background, double voxelSize, const Vec3d& offset,
                   bool levelSet, bool activeTiles = true) {
    GridPair g{FloatGrid::create(background), openvdb::FloatGrid::create(background)};
    applyOurs(g.ours->tree(), randomWrites(seed, activeTiles));
    applyTheirs(g.theirs->tree(), randomWrites(seed, activeTiles));
    g.ours->setTransform(math::Transform::createLinearTransform(voxelSize));
    g.ours->transform().postTranslate(offset);
    g.theirs->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
    g.theirs->transform().postTranslate(openvdb::Vec3d(offset[0], offset[1], offset[2]));
    if (levelSet) {
        g.ours->setGridClass(GRID_LEVEL_SET);
        g.theirs->setGridClass(openvdb::GRID_LEVEL_SET);
    }
    return g;
}

// OpenVDB 10's box and mask clips drop active tiles (and the inside tiles of a level set) that
// lie in no internal node of the clipped leaves: its final pass only visits the tiles of the
// new tree. The inputs of these comparisons therefore hold active values in leaves only; the
// difference itself is pinned by ClipKeepsTheActiveTilesOpenVdbDrops.
TEST_F(ClipMaskCompat, ClipByBoxMatchesOpenVdb) {
    for (bool levelSet : {false, true}) {
        for (bool keep : {true, false}) {
            const GridPair g = makeGrids(1, 2.0f, 0.5, Vec3d(0.013, -0.21, 0.37), levelSet, false);
            const BBoxd box(Vec3d(-9.31, -4.07, -3.3), Vec3d(7.77, 11.1, 5.03));
            const auto ours = tools::clip(*g.ours, box, keep);
            const auto theirs =
                openvdb::tools::clip(*g.theirs,
                                     openvdb::BBoxd(openvdb::Vec3d(-9.31, -4.07, -3.3),
                                                    openvdb::Vec3d(7.77, 11.1, 5.03)),
                                     keep);
            SCOPED_TRACE(testing::Message() << "levelSet " << levelSet << " keep " << keep);
            expectSame(ours->tree(), theirs->tree(), kRegion);
        }
    }
}

TEST_F(ClipMaskCompat, ClipByFrustumMatchesOpenVdb) {
    const GridPair g = makeGrids(2, 2.0f, 1.0, Vec3d(0.0), true);
    const BBoxd fbox(Vec3d(0.0), Vec3d(20.0, 16.0, 12.0));
    auto ours = math::Transform::createFrustumTransform(fbox, 0.6, 1.5, 40.0);
    ours->postRotate(0.3, math::Axis::Y);
    ours->postTranslate(Vec3d(3.3, -2.1, -20.7));
    auto theirs = openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0.0), openvdb::Vec3d(20.0, 16.0, 12.0)), 0.6, 1.5, 40.0);
    theirs->postRotate(0.3, openvdb::math::Y_AXIS);
    theirs->postTranslate(openvdb::Vec3d(3.3, -2.1, -20.7));
    // The two frustum maps agree.
    const openvdb::Vec3d p = theirs->worldToIndex(openvdb::Vec3d(1.0, 2.0, 3.0));
    const Vec3d q = ours->worldToIndex(Vec3d(1.0, 2.0, 3.0));
    ASSERT_NEAR(p[0], q[0], 1e-9);
    ASSERT_NEAR(p[2], q[2], 1e-9);
    const auto map = theirs->constMap<openvdb::math::NonlinearFrustumMap>();
    ASSERT_TRUE(map);
    for (bool keep : {true, false}) {
        const auto a = tools::clip(*g.ours, *ours, keep);
        const auto b = openvdb::tools::clip(*g.theirs, *map, keep);
        EXPECT_EQ(a->getGridClass(), GRID_UNKNOWN);
        expectSame(a->tree(), b->tree(), kRegion);
    }
}

TEST_F(ClipMaskCompat, ClipByMaskOnTheSameAndAnotherTransformMatchesOpenVdb) {
    for (bool sameTransform : {true, false}) {
        const GridPair g = makeGrids(3, -1.0f, 0.5, Vec3d(0.0), false, false);
        auto maskOurs = BoolGrid::create(false);
        auto maskTheirs = openvdb::BoolGrid::create(false);
        std::mt19937 rng(9);
        std::uniform_int_distribution<Int32> c(-30, 30);
        for (int n = 0; n < 500; ++n) {
            const Coord ijk(c(rng), c(rng), c(rng));
            maskOurs->tree().setValueOn(ijk, true);
            maskTheirs->tree().setValueOn(ov(ijk), true);
        }
        maskOurs->tree().fill(CoordBBox(Coord(-5, -6, -7), Coord(9, 4, 3)), true, true);
        maskTheirs->tree().fill(
            openvdb::CoordBBox(openvdb::Coord(-5, -6, -7), openvdb::Coord(9, 4, 3)), true, true);
        if (sameTransform) {
            maskOurs->setTransform(g.ours->transform().copy());
            maskTheirs->setTransform(g.theirs->transform().copy());
        } else {
            maskOurs->setTransform(math::Transform::createLinearTransform(0.73));
            maskOurs->transform().postTranslate(Vec3d(0.111, -0.237, 0.05));
            maskTheirs->setTransform(openvdb::math::Transform::createLinearTransform(0.73));
            maskTheirs->transform().postTranslate(openvdb::Vec3d(0.111, -0.237, 0.05));
        }
        // OpenVDB 10's clip(grid, maskGrid) always instantiates its resampling path
        // (resampleToMatch), whose tbb::parallel_reduce bodies do not compile under C++20 with
        // oneTBB; so the mask is turned into the MaskGrid that clip would build and passed to
        // the function clip ends in, clip_internal::doClip. On another transform, the mask is
        // resampled with OpenVDB's rule (the mask voxel holding each voxel's center: floor of
        // the position mapped by OpenVDB's transforms).
        openvdb::BoolGrid::Ptr resampled = maskTheirs;
        if (!sameTransform) {
            resampled = openvdb::BoolGrid::create(false);
            resampled->setTransform(g.theirs->transform().copy());
            const auto maskAcc = maskTheirs->getConstAccessor();
            for (Int32 x = kRegion.min()[0]; x <= kRegion.max()[0]; ++x)
                for (Int32 y = kRegion.min()[1]; y <= kRegion.max()[1]; ++y)
                    for (Int32 z = kRegion.min()[2]; z <= kRegion.max()[2]; ++z) {
                        const openvdb::Vec3d p = maskTheirs->transform().worldToIndex(
                            g.theirs->transform().indexToWorld(openvdb::Vec3d(x, y, z)));
                        if (maskAcc.isValueOn(openvdb::Coord::floor(p)))
                            resampled->tree().setValueOn(openvdb::Coord(x, y, z), true);
                    }
        }
        for (bool keep : {true, false}) {
            SCOPED_TRACE(testing::Message() << "same " << sameTransform << " keep " << keep);
            const auto a = tools::clip(*g.ours, *maskOurs, keep);
            openvdb::MaskGrid mask(false);
            mask.setTransform(resampled->transform().copy());
            mask.tree().topologyUnion(resampled->tree());
            const auto b = openvdb::tools::clip_internal::doClip(*g.theirs, mask, keep);
            expectSame(a->tree(), b->tree(), kRegion);
        }
    }
}

TEST_F(ClipMaskCompat, ClipKeepsTheActiveTilesOpenVdbDrops) {
    GridPair g{FloatGrid::create(0.5f), openvdb::FloatGrid::create(0.5f)};
    g.ours->tree().addTile(2, Coord(0), 3.0f, true);
    g.theirs->tree().addTile(2, openvdb::Coord(0), 3.0f, true);
    const auto ours = tools::clip(*g.ours, BBoxd(Vec3d(-10.0), Vec3d(20.2, 20.0, 20.0)));
    const auto theirs = openvdb::tools::clip(
        *g.theirs, openvdb::BBoxd(openvdb::Vec3d(-10.0), openvdb::Vec3d(20.2, 20.0, 20.0)));
    EXPECT_EQ(ours->activeVoxelCount(), 21u * 21u * 21u);
    EXPECT_EQ(ours->tree().getValue(Coord(20, 20, 20)), 3.0f);
    // OpenVDB keeps only the part of the tile its final pass reaches (5165 voxels here).
    EXPECT_LT(theirs->activeVoxelCount(), ours->activeVoxelCount());
}

TEST_F(ClipMaskCompat, InteriorMaskMatchesOpenVdb) {
    const auto ours = tools::createLevelSetSphere<FloatGrid>(9.0f, Vec3f(1.5f, -2.0f, 0.25f), 0.5f);
    const auto theirs = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        9.0f, openvdb::Vec3f(1.5f, -2.0f, 0.25f), 0.5f);
    for (double iso : {0.0, 0.3}) {
        expectSame(tools::interiorMask(*ours, iso)->tree(),
                   openvdb::tools::interiorMask(*theirs, iso)->tree(), kRegion);
    }
    const GridPair fog = makeGrids(4, 0.0f, 1.0, Vec3d(0.0), false);
    expectSame(tools::interiorMask(*fog.ours, 0.5)->tree(),
               openvdb::tools::interiorMask(*fog.theirs, 0.5)->tree(), kRegion);
}

TEST_F(ClipMaskCompat, ActivateAndDeactivateMatchOpenVdb) {
    for (float tolerance : {0.0f, 0.3f}) {
        const GridPair g = makeGrids(5, 0.0f, 1.0, Vec3d(0.0), false);
        tools::activate(*g.ours, 1.0f, tolerance);
        openvdb::tools::activate(*g.theirs, 1.0f, tolerance);
        tools::deactivate(*g.ours, -2.0f, tolerance);
        openvdb::tools::deactivate(*g.theirs, -2.0f, tolerance);
        tools::activate(*g.ours, 0.0f);
        openvdb::tools::activate(*g.theirs, 0.0f);
        expectSame(g.ours->tree(), g.theirs->tree(), kRegion);
    }
}

TEST_F(ClipMaskCompat, EveryCompositingOperationMatchesOpenVdb) {
    const std::vector<std::function<void(FloatGrid&, FloatGrid&)>> ours = {
        [](auto& a, auto& b) { tools::compMax(a, b); },
        [](auto& a, auto& b) { tools::compMin(a, b); },
        [](auto& a, auto& b) { tools::compSum(a, b); },
        [](auto& a, auto& b) { tools::compMul(a, b); },
        [](auto& a, auto& b) { tools::compDiv(a, b); },
        [](auto& a, auto& b) { tools::compReplace(a, b); }};
    const std::vector<std::function<void(openvdb::FloatGrid&, openvdb::FloatGrid&)>> theirs = {
        [](auto& a, auto& b) { openvdb::tools::compMax(a, b); },
        [](auto& a, auto& b) { openvdb::tools::compMin(a, b); },
        [](auto& a, auto& b) { openvdb::tools::compSum(a, b); },
        [](auto& a, auto& b) { openvdb::tools::compMul(a, b); },
        [](auto& a, auto& b) { openvdb::tools::compDiv(a, b); },
        [](auto& a, auto& b) { openvdb::tools::compReplace(a, b); }};
    for (size_t op = 0; op < ours.size(); ++op) {
        SCOPED_TRACE(testing::Message() << "operation " << op);
        GridPair a = makeGrids(6, 0.5f, 1.0, Vec3d(0.0), false);
        GridPair b = makeGrids(7, -3.0f, 1.0, Vec3d(0.0), false);
        ours[op](*a.ours, *b.ours);
        theirs[op](*a.theirs, *b.theirs);
        expectSame(a.ours->tree(), a.theirs->tree(), kRegion);
        EXPECT_EQ(a.ours->background(), a.theirs->background());
        EXPECT_EQ(b.ours->tree().empty(), b.theirs->tree().empty());
    }
}

TEST_F(ClipMaskCompat, ForeachAndTransformValuesMatchOpenVdb) {
    const GridPair g = makeGrids(8, 0.0f, 1.0, Vec3d(0.0), false);
    tools::foreach (g.ours->beginValueOn(),
                    [](const FloatGrid::ValueOnIter& it) { it.setValue(*it * 3.0f - 1.0f); });
    openvdb::tools::foreach (
        g.theirs->beginValueOn(),
        [](const openvdb::FloatGrid::ValueOnIter& it) { it.setValue(*it * 3.0f - 1.0f); });
    expectSame(g.ours->tree(), g.theirs->tree(), kRegion);

    auto outOurs = Int32Grid::create(-5);
    auto outTheirs = openvdb::Int32Grid::create(-5);
    tools::transformValues(g.ours->cbeginValueOn(), *outOurs,
                           [](const FloatGrid::ValueOnCIter& it, Int32Grid::Accessor& acc) {
                               if (it.isVoxelValue())
                                   acc.setValue(it.getCoord(), Int32(*it * 8.0f));
                           });
    // OpenVDB 10's transformValues does not compile under C++20 with oneTBB (its
    // tbb::parallel_reduce body); its serial definition, op(it, acc) over the iterator, is
    // written out here.
    {
        auto acc = outTheirs->getAccessor();
        for (auto it = g.theirs->cbeginValueOn(); it; ++it) {
            if (it.isVoxelValue())
                acc.setValue(it.getCoord(), Int32(*it * 8.0f));
        }
    }
    expectSame(outOurs->tree(), outTheirs->tree(), kRegion);
}

}  // namespace
}  // namespace vdb
