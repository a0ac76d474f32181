// SPDX-License-Identifier: Apache-2.0
// io::File round trips inside the library: every standard grid type through every compression
// setting, half floats, names, instances, maps, metadata, statistics, atomic replacement, and
// hostile input (every truncation and random byte flips of real files).

#include <vdb/Grid.h>
#include <vdb/io/Archive.h>
#include <vdb/io/File.h>

#include <GridContents.h>
#include <Oracles.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;

std::string tempPath(const std::string& name) {
    return test::tempPath("vdb_io_test_", name);
}
using test::fileBytes;

void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

/// The grid's metadata without the statistics a writer adds.
MetaMap userMeta(const GridBase& g) {
    MetaMap m = g;
    for (const char* k : {"file_bbox_min", "file_bbox_max", "file_compression", "file_mem_bytes",
                          "file_voxel_count"})
        m.removeMeta(k);
    return m;
}

/// Checks that `b` holds exactly what `a` held when written with `half`: voxels and internal
/// tiles rounded to half precision, root tiles at full precision.
/// `written` is treeContents(a.tree()), for callers that compare `a` with many files.
template <typename GridT, typename ItemsT>
::testing::AssertionResult sameContents(const GridT& a, const ItemsT& written, const GridT& b,
                                        bool half) {
    using ValueT = typename GridT::ValueType;
    using RootT = typename GridT::TreeType::TopNodeType;
    auto round = [&](const ValueT& v) { return half ? io::detail::roundToHalf(v) : v; };
    if (!test::sameBits(round(a.background()), b.background()))
        return ::testing::AssertionFailure() << "backgrounds differ";
    const auto& ia = written;
    const auto ib = test::treeContents(b.tree());
    if (ia.size() != ib.size())
        return ::testing::AssertionFailure()
               << ia.size() << " values written, " << ib.size() << " read";
    for (size_t i = 0; i < ia.size(); ++i) {
        const auto& x = ia[i];
        const auto& y = ib[i];
        const ValueT expected = x.level == int(RootT::LEVEL) ? x.value : round(x.value);
        if (x.min != y.min || x.max != y.max || x.level != y.level || x.active != y.active ||
            !test::sameBits(expected, y.value)) {
            return ::testing::AssertionFailure()
                   << "item " << i << " at " << x.min << " level " << x.level << " differs";
        }
    }
    return ::testing::AssertionSuccess();
}

template <typename GridT>
::testing::AssertionResult sameContents(const GridT& a, const GridT& b, bool half) {
    return sameContents(a, test::treeContents(a.tree()), b, half);
}

template <typename GridT>
class FileRoundTrip : public ::testing::Test {};

using AllGrids = ::testing::Types<FloatGrid, DoubleGrid, Int32Grid, Int64Grid, BoolGrid, MaskGrid,
                                  Vec3SGrid, Vec3DGrid, Vec3IGrid>;
TYPED_TEST_SUITE(FileRoundTrip, AllGrids);

/// A grid of random values (from `seed`) named `name`, with a string metadata entry.
template <typename GridT>
typename GridT::Ptr namedTestGrid(unsigned seed, const char* name) {
    auto grid = GridT::create(test::randomValue<typename GridT::ValueType>(seed));
    test::fillTestGrid(*grid, seed + 4u);
    grid->setName(name);
    grid->insertMeta("note", std::string("round trip of ") + name);
    return grid;
}

TYPED_TEST(FileRoundTrip, EveryCompressionAndHalfSetting) {
    using GridT = TypeParam;
    auto grid = namedTestGrid<GridT>(7u, "g");
    const std::string path = tempPath("roundtrip_" + grid->valueType() + ".vdb");
    const auto written = test::treeContents(grid->tree());
    for (uint32_t flags : {io::COMPRESS_NONE, io::COMPRESS_ACTIVE_MASK, io::COMPRESS_ZIP,
                           io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK, io::COMPRESS_BLOSC,
                           io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK}) {
        for (bool half : {false, true}) {
            SCOPED_TRACE("flags " + std::to_string(flags) + (half ? " half" : ""));
            grid->setSaveFloatAsHalf(half);
            io::File out(path);
            out.setCompression(flags);
            out.write({grid});
            io::File in(path);
            in.open();
            EXPECT_EQ(in.fileVersion(), 224u);
            auto read = gridPtrCast<GridT>(in.readGrid("g"));
            ASSERT_TRUE(read);
            EXPECT_TRUE(sameContents(*grid, written, *read, half));
            EXPECT_EQ(userMeta(*read), userMeta(*grid));
            EXPECT_EQ(read->template metaValue<std::string>("file_compression"),
                      io::compressionToString(flags));
            EXPECT_EQ(read->template metaValue<Int64>("file_voxel_count"),
                      Int64(grid->activeVoxelCount()));
        }
    }
}

TYPED_TEST(FileRoundTrip, StreamsCarryTheBytesFilesDo) {
    using GridT = TypeParam;
    auto grid = namedTestGrid<GridT>(9u, "s");
    grid->setTransform(math::Transform::createLinearTransform(0.25));
    auto twin = grid->copyGrid();  // shares the tree: written as an instance
    twin->setName("twin");
    MetaMap fileMeta;
    fileMeta.insertMeta("creator", std::string("stream test"));
    const auto written = test::treeContents(grid->tree());
    for (uint32_t flags : {io::COMPRESS_NONE, io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK,
                           io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK}) {
        SCOPED_TRACE("flags " + std::to_string(flags));
        std::ostringstream os;
        io::Stream out(os);
        out.setCompression(flags);
        out.write(GridPtrVec{grid, twin}, fileMeta);
        const std::string bytes = os.str();

        std::istringstream is(bytes);
        io::Stream in(is);
        EXPECT_EQ(in.getMetadata(), fileMeta);
        auto grids = in.getGrids();
        ASSERT_EQ(grids->size(), 2u);
        for (const auto& g : *grids) {
            auto read = gridPtrCast<GridT>(g);
            ASSERT_TRUE(read);
            EXPECT_TRUE(sameContents(*grid, written, *read, false));
            EXPECT_EQ(read->transform(), grid->transform());
        }
        EXPECT_EQ(userMeta(*grids->at(0)), userMeta(*grid));

        // The same bytes are a file that File reads.
        const std::string path = tempPath("stream_" + grid->valueType() + ".vdb");
        writeBytes(path, std::vector<uint8_t>(bytes.begin(), bytes.end()));
        io::File file(path);
        file.open();
        auto fromFile = gridPtrCast<GridT>(file.readGrid("s"));
        ASSERT_TRUE(fromFile);
        EXPECT_TRUE(sameContents(*grid, written, *fromFile, false));
    }
}

TEST(Stream, RefusesDamageAndTheWrongDirection) {
    auto grid = FloatGrid::create(1.0f);
    test::fillTestGrid(*grid, 3);
    std::ostringstream os;
    io::Stream(os).write({grid});
    const std::string bytes = os.str();
    // Every cut of the archive is an IoError, never a crash.
    const size_t step = std::max<size_t>(1, bytes.size() / 300);
    for (size_t n = 0; n < bytes.size(); n += (n < 256 ? 1 : step)) {
        std::istringstream is(bytes.substr(0, n));
        EXPECT_THROW(
            {
                io::Stream in(is);
                in.getGrids();
            },
            IoError)
            << "cut at " << n;
    }
    std::istringstream is(bytes);
    io::Stream reader(is);
    EXPECT_THROW(reader.write({grid}), IoError);
    std::ostringstream sink;
    io::Stream writer(sink);
    EXPECT_THROW(writer.getGrids(), IoError);
    EXPECT_THROW(writer.getMetadata(), IoError);
}

TEST(File, LevelSetsAndFogVolumesDropZip) {
    auto grid = FloatGrid::create(3.0f);
    grid->tree().setValueOn(Coord(1, 2, 3), 1.0f);
    grid->setGridClass(GRID_LEVEL_SET);
    const std::string path = tempPath("levelset_zip.vdb");
    io::File out(path);
    out.setCompression(io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK);
    out.write({grid});
    io::File in(path);
    in.open();
    auto g = in.getGrids()->at(0);
    EXPECT_EQ(g->metaValue<std::string>("file_compression"), "active values");
    EXPECT_EQ(g->getGridClass(), GRID_LEVEL_SET);
}

TEST(File, DuplicateAndEmptyNamesGetUniqueSuffixes) {
    GridPtrVec grids;
    for (const char* name : {"dup", "dup", "", "other"}) {
        auto g = FloatGrid::create(float(grids.size()));
        g->tree().setValueOn(Coord(Int32(grids.size()), 0, 0), 1.0f);
        if (*name)
            g->setName(name);
        grids.push_back(g);
    }
    const std::string path = tempPath("names.vdb");
    io::File(path).write(grids);
    io::File in(path);
    in.open();
    EXPECT_EQ(in.getGridNames(), (std::vector<std::string>{"dup[0]", "dup[1]", "[0]", "other"}));
    // A display name finds its first grid; the printed unique name finds each.
    EXPECT_EQ(gridPtrCast<FloatGrid>(in.readGrid("dup"))->background(), 0.0f);
    EXPECT_EQ(gridPtrCast<FloatGrid>(in.readGrid("dup[1]"))->background(), 1.0f);
    EXPECT_EQ(gridPtrCast<FloatGrid>(in.readGrid("[0]"))->background(), 2.0f);
    EXPECT_FALSE(in.readGrid("[0]")->hasMeta("name"));
    // getGrids() sorts by name, as OpenVDB does.
    std::vector<float> order;
    const auto all = in.getGrids();
    for (const auto& g : *all)
        order.push_back(gridPtrCast<FloatGrid>(g)->background());
    EXPECT_EQ(order, (std::vector<float>{2, 0, 1, 3}));
    EXPECT_THROW(in.readGrid("missing"), IoError);
}

TEST(File, GridsSharingATreeAreWrittenOnceAsInstances) {
    auto a = FloatGrid::create(0.0f);
    test::fillTestGrid(*a, 3);
    a->setName("a");
    auto b = a->copy();  // shares the tree
    b->setName("b");
    b->setTransform(math::Transform::createLinearTransform(0.5));
    const std::string single = tempPath("single.vdb"), both = tempPath("instanced.vdb");
    io::File(single).write({a});
    io::File(both).write({a, b});
    EXPECT_LT(fs::file_size(both), fs::file_size(single) + 1024);
    io::File in(both);
    in.open();
    auto grids = in.getGrids();
    ASSERT_EQ(grids->size(), 2u);
    auto ra = gridPtrCast<FloatGrid>(grids->at(0));
    auto rb = gridPtrCast<FloatGrid>(grids->at(1));
    EXPECT_EQ(ra->treePtr(), rb->treePtr());  // shared again after reading
    EXPECT_TRUE(sameContents(*a, *rb, false));
    EXPECT_EQ(rb->voxelSize(), Vec3d(0.5));
    // Reading the instance alone loads its parent's tree.
    auto alone = gridPtrCast<FloatGrid>(in.readGrid("b"));
    EXPECT_TRUE(sameContents(*a, *alone, false));
}

TEST(File, EveryMapTypeRoundTrips) {
    std::vector<math::MapParams> maps(8);
    maps[0].type = math::MapType::UniformScale;
    maps[0].scale = Vec3d(0.25);
    maps[1].type = math::MapType::UniformScaleTranslate;
    maps[1].scale = Vec3d(2.0);
    maps[1].translation = Vec3d(1, -2, 3);
    maps[2].type = math::MapType::Scale;
    maps[2].scale = Vec3d(1, 2, 3);
    maps[3].type = math::MapType::ScaleTranslate;
    maps[3].scale = Vec3d(0.5, 0.25, 4);
    maps[3].translation = Vec3d(-7, 8, 9);
    maps[4].type = math::MapType::Translation;
    maps[4].translation = Vec3d(5, 6, 7);
    maps[5].type = math::MapType::Affine;
    maps[5].matrix = Mat4d(0.8, 0.6, 0, 0, -0.6, 0.8, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1);
    maps[6].type = math::MapType::Unitary;
    maps[6].matrix = Mat4d(0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1);
    maps[7].type = math::MapType::NonlinearFrustum;
    maps[7].frustumBBox = BBoxd(Vec3d(0, 0, 0), Vec3d(99, 99, 49));
    maps[7].frustumTaper = 0.5;
    maps[7].frustumDepth = 2.0;
    maps[7].matrix = Mat4d(2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 1, 1, 1);
    GridPtrVec grids;
    for (size_t i = 0; i < maps.size(); ++i) {
        auto g = FloatGrid::create(0.0f);
        g->setName("map" + std::to_string(i));
        g->setTransform(math::Transform::createFromMap(maps[i]));
        grids.push_back(g);
    }
    const std::string path = tempPath("maps.vdb");
    io::File(path).write(grids);
    io::File in(path);
    in.open();
    for (size_t i = 0; i < maps.size(); ++i) {
        auto g = in.readGridMetadata("map" + std::to_string(i));
        const math::MapParams p = g->transform().mapParams();
        const math::MapParams q = grids[i]->transform().mapParams();
        EXPECT_EQ(p.type, q.type) << i;
        EXPECT_EQ(p.scale, q.scale) << i;
        EXPECT_EQ(p.translation, q.translation) << i;
        EXPECT_EQ(p.matrix, q.matrix) << i;
        EXPECT_EQ(p.frustumTaper, q.frustumTaper) << i;
        EXPECT_EQ(p.frustumDepth, q.frustumDepth) << i;
    }
}

TEST(File, MetadataOfEveryTypeRoundTrips) {
    MetaMap fileMeta;
    fileMeta.insertMeta("creator", std::string("vdb tests"));
    fileMeta.insertMeta("b", true);
    fileMeta.insertMeta("i32", Int32(-2));
    fileMeta.insertMeta("i64", Int64(1) << 40);
    fileMeta.insertMeta("f", 1.5f);
    fileMeta.insertMeta("d", -2.25);
    fileMeta.insertMeta("v3i", Vec3i(1, -2, 3));
    fileMeta.insertMeta("v3s", Vec3s(0.5f, 1.5f, -2.5f));
    fileMeta.insertMeta("v3d", Vec3d(1e-300, 2, 3));
    fileMeta.insertMeta("m4d", OpaqueMetadata{"mat4d", std::vector<uint8_t>(128, 7)});
    fileMeta.insertMeta("future", OpaqueMetadata{"someFutureType", {1, 2, 3}});
    auto g = FloatGrid::create(1.0f);
    for (const auto& [name, value] : fileMeta.metadata())
        g->insertMeta(name, value);
    const std::string path = tempPath("meta.vdb");
    io::File(path).write({g}, fileMeta);
    io::File in(path);
    in.open();
    EXPECT_EQ(in.getMetadata(), fileMeta);
    EXPECT_EQ(userMeta(*in.getGrids()->at(0)), userMeta(*g));
}

TEST(File, StatisticsOfAnEmptyGridFollowOpenVdb) {
    auto g = FloatGrid::create(1.0f);
    g->setName("empty");
    const std::string path = tempPath("empty.vdb");
    io::File(path).write({g});
    io::File in(path);
    in.open();
    auto r = in.readGrid("empty");
    EXPECT_TRUE(r->empty());
    EXPECT_EQ(r->metaValue<Vec3i>("file_bbox_min"), Vec3i(std::numeric_limits<Int32>::max()));
    EXPECT_EQ(r->metaValue<Vec3i>("file_bbox_max"), Vec3i(std::numeric_limits<Int32>::min()));
    EXPECT_EQ(r->metaValue<Int64>("file_voxel_count"), 0);

    io::File quiet(path);
    quiet.setGridStatsMetadataEnabled(false);
    quiet.write({g});
    io::File again(path);
    again.open();
    EXPECT_FALSE(again.readGrid("empty")->hasMeta("file_bbox_min"));
}

TEST(File, TreesOfRegisteredNodeDimensionsRoundTrip) {
    using Grid432 = Grid<tree::HashTree432<float>>;
    io::registerGridType<Grid432>();
    auto g = Grid432::create(-1.0f);
    test::fillTestGrid(*g, 5);
    g->setName("small nodes");
    const std::string path = tempPath("432.vdb");
    io::File(path).write({g});
    io::File in(path);
    in.open();
    auto r = gridPtrCast<Grid432>(in.readGrid("small nodes"));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->type(), "Tree_float_4_3_2");
    EXPECT_TRUE(sameContents(*g, *r, false));
}

TEST(File, WritingReplacesTheFileAtomically) {
    const std::string path = tempPath("atomic.vdb");
    writeBytes(path, {'o', 'l', 'd'});
    using UnregisteredGrid = Grid<tree::MapTree543<float>>;
    auto bad = UnregisteredGrid::create(0.0f);
    EXPECT_THROW(io::File(path).write({bad}), TypeError);
    EXPECT_EQ(fileBytes(path), (std::vector<uint8_t>{'o', 'l', 'd'}));  // untouched
    EXPECT_THROW(io::File(tempPath("no/such/dir/x.vdb")).write({FloatGrid::create()}), IoError);
    io::File(path).write({FloatGrid::create()});
    io::File in(path);
    EXPECT_NO_THROW(in.open());
    for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path()))
        EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST(File, MissingAndForeignFilesGiveClearErrors) {
    io::File missing(tempPath("does-not-exist.vdb"));
    try {
        missing.open();
        FAIL() << "opened a missing file";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("does-not-exist.vdb"), std::string::npos);
    }
    const std::string text = tempPath("text.vdb");
    writeBytes(text, {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'});
    EXPECT_THROW(io::File(text).open(), IoError);
    const std::string empty = tempPath("zero.vdb");
    writeBytes(empty, {});
    EXPECT_THROW(io::File(empty).open(), IoError);
}

/// Opens `path` and reads every grid; IoError is the only failure allowed.
bool readsCleanly(const std::string& path) {
    try {
        io::File in(path);
        in.open();
        const auto grids = in.getGrids();
        for (const auto& g : *grids)
            (void)g->activeVoxelCount();
        return true;
    } catch (const IoError&) {
        return false;
    }
}

/// A small file with two grids (one half-float vector grid, one float grid with tiles) in the
/// given compression.
std::vector<uint8_t> smallFile(uint32_t flags) {
    auto a = FloatGrid::create(0.5f);
    test::fillTestGrid(*a, 21);
    a->setName("a");
    auto v = Vec3SGrid::create(Vec3s(0.0f));
    v->tree().setValueOn(Coord(1, 2, 3), Vec3s(1, 2, 3));
    v->tree().setValueOn(Coord(-100, 2, 3), Vec3s(4, 5, 6));
    v->setSaveFloatAsHalf(true);
    const std::string path = tempPath("small.vdb");
    io::File out(path);
    out.setCompression(flags);
    out.write({a, v});
    return fileBytes(path);
}

TEST(FileCorruption, EveryTruncationFailsCleanly) {
    for (uint32_t flags : {io::COMPRESS_ACTIVE_MASK, io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK,
                           io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK}) {
        const auto bytes = smallFile(flags);
        const std::string path = tempPath("truncated.vdb");
        // Every cut in the header, file metadata and first descriptor, then about 400 cuts
        // spread over the rest: each must be reported, since every grid's bytes are needed.
        const size_t step =
            std::max<size_t>(1, size_t(double(bytes.size()) / 400.0 / test::workloadScale()));
        for (size_t n = 0; n < bytes.size(); n += (n < 512 ? 1 : step)) {
            writeBytes(path, std::vector<uint8_t>(bytes.begin(), bytes.begin() + long(n)));
            EXPECT_FALSE(readsCleanly(path)) << "a file cut at " << n << " of " << bytes.size()
                                             << " bytes was read without an error";
        }
    }
}

TEST(FileCorruption, RandomByteFlipsNeverCrash) {
    // The format has no checksums: a flipped value byte reads as another value. What must
    // hold is that every flip either reads or raises IoError, never crashes or hangs.
    std::mt19937 rng(99);
    for (uint32_t flags : {io::COMPRESS_ACTIVE_MASK, io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK,
                           io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK}) {
        const auto bytes = smallFile(flags);
        const std::string path = tempPath("flipped.vdb");
        const int rounds = test::scaledBatchCount(600);
        int failures = 0;
        for (int i = 0; i < rounds; ++i) {
            auto copy = bytes;
            const int flips = 1 + int(rng() % 4);
            for (int f = 0; f < flips; ++f)
                copy[rng() % copy.size()] ^= uint8_t(1u << (rng() % 8));
            writeBytes(path, copy);
            failures += readsCleanly(path) ? 0 : 1;
        }
        EXPECT_GT(failures, 0);  // the checks do notice damage
    }
}

}  // namespace
}  // namespace vdb
