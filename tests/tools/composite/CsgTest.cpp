// SPDX-License-Identifier: Apache-2.0
// Oracles: (1) the inputs themselves, read voxel by voxel with getValue/probeValue over every
// coordinate of the shapes' bounding boxes (tiles included): the result must be min(a, b),
// max(a, b) or max(a, -b) with the active state of the input the value came from (a on ties);
// (2) the exact signed distance of the union, intersection and difference of two spheres,
// computed in double precision from the spheres and the circle where they meet.
// Level sets are built here from analytic distances: voxels with |d| < background are active
// with value d, other voxels of touched leaves hold -+background, whole inside blocks are
// filled with -background and then pruned into tiles.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/Composite.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace vdb {
namespace {

using Sdf = std::function<double(const Coord&)>;

struct Sphere {
    double x, y, z, r;
    double distance(const Coord& ijk) const {
        const double dx = ijk[0] - x, dy = ijk[1] - y, dz = ijk[2] - z;
        return std::sqrt(dx * dx + dy * dy + dz * dz) - r;
    }
    /// The voxels within `margin` of the sphere's bounding box.
    CoordBBox bbox(int margin) const {
        return CoordBBox(Coord(Int32(std::floor(x - r)) - margin, Int32(std::floor(y - r)) - margin,
                               Int32(std::floor(z - r)) - margin),
                         Coord(Int32(std::ceil(x + r)) + margin, Int32(std::ceil(y + r)) + margin,
                               Int32(std::ceil(z + r)) + margin));
    }
};

/// The signed distance of the union of `spheres` approximated by the minimum of theirs (what a
/// level set union stores); exact for disjoint spheres.
Sdf unionOf(std::vector<Sphere> spheres) {
    return [spheres](const Coord& ijk) {
        double d = spheres[0].distance(ijk);
        for (const Sphere& s : spheres)
            d = std::min(d, s.distance(ijk));
        return d;
    };
}

/// Builds a narrow-band level set of `sdf` over the leaf-aligned blocks covering `boxes`:
/// whole blocks further than the band from the surface become -background fills (inside) or
/// stay background (outside); the others are set voxel by voxel. Then prune() turns constant
/// inside nodes into tiles. Every voxel of the boxes then holds sdf clamped to the band.
template <typename TreeT>
void addLevelSet(TreeT& tree, const Sdf& sdf, const std::vector<CoordBBox>& boxes) {
    using ValueT = typename TreeT::ValueType;
    const ValueT bg = tree.background();
    constexpr Int32 dim = Int32(TreeT::LeafNodeType::DIM);
    const double halfDiagonal = dim * std::sqrt(3.0) / 2.0;
    typename TreeT::Accessor acc(tree);
    for (const CoordBBox& bbox : boxes) {
        const Coord lo = bbox.min().alignedDown(TreeT::LeafNodeType::LOG2DIM);
        for (Int32 x = lo[0]; x <= bbox.max()[0]; x += dim)
            for (Int32 y = lo[1]; y <= bbox.max()[1]; y += dim)
                for (Int32 z = lo[2]; z <= bbox.max()[2]; z += dim) {
                    const CoordBBox block = CoordBBox::createCube(Coord(x, y, z), dim);
                    const double center = sdf(Coord(x + dim / 2, y + dim / 2, z + dim / 2));
                    if (center > double(bg) + halfDiagonal + 1)
                        continue;
                    if (center < -double(bg) - halfDiagonal - 1) {
                        tree.fill(block, ValueT(-bg), false);
                        continue;
                    }
                    for (Int32 i = x; i < x + dim; ++i)
                        for (Int32 j = y; j < y + dim; ++j)
                            for (Int32 k = z; k < z + dim; ++k) {
                                const Coord ijk(i, j, k);
                                const ValueT d = ValueT(sdf(ijk));
                                if (std::abs(d) < bg) {
                                    acc.setValueOn(ijk, d);
                                } else if (d < 0) {
                                    acc.setValueOff(ijk, ValueT(-bg));
                                }
                            }
                }
    }
    tree.prune();
}

/// A level set of the union of `spheres`, over their bounding boxes grown by `margin`.
template <typename TreeT>
void addSpheres(TreeT& tree, const std::vector<Sphere>& spheres, int margin = 12) {
    std::vector<CoordBBox> boxes;
    for (const Sphere& s : spheres)
        boxes.push_back(s.bbox(margin));
    addLevelSet(tree, unionOf(spheres), boxes);
}

enum class Op { Union, Intersection, Difference };

template <typename TreeT>
void applyInPlace(Op op, TreeT& a, TreeT& b, bool prune = true, bool threaded = true) {
    switch (op) {
        case Op::Union:
            tools::csgUnion(a, b, prune, threaded);
            break;
        case Op::Intersection:
            tools::csgIntersection(a, b, prune, threaded);
            break;
        case Op::Difference:
            tools::csgDifference(a, b, prune, threaded);
            break;
    }
}

template <typename TreeT>
std::unique_ptr<TreeT> applyCopy(Op op, const TreeT& a, const TreeT& b, bool threaded = true) {
    switch (op) {
        case Op::Union:
            return tools::csgUnionCopy(a, b, threaded);
        case Op::Intersection:
            return tools::csgIntersectionCopy(a, b, threaded);
        default:
            return tools::csgDifferenceCopy(a, b, threaded);
    }
}

const char* opName(Op op) {
    return op == Op::Union ? "union" : op == Op::Intersection ? "intersection" : "difference";
}

/// The value and state the rule gives a voxel from the inputs' values and states.
template <typename ValueT>
std::pair<ValueT, bool> combine(Op op, ValueT a, bool aOn, ValueT b, bool bOn) {
    if (op == Op::Difference)
        b = -b;
    const bool fromB = op == Op::Union ? b < a : a < b;
    return fromB ? std::make_pair(b, bOn) : std::make_pair(a, aOn);
}

/// Scans visit every x-y row of a box, or every third one in the sanitizer's reduced workload.
Int32 scanStride() {
    return test::workloadScale() < 0.5 ? 3 : 1;
}

/// Every voxel of `boxes` holds the combination of the inputs' values and states; every leaf
/// has an active voxel (the result was pruned as a level set).
template <typename TreeT>
::testing::AssertionResult resultMatchesRule(Op op, const TreeT& a, const TreeT& b,
                                             const TreeT& result,
                                             const std::vector<CoordBBox>& boxes) {
    using ValueT = typename TreeT::ValueType;
    typename TreeT::ConstAccessor accA(a), accB(b), accR(result);
    const Int32 stride = scanStride();
    for (const CoordBBox& box : boxes) {
        for (Int32 x = box.min()[0]; x <= box.max()[0]; x += stride)
            for (Int32 y = box.min()[1]; y <= box.max()[1]; y += stride)
                for (Int32 z = box.min()[2]; z <= box.max()[2]; ++z) {
                    const Coord ijk(x, y, z);
                    ValueT va, vb, vr;
                    const bool sa = accA.probeValue(ijk, va);
                    const bool sb = accB.probeValue(ijk, vb);
                    const bool sr = accR.probeValue(ijk, vr);
                    const auto [ve, se] = combine(op, va, sa, vb, sb);
                    if (vr != ve || sr != se)
                        return ::testing::AssertionFailure()
                               << opName(op) << " at " << ijk << ": got " << vr
                               << (sr ? " on" : " off") << ", expected " << ve
                               << (se ? " on" : " off") << " from a=" << va << (sa ? " on" : " off")
                               << " b=" << vb << (sb ? " on" : " off");
                }
    }
    for (auto it = result.cbeginLeaf(); it; ++it) {
        if (it->isEmpty())
            return ::testing::AssertionFailure()
                   << opName(op) << ": leaf at " << it->origin() << " has no active voxel";
    }
    return ::testing::AssertionSuccess();
}

// ---- Structural identity of two trees

template <typename ValueT>
bool sameBits(const ValueT& x, const ValueT& y) {
    return std::memcmp(&x, &y, sizeof(ValueT)) == 0;
}

/// Same masks, same tile values and same voxel values (bit for bit), recursively.
template <typename NodeT>
::testing::AssertionResult identicalNodes(const NodeT& x, const NodeT& y) {
    if (!(x.origin() == y.origin()) || !(x.getValueMask() == y.getValueMask()))
        return ::testing::AssertionFailure() << "node at " << x.origin() << " differs";
    if constexpr (NodeT::LEVEL == 0) {
        const auto vx = x.buffer(0), vy = y.buffer(0);
        if (std::memcmp(vx.data(), vy.data(), vx.size_bytes()) != 0)
            return ::testing::AssertionFailure() << "leaf values at " << x.origin() << " differ";
    } else {
        if (!(x.getChildMask() == y.getChildMask()))
            return ::testing::AssertionFailure() << "children of " << x.origin() << " differ";
        for (Index n : x.getChildMask().offBits()) {
            if (!sameBits(x.getTileValue(n), y.getTileValue(n)))
                return ::testing::AssertionFailure()
                       << "tile " << x.offsetToGlobalCoord(n) << " differs";
        }
        for (Index n : x.getChildMask().onBits()) {
            auto result = identicalNodes(*x.getChild(n), *y.getChild(n));
            if (!result)
                return result;
        }
    }
    return ::testing::AssertionSuccess();
}

/// The two trees store the same nodes, tiles and values, bit for bit.
template <typename TreeT>
::testing::AssertionResult identical(const TreeT& x, const TreeT& y) {
    if (!sameBits(x.background(), y.background()))
        return ::testing::AssertionFailure() << "backgrounds differ";
    if constexpr (TreeT::BOUNDED) {
        return identicalNodes(x.topNode(), y.topNode());
    } else {
        const auto& rx = x.root();
        const auto& ry = y.root();
        if (rx.entryCount() != ry.entryCount())
            return ::testing::AssertionFailure() << "root entry counts differ";
        for (auto c = rx.cbegin(); rx.valid(c); rx.next(c)) {
            const auto& ex = rx.entry(c);
            const auto* ey = ry.findEntry(rx.key(c));
            if (!ey || bool(ex.child) != bool(ey->child))
                return ::testing::AssertionFailure() << "root entry " << rx.key(c) << " differs";
            if (ex.child) {
                auto result = identicalNodes(*ex.child, *ey->child);
                if (!result)
                    return result;
            } else if (!sameBits(ex.tile, ey->tile) || ex.active != ey->active) {
                return ::testing::AssertionFailure() << "root tile " << rx.key(c) << " differs";
            }
        }
        return ::testing::AssertionSuccess();
    }
}

/// The Copy form of `op` leaves `a` and `b` as they were and returns exactly what the in-place
/// form (with pruning) leaves in a copy of `a`.
template <typename TreeT>
::testing::AssertionResult copyEqualsInPlace(Op op, const TreeT& a, const TreeT& b) {
    const TreeT a0(a), b0(b);
    for (bool threaded : {true, false}) {
        const auto copy = applyCopy(op, a, b, threaded);
        if (!identical(a, a0) || !identical(b, b0))
            return ::testing::AssertionFailure() << opName(op) << " copy changed an input";
        TreeT x(a), y(b);
        applyInPlace(op, x, y);
        auto same = identical(*copy, x);
        if (!same)
            return same << " (" << opName(op) << (threaded ? ", threaded" : "") << ")";
    }
    return ::testing::AssertionSuccess();
}

// ---- The scene

struct Scene {
    std::vector<Sphere> a, b;
    std::vector<CoordBBox> boxes;  // every voxel the shapes and their bands touch
};

/// A: a big sphere across the origin, a small one deep inside B's big sphere, and a far one.
/// B: a big sphere overlapping A's, a small one deep inside A's big sphere, and a far one. The
/// far spheres sit at x = -far and +far, in top-level regions the other tree does not have.
Scene makeScene(Int32 far) {
    Scene s;
    s.a = {{-8.25, 4.5, -3.0, 30.0}, {25.0, -9.0, 13.0, 3.5}, {double(far), -20.0, 30.0, 9.0}};
    s.b = {{24.0, -10.0, 12.0, 28.0}, {-10.0, 4.0, -5.0, 5.0}, {double(-far), 60.0, -50.0, 10.5}};
    for (const auto* list : {&s.a, &s.b}) {
        for (const Sphere& sphere : *list)
            s.boxes.push_back(sphere.bbox(12));
    }
    return s;
}

template <typename C>
class Csg : public ::testing::Test {
protected:
    using TreeT = typename C::TreeType;
    using ValueT = typename TreeT::ValueType;

    /// The x of the far spheres: past the top-level region next to the origin.
    static Int32 far() {
        if constexpr (TreeT::BOUNDED) {
            return 1000;
        } else {
            return Int32(TreeT::TopNodeType::ChildNodeType::DIM) + 100;
        }
    }

    // The inputs are built once per configuration and copied by the tests that change them.
    static void SetUpTestSuite() {
        sScene = makeScene(far());
        sA = std::make_unique<TreeT>(ValueT(3));
        sB = std::make_unique<TreeT>(ValueT(3));
        addSpheres(*sA, sScene.a);
        addSpheres(*sB, sScene.b);
    }
    static void TearDownTestSuite() {
        sA.reset();
        sB.reset();
    }

    void checkInPlace(Op op) {
        TreeT x(a), y(b);
        applyInPlace(op, x, y);
        EXPECT_TRUE(resultMatchesRule(op, a, b, x, scene.boxes));
        EXPECT_TRUE(y.empty());
        EXPECT_EQ(y.leafCount(), 0u);
        EXPECT_EQ(x.background(), a.background());
        // Nothing active outside the scene's boxes.
        for (auto it = x.cbeginValueOn(); it; ++it) {
            bool inside = false;
            for (const CoordBBox& box : scene.boxes)
                inside = inside || box.isInside(it.getCoord());
            ASSERT_TRUE(inside) << it.getCoord();
        }
    }

    static inline std::unique_ptr<TreeT> sA, sB;
    static inline Scene sScene;
    const TreeT& a = *sA;
    const TreeT& b = *sB;
    const Scene& scene = sScene;
};

struct DoubleTree543 : test::TreeConfig<DoubleTree, false, 5, 4, 3> {
    static constexpr const char* NAME = "DoubleTree543";
};
using Configs = ::testing::Types<test::configs::HashTree543, test::configs::HashTree432,
                                 test::configs::FixedTree3333, test::configs::FixedTree6542,
                                 test::configs::FixedTree643, DoubleTree543>;
TYPED_TEST_SUITE(Csg, Configs, test::ConfigName);

TYPED_TEST(Csg, UnionIsVoxelwiseMinimumWithTheWinnersState) {
    this->checkInPlace(Op::Union);
}

TYPED_TEST(Csg, IntersectionIsVoxelwiseMaximumWithTheWinnersState) {
    this->checkInPlace(Op::Intersection);
}

TYPED_TEST(Csg, DifferenceIsVoxelwiseMaximumOfANegatedBWithTheWinnersState) {
    this->checkInPlace(Op::Difference);
}

TYPED_TEST(Csg, CopiesEqualTheInPlaceResultAndLeaveTheInputsIntact) {
    using TreeT = typename TestFixture::TreeT;
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        const TreeT a0(this->a), b0(this->b);
        const auto copy = applyCopy(op, this->a, this->b);
        EXPECT_TRUE(identical(this->a, a0)) << opName(op);
        EXPECT_TRUE(identical(this->b, b0)) << opName(op);
        TreeT x(this->a), y(this->b);
        applyInPlace(op, x, y);
        EXPECT_TRUE(identical(*copy, x)) << opName(op);
    }
}

TYPED_TEST(Csg, ThreadedEqualsSingleThreadedBitForBit) {
    using TreeT = typename TestFixture::TreeT;
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        for (bool prune : {false, true}) {
            TreeT x1(this->a), y1(this->b), x2(this->a), y2(this->b);
            applyInPlace(op, x1, y1, prune, /*threaded=*/true);
            applyInPlace(op, x2, y2, prune, /*threaded=*/false);
            EXPECT_TRUE(identical(x1, x2)) << opName(op) << " prune " << prune;
        }
        EXPECT_TRUE(identical(*applyCopy(op, this->a, this->b, true),
                              *applyCopy(op, this->a, this->b, false)))
            << opName(op);
    }
}

TYPED_TEST(Csg, WithoutPruningValuesAndStatesFollowTheSameRule) {
    using TreeT = typename TestFixture::TreeT;
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        TreeT x(this->a), y(this->b);
        applyInPlace(op, x, y, /*prune=*/false);
        typename TreeT::ConstAccessor accA(this->a), accB(this->b), accX(x);
        for (const CoordBBox& box : this->scene.boxes) {
            for (Int32 i = box.min()[0]; i <= box.max()[0]; i += 3)
                for (Int32 j = box.min()[1]; j <= box.max()[1]; j += 2)
                    for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                        const Coord ijk(i, j, k);
                        typename TreeT::ValueType va, vb, vx;
                        const bool sa = accA.probeValue(ijk, va), sb = accB.probeValue(ijk, vb);
                        const bool sx = accX.probeValue(ijk, vx);
                        const auto expected = combine(op, va, sa, vb, sb);
                        ASSERT_EQ(vx, expected.first) << opName(op) << " " << ijk;
                        ASSERT_EQ(sx, expected.second) << opName(op) << " " << ijk;
                    }
        }
    }
}

TYPED_TEST(Csg, GridFormsWorkOnTheTreesAndKeepATransformAndMetadata) {
    using TreeT = typename TestFixture::TreeT;
    using GridT = Grid<TreeT>;
    auto ga = GridT::create(std::make_shared<TreeT>(this->a));
    auto gb = GridT::create(std::make_shared<TreeT>(this->b));
    ga->setName("a");
    ga->setTransform(math::Transform::createLinearTransform(0.25));
    ga->setGridClass(GRID_LEVEL_SET);
    // Grids in different index spaces are refused, by every form, before anything changes.
    EXPECT_THROW(tools::csgDifferenceCopy(*ga, *gb), ValueError);
    EXPECT_THROW(tools::csgUnion(*ga, *gb), ValueError);
    EXPECT_THROW(tools::csgIntersection(*ga, *gb), ValueError);
    EXPECT_TRUE(identical(gb->tree(), this->b));
    // The same voxel size, rounded through float on one side, is one index space.
    gb->setTransform(math::Transform::createLinearTransform(double(0.25f * (1.0f + 1e-7f))));
    auto copy = tools::csgDifferenceCopy(*ga, *gb);
    EXPECT_EQ(copy->getName(), "a");
    EXPECT_EQ(copy->getGridClass(), GRID_LEVEL_SET);
    EXPECT_DOUBLE_EQ(copy->voxelSize()[0], 0.25);
    EXPECT_TRUE(identical(ga->tree(), this->a));
    tools::csgDifference(*ga, *gb);
    EXPECT_TRUE(gb->empty());
    EXPECT_TRUE(identical(ga->tree(), copy->tree()));
    EXPECT_TRUE(resultMatchesRule(Op::Difference, this->a, this->b, ga->tree(), this->scene.boxes));
}

// ---- Analytic: two intersecting spheres

/// The exact signed distance of A op B for two spheres, from the pieces of the two spheres that
/// bound the result: union: A's surface outside B and B's outside A; intersection: each inside
/// the other; difference: A's surface outside B and B's inside A. The distance to a piece is
/// the distance to the sphere when the radial projection lies on the piece, else to the circle
/// where the spheres meet.
struct TwoSpheres {
    Sphere s[2];

    double seamDistance(double px, double py, double pz) const {
        const double ax = s[1].x - s[0].x, ay = s[1].y - s[0].y, az = s[1].z - s[0].z;
        const double d = std::sqrt(ax * ax + ay * ay + az * az);
        const double nx = ax / d, ny = ay / d, nz = az / d;
        const double h = (d * d + s[0].r * s[0].r - s[1].r * s[1].r) / (2 * d);
        const double rc = std::sqrt(s[0].r * s[0].r - h * h);
        const double qx = px - (s[0].x + h * nx), qy = py - (s[0].y + h * ny),
                     qz = pz - (s[0].z + h * nz);
        const double along = qx * nx + qy * ny + qz * nz;
        const double ox = qx - along * nx, oy = qy - along * ny, oz = qz - along * nz;
        const double radial = std::sqrt(ox * ox + oy * oy + oz * oz) - rc;
        return std::sqrt(radial * radial + along * along);
    }
    /// Distance from p to the part of sphere `i` inside (or outside) sphere `1 - i`.
    double pieceDistance(int i, bool insideOther, const Coord& p) const {
        const Sphere& me = s[i];
        const Sphere& other = s[1 - i];
        const double dx = p[0] - me.x, dy = p[1] - me.y, dz = p[2] - me.z;
        const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
        const double qx = me.x + me.r * dx / len, qy = me.y + me.r * dy / len,
                     qz = me.z + me.r * dz / len;
        const double ex = qx - other.x, ey = qy - other.y, ez = qz - other.z;
        const bool projectionInside = std::sqrt(ex * ex + ey * ey + ez * ez) < other.r;
        if (projectionInside == insideOther)
            return std::abs(len - me.r);
        return seamDistance(p[0], p[1], p[2]);
    }
    double exact(Op op, const Coord& p) const {
        const bool inA = s[0].distance(p) < 0, inB = s[1].distance(p) < 0;
        bool inside;
        double dist;
        switch (op) {
            case Op::Union:
                inside = inA || inB;
                dist = std::min(pieceDistance(0, false, p), pieceDistance(1, false, p));
                break;
            case Op::Intersection:
                inside = inA && inB;
                dist = std::min(pieceDistance(0, true, p), pieceDistance(1, true, p));
                break;
            default:
                inside = inA && !inB;
                dist = std::min(pieceDistance(0, false, p), pieceDistance(1, true, p));
                break;
        }
        return inside ? -dist : dist;
    }
};

TEST(CsgAnalytic, TwoIntersectingSpheresGiveTheSignedDistanceOfTheCombinedShape) {
    const TwoSpheres spheres{{{-9.5, 3.25, -2.0, 23.0}, {11.0, -4.0, 6.5, 19.0}}};
    const float bg = 3.0f;
    FloatTree a(bg), b(bg);
    addSpheres(a, {spheres.s[0]}, 8);
    addSpheres(b, {spheres.s[1]}, 8);
    CoordBBox box = spheres.s[0].bbox(8);
    box.expand(spheres.s[1].bbox(8));
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        const auto result = applyCopy(op, a, b);
        FloatTree::ConstAccessor acc(*result);
        Index64 active = 0;
        for (Int32 x = box.min()[0]; x <= box.max()[0]; ++x)
            for (Int32 y = box.min()[1]; y <= box.max()[1]; ++y)
                for (Int32 z = box.min()[2]; z <= box.max()[2]; ++z) {
                    const Coord ijk(x, y, z);
                    const double exact = spheres.exact(op, ijk);
                    float value;
                    const bool on = acc.probeValue(ijk, value);
                    // Min/max of the two distances is exact away from the circle where the
                    // spheres meet. Near it, it is a bound on the exact distance (from above for
                    // a union, from below otherwise) that can be off by part of the band.
                    const bool nearSeam = spheres.seamDistance(x, y, z) < 2.0 * bg;
                    if (on) {
                        ++active;
                        if (!nearSeam) {
                            ASSERT_NEAR(value, exact, 1e-4) << opName(op) << " at " << ijk;
                        } else {
                            const double excess = op == Op::Union ? exact - value : value - exact;
                            ASSERT_LE(excess, 1e-4) << opName(op) << " at " << ijk;
                            ASSERT_LT(std::abs(value - exact), bg) << opName(op) << " at " << ijk;
                        }
                    } else {
                        // Inactive values are the background with the sign of the shape, and
                        // lie outside the band of the exact distance too.
                        ASSERT_EQ(std::abs(value), bg) << opName(op) << " at " << ijk;
                        ASSERT_GT(std::abs(exact), bg - 1e-4) << opName(op) << " at " << ijk;
                        ASSERT_EQ(value < 0, exact < 0) << opName(op) << " at " << ijk;
                    }
                    // Every voxel the exact distance puts in the band is active.
                    if (std::abs(exact) < bg - 1e-4) {
                        ASSERT_TRUE(on) << opName(op) << " at " << ijk << " exact " << exact;
                    }
                }
        EXPECT_GT(active, 0u);
    }
}

// ---- Tiles at the top level, backgrounds, validation

TEST(CsgTiles, RootTilesDecideWholeRegions) {
    using TreeT = tree::HashTree432<float>;  // root children of 512^3 voxels
    const float bg = 2.0f;
    TreeT a(bg), b(bg);
    // a: a whole root region inside (one root tile); b: a sphere inside that region, a sphere
    // in an empty region, and an inside root tile over a's sphere.
    a.fill(CoordBBox::createCube(Coord(-512, 0, 0), 512), -bg, false);
    const Sphere aSphere{700.0, 40.0, 30.0, 12.0};
    addSpheres(a, {aSphere}, 6);
    const Sphere bInside{-300.0, 200.0, 250.0, 14.0}, bOut{-1200.0, 10.0, 10.0, 9.0};
    addSpheres(b, {bInside, bOut}, 6);
    b.fill(CoordBBox::createCube(Coord(512, 0, 0), 512), -bg, false);
    const std::vector<CoordBBox> boxes = {aSphere.bbox(6), bInside.bbox(6), bOut.bbox(6)};
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        TreeT x(a), y(b);
        applyInPlace(op, x, y);
        EXPECT_TRUE(resultMatchesRule(op, a, b, x, boxes));
        for (const Coord& ijk : {Coord(-500, 5, 5), Coord(-3, 511, 511), Coord(600, 300, 400),
                                 Coord(1023, 0, 511), Coord(-1500, 0, 0), Coord(5000, 5, 5)}) {
            float va, vb, vx;
            const bool sa = a.probeValue(ijk, va), sb = b.probeValue(ijk, vb);
            const bool sx = x.probeValue(ijk, vx);
            const auto expected = combine(op, va, sa, vb, sb);
            EXPECT_EQ(vx, expected.first) << opName(op) << " at " << ijk;
            EXPECT_EQ(sx, expected.second) << opName(op) << " at " << ijk;
        }
    }
    // The Copy forms never copy the branches the root tiles decide, and give the same trees.
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        EXPECT_TRUE(copyEqualsInPlace(op, a, b));
        EXPECT_TRUE(copyEqualsInPlace(op, b, a));
    }
    // Union: b's sphere inside a's tile is dropped, a's sphere inside b's tile too; only b's
    // far sphere is left, moved over whole.
    TreeT u(a), v(b);
    tools::csgUnion(u, v);
    Index64 farActive = 0;
    for (auto it = b.cbeginValueOn(); it; ++it)
        farActive += bOut.bbox(6).isInside(it.getCoord()) ? 1 : 0;
    EXPECT_GT(farActive, 0u);
    EXPECT_EQ(u.activeVoxelCount(), farActive);
    EXPECT_EQ(u.probeConstLeaf(Coord(-300, 200, 236)), nullptr);
    EXPECT_EQ(u.probeConstLeaf(Coord(700, 40, 42)), nullptr);
    // Difference: b's sphere moves negated into a's inside tile (a hollow), b's tile frees a's
    // sphere, and b's far sphere is dropped.
    TreeT d(a), e(b);
    tools::csgDifference(d, e);
    EXPECT_EQ(d.probeConstLeaf(Coord(700, 40, 30)), nullptr);
    EXPECT_GT(d.getValue(Coord(-300, 200, 250)), 0.0f);
    EXPECT_LT(d.getValue(Coord(-300, 200, 270)), 0.0f);
    EXPECT_EQ(d.getValue(Coord(-1200, 10, 10)), bg);
}

TEST(CsgTiles, WinningTilesBecomePlusMinusBackgroundAndBackgroundRootTilesGo) {
    const float bg = 3.0f;
    FloatTree a(bg), b(bg);
    const Sphere s{20.0, 20.0, 20.0, 10.0};
    addSpheres(a, {s}, 6);
    // b: an inside tile of -1 over a's sphere (a level-2 tile), an outside root tile of 1.
    b.fill(CoordBBox::createCube(Coord(0), 128), -1.0f, false);
    b.fill(CoordBBox::createCube(Coord(-4096, 0, 0), 4096), 1.0f, false);
    // a: an inside root tile of -2 and an outside root tile of 2.
    a.fill(CoordBBox::createCube(Coord(0, 4096, 0), 4096), -2.0f, false);
    a.fill(CoordBBox::createCube(Coord(0, -4096, 0), 4096), 2.0f, false);
    FloatTree x(a), y(b);
    tools::csgUnion(x, y, /*prune=*/false);
    EXPECT_EQ(x.getValue(Coord(20, 20, 20)), -bg);  // b's tile replaced a's sphere
    EXPECT_EQ(x.probeConstLeaf(Coord(20, 20, 30)), nullptr);
    EXPECT_EQ(x.getValue(Coord(5, 5000, 5)), -bg);  // a's inside root tile, normalised
    EXPECT_EQ(x.getValue(Coord(5, -5, 5)), bg);     // a's outside root tile: dropped
    EXPECT_EQ(x.getValue(Coord(-5, 5, 5)), bg);     // b's outside root tile: dropped
    // Root entries: a's inside root tile and the root child holding b's tile.
    EXPECT_EQ(x.root().entryCount(), 2u);
    for (auto c = x.root().cbegin(); x.root().valid(c); x.root().next(c)) {
        const auto& e = x.root().entry(c);
        EXPECT_TRUE(e.child || e.tile == -bg) << x.root().key(c);
    }
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        EXPECT_TRUE(copyEqualsInPlace(op, a, b));
        EXPECT_TRUE(copyEqualsInPlace(op, b, a));
    }
}

TEST(CsgBackground, MovedBranchesTakeTheBackgroundOfA) {
    FloatTree a(3.0f), b(2.0f);
    const Sphere big{0.0, 0.0, 0.0, 30.0}, small{2.0, 1.0, -1.0, 6.0}, far{200.0, 0.0, 0.0, 7.0};
    addSpheres(a, {big}, 6);
    addSpheres(b, {small, far}, 6);
    // Union: b's far sphere arrives with +-3 instead of +-2 in its inactive voxels.
    {
        FloatTree x(a), y(b);
        tools::csgUnion(x, y);
        EXPECT_EQ(x.background(), 3.0f);
        const auto* leaf = x.probeConstLeaf(Coord(200, 0, 7));
        ASSERT_NE(leaf, nullptr);
        for (auto it = leaf->cbeginValueOff(); it; ++it)
            EXPECT_EQ(std::abs(*it), 3.0f) << it.getCoord();
        EXPECT_EQ(x.getValue(Coord(200, 0, 7)), 0.0f);
        EXPECT_EQ(x.getValue(Coord(200, 0, 8)), 1.0f);
    }
    // Difference: b's small sphere moves negated into a's inside tiles, a hollow: b's inside
    // (-2) becomes +3, b's outside (+2) becomes -3, band values change sign.
    {
        FloatTree x(a), y(b);
        tools::csgDifference(x, y);
        EXPECT_EQ(x.getValue(Coord(2, 1, -1)), 3.0f);
        EXPECT_FALSE(x.isValueOn(Coord(2, 1, -1)));
        EXPECT_EQ(x.getValue(Coord(2, 1, 4)), 1.0f);
        EXPECT_TRUE(x.isValueOn(Coord(2, 1, 4)));
        EXPECT_EQ(x.getValue(Coord(2, 1, 9)), -3.0f);
        EXPECT_FALSE(x.isValueOn(Coord(2, 1, 9)));
    }
    // The Copy forms fix the values of the branches they copy over from b the same way.
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        EXPECT_TRUE(copyEqualsInPlace(op, a, b));
        EXPECT_TRUE(copyEqualsInPlace(op, b, a));
    }
}

/// Every leaf of `x` has the same number of value buffers as the leaf of `y` at its origin,
/// and the same values in the buffers after the first (which identical() compares).
template <typename TreeT>
::testing::AssertionResult sameExtraBuffers(const TreeT& x, const TreeT& y) {
    if (x.leafCount() != y.leafCount())
        return ::testing::AssertionFailure() << "leaf counts differ";
    for (auto it = x.cbeginLeaf(); it; ++it) {
        const auto* other = y.probeConstLeaf(it->origin());
        if (!other || other->bufferCount() != it->bufferCount())
            return ::testing::AssertionFailure() << "buffers of leaf " << it->origin() << " differ";
        for (Index i = 1; i < it->bufferCount(); ++i) {
            const auto bx = it->buffer(i), by = other->buffer(i);
            if (std::memcmp(bx.data(), by.data(), bx.size_bytes()) != 0)
                return ::testing::AssertionFailure()
                       << "buffer " << i << " of leaf " << it->origin() << " differs";
        }
    }
    return ::testing::AssertionSuccess();
}

TEST(CsgTiles, CopiesBuildLeafSizedTilesAndExtraBuffersAsTheInPlaceFormsLeaveThem) {
    // The Copy forms write every leaf and level-1 node of their result themselves: leaf-sized
    // tiles (inside, active, zero and other values) over the other tree's band leaves and
    // tiles, leaves with a second value buffer, and different backgrounds (moved values are
    // fixed in the first buffer only) must come out as the in-place forms leave them.
    FloatTree a(3.0f), b(2.0f);
    addSpheres(a, {{0.0, 0.0, 0.0, 20.0}}, 6);
    addSpheres(b, {{14.0, 3.0, -2.0, 15.0}}, 6);
    struct Tile {
        FloatTree* tree;
        Coord origin;
        float value;
        bool active;
    };
    const Tile tiles[] = {
        {&a, Coord(16, 0, 0), -3.0f, false},   {&a, Coord(16, 8, 0), -3.0f, true},
        {&a, Coord(24, 0, 0), 0.0f, false},    {&a, Coord(24, 8, 0), 1.0f, true},
        {&a, Coord(-24, -8, 0), -1.5f, false}, {&b, Coord(0, 16, 0), -2.0f, false},
        {&b, Coord(8, 16, 0), -2.0f, true},    {&b, Coord(-16, 0, 0), 0.0f, false},
        {&b, Coord(-16, 8, 0), 2.0f, false},   {&b, Coord(0, -24, 0), -0.5f, true},
        {&b, Coord(24, 0, 0), -2.0f, false}};
    for (const Tile& t : tiles) {
        t.tree->fill(CoordBBox::createCube(t.origin, 8), t.value, t.active);
        ASSERT_EQ(t.tree->probeConstLeaf(t.origin), nullptr) << t.origin;
    }
    for (auto [tree, value] : {std::pair{&a, 7.0f}, std::pair{&b, 9.0f}}) {
        for (auto it = tree->beginLeaf(); it; ++it) {
            it->setBufferCount(2);
            const auto second = it->buffer(1);
            std::fill(second.begin(), second.end(), value);
        }
    }
    for (Op op : {Op::Union, Op::Intersection, Op::Difference}) {
        for (const auto& [x, y] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
            EXPECT_TRUE(copyEqualsInPlace(op, *x, *y));
            FloatTree inPlace(*x), emptied(*y);
            applyInPlace(op, inPlace, emptied);
            EXPECT_TRUE(sameExtraBuffers(*applyCopy(op, *x, *y), inPlace)) << opName(op);
        }
    }
}

TEST(CsgValidation, NonPositiveBackgroundsAndAliasesAreRejected) {
    FloatTree a(3.0f), b(-3.0f), c(0.0f), d(1.0f);
    EXPECT_THROW(tools::csgUnion(a, b), ValueError);
    EXPECT_THROW(tools::csgIntersection(c, a), ValueError);
    EXPECT_THROW(tools::csgDifferenceCopy(a, b), ValueError);
    EXPECT_THROW(tools::csgUnion(a, a), ValueError);
    EXPECT_NO_THROW(tools::csgUnion(a, d));
    EXPECT_EQ(a.background(), 3.0f);
}

TEST(CsgValidation, EmptyInputsGiveTheOtherOperandOrNothing) {
    const Sphere s{-3.0, 4.0, 5.0, 15.0};
    FloatTree shape(3.0f);
    addSpheres(shape, {s}, 6);
    const FloatTree empty(3.0f);
    EXPECT_TRUE(identical(*tools::csgUnionCopy(shape, empty), shape));
    EXPECT_TRUE(identical(*tools::csgUnionCopy(empty, shape), shape));
    EXPECT_TRUE(tools::csgIntersectionCopy(shape, empty)->empty());
    EXPECT_TRUE(tools::csgIntersectionCopy(empty, shape)->empty());
    EXPECT_TRUE(identical(*tools::csgDifferenceCopy(shape, empty), shape));
    EXPECT_TRUE(tools::csgDifferenceCopy(empty, shape)->empty());
}

}  // namespace
}  // namespace vdb
