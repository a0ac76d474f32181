// SPDX-License-Identifier: Apache-2.0
// The chunk codecs on top of libdeflate (zlib streams) and c-blosc 1.x (blosc frames).

#include <vdb/io/Codecs.h>

#include <blosc.h>
#include <libdeflate.h>

#include <array>
#include <memory>
#include <new>
#include <string>

// Decompressing an untrusted frame is bounds-checked only from c-blosc 1.16 on, which is also
// the release that added blosc_cbuffer_validate().
#if BLOSC_VERSION_MAJOR < 1 || (BLOSC_VERSION_MAJOR == 1 && BLOSC_VERSION_MINOR < 16)
#error "c-blosc 1.16 or newer is required: older releases do not bounds-check decompression"
#endif

namespace vdb::io {
namespace {

// ---- libdeflate state, one set per thread ----

constexpr int MIN_ZIP_LEVEL = 1;
constexpr int MAX_ZIP_LEVEL = 12;

struct CompressorDeleter {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};
struct DecompressorDeleter {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// Allocating a compressor costs far more than compressing one leaf, and a libdeflate object
// must not be shared between threads while in use, so each thread keeps its own, one per level.
// thread_local unique_ptrs free them when the thread exits.
libdeflate_compressor* threadCompressor(int level) {
    thread_local std::array<std::unique_ptr<libdeflate_compressor, CompressorDeleter>,
                            MAX_ZIP_LEVEL + 1>
        compressors;
    auto& compressor = compressors[static_cast<size_t>(level)];
    if (!compressor) {
        compressor.reset(libdeflate_alloc_compressor(level));
        if (!compressor) {
            throw std::bad_alloc();
        }
    }
    return compressor.get();
}

libdeflate_decompressor* threadDecompressor() {
    thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> decompressor;
    if (!decompressor) {
        decompressor.reset(libdeflate_alloc_decompressor());
        if (!decompressor) {
            throw std::bad_alloc();
        }
    }
    return decompressor.get();
}

// An empty span may carry a null pointer, which the C libraries are not promised to accept
// even with a zero length; these give them a valid address instead.
const uint8_t* orDummy(std::span<const uint8_t> bytes) {
    static const uint8_t dummy = 0;
    return bytes.empty() ? &dummy : bytes.data();
}
uint8_t* orDummy(std::span<uint8_t> bytes) {
    thread_local uint8_t dummy = 0;
    return bytes.empty() ? &dummy : bytes.data();
}

// ---- blosc frame header ----

// The fields of a blosc frame's 16-byte header that decide whether the frame is safe to hand to
// blosc_decompress_ctx(), which trusts the header for the frame's length.
struct BloscHeader {
    size_t nbytes = 0;     // uncompressed bytes
    size_t cbytes = 0;     // bytes of the whole frame, header included
    size_t blocksize = 0;  // uncompressed bytes per block
    int flags = 0;
};

constexpr int MAX_BLOSC_COMPRESSOR_FORMAT = 4;  // blosclz, lz4, snappy, zlib, zstd

// Reads and checks the header at the start of `src`; looks at the first 16 bytes only.
BloscHeader readBloscHeader(std::span<const uint8_t> src) {
    if (src.size() < BLOSC_MIN_HEADER_LENGTH) {
        throw IoError("blosc frame shorter than its 16-byte header");
    }
    BloscHeader header;
    // blosc_cbuffer_sizes() zeroes all three sizes for a format version it does not know.
    blosc_cbuffer_sizes(src.data(), &header.nbytes, &header.cbytes, &header.blocksize);
    size_t typesize = 0;
    blosc_cbuffer_metainfo(src.data(), &typesize, &header.flags);

    if (src[0] == 0 || header.cbytes < BLOSC_MIN_HEADER_LENGTH ||
        header.nbytes > size_t(BLOSC_MAX_BUFFERSIZE) ||
        (src[2] >> 5) > MAX_BLOSC_COMPRESSOR_FORMAT) {
        throw IoError("invalid blosc header");
    }
    if (header.nbytes == 0) {
        return header;
    }
    if (header.flags & BLOSC_MEMCPYED) {
        // A memcpyed frame is the header followed by the raw bytes.
        if (header.cbytes < header.nbytes + BLOSC_MAX_OVERHEAD) {
            throw IoError("invalid blosc header: raw payload longer than the frame");
        }
    } else {
        // A compressed frame starts with one 32-bit offset per block.
        if (header.blocksize == 0 || typesize == 0) {
            throw IoError("invalid blosc header");
        }
        const size_t nblocks = (header.nbytes + header.blocksize - 1) / header.blocksize;
        if (nblocks > (header.cbytes - BLOSC_MIN_HEADER_LENGTH) / 4) {
            throw IoError("invalid blosc header: block table longer than the frame");
        }
    }
    return header;
}

}  // namespace

// ---- zip ----

size_t zipCompress(std::span<const uint8_t> src, std::vector<uint8_t>& out, int level) {
    if (level < MIN_ZIP_LEVEL || level > MAX_ZIP_LEVEL) {
        throw ValueError("zip compression level " + std::to_string(level) + " is outside 1..12");
    }
    libdeflate_compressor* compressor = threadCompressor(level);
    const size_t start = out.size();
    out.resize(start + libdeflate_zlib_compress_bound(compressor, src.size()));
    // With room for the bound, compression cannot run out of space and so never returns 0.
    const size_t written = libdeflate_zlib_compress(compressor, orDummy(src), src.size(),
                                                    out.data() + start, out.size() - start);
    out.resize(start + written);
    return written;
}

void zipDecompress(std::span<const uint8_t> src, std::span<uint8_t> dst) {
    size_t produced = 0;
    const libdeflate_result result = libdeflate_zlib_decompress(
        threadDecompressor(), orDummy(src), src.size(), orDummy(dst), dst.size(), &produced);
    switch (result) {
        case LIBDEFLATE_SUCCESS:
            if (produced != dst.size()) {
                throw IoError("zip stream inflates to " + std::to_string(produced) +
                              " bytes, expected " + std::to_string(dst.size()));
            }
            return;
        case LIBDEFLATE_INSUFFICIENT_SPACE:
            throw IoError("zip stream inflates to more than the expected " +
                          std::to_string(dst.size()) + " bytes");
        default:
            throw IoError("corrupt zip stream");
    }
}

// ---- blosc ----

size_t bloscCompress(std::span<const uint8_t> src, std::vector<uint8_t>& out) {
    if (src.size() > size_t(BLOSC_MAX_BUFFERSIZE)) {
        return 0;
    }
    const size_t start = out.size();
    const size_t capacity = src.size() + BLOSC_MAX_OVERHEAD;
    out.resize(start + capacity);
    // OpenVDB's parameters: typesize 4 even for doubles and halves, and one block for the whole
    // array (a blocksize of 0, for an empty input, lets blosc choose).
    const int written =
        blosc_compress_ctx(/*clevel=*/9, BLOSC_SHUFFLE, /*typesize=*/4, src.size(), orDummy(src),
                           out.data() + start, capacity, BLOSC_LZ4_COMPNAME,
                           /*blocksize=*/src.size(), /*numinternalthreads=*/1);
    if (written <= 0) {
        out.resize(start);
        return 0;
    }
    out.resize(start + static_cast<size_t>(written));
    return static_cast<size_t>(written);
}

void bloscDecompress(std::span<const uint8_t> src, std::span<uint8_t> dst) {
    const BloscHeader header = readBloscHeader(src);
    if (header.cbytes > src.size()) {
        throw IoError("blosc frame of " + std::to_string(header.cbytes) +
                      " bytes is longer than its " + std::to_string(src.size()) + "-byte chunk");
    }
    if (header.nbytes != dst.size()) {
        throw IoError("blosc frame holds " + std::to_string(header.nbytes) + " bytes, expected " +
                      std::to_string(dst.size()));
    }
    size_t validated = 0;
    if (blosc_cbuffer_validate(src.data(), header.cbytes, &validated) != 0 ||
        validated != dst.size()) {
        throw IoError("invalid blosc frame");
    }
    if (dst.empty()) {
        return;
    }
    const int produced =
        blosc_decompress_ctx(src.data(), dst.data(), dst.size(), /*numinternalthreads=*/1);
    if (produced < 0 || static_cast<size_t>(produced) != dst.size()) {
        throw IoError("corrupt blosc frame");
    }
}

size_t bloscDecompressedSize(std::span<const uint8_t> src) {
    return readBloscHeader(src).nbytes;
}

}  // namespace vdb::io
