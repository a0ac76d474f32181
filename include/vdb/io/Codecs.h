// SPDX-License-Identifier: Apache-2.0
/// @file
/// The two chunk codecs of the .vdb format: zlib streams (COMPRESS_ZIP) and c-blosc 1.x frames
/// (COMPRESS_BLOSC), applied to each value array on its own.
///
/// These functions deal only in bytes: the length prefixes, the raw fallback and the half
/// conversion belong to the callers. Compression appends to a caller-owned vector so that a
/// writer can reuse one buffer per thread; decompression fills a caller-sized span and insists
/// on the exact size the file promised, so a corrupt file can never make it write out of bounds.
///
/// Threads: every function may be called concurrently from any number of threads. Each thread
/// keeps its own libdeflate state (one compressor per level, one decompressor), created on first
/// use and freed when the thread exits; blosc runs through its context API with one internal
/// thread, never through its global state.
///
/// @code
/// const std::vector<float> values = leafValues();
/// const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(values.data()),
///                                      values.size() * sizeof(float));
/// std::vector<uint8_t> stream;
/// vdb::io::zipCompress(bytes, stream);
/// std::vector<float> back(values.size());
/// vdb::io::zipDecompress(stream, {reinterpret_cast<uint8_t*>(back.data()), bytes.size()});
/// @endcode

#pragma once

#include <vdb/Exceptions.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vdb::io {

/// Appends to `out` a zlib stream (RFC 1950: 2-byte header, raw deflate, Adler-32) of `src`,
/// readable by zlib's uncompress(). `level` is libdeflate's scale, 1 (fastest) to 12 (smallest);
/// 6 matches zlib's default and gives the `78 9c` header OpenVDB writes.
/// Returns the number of bytes appended. Throws ValueError when `level` is outside 1..12.
/// Cost: O(src.size()); the first call per thread and level allocates the compressor.
size_t zipCompress(std::span<const uint8_t> src, std::vector<uint8_t>& out, int level = 6);

/// Inflates the zlib stream `src` into exactly dst.size() bytes. Bytes after the end of the
/// stream are ignored, as zlib's uncompress() ignores them. Throws IoError, with a short reason
/// and no file name, when the stream is corrupt or does not inflate to exactly dst.size() bytes.
void zipDecompress(std::span<const uint8_t> src, std::span<uint8_t> dst);

/// Appends a c-blosc 1.x frame of `src` made with OpenVDB's parameters: clevel 9, byte shuffle,
/// typesize 4 whatever the element type, the lz4 compressor, one block spanning the whole input
/// and one thread. Small inputs come out as "memcpyed" frames (header plus raw bytes).
/// Returns the number of bytes appended, or 0 when blosc reports an error; then nothing is
/// appended and the caller writes the raw bytes instead, as OpenVDB does.
size_t bloscCompress(std::span<const uint8_t> src, std::vector<uint8_t>& out);

/// Decompresses the blosc frame at the start of `src` into exactly dst.size() bytes. The header
/// is checked before blosc sees the frame: the frame must fit in `src` and state an uncompressed
/// size of dst.size(). Throws IoError when it does not, or when decompression fails. Reads stay
/// inside `src` and writes inside `dst` whatever the bytes.
void bloscDecompress(std::span<const uint8_t> src, std::span<uint8_t> dst);

/// Returns the uncompressed byte count stated by the header of the blosc frame `src`. Only the
/// 16-byte header is read. Throws IoError when `src` is shorter than a header or the header is
/// not one that bloscDecompress() could accept.
size_t bloscDecompressedSize(std::span<const uint8_t> src);

}  // namespace vdb::io
