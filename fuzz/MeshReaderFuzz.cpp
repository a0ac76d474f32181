// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the mesh reader (vdb::meshio): any input must either read or raise
// vdb::IoError, never crash, hang, leak or allocate more than the file can hold (the fuzzer's
// -malloc_limit_mb catches a single large allocation). The first byte of an input picks the
// file name's extension (.obj, .ply, .stl or .off, which steers assimp's choice of reader), the
// rest is the file. A mesh that reads is checked against the reader's invariants.
// Run: scripts/fuzz [seconds] (both targets), or build/fuzz/fuzz/vdb_mesh_reader_fuzz CORPUS.

#include <vdb/Exceptions.h>
#include <vdb/meshio/MeshReader.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

/// The folder the inputs are written to, one per process, removed at exit.
class InputFolder {
public:
    InputFolder()
        : mDir(std::filesystem::temp_directory_path() /
               ("vdb_mesh_fuzz_" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(mDir);
    }
    ~InputFolder() {
        std::error_code ec;
        std::filesystem::remove_all(mDir, ec);
    }
    std::string write(const char* extension, const uint8_t* data, size_t size) const {
        const std::string path = (mDir / (std::string("input") + extension)).string();
        std::ofstream(path, std::ios::binary | std::ios::trunc)
            .write(reinterpret_cast<const char*>(data), std::streamsize(size));
        return path;
    }

private:
    std::filesystem::path mDir;
};

volatile uint64_t gSink = 0;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const InputFolder folder;
    if (size == 0)
        return 0;
    static const char* const extensions[] = {".obj", ".ply", ".stl", ".off"};
    const std::string path = folder.write(extensions[data[0] & 3], data + 1, size - 1);
    try {
        const vdb::meshio::Mesh mesh = vdb::meshio::readMesh(path);
        // The invariants readMesh() promises.
        if (mesh.triangles.empty() && mesh.quads.empty())
            std::abort();
        for (const vdb::Vec3s& p : mesh.points) {
            if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
                std::abort();
        }
        for (const vdb::Vec3I& t : mesh.triangles) {
            for (int k = 0; k < 3; ++k) {
                if (t[k] >= mesh.points.size())
                    std::abort();
            }
        }
        for (const vdb::Vec4I& q : mesh.quads) {
            for (int k = 0; k < 4; ++k) {
                if (q[k] >= mesh.points.size())
                    std::abort();
            }
        }
        gSink = gSink + mesh.points.size() + mesh.triangles.size() + mesh.quads.size();
    } catch (const vdb::IoError&) {
        // The one failure allowed.
    }
    return 0;
}
