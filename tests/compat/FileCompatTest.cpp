// SPDX-License-Identifier: Apache-2.0
// `.vdb` compatibility with OpenVDB 10, both ways: files OpenVDB writes read here with the same
// voxels, tiles, states, values, transform and metadata; files written here read in OpenVDB
// the same way; and without ZIP or Blosc both libraries write the same bytes (apart from the
// random UUID and `file_mem_bytes`). Real-world files (a sample folder kept out of the
// repository for licence reasons: CMake's VDB_SAMPLES_DIR, by default
// <repo>/../shared/vdb-samples) read here exactly as OpenVDB reads them.

#include <vdb/Grid.h>
#include <vdb/io/File.h>

#include "OpenVdbConvert.h"
#include <GridContents.h>
#include <Oracles.h>
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace vdb {
namespace {

std::string tempPath(const std::string& name) {
    return test::tempPath("vdb_compat_io_", name);
}
using test::fileBytes;

/// The same value in the other library (identical memory layout).
template <typename To, typename From>
To sameBitsAs(const From& v) {
    static_assert(sizeof(To) == sizeof(From));
    if constexpr (std::is_same_v<To, bool>) {
        return bool(v);
    } else {
        To out;
        std::memcpy(static_cast<void*>(&out), &v, sizeof(To));
        return out;
    }
}

/// The same contents as an OpenVDB grid: every voxel and tile, added at its level; same name,
/// uniform voxel size.
template <typename TheirGrid, typename OurGrid>
typename TheirGrid::Ptr toOpenVdbGrid(const OurGrid& grid) {
    using TheirValue = typename TheirGrid::ValueType;
    auto out = TheirGrid::create(sameBitsAs<TheirValue>(grid.background()));
    auto& tree = out->tree();
    auto acc = out->getAccessor();
    for (const auto& item : test::treeContents(grid.tree())) {
        const auto v = sameBitsAs<TheirValue>(item.value);
        const openvdb::Coord ijk(item.min[0], item.min[1], item.min[2]);
        if (item.level == 0) {
            if (item.active)
                acc.setValueOn(ijk, v);
            else
                acc.setValueOff(ijk, v);
        } else {
            tree.addTile(openvdb::Index(item.level), ijk, v, item.active);
        }
    }
    out->setName(grid.getName());
    out->setTransform(openvdb::math::Transform::createLinearTransform(grid.voxelSize()[0]));
    return out;
}

template <typename Ours, typename Theirs>
struct Pair {
    using OurGrid = Ours;
    using TheirGrid = Theirs;
};
using GridPairs =
    ::testing::Types<Pair<FloatGrid, openvdb::FloatGrid>, Pair<DoubleGrid, openvdb::DoubleGrid>,
                     Pair<Int32Grid, openvdb::Int32Grid>, Pair<Int64Grid, openvdb::Int64Grid>,
                     Pair<BoolGrid, openvdb::BoolGrid>, Pair<MaskGrid, openvdb::MaskGrid>,
                     Pair<Vec3SGrid, openvdb::Vec3SGrid>, Pair<Vec3DGrid, openvdb::Vec3DGrid>,
                     Pair<Vec3IGrid, openvdb::Vec3IGrid>>;

template <typename P>
class FileCompat : public ::testing::Test {
public:
    using OurGrid = typename P::OurGrid;
    using TheirGrid = typename P::TheirGrid;
    using OurValue = typename OurGrid::ValueType;
    using TheirValue = typename TheirGrid::ValueType;

    static void SetUpTestSuite() { openvdb::initialize(); }

    static typename TheirGrid::Ptr toOpenVdb(const OurGrid& grid) {
        return toOpenVdbGrid<TheirGrid>(grid);
    }

    /// OpenVDB's grid listed as this library lists its own.
    static auto contentsOf(const TheirGrid& grid) {
        std::vector<test::ContentItem<OurValue>> items;
        for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
            openvdb::CoordBBox box;
            it.getBoundingBox(box);
            items.push_back({Coord(box.min()[0], box.min()[1], box.min()[2]),
                             Coord(box.max()[0], box.max()[1], box.max()[2]), int(it.getLevel()),
                             it.isValueOn(), sameBitsAs<OurValue>(it.getValue())});
        }
        std::sort(items.begin(), items.end(), [](const auto& a, const auto& b) {
            return std::tie(a.min, a.level) < std::tie(b.min, b.level);
        });
        return items;
    }

    static ::testing::AssertionResult same(const std::vector<test::ContentItem<OurValue>>& a,
                                           const std::vector<test::ContentItem<OurValue>>& b) {
        if (a.size() != b.size())
            return ::testing::AssertionFailure() << a.size() << " vs " << b.size() << " values";
        for (size_t i = 0; i < a.size(); ++i) {
            if (a[i].min != b[i].min || a[i].max != b[i].max || a[i].level != b[i].level ||
                a[i].active != b[i].active || !test::sameBits(a[i].value, b[i].value)) {
                return ::testing::AssertionFailure() << "value " << i << " at " << a[i].min
                                                     << " (level " << a[i].level << ") differs";
            }
        }
        return ::testing::AssertionSuccess();
    }
};
TYPED_TEST_SUITE(FileCompat, GridPairs);

constexpr uint32_t kSettings[] = {io::COMPRESS_NONE, io::COMPRESS_ACTIVE_MASK,
                                  io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK,
                                  io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK};

TYPED_TEST(FileCompat, FilesWrittenByOpenVdbReadTheSame) {
    using OurGrid = typename TestFixture::OurGrid;
    auto ours = OurGrid::create(
        test::randomValue<typename OurGrid::ValueType>(*std::make_unique<std::mt19937>(3)));
    test::fillTestGrid(*ours, 17);
    ours->setName("grid");
    auto theirs = TestFixture::toOpenVdb(*ours);
    if constexpr (!std::is_same_v<OurGrid, MaskGrid>) {
        // The copy is exact (for mask grids OpenVDB's tiles and voxels carry no separate
        // value, so only the file comparison below applies).
        ASSERT_TRUE(
            TestFixture::same(TestFixture::contentsOf(*theirs), test::treeContents(ours->tree())));
    }
    const std::string path = tempPath("from_openvdb.vdb");
    for (uint32_t flags : kSettings) {
        for (bool half : {false, true}) {
            SCOPED_TRACE("flags " + std::to_string(flags) + (half ? " half" : ""));
            theirs->setSaveFloatAsHalf(half);
            {
                openvdb::io::File out(path);
                out.setCompression(flags);
                out.write({theirs});
            }
            // OpenVDB's own reading of its file is the reference (it applies the half rounding).
            openvdb::io::File check(path);
            check.open(false);
            auto back =
                openvdb::gridPtrCast<typename TestFixture::TheirGrid>(check.readGrid("grid"));
            io::File in(path);
            in.open();
            auto read = gridPtrCast<OurGrid>(in.readGrid("grid"));
            ASSERT_TRUE(read);
            EXPECT_TRUE(TestFixture::same(TestFixture::contentsOf(*back),
                                          test::treeContents(read->tree())));
            EXPECT_EQ(read->saveFloatAsHalf(), half);
            EXPECT_EQ(read->template metaValue<Int64>("file_voxel_count"),
                      Int64(back->activeVoxelCount()));
        }
    }
}

TYPED_TEST(FileCompat, FilesWrittenHereReadTheSameInOpenVdb) {
    using OurGrid = typename TestFixture::OurGrid;
    auto ours = OurGrid::create(
        test::randomValue<typename OurGrid::ValueType>(*std::make_unique<std::mt19937>(5)));
    test::fillTestGrid(*ours, 19);
    ours->setName("grid");
    const std::string path = tempPath("to_openvdb.vdb");
    for (uint32_t flags : kSettings) {
        for (bool half : {false, true}) {
            SCOPED_TRACE("flags " + std::to_string(flags) + (half ? " half" : ""));
            ours->setSaveFloatAsHalf(half);
            io::File out(path);
            out.setCompression(flags);
            out.write({ours});
            // Our own reading is the reference for the half rounding; it must equal OpenVDB's.
            io::File again(path);
            again.open();
            auto mine = gridPtrCast<OurGrid>(again.readGrid("grid"));
            openvdb::io::File in(path);
            in.open(false);
            auto theirs =
                openvdb::gridPtrCast<typename TestFixture::TheirGrid>(in.readGrid("grid"));
            ASSERT_TRUE(theirs);
            EXPECT_TRUE(TestFixture::same(TestFixture::contentsOf(*theirs),
                                          test::treeContents(mine->tree())));
            EXPECT_EQ(theirs->getName(), "grid");
            if (!half) {
                EXPECT_TRUE(TestFixture::same(TestFixture::contentsOf(*theirs),
                                              test::treeContents(ours->tree())));
            }
        }
    }
}

/// The byte ranges that may differ between two writers: the UUID and the file_mem_bytes value.
std::vector<uint8_t> withoutVolatileBytes(std::vector<uint8_t> bytes) {
    std::fill(bytes.begin() + 21, bytes.begin() + 57, 0);
    const std::string key = "file_mem_bytes";
    auto it = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    while (it != bytes.end()) {
        // name, then u32 5 + "int64", then u32 8, then the value
        const auto value = it + long(key.size()) + 4 + 5 + 4;
        if (value + 8 <= bytes.end())
            std::fill(value, value + 8, 0);
        it = std::search(it + 1, bytes.end(), key.begin(), key.end());
    }
    return bytes;
}

TEST(FileCompatBytes, WithoutCodecsBothLibrariesWriteTheSameBytes) {
    openvdb::initialize();
    auto ours = FloatGrid::create(2.0f);
    test::fillTestGrid(*ours, 23);
    ours->setName("density");
    ours->setGridClass(GRID_FOG_VOLUME);
    auto theirs = toOpenVdbGrid<openvdb::FloatGrid>(*ours);
    theirs->setGridClass(openvdb::GRID_FOG_VOLUME);
    for (uint32_t flags : {io::COMPRESS_NONE, io::COMPRESS_ACTIVE_MASK}) {
        for (bool half : {false, true}) {
            SCOPED_TRACE("flags " + std::to_string(flags) + (half ? " half" : ""));
            ours->setSaveFloatAsHalf(half);
            theirs->setSaveFloatAsHalf(half);
            const std::string a = tempPath("bytes_ours.vdb"), b = tempPath("bytes_theirs.vdb");
            io::File out(a);
            out.setCompression(flags);
            out.write({ours});
            openvdb::io::File ref(b);
            ref.setCompression(flags);
            ref.write({theirs});
            ref.close();
            const auto x = withoutVolatileBytes(fileBytes(a));
            const auto y = withoutVolatileBytes(fileBytes(b));
            ASSERT_EQ(x.size(), y.size());
            const auto diff = std::mismatch(x.begin(), x.end(), y.begin());
            EXPECT_TRUE(diff.first == x.end())
                << "first difference at byte " << (diff.first - x.begin());
        }
    }
}

// ---- Real-world files ------------------------------------------------------------------------

namespace fs = std::filesystem;

/// The sample folder (CMake cache variable VDB_SAMPLES_DIR).
fs::path samplesDir() {
    return fs::path(VDB_SAMPLES_DIR).lexically_normal();
}

/// Files of the sample folder that no reader can read (OpenVDB 10 fails on them too).
const std::set<std::string> kBrokenSamples = {"truncated.vdb"};

std::vector<fs::path> sampleFiles() {
    std::vector<fs::path> files;
    const fs::path dir = samplesDir();
    if (!fs::is_directory(dir))
        return files;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().extension() == ".vdb")
            files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

/// A metadata value as files store it: type name, then u32 size and payload.
std::string serialized(const MetaValue& value) {
    std::string out(metaTypeName(value));
    out += ':';
    std::visit(
        [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::string>) {
                out += v;
            } else if constexpr (std::is_same_v<T, OpaqueMetadata>) {
                out.append(v.bytes.begin(), v.bytes.end());
            } else if constexpr (std::is_same_v<T, bool>) {
                out += char(v ? 1 : 0);
            } else {
                out.append(reinterpret_cast<const char*>(&v), sizeof(T));
            }
        },
        value);
    return out;
}
std::string serialized(const openvdb::Metadata& value) {
    std::ostringstream bytes;
    value.write(bytes);  // u32 size, then the payload
    return value.typeName() + ":" + bytes.str().substr(4);
}

/// Checks that both libraries see the same metadata (entries private to the writer, whose
/// type names start with "__", are dropped by both).
::testing::AssertionResult sameMetadata(const openvdb::MetaMap& theirs, const MetaMap& ours) {
    std::map<std::string, std::string> a, b;
    for (auto it = theirs.beginMeta(); it != theirs.endMeta(); ++it)
        if (!it->second->typeName().starts_with("__"))
            a[it->first] = serialized(*it->second);
    for (auto it = ours.beginMeta(); it != ours.endMeta(); ++it)
        b[it->first] = serialized(it->second);
    for (const auto& [name, value] : a) {
        if (!b.count(name))
            return ::testing::AssertionFailure() << "metadata \"" << name << "\" is missing";
        if (b[name] != value)
            return ::testing::AssertionFailure() << "metadata \"" << name << "\" differs";
    }
    if (a.size() != b.size())
        return ::testing::AssertionFailure() << b.size() << " metadata entries vs " << a.size();
    return ::testing::AssertionSuccess();
}

/// Compares the trees of one grid when its type is P's; returns false for other types.
template <typename P>
bool compareTrees(const GridBase::Ptr& ours, const openvdb::GridBase::Ptr& theirs) {
    using Fixture = FileCompat<P>;
    const auto our = gridPtrCast<typename P::OurGrid>(ours);
    if (!our)
        return false;
    const auto their = openvdb::gridPtrCast<typename P::TheirGrid>(theirs);
    EXPECT_TRUE(their) << "OpenVDB reads type " << theirs->type();
    if (their) {
        EXPECT_TRUE(Fixture::same(Fixture::contentsOf(*their), test::treeContents(our->tree())));
    }
    return true;
}

template <typename... Ps>
bool compareTreesOfAnyType(const GridBase::Ptr& ours, const openvdb::GridBase::Ptr& theirs,
                           ::testing::Types<Ps...>*) {
    return (compareTrees<Ps>(ours, theirs) || ...);
}

TEST(FileSamples, EveryGridReadsAsOpenVdbReadsIt) {
    const auto files = sampleFiles();
    if (files.empty())
        GTEST_SKIP() << "no sample folder at " << samplesDir()
                     << " (configure with -DVDB_SAMPLES_DIR=...)";
    openvdb::initialize();
    int grids = 0, skipped = 0;
    for (const fs::path& path : files) {
        if (kBrokenSamples.count(path.filename().string()))
            continue;
        SCOPED_TRACE(path.filename().string());
        openvdb::io::File theirs(path.string());
        theirs.open(false);
        io::File ours(path.string());
        ASSERT_NO_THROW(ours.open(false));
        EXPECT_TRUE(sameMetadata(*theirs.getMetadata(), ours.getMetadata()));

        // Grid names: the readable ones plus the reported ones are OpenVDB's list.
        std::vector<std::string> theirNames, ourNames = ours.getGridNames();
        for (auto it = theirs.beginName(); it != theirs.endName(); ++it)
            theirNames.push_back(*it);
        std::multiset<std::string> unsupportedNames;
        for (const auto& u : ours.unsupportedGrids()) {
            EXPECT_TRUE(u.type.starts_with("Tree_ptdataidx")) << u.name << ": " << u.type;
            unsupportedNames.insert(u.name);
            ++skipped;
        }
        EXPECT_EQ(ourNames.size() + unsupportedNames.size(), theirNames.size());
        for (const std::string& name : unsupportedNames)
            EXPECT_NE(std::find(theirNames.begin(), theirNames.end(), name), theirNames.end())
                << "unsupported grid \"" << name << "\" is not in the file";
        ASSERT_NO_THROW((void)ours.getGrids());  // unsupported grids are skipped cleanly

        io::File delayedFile(path.string());
        delayedFile.open(true);
        for (const std::string& name : ourNames) {
            SCOPED_TRACE(name);
            ++grids;
            const auto our = ours.readGrid(name);
            const auto their = theirs.readGrid(name);
            ASSERT_TRUE(our && their);
            EXPECT_EQ(our->type(), their->type());
            EXPECT_EQ(our->getName(), their->getName());
            EXPECT_EQ(our->activeVoxelCount(), uint64_t(their->activeVoxelCount()));
            EXPECT_TRUE(sameMetadata(*their, *our));
            EXPECT_EQ(std::string(our->transform().mapTypeName()), their->transform().mapType());
            for (const Coord& ijk : {Coord(0), Coord(1, 2, 3), Coord(-70, 15, 1000)}) {
                const Vec3d a = our->transform().indexToWorld(ijk);
                const openvdb::Vec3d b = their->transform().indexToWorld(test::toOvdb(ijk));
                for (int i = 0; i < 3; ++i)
                    EXPECT_NEAR(a[i], b[i], 1e-9 * (1.0 + std::abs(b[i])));
            }
            EXPECT_TRUE(compareTreesOfAnyType(our, their, static_cast<GridPairs*>(nullptr)))
                << "type " << our->type();
            // Delayed loading reads the same values.
            EXPECT_TRUE(compareTreesOfAnyType(delayedFile.readGrid(name), their,
                                              static_cast<GridPairs*>(nullptr)));
        }
    }
    EXPECT_GT(grids, 0);
    std::cout << grids << " grids compared, " << skipped << " unsupported grids skipped\n";
}

TEST(FileSamples, BrokenFilesRaiseIoError) {
    const auto files = sampleFiles();
    if (files.empty())
        GTEST_SKIP() << "no sample folder at " << samplesDir()
                     << " (configure with -DVDB_SAMPLES_DIR=...)";
    int seen = 0;
    for (const fs::path& path : files) {
        if (!kBrokenSamples.count(path.filename().string()))
            continue;
        ++seen;
        SCOPED_TRACE(path.filename().string());
        try {
            io::File in(path.string());
            in.open();
            for (const auto& g : *in.getGrids())
                (void)g->activeVoxelCount();
            ADD_FAILURE() << "read without an error";
        } catch (const IoError& e) {
            EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos);
        }
    }
    EXPECT_EQ(seen, int(kBrokenSamples.size()));
}

}  // namespace
}  // namespace vdb
