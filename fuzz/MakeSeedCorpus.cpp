// SPDX-License-Identifier: Apache-2.0
// Writes the fuzzers' seed corpora: for the .vdb reader, small .vdb files of every standard
// grid type in every compression setting, with and without half floats, with tiles at every
// level, instances, metadata and several grids per file (each file a few kilobytes); for the
// mesh reader (second folder), a tetrahedron and a quad in every mesh format, each file
// prefixed with the byte that picks its extension (MeshReaderFuzz.cpp).
// Usage: vdb_fuzz_seed_corpus <.vdb output folder> [<mesh output folder>]

#include <vdb/Grid.h>
#include <vdb/io/File.h>
#include <vdb/math/Transform.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
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

template <typename T>
void append(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

/// Writes the mesh seeds: one file per format, its first byte the extension index of
/// MeshReaderFuzz.cpp (0 .obj, 1 .ply, 2 .stl, 3 .off).
int writeMeshSeeds(const std::filesystem::path& dir) {
    std::filesystem::create_directories(dir);
    const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const auto save = [&](const std::string& name, char extension, const std::string& bytes) {
        std::ofstream(dir / name, std::ios::binary) << extension << bytes;
    };
    std::ostringstream obj, plyAscii, off, stlAscii;
    for (const auto& v : p)
        obj << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    obj << "vn 0 0 1\nvt 0 0\nf 1/1/1 3/1/1 2/1/1\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 2 3 4\n";
    save("tet.obj.seed", 0, obj.str());
    plyAscii << "ply\nformat ascii 1.0\ncomment seed\nelement vertex 4\nproperty float x\n"
                "property float y\nproperty float z\nelement face 4\n"
                "property list uchar int vertex_indices\nend_header\n";
    for (const auto& v : p)
        plyAscii << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const auto& t : f)
        plyAscii << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    save("tet-ascii.ply.seed", 1, plyAscii.str());
    std::string plyBinary =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nelement face 4\n"
        "property list uchar int vertex_indices\nend_header\n";
    for (const auto& v : p)
        for (float c : v)
            append(plyBinary, c);
    for (const auto& t : f) {
        append(plyBinary, uint8_t(3));
        for (int i : t)
            append(plyBinary, int32_t(i));
    }
    save("tet-binary.ply.seed", 1, plyBinary);
    std::string stlBinary(80, ' ');
    append(stlBinary, uint32_t(4));
    stlAscii << "solid seed\n";
    for (const auto& t : f) {
        for (int k = 0; k < 3; ++k)
            append(stlBinary, 0.0f);
        stlAscii << " facet normal 0 0 0\n  outer loop\n";
        for (int i : t) {
            for (float c : p[i])
                append(stlBinary, c);
            stlAscii << "   vertex " << p[i][0] << ' ' << p[i][1] << ' ' << p[i][2] << '\n';
        }
        append(stlBinary, uint16_t(0));
        stlAscii << "  endloop\n endfacet\n";
    }
    stlAscii << "endsolid seed\n";
    save("tet-binary.stl.seed", 2, stlBinary);
    save("tet-ascii.stl.seed", 2, stlAscii.str());
    off << "OFF\n4 4 6\n";
    for (const auto& v : p)
        off << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const auto& t : f)
        off << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    save("tet.off.seed", 3, off.str());
    return 6;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2 && argc != 3) {
        std::fprintf(stderr, "usage: %s <.vdb output folder> [<mesh output folder>]\n", argv[0]);
        return 2;
    }
    if (argc == 3) {
        const int meshes = writeMeshSeeds(argv[2]);
        std::printf("%d mesh seed files in %s\n", meshes, argv[2]);
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
