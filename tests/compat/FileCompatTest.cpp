// SPDX-License-Identifier: Apache-2.0
// `.vdb` compatibility with OpenVDB 10, both ways: files OpenVDB writes read here with the same
// voxels, tiles, states, values, transform and metadata; files written here read in OpenVDB
// the same way; and without ZIP or Blosc both libraries write the same bytes (apart from the
// random UUID and `file_mem_bytes`).

#include <vdb/Grid.h>
#include <vdb/io/File.h>

#include "OpenVdbConvert.h"
#include <GridContents.h>
#include <Oracles.h>
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
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
protected:
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

}  // namespace
}  // namespace vdb
