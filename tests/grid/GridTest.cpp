// SPDX-License-Identifier: Apache-2.0
// Oracles: values written through one handle and read back through another; deep copies
// checked for independence by mutating one side; type strings checked against the `.vdb`
// format's names.

#include <vdb/Grid.h>
#include <vdb/Metadata.h>

#include <gtest/gtest.h>

#include <string>

namespace vdb {
namespace {

TEST(Grid, CreateGivesEmptyTreeWithBackgroundAndUnitTransform) {
    FloatGrid::Ptr grid = FloatGrid::create(2.5f);
    EXPECT_TRUE(grid->empty());
    EXPECT_EQ(grid->background(), 2.5f);
    EXPECT_EQ(grid->tree().getValue(Coord(7, -3, 100)), 2.5f);
    EXPECT_EQ(grid->voxelSize(), Vec3d(1.0));
    EXPECT_EQ(grid->getGridClass(), GRID_UNKNOWN);
    EXPECT_EQ(grid->getName(), "");
}

TEST(Grid, TypeStringsMatchTheFileFormat) {
    EXPECT_EQ(FloatGrid::gridType(), "Tree_float_5_4_3");
    EXPECT_EQ(DoubleGrid::gridType(), "Tree_double_5_4_3");
    EXPECT_EQ(Int32Grid::gridType(), "Tree_int32_5_4_3");
    EXPECT_EQ(Int64Grid::gridType(), "Tree_int64_5_4_3");
    EXPECT_EQ(BoolGrid::gridType(), "Tree_bool_5_4_3");
    EXPECT_EQ(MaskGrid::gridType(), "Tree_mask_5_4_3");
    EXPECT_EQ(Vec3SGrid::gridType(), "Tree_vec3s_5_4_3");
    EXPECT_EQ(Vec3DGrid::gridType(), "Tree_vec3d_5_4_3");
    EXPECT_EQ(Vec3IGrid::gridType(), "Tree_vec3i_5_4_3");
    EXPECT_EQ(treeTypeName<tree::HashTree432<float>>(), "Tree_float_4_3_2");
    EXPECT_EQ(treeTypeName<tree::FixedTree6543<float>>(), "FixedTree_float_6_5_4_3");
    EXPECT_EQ(Vec3SGrid::create()->valueType(), "vec3s");
}

TEST(Grid, NameClassAndHalfFlagLiveInMetadata) {
    FloatGrid::Ptr grid = FloatGrid::create();
    grid->setName("density");
    grid->setGridClass(GRID_LEVEL_SET);
    grid->setSaveFloatAsHalf(true);
    EXPECT_EQ(grid->getName(), "density");
    EXPECT_EQ(grid->metaValue<std::string>("name"), "density");
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
    EXPECT_EQ(grid->metaValue<std::string>("class"), "level set");
    EXPECT_TRUE(grid->saveFloatAsHalf());
    EXPECT_TRUE(grid->metaValue<bool>("is_saved_as_half_float"));
    grid->setGridClass(GRID_FOG_VOLUME);
    EXPECT_EQ(grid->getGridClass(), GRID_FOG_VOLUME);
    EXPECT_EQ(stringToGridClass("staggered"), GRID_STAGGERED);
    EXPECT_EQ(stringToGridClass("nonsense"), GRID_UNKNOWN);
}

TEST(Metadata, EveryTypedValueRoundTripsWithItsFileTypeName) {
    MetaMap meta;
    meta.insertMeta("s", "text");
    meta.insertMeta("b", true);
    meta.insertMeta("i", Int32(-7));
    meta.insertMeta("l", Int64(1) << 40);
    meta.insertMeta("f", 1.5f);
    meta.insertMeta("d", 2.25);
    meta.insertMeta("v3i", Vec3i(1, -2, 3));
    meta.insertMeta("v3s", Vec3s(0.5f, 1.5f, -2.5f));
    meta.insertMeta("v3d", Vec3d(1e-9, 2.0, 3.0));
    meta.insertMeta("odd", OpaqueMetadata{"mat4d", {1, 2, 3}});
    EXPECT_EQ(meta.metaCount(), 10u);
    EXPECT_EQ(meta.metaValue<std::string>("s"), "text");
    EXPECT_EQ(meta.metaValue<bool>("b"), true);
    EXPECT_EQ(meta.metaValue<Int32>("i"), -7);
    EXPECT_EQ(meta.metaValue<Int64>("l"), Int64(1) << 40);
    EXPECT_EQ(meta.metaValue<float>("f"), 1.5f);
    EXPECT_EQ(meta.metaValue<double>("d"), 2.25);
    EXPECT_EQ(meta.metaValue<Vec3i>("v3i"), Vec3i(1, -2, 3));
    EXPECT_EQ(meta.metaValue<Vec3s>("v3s"), Vec3s(0.5f, 1.5f, -2.5f));
    EXPECT_EQ(meta.metaValue<Vec3d>("v3d"), Vec3d(1e-9, 2.0, 3.0));
    EXPECT_EQ(meta.metaValue<OpaqueMetadata>("odd").bytes, (std::vector<uint8_t>{1, 2, 3}));
    const char* expected[][2] = {
        {"s", "string"}, {"b", "bool"},    {"i", "int32"},   {"l", "int64"},   {"f", "float"},
        {"d", "double"}, {"v3i", "vec3i"}, {"v3s", "vec3s"}, {"v3d", "vec3d"}, {"odd", "mat4d"}};
    for (const auto& [name, type] : expected) {
        EXPECT_EQ(metaTypeName(*meta.findMeta(name)), type) << name;
    }
    // Entries are ordered by name, the order files store them in.
    std::string previous;
    for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it) {
        EXPECT_LT(previous, it->first);
        previous = it->first;
    }
}

TEST(Metadata, WrongTypeAndMissingNameThrowTypedErrors) {
    MetaMap meta;
    meta.insertMeta("f", 1.0f);
    EXPECT_THROW(meta.metaValue<double>("f"), TypeError);
    EXPECT_THROW(meta.metaValue<float>("absent"), ValueError);
    EXPECT_EQ(meta.getMeta<double>("f"), nullptr);
    EXPECT_NE(meta.getMeta<float>("f"), nullptr);
    meta.insertMeta("f", 2.0);  // replacing changes the type
    EXPECT_EQ(meta.metaValue<double>("f"), 2.0);
    meta.removeMeta("f");
    EXPECT_FALSE(meta.hasMeta("f"));
}

TEST(Grid, DeepCopyIsIndependentOfTheOriginal) {
    FloatGrid::Ptr grid = FloatGrid::create(1.0f);
    grid->setName("a");
    grid->setTransform(math::Transform::createLinearTransform(0.25));
    grid->tree().setValue(Coord(1, 2, 3), 5.0f);
    FloatGrid::Ptr copy = grid->deepCopy();
    copy->tree().setValue(Coord(1, 2, 3), 6.0f);
    copy->tree().setValue(Coord(-100, 0, 0), 7.0f);
    copy->setName("b");
    copy->transform().postTranslate(Vec3d(1, 0, 0));
    EXPECT_EQ(grid->tree().getValue(Coord(1, 2, 3)), 5.0f);
    EXPECT_EQ(grid->activeVoxelCount(), 1u);
    EXPECT_EQ(copy->activeVoxelCount(), 2u);
    EXPECT_EQ(grid->getName(), "a");
    EXPECT_EQ(grid->indexToWorld(Vec3d(0)), Vec3d(0));
    EXPECT_EQ(copy->indexToWorld(Vec3d(0)), Vec3d(1, 0, 0));
    EXPECT_EQ(copy->voxelSize(), Vec3d(0.25));
}

TEST(Grid, ShallowCopySharesTheTree) {
    FloatGrid::Ptr grid = FloatGrid::create();
    FloatGrid::Ptr instance = grid->copy();
    instance->tree().setValue(Coord(0), 3.0f);
    EXPECT_EQ(grid->tree().getValue(Coord(0)), 3.0f);
    EXPECT_EQ(grid->treePtr(), instance->treePtr());
}

TEST(Grid, PtrCastRecoversTheTypeOrGivesNull) {
    GridPtrVec grids{FloatGrid::create(), Vec3SGrid::create(), MaskGrid::create()};
    EXPECT_NE(gridPtrCast<FloatGrid>(grids[0]), nullptr);
    EXPECT_EQ(gridPtrCast<DoubleGrid>(grids[0]), nullptr);
    EXPECT_NE(gridPtrCast<Vec3SGrid>(grids[1]), nullptr);
    EXPECT_NE(gridPtrCast<MaskGrid>(grids[2]), nullptr);
    EXPECT_EQ(grids[2]->type(), "Tree_mask_5_4_3");
}

TEST(Grid, AccessorsAndIteratorsForwardToTheTree) {
    Int32Grid::Ptr grid = Int32Grid::create(-1);
    auto acc = grid->getAccessor();
    for (int i = 0; i < 100; ++i)
        acc.setValue(Coord(i, -i, 2 * i), i);
    const Int32Grid& cgrid = *grid;
    auto cacc = cgrid.getConstAccessor();
    Int64 sum = 0;
    Index64 n = 0;
    for (auto it = cgrid.cbeginValueOn(); it; ++it, ++n) {
        sum += *it;
        EXPECT_EQ(cacc.getValue(it.getCoord()), *it);
    }
    EXPECT_EQ(n, 100u);
    EXPECT_EQ(sum, 99 * 100 / 2);
    EXPECT_EQ(grid->evalActiveVoxelBoundingBox(), CoordBBox(Coord(0, -99, 0), Coord(99, 0, 198)));
    EXPECT_GT(grid->memUsage(), grid->tree().memUsage());
    grid->clear();
    EXPECT_TRUE(grid->empty());
}

TEST(Grid, NullTreeOrTransformIsRejected) {
    EXPECT_THROW(FloatGrid::create(FloatGrid::TreePtr()), ValueError);
    FloatGrid::Ptr grid = FloatGrid::create();
    EXPECT_THROW(grid->setTransform(nullptr), ValueError);
    EXPECT_THROW(grid->setTree(nullptr), ValueError);
}

}  // namespace
}  // namespace vdb
