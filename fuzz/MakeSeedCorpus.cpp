// SPDX-License-Identifier: Apache-2.0
// Writes the fuzzer's seed corpus: small .vdb files of every standard grid type in every
// compression setting, with and without half floats, with tiles at every level, instances,
// metadata and several grids per file (each file a few kilobytes).
// Usage: vdb_fuzz_seed_corpus <output folder>

#include <vdb/Grid.h>
#include <vdb/io/File.h>
#include <vdb/math/Transform.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace {

template <typename GridT>
typename GridT::Ptr smallGrid(const typename GridT::ValueType& a,
                              const typename GridT::ValueType& b) {
    auto grid = GridT::create(a);
    auto& tree = grid->tree();
    tree.setValueOn(vdb::Coord(1, 2, 3), b);
    tree.setValueOff(vdb::Coord(-9, 4, 100), b);
    for (int i = 0; i < 8; ++i)
        tree.setValueOn(vdb::Coord(16 + i, 16, 16 + i), i % 2 ? a : b);
    tree.fill(vdb::CoordBBox::createCube(vdb::Coord(64, 0, 0), 8), b, true);
    tree.fill(vdb::CoordBBox::createCube(vdb::Coord(128, 0, 0), 128), a, false);
    tree.topNode().setTile(vdb::Coord(4096, 0, 0), b, true);
    grid->setName(grid->valueType());
    grid->insertMeta("note", std::string("seed"));
    return grid;
}

void write(const std::filesystem::path& dir, const std::string& name, vdb::GridPtrVec grids,
           uint32_t flags) {
    vdb::io::File file((dir / name).string());
    file.setCompression(flags);
    vdb::MetaMap meta;
    meta.insertMeta("creator", std::string("seed corpus"));
    file.write(grids, meta);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
        return 2;
    }
    using namespace vdb;
    const std::filesystem::path dir(argv[1]);
    std::filesystem::create_directories(dir);
    const uint32_t settings[] = {io::COMPRESS_NONE, io::COMPRESS_ACTIVE_MASK,
                                 io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK,
                                 io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK, io::COMPRESS_BLOSC};
    int n = 0;
    for (uint32_t flags : settings) {
        for (bool half : {false, true}) {
            const std::string tag = std::to_string(flags) + (half ? "h" : "");
            auto f = smallGrid<FloatGrid>(0.5f, -2.0f);
            f->setSaveFloatAsHalf(half);
            f->setGridClass(GRID_LEVEL_SET);
            auto v = smallGrid<Vec3SGrid>(Vec3s(0.0f), Vec3s(1, 2, 3));
            v->setSaveFloatAsHalf(half);
            v->setTransform(math::Transform::createLinearTransform(0.25));
            auto instance = FloatGrid::create(0.5f);
            instance->setTree(f->treePtr());  // written as an instance of f
            instance->setName("instance");
            write(dir, "float_vec3s_" + tag + ".vdb", {f, v, instance}, flags);
            ++n;
            if (half)
                continue;
            write(dir, "double_int_" + tag + ".vdb",
                  {smallGrid<DoubleGrid>(1.0, 3.0), smallGrid<Int32Grid>(0, 7),
                   smallGrid<Int64Grid>(5, -1)},
                  flags);
            write(dir, "bool_mask_vec_" + tag + ".vdb",
                  {smallGrid<BoolGrid>(false, true), smallGrid<MaskGrid>(false, true),
                   smallGrid<Vec3DGrid>(Vec3d(0.0), Vec3d(1, 2, 3)),
                   smallGrid<Vec3IGrid>(Vec3i(0), Vec3i(4, 5, 6))},
                  flags);
            n += 2;
        }
    }
    std::printf("%d seed files in %s\n", n, dir.string().c_str());
    return 0;
}
