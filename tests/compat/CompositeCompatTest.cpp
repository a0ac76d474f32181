// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10. The same trees (ours converted node by node into OpenVDB's, then checked
// equal) go through OpenVDB's csgUnion / csgIntersection / csgDifference, Tree::combine /
// combineExtended and topologyUnion / topologyIntersection / topologyDifference and through ours;
// the results must hold the same values, states and tiles everywhere: every voxel and every tile of
// every level, compared bit for bit, plus the background and the node counts.

#include <vdb/Grid.h>
#include <vdb/tools/Composite.h>
#include <vdb/tree/TreeConfigs.h>

#include "OpenVdbConvert.h"
#include <Oracles.h>
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

namespace vdb {
namespace {

// ---- Converting between the libraries ---------------------------------------------------------

using test::fromOvdb;
using test::sameBits;
using test::toOvdb;

/// The OpenVDB tree of the same layout and value type as our 5-4-3 tree `TreeT`.
template <typename TreeT>
struct OvdbTreeOf;
template <>
struct OvdbTreeOf<FloatTree> {
    using Type = openvdb::FloatTree;
};
template <>
struct OvdbTreeOf<DoubleTree> {
    using Type = openvdb::DoubleTree;
};
template <>
struct OvdbTreeOf<BoolTree> {
    using Type = openvdb::BoolTree;
};
template <>
struct OvdbTreeOf<MaskTree> {
    using Type = openvdb::MaskTree;
};

/// Copies our level set tree into a new OpenVDB tree: every tile that is not inactive background
/// with its level, every leaf with its mask and values.
template <typename TreeT>
typename OvdbTreeOf<TreeT>::Type::Ptr toOvdbTree(const TreeT& tree) {
    using OvdbTreeT = typename OvdbTreeOf<TreeT>::Type;
    auto out = std::make_shared<OvdbTreeT>(tree.background());
    for (auto it = tree.cbeginValueAll(); it; ++it) {
        if (!it.isTileValue())
            continue;
        if (!it.isValueOn() && sameBits(it.getValue(), tree.background()))
            continue;
        CoordBBox box;
        it.getBoundingBox(box);
        const Index level = box.dim()[0] == 8 ? 1 : box.dim()[0] == 128 ? 2 : 3;
        out->addTile(level, toOvdb(box.min()), it.getValue(), it.isValueOn());
    }
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        auto* leaf = out->touchLeaf(toOvdb(it->origin()));
        for (Index n = 0; n < TreeT::LeafNodeType::NUM_VALUES; ++n) {
            leaf->setValueOnly(n, it->getValue(n));
            leaf->setActiveState(n, it->isValueOn(n));
        }
    }
    return out;
}

// ---- Node-by-node comparison --------------------------------------------------------------------

/// Same origin, masks, tile values and voxel values (bit for bit), recursively. Our node and
/// OpenVDB's have the same table layout, so entry n of one is entry n of the other.
template <typename NodeT, typename OvdbNodeT>
::testing::AssertionResult sameNodes(const NodeT& x, const OvdbNodeT& y) {
    using ValueT = typename NodeT::ValueType;
    if (x.origin() != fromOvdb(y.origin()))
        return ::testing::AssertionFailure() << "node origins differ at " << x.origin();
    for (Index w = 0; w < NodeT::MaskType::WORD_COUNT; ++w) {
        if (x.getValueMask().getWord(w) != y.getValueMask().template getWord<uint64_t>(w))
            return ::testing::AssertionFailure() << "value masks differ in node " << x.origin();
    }
    if constexpr (NodeT::LEVEL == 0) {
        for (Index n = 0; n < NodeT::NUM_VALUES; ++n) {
            if (!sameBits(x.getValue(n), ValueT(y.getValue(n))))
                return ::testing::AssertionFailure()
                       << "voxel " << x.offsetToGlobalCoord(n) << ": ours " << x.getValue(n)
                       << ", OpenVDB " << y.getValue(n);
        }
    } else {
        for (Index w = 0; w < NodeT::MaskType::WORD_COUNT; ++w) {
            if (x.getChildMask().getWord(w) != y.getChildMask().template getWord<uint64_t>(w))
                return ::testing::AssertionFailure() << "child masks differ in node " << x.origin();
        }
        const auto* table = y.getTable();
        for (Index n : x.getChildMask().offBits()) {
            if (!sameBits(x.getTileValue(n), ValueT(table[n].getValue())))
                return ::testing::AssertionFailure()
                       << "tile " << x.offsetToGlobalCoord(n) << ": ours " << x.getTileValue(n)
                       << ", OpenVDB " << table[n].getValue();
        }
        for (Index n : x.getChildMask().onBits()) {
            auto result = sameNodes(*x.getChild(n), *table[n].getChild());
            if (!result)
                return result;
        }
    }
    return ::testing::AssertionSuccess();
}

/// Same background, root entries, and every node, tile and voxel (see sameNodes).
template <typename TreeT, typename OvdbTreeT>
::testing::AssertionResult sameTrees(const TreeT& ours, const OvdbTreeT& theirs) {
    using ValueT = typename TreeT::ValueType;
    if (!sameBits(ours.background(), ValueT(theirs.background())))
        return ::testing::AssertionFailure() << "backgrounds differ";
    if (ours.leafCount() != theirs.leafCount())
        return ::testing::AssertionFailure() << "leaf counts differ: ours " << ours.leafCount()
                                             << ", OpenVDB " << theirs.leafCount();
    if (ours.activeVoxelCount() != theirs.activeVoxelCount())
        return ::testing::AssertionFailure()
               << "active voxel counts differ: ours " << ours.activeVoxelCount() << ", OpenVDB "
               << theirs.activeVoxelCount();
    const auto& x = ours.root();
    const auto& y = theirs.root();
    if (x.entryCount() != y.getTableSize())
        return ::testing::AssertionFailure() << "root entry counts differ: ours " << x.entryCount()
                                             << ", OpenVDB " << y.getTableSize();
    for (auto it = y.cbeginValueAll(); it; ++it) {
        const auto* e = x.findEntry(fromOvdb(it.getCoord()));
        if (!e || e->child || e->active != it.isValueOn() ||
            !sameBits(e->tile, ValueT(it.getValue())))
            return ::testing::AssertionFailure()
                   << "root tile " << fromOvdb(it.getCoord()) << " differs";
    }
    for (auto it = y.cbeginChildOn(); it; ++it) {
        const auto* e = x.findEntry(fromOvdb(it.getCoord()));
        if (!e || !e->child)
            return ::testing::AssertionFailure()
                   << "root child " << fromOvdb(it.getCoord()) << " is missing";
        auto result = sameNodes(*e->child, *it);
        if (!result)
            return result;
    }
    return ::testing::AssertionSuccess();
}

// ---- Level sets of spheres, with extra tiles ----------------------------------------------------

struct Sphere {
    double x, y, z, r;
    double distance(const Coord& p) const {
        const double dx = p[0] - x, dy = p[1] - y, dz = p[2] - z;
        return std::sqrt(dx * dx + dy * dy + dz * dz) - r;
    }
};

/// A narrow-band level set of the union of `spheres`: |d| < background active with value d,
/// the rest of each touched leaf -+background, whole inside blocks filled with -background,
/// then pruned into tiles.
template <typename TreeT>
void addSpheres(TreeT& tree, const std::vector<Sphere>& spheres) {
    using ValueT = typename TreeT::ValueType;
    const ValueT bg = tree.background();
    auto sdf = [&](const Coord& p) {
        double d = spheres[0].distance(p);
        for (const Sphere& s : spheres)
            d = std::min(d, s.distance(p));
        return d;
    };
    typename TreeT::Accessor acc(tree);
    for (const Sphere& s : spheres) {
        const Int32 m = Int32(std::ceil(s.r)) + 12;
        const Coord c(Int32(s.x), Int32(s.y), Int32(s.z));
        const Coord lo = c.offsetBy(-m).alignedDown(3), hi = c.offsetBy(m);
        for (Int32 x = lo[0]; x <= hi[0]; x += 8)
            for (Int32 y = lo[1]; y <= hi[1]; y += 8)
                for (Int32 z = lo[2]; z <= hi[2]; z += 8) {
                    const double center = sdf(Coord(x + 4, y + 4, z + 4));
                    if (center > double(bg) + 8)
                        continue;
                    if (center < -double(bg) - 8) {
                        tree.fill(CoordBBox::createCube(Coord(x, y, z), 8), ValueT(-bg), false);
                        continue;
                    }
                    for (Int32 i = x; i < x + 8; ++i)
                        for (Int32 j = y; j < y + 8; ++j)
                            for (Int32 k = z; k < z + 8; ++k) {
                                const ValueT d = ValueT(sdf(Coord(i, j, k)));
                                if (std::abs(d) < bg) {
                                    acc.setValueOn(Coord(i, j, k), d);
                                } else if (d < 0) {
                                    acc.setValueOff(Coord(i, j, k), ValueT(-bg));
                                }
                            }
                }
    }
    tree.prune();
}

enum class Op { Union, Intersection, Difference };
const char* opName(Op op) {
    return op == Op::Union ? "union" : op == Op::Intersection ? "intersection" : "difference";
}

template <typename TreeT>
void oursInPlace(Op op, TreeT& a, TreeT& b, bool prune) {
    if (op == Op::Union) {
        tools::csgUnion(a, b, prune);
    } else if (op == Op::Intersection) {
        tools::csgIntersection(a, b, prune);
    } else {
        tools::csgDifference(a, b, prune);
    }
}

template <typename TreeT>
std::unique_ptr<TreeT> oursCopy(Op op, const TreeT& a, const TreeT& b) {
    if (op == Op::Union)
        return tools::csgUnionCopy(a, b);
    if (op == Op::Intersection)
        return tools::csgIntersectionCopy(a, b);
    return tools::csgDifferenceCopy(a, b);
}

template <typename OvdbTreeT>
void theirsInPlace(Op op, OvdbTreeT& a, OvdbTreeT& b, bool prune) {
    if (op == Op::Union) {
        openvdb::tools::csgUnion(a, b, prune);
    } else if (op == Op::Intersection) {
        openvdb::tools::csgIntersection(a, b, prune);
    } else {
        openvdb::tools::csgDifference(a, b, prune);
    }
}

template <typename OvdbTreeT>
typename OvdbTreeT::Ptr theirsCopy(Op op, const OvdbTreeT& a, const OvdbTreeT& b) {
    if (op == Op::Union)
        return openvdb::tools::csgUnionCopy(a, b);
    if (op == Op::Intersection)
        return openvdb::tools::csgIntersectionCopy(a, b);
    return openvdb::tools::csgDifferenceCopy(a, b);
}

class CompositeCompat : public ::testing::Test {
protected:
    static void SetUpTestSuite() { openvdb::initialize(); }

    /// Runs every operation, pruned and not, in place and as a copy, through both libraries.
    template <typename TreeT>
    static void compareCsg(const TreeT& a, const TreeT& b) {
        const auto ovA = toOvdbTree(a);
        const auto ovB = toOvdbTree(b);
        ASSERT_TRUE(sameTrees(a, *ovA));
        ASSERT_TRUE(sameTrees(b, *ovB));
        ASSERT_GT(a.leafCount(), 0u);
        ASSERT_GT(b.leafCount(), 0u);
        for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
            for (bool prune : {true, false}) {
                SCOPED_TRACE(::testing::Message() << opName(op) << (prune ? " pruned" : ""));
                TreeT x(a), y(b);
                oursInPlace(op, x, y, prune);
                auto ovX = std::make_shared<typename OvdbTreeOf<TreeT>::Type>(*ovA);
                auto ovY = std::make_shared<typename OvdbTreeOf<TreeT>::Type>(*ovB);
                theirsInPlace(op, *ovX, *ovY, prune);
                EXPECT_TRUE(sameTrees(x, *ovX));
                EXPECT_TRUE(y.empty());
                if (op == Op::Union) {
                    EXPECT_GT(x.leafCount(), 0u);
                }
                if (prune) {
                    EXPECT_TRUE(sameTrees(*oursCopy(op, a, b), *ovX));
                }
            }
        }
    }
};

// ---- CSG ----------------------------------------------------------------------------------------

TEST_F(CompositeCompat, CsgOfOverlappingNestedAndDistantSpheresMatchesOpenVdb) {
    FloatTree a(3.0f), b(3.0f);
    addSpheres(a, {{-8.25, 4.5, -3.0, 30.0}, {25.0, -9.0, 13.0, 3.5}, {4196.0, -20.0, 30.0, 9.0}});
    addSpheres(b,
               {{24.0, -10.0, 12.0, 28.0}, {-10.0, 4.0, -5.0, 5.0}, {-4196.0, 60.0, -50.0, 10.5}});
    compareCsg(a, b);
}

TEST_F(CompositeCompat, CsgWithTilesAtEveryLevelMatchesOpenVdb) {
    const float bg = 2.0f;
    FloatTree a(bg), b(bg);
    // Root tiles (4096^3) and level-2 tiles (128^3) of inside, each with a sphere of the other
    // tree in it; an outside tile of a non-background value; a sphere under nothing.
    a.fill(CoordBBox::createCube(Coord(-4096, 0, 0), 4096), -bg, false);
    a.fill(CoordBBox::createCube(Coord(256, 0, 0), 128), -bg, false);
    a.fill(CoordBBox::createCube(Coord(0, 512, 0), 128), 1.5f, false);
    addSpheres(a,
               {{100.0, 1000.0, 30.0, 12.0}, {4500.0, 40.0, 30.0, 11.0}, {60.0, 570.0, 60.0, 9.0}});
    addSpheres(b, {{-300.0, 200.0, 250.0, 14.0},
                   {300.0, 60.0, 70.0, 10.0},
                   {-5000.0, 9.0, 9.0, 9.0},
                   {64.0, 576.0, 64.0, 10.0}});
    b.fill(CoordBBox::createCube(Coord(4096, 0, 0), 4096), -bg, false);
    b.fill(CoordBBox::createCube(Coord(0, 896, 0), 128), -bg, false);
    compareCsg(a, b);
}

TEST_F(CompositeCompat, CombineAndCombineExtendedMatchOpenVdb) {
    // tools::combine / combineExtended against Tree::combine / combineExtended, pruned and not:
    // tiles at every level and leaves on both sides, different backgrounds, ops that leave
    // constant leaves behind (pruned away) and one that chooses the result's state.
    FloatTree a(2.0f), b(-1.5f);
    a.fill(CoordBBox::createCube(Coord(-4096, 0, 0), 4096), -2.0f, true);
    a.fill(CoordBBox::createCube(Coord(256, 0, 0), 128), 0.5f, false);
    addSpheres(a,
               {{100.0, 1000.0, 30.0, 12.0}, {-4000.0, 40.0, 30.0, 11.0}, {20.0, 20.0, 20.0, 9.0}});
    addSpheres(b, {{300.0, 60.0, 70.0, 10.0}, {-5000.0, 9.0, 9.0, 9.0}, {24.0, 30.0, 20.0, 12.0}});
    b.fill(CoordBBox::createCube(Coord(4096, 0, 0), 4096), 3.0f, false);
    b.fill(CoordBBox::createCube(Coord(0, 896, 0), 128), -0.5f, true);
    const auto ovA = toOvdbTree(a);
    const auto ovB = toOvdbTree(b);
    ASSERT_TRUE(sameTrees(a, *ovA));
    ASSERT_TRUE(sameTrees(b, *ovB));
    const auto clamp = [](const float& x, const float& y, float& r) {
        r = std::min(std::max(x, y), 1.0f);
    };
    const auto blend = [](const float& x, const float& y, float& r) { r = 0.25f * x + y; };
    const auto merge = [](auto& args) {
        const bool takeB = !args.aIsActive() && args.bIsActive();
        args.setResult(takeB ? args.b() : args.a());
        args.setResultIsActive(args.aIsActive() || takeB);
    };
    for (bool prune : {false, true}) {
        for (int op = 0; op < 3; ++op) {
            SCOPED_TRACE(::testing::Message() << "op " << op << (prune ? " pruned" : ""));
            FloatTree x(a), y(b);
            auto ovX = std::make_shared<openvdb::FloatTree>(*ovA);
            auto ovY = std::make_shared<openvdb::FloatTree>(*ovB);
            if (op == 0) {
                tools::combine(x, y, clamp, prune);
                ovX->combine(*ovY, clamp, prune);
            } else if (op == 1) {
                tools::combine(x, y, blend, prune, false);
                ovX->combine(*ovY, blend, prune);
            } else {
                tools::combineExtended(
                    x, y, [&](CombineArgs<float>& args) { merge(args); }, prune);
                ovX->combineExtended(
                    *ovY, [&](openvdb::CombineArgs<float>& args) { merge(args); }, prune);
            }
            EXPECT_TRUE(sameTrees(x, *ovX));
            EXPECT_EQ(x.nonLeafCount(), ovX->nonLeafCount());
            EXPECT_TRUE(y.empty());
            EXPECT_TRUE(ovY->empty());
        }
    }
}

TEST_F(CompositeCompat, CsgWithActiveAndZeroTilesMatchesOpenVdb) {
    const float bg = 3.0f;
    FloatTree a(bg), b(bg);
    // Tiles a level set would not hold, whose handling follows OpenVDB's rules exactly.
    a.fill(CoordBBox::createCube(Coord(-4096, -4096, 0), 4096), -bg, true);
    a.fill(CoordBBox::createCube(Coord(0, -128, 0), 128), 0.0f, false);
    a.fill(CoordBBox::createCube(Coord(-128, -128, 0), 128), 2.0f, true);
    addSpheres(a, {{20.0, 20.0, 20.0, 15.0}});
    addSpheres(b, {{-200.0, -200.0, 300.0, 9.0},
                   {60.0, -60.0, 60.0, 12.0},
                   {-60.0, -60.0, 60.0, 12.0},
                   {20.0, 30.0, 20.0, 12.0}});
    b.fill(CoordBBox::createCube(Coord(-4096, 4096, 0), 4096), -bg, true);
    b.fill(CoordBBox::createCube(Coord(0, 0, 128), 128), 0.0f, false);
    // Tiles of values other than +-background, which the root normalises.
    a.fill(CoordBBox::createCube(Coord(4096, -4096, 0), 4096), -1.0f, false);
    a.fill(CoordBBox::createCube(Coord(-8192, 0, 0), 4096), 1.0f, false);
    b.fill(CoordBBox::createCube(Coord(-8192, 0, 0), 4096), -1.25f, false);
    b.fill(CoordBBox::createCube(Coord(-8192, -4096, 0), 4096), 2.5f, false);
    b.fill(CoordBBox::createCube(Coord(128, 0, 0), 128), -1.0f, false);
    b.fill(CoordBBox::createCube(Coord(0, 128, 0), 128), 1.0f, true);
    compareCsg(a, b);
}

TEST_F(CompositeCompat, CsgWithDifferentBackgroundsMatchesOpenVdb) {
    FloatTree a(3.0f), b(2.0f);
    addSpheres(a, {{0.0, 0.0, 0.0, 30.0}, {-4196.0, 5.0, 5.0, 8.0}});
    addSpheres(b, {{2.0, 1.0, -1.0, 6.0},
                   {200.0, 0.0, 0.0, 7.0},
                   {40.0, 0.0, 0.0, 15.0},
                   {4196.0, 5.0, 5.0, 8.0}});
    compareCsg(a, b);
    compareCsg(b, a);
}

TEST_F(CompositeCompat, CsgOfDoubleLevelSetsMatchesOpenVdb) {
    DoubleTree a(2.5), b(2.5);
    addSpheres(a, {{-5.5, 3.0, 1.0, 20.0}, {3000.0, 0.0, 0.0, 5.0}});
    addSpheres(b, {{10.0, -4.0, 6.0, 17.0}, {-3.0, 2.0, 0.0, 6.0}});
    compareCsg(a, b);
}

// Our Copy forms equal the in-place result; OpenVDB's csg*Copy builds its result from leaves
// and a signed flood fill instead, so only the active voxels and their values are compared.
TEST_F(CompositeCompat, CsgCopyHasTheActiveVoxelsOfOpenVdbsCopy) {
    FloatTree a(3.0f), b(3.0f);
    addSpheres(a, {{-8.25, 4.5, -3.0, 30.0}, {25.0, -9.0, 13.0, 3.5}});
    addSpheres(b,
               {{24.0, -10.0, 12.0, 28.0}, {-10.0, 4.0, -5.0, 5.0}, {-4196.0, 60.0, -50.0, 10.5}});
    const auto ovA = toOvdbTree(a);
    const auto ovB = toOvdbTree(b);
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        SCOPED_TRACE(opName(op));
        const auto ours = oursCopy(op, a, b);
        const auto theirs = theirsCopy(op, *ovA, *ovB);
        EXPECT_EQ(ours->activeVoxelCount(), theirs->activeVoxelCount());
        openvdb::tree::ValueAccessor<const openvdb::FloatTree> acc(*theirs);
        for (auto it = ours->cbeginValueOn(); it; ++it) {
            ASSERT_TRUE(it.isVoxelValue());
            float value;
            ASSERT_TRUE(acc.probeValue(toOvdb(it.getCoord()), value)) << it.getCoord();
            ASSERT_TRUE(sameBits(value, *it)) << it.getCoord();
        }
    }
}

// ---- Topology booleans ------------------------------------------------------------------------

/// The same writes into both libraries: voxels and box fills, active or not.
struct Write {
    Coord ijk;
    float value;
    bool on;
    Int32 dim;
};

std::vector<Write> randomWrites(uint32_t seed, int count) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> near(-200, 199), far(-9000, 8999);
    // Most writes land near the origin; a few far away create root entries of their own.
    std::vector<Write> writes;
    auto value = [&] { return float(int(rng() % 200u) - 100) / 4.0f; };
    // Tiles of every level, some overlapping, some inactive with values.
    for (Int32 dim : {8, 128, 4096}) {
        for (int i = 0; i < 3; ++i) {
            const Coord ijk = Coord(near(rng), near(rng), near(rng))
                                  .alignedDown(dim == 8     ? 3
                                               : dim == 128 ? 7
                                                            : 12);
            writes.push_back({ijk, value(), (rng() % 3u) != 0, dim});
        }
    }
    for (int i = 0; i < count; ++i) {
        const bool distant = (rng() % 64u) == 0;
        const Coord ijk =
            distant ? Coord(far(rng), far(rng), far(rng)) : Coord(near(rng), near(rng), near(rng));
        writes.push_back({ijk, value(), (rng() % 4u) != 0, (rng() % 40u) == 0 ? 8 : 1});
    }
    return writes;
}

template <typename TreeT, typename OvdbTreeT>
void applyWrites(const std::vector<Write>& writes, TreeT& ours, OvdbTreeT& theirs) {
    using ValueT = typename TreeT::ValueType;
    constexpr bool MASK = std::is_same_v<typename TreeT::BuildType, ValueMask>;
    for (const Write& w : writes) {
        // Bool trees get a value from the sign; mask trees' values are their states.
        ValueT value;
        if constexpr (MASK) {
            value = w.on;
        } else if constexpr (std::is_same_v<ValueT, bool>) {
            value = w.value > 0;
        } else {
            value = ValueT(w.value);
        }
        if (w.dim > 1) {
            const CoordBBox box = CoordBBox::createCube(w.ijk, w.dim);
            ours.fill(box, value, w.on);
            theirs.fill(openvdb::CoordBBox(toOvdb(box.min()), toOvdb(box.max())), value, w.on);
        } else if (w.on) {
            ours.setValueOn(w.ijk, value);
            theirs.setValueOn(toOvdb(w.ijk), value);
        } else {
            ours.setValueOff(w.ijk, value);
            theirs.setValueOff(toOvdb(w.ijk), value);
        }
    }
}

template <typename OtherTreeT>
void compareTopology(uint32_t seed) {
    using OvdbOtherT = typename OvdbTreeOf<OtherTreeT>::Type;
    const int count = std::max(200, int(4000 * test::workloadScale()));
    FloatTree a(0.5f);
    openvdb::FloatTree ovA(0.5f);
    applyWrites(randomWrites(seed, count), a, ovA);
    ASSERT_TRUE(sameTrees(a, ovA));
    OtherTreeT b;
    OvdbOtherT ovB;
    applyWrites(randomWrites(seed + 1, count), b, ovB);
    if constexpr (!std::is_same_v<OtherTreeT, MaskTree>) {
        ASSERT_TRUE(sameTrees(b, ovB));
    }
    ASSERT_EQ(b.activeVoxelCount(), ovB.activeVoxelCount());
    for (int op = 0; op < 4; ++op) {
        SCOPED_TRACE(op);
        FloatTree x(a);
        openvdb::FloatTree ovX(ovA);
        if (op == 0) {
            x.topologyUnion(b);
            ovX.topologyUnion(ovB);
        } else if (op == 1) {
            x.topologyUnion(b, /*preserveTiles=*/true);
            ovX.topologyUnion(ovB, /*preserveTiles=*/true);
        } else if (op == 2) {
            x.topologyIntersection(b);
            ovX.topologyIntersection(ovB);
        } else {
            x.topologyDifference(b);
            ovX.topologyDifference(ovB);
        }
        EXPECT_TRUE(sameTrees(x, ovX));
    }
}

TEST_F(CompositeCompat, TopologyBooleansWithAFloatTreeMatchOpenVdb) {
    compareTopology<FloatTree>(1);
    compareTopology<FloatTree>(5);
}

TEST_F(CompositeCompat, TopologyBooleansWithABoolTreeMatchOpenVdb) {
    compareTopology<BoolTree>(2);
}

TEST_F(CompositeCompat, TopologyBooleansWithAMaskTreeMatchOpenVdb) {
    compareTopology<MaskTree>(3);
}

}  // namespace
}  // namespace vdb
