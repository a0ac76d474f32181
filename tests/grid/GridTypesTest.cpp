// SPDX-License-Identifier: Apache-2.0
// The lists of grid types and dispatchGrid() of GridTypes.h. Oracles: the nine tree type strings of
// the `.vdb` format written out by hand, the object handed over compared by address with the
// grid dispatched, and a grid type outside the lists (a [4,3,2] tree) that must throw.

#include <vdb/GridTypes.h>

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <typeinfo>
#include <vector>

namespace vdb {
namespace {

/// The standard grids as the file format names them, in OpenVDB's registration order of
/// value types.
const std::vector<std::string> STANDARD_TYPES = {
    "Tree_float_5_4_3", "Tree_double_5_4_3", "Tree_int32_5_4_3",
    "Tree_int64_5_4_3", "Tree_bool_5_4_3",   "Tree_mask_5_4_3",
    "Tree_vec3s_5_4_3", "Tree_vec3d_5_4_3",  "Tree_vec3i_5_4_3"};

/// One grid of each type of `ListT`.
template <typename ListT>
std::vector<GridBase::Ptr> oneGridOfEach() {
    std::vector<GridBase::Ptr> grids;
    ListT::forEach([&]<typename GridT>() { grids.push_back(GridT::create()); });
    return grids;
}

TEST(GridTypes, ListTheNineStandardGridsOnce) {
    static_assert(GridTypes::Size == 9);
    static_assert(GridTypes::Contains<FloatGrid> && GridTypes::Contains<Vec3IGrid> &&
                  GridTypes::Contains<MaskGrid>);
    using OddGrid = Grid<tree::HashTree432<float>>;
    static_assert(!GridTypes::Contains<OddGrid>);
    std::vector<std::string> types;
    for (const auto& g : oneGridOfEach<GridTypes>())
        types.push_back(g->type());
    EXPECT_EQ(types, STANDARD_TYPES);
    EXPECT_EQ(gridTypeNames<GridTypes>(),
              "float, double, int32, int64, bool, mask, vec3s, vec3d, vec3i");
}

TEST(GridTypes, SubsetsHoldTheirValueTypes) {
    EXPECT_EQ(gridTypeNames<RealGridTypes>(), "float, double");
    EXPECT_EQ(gridTypeNames<IntegerGridTypes>(), "int32, int64");
    EXPECT_EQ(gridTypeNames<NumericGridTypes>(), "float, double, int32, int64");
    EXPECT_EQ(gridTypeNames<Vec3GridTypes>(), "vec3i, vec3s, vec3d");
    EXPECT_EQ(gridTypeNames<FloatingPointGridTypes>(), "float, double, vec3s, vec3d");
    using NotBoolOrMask = GridTypes::Remove<BoolGrid, MaskGrid>;
    EXPECT_EQ(gridTypeNames<NotBoolOrMask>(), "float, double, int32, int64, vec3s, vec3d, vec3i");
    // Every subset lies in GridTypes.
    FloatingPointGridTypes::forEach(
        [&]<typename GridT>() { EXPECT_TRUE(GridTypes::Contains<GridT>); });
    NumericGridTypes::Append<Vec3GridTypes>::forEach(
        [&]<typename GridT>() { EXPECT_TRUE(GridTypes::Contains<GridT>); });
}

TEST(GridTypes, DispatchHandsOverTheGridAsItsOwnType) {
    for (const auto& base : oneGridOfEach<GridTypes>()) {
        base->setName("g");
        int calls = 0;
        dispatchGrid(*base, [&](auto& g) {
            using GridT = std::remove_reference_t<decltype(g)>;
            static_assert(!std::is_const_v<GridT>);
            ++calls;
            EXPECT_EQ(static_cast<GridBase*>(&g), base.get());
            const GridBase& ref = *base;
            EXPECT_TRUE(typeid(GridT) == typeid(ref));
            EXPECT_EQ(GridT::gridType(), base->type());
            // A mutation through the typed grid shows through the handle.
            g.tree().setValueOn(Coord(1, 2, 3));
        });
        EXPECT_EQ(calls, 1) << base->type();
        EXPECT_EQ(base->activeVoxelCount(), 1u) << base->type();
    }
}

TEST(GridTypes, DispatchOfAConstGridHandsOverAConstGrid) {
    std::vector<std::string> reached;
    for (const auto& grid : oneGridOfEach<GridTypes>()) {
        const GridBase& base = *grid;
        dispatchGrid(base, [&](auto& g) {
            using GridT = std::remove_reference_t<decltype(g)>;
            static_assert(std::is_const_v<GridT>);
            EXPECT_EQ(static_cast<const GridBase*>(&g), &base);
            reached.push_back(g.type());
        });
    }
    EXPECT_EQ(reached, STANDARD_TYPES);
}

TEST(GridTypes, DispatchReturnsTheResultOfTheCall) {
    const FloatGrid::Ptr f = FloatGrid::create(2.5f);
    const DoubleGrid::Ptr d = DoubleGrid::create(-4.0);
    const auto background = [](const auto& g) { return double(g.background()); };
    EXPECT_EQ(dispatchGrid<RealGridTypes>(static_cast<const GridBase&>(*f), background), 2.5);
    EXPECT_EQ(dispatchGrid<RealGridTypes>(static_cast<GridBase&>(*d), background), -4.0);
}

TEST(GridTypes, AGridOutsideTheListThrowsATypeErrorNamingIt) {
    using OddGrid = Grid<tree::HashTree432<float>>;
    const OddGrid::Ptr odd = OddGrid::create();
    odd->setName("odd");
    bool called = false;
    try {
        dispatchGrid(*odd, [&](auto&) { called = true; });
        FAIL() << "no TypeError";
    } catch (const TypeError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("\"odd\""), std::string::npos) << msg;
        EXPECT_NE(msg.find("Tree_float_4_3_2"), std::string::npos) << msg;
        EXPECT_NE(msg.find("vec3i"), std::string::npos) << msg;
    }
    EXPECT_FALSE(called);
    EXPECT_FALSE(tryDispatchGrid<GridTypes>(*odd, [&](auto&) { called = true; }));
    EXPECT_FALSE(called);
    EXPECT_FALSE(gridIsOneOf<GridTypes>(*odd));
}

TEST(GridTypes, ASubsetRejectsTheOtherStandardTypes) {
    const Int32Grid::Ptr ints = Int32Grid::create();
    ints->setName("count");
    try {
        dispatchGrid<RealGridTypes>(*ints, [](auto&) {});
        FAIL() << "no TypeError";
    } catch (const TypeError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "grid \"count\" has type Tree_int32_5_4_3, which is not one of the grid types "
                  "float, double");
    }
    size_t accepted = 0;
    for (const auto& g : oneGridOfEach<GridTypes>()) {
        const bool real = g->type() == "Tree_float_5_4_3" || g->type() == "Tree_double_5_4_3";
        EXPECT_EQ(gridIsOneOf<RealGridTypes>(*g), real) << g->type();
        EXPECT_TRUE(gridIsOneOf<GridTypes>(*g)) << g->type();
        accepted += gridIsOneOf<FloatingPointGridTypes>(*g);
    }
    EXPECT_EQ(accepted, 4u);
}

}  // namespace
}  // namespace vdb
