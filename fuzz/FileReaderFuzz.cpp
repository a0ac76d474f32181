// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the .vdb reader: any input must either read or raise vdb::IoError,
// never crash, hang, leak or exhaust memory. Each input is opened twice, eagerly and with
// delayed loading, and every value of every grid is visited (which loads out-of-core leaves);
// then the same bytes are read through io::Stream.
// Run: scripts/fuzz [seconds].

#include <vdb/Grid.h>
#include <vdb/io/File.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

namespace {

/// An in-memory file with a path (/proc/self/fd/N) that io::File can open.
class MemoryFile {
public:
    MemoryFile() : mFd(::memfd_create("vdb_fuzz_input", MFD_CLOEXEC)) {
        if (mFd < 0)
            std::abort();
        mPath = "/proc/self/fd/" + std::to_string(mFd);
    }
    const std::string& path() const { return mPath; }
    void assign(const uint8_t* data, size_t size) {
        if (::ftruncate(mFd, 0) != 0)
            std::abort();
        size_t done = 0;
        while (done < size) {
            const ssize_t n = ::pwrite(mFd, data + done, size - done, off_t(done));
            if (n <= 0)
                std::abort();
            done += size_t(n);
        }
    }

private:
    int mFd;
    std::string mPath;
};

/// Visits every value (voxels and tiles) of `grid` if it is a `GridT`; returns a checksum.
template <typename GridT>
uint64_t visit(const vdb::GridBase::Ptr& base) {
    const auto grid = vdb::gridPtrCast<GridT>(base);
    if (!grid)
        return 0;
    uint64_t sum = grid->activeVoxelCount() + grid->memUsage();
    for (auto it = grid->tree().cbeginValueAll(); it; ++it) {
        const auto value = it.getValue();
        unsigned char bytes[sizeof(value)];
        std::memcpy(bytes, &value, sizeof(value));
        for (unsigned char b : bytes)
            sum = sum * 31 + b;
        sum += it.isValueOn();
    }
    return sum;
}

uint64_t visitAll(const vdb::GridBase::Ptr& g) {
    using namespace vdb;
    return visit<FloatGrid>(g) + visit<DoubleGrid>(g) + visit<Int32Grid>(g) + visit<Int64Grid>(g) +
           visit<BoolGrid>(g) + visit<MaskGrid>(g) + visit<Vec3SGrid>(g) + visit<Vec3DGrid>(g) +
           visit<Vec3IGrid>(g);
}

volatile uint64_t gSink = 0;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static MemoryFile input;
    input.assign(data, size);
    for (bool delayed : {false, true}) {
        try {
            vdb::io::File file(input.path());
            file.open(delayed);
            (void)file.getMetadata();
            (void)file.unsupportedGrids();
            for (const auto& name : file.getGridNames())
                (void)file.readGridMetadata(name);
            const auto grids = file.getGrids();
            file.close();  // delayed grids keep the file open themselves
            for (const auto& g : *grids)
                gSink = gSink + visitAll(g);
        } catch (const vdb::IoError&) {
            // The one failure allowed.
        }
    }
    // The same bytes through io::Stream (an in-memory archive, read at once).
    try {
        std::istringstream is(std::string(reinterpret_cast<const char*>(data), size));
        vdb::io::Stream stream(is);
        (void)stream.getMetadata();
        (void)stream.unsupportedGrids();
        const auto grids = stream.getGrids();  // held: the loop must not outlive it
        for (const auto& g : *grids)
            gSink = gSink + visitAll(g);
    } catch (const vdb::IoError&) {
    }
    return 0;
}
