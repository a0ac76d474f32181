// SPDX-License-Identifier: Apache-2.0
/// @file
/// Constants of the `.vdb` format and the bounds-checked byte cursor every reader goes through.
///
/// All numbers in a `.vdb` file are little-endian and packed without alignment; this library
/// (like OpenVDB) copies raw memory, so it builds only for little-endian targets.
///
/// ByteReader is the one place where file bytes are consumed: every read states how many
/// bytes it needs and fails with IoError when they are not there, so a truncated or hostile
/// file can never make a reader run past its buffer or allocate more than the file holds.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace vdb::io {

static_assert(std::endian::native == std::endian::little,
              "the .vdb format stores raw little-endian memory; big-endian hosts are unsupported");

/// The first 8 bytes of every `.vdb` file: " BDV" followed by four zero bytes.
inline constexpr uint64_t FILE_MAGIC = 0x56444220;
/// The file version this library writes (OpenVDB 10 to 12 write it too).
inline constexpr uint32_t FILE_VERSION = 224;
/// The oldest and newest file versions this library reads.
inline constexpr uint32_t OLDEST_FILE_VERSION = 220;
inline constexpr uint32_t NEWEST_FILE_VERSION = 225;
/// Versions at which the layout changed (FORMAT.md 1.14).
inline constexpr uint32_t FILE_VERSION_NODE_MASK_COMPRESSION = 222;  // code byte, per-grid flags
/// The library version written into headers: readers accept any value.
inline constexpr uint32_t WRITER_LIBRARY_MAJOR = 10;
inline constexpr uint32_t WRITER_LIBRARY_MINOR = 0;

/// A read cursor over bytes that all belong to one named source (a file name, for messages).
/// Every accessor checks the remaining length first and throws IoError("<source>: <what>
/// (at byte N)") when a read would cross the end. The reader views both the bytes and the
/// name: they must outlive it (readers are made per leaf, so they copy nothing).
class ByteReader {
public:
    ByteReader(std::span<const uint8_t> bytes, std::string_view source)
        : mBytes(bytes), mSource(source) {}

    size_t pos() const { return mPos; }
    size_t size() const { return mBytes.size(); }
    size_t remaining() const { return mBytes.size() - mPos; }
    std::string_view source() const { return mSource; }
    std::span<const uint8_t> bytes() const { return mBytes; }

    /// Moves to absolute position `pos` (at most size()).
    void seek(uint64_t pos) {
        if (pos > mBytes.size())
            fail("offset " + std::to_string(pos) + " lies past the end of the data");
        mPos = size_t(pos);
    }
    /// The next `n` bytes, consumed; `what` names them in the error message.
    std::span<const uint8_t> take(uint64_t n, std::string_view what) {
        if (n > remaining()) {
            fail("unexpected end of data while reading " + std::string(what) + " (" +
                 std::to_string(n) + " bytes needed, " + std::to_string(remaining()) + " left)");
        }
        const auto out = mBytes.subspan(mPos, size_t(n));
        mPos += size_t(n);
        return out;
    }
    void skip(uint64_t n, std::string_view what) { (void)take(n, what); }

    /// A trivially copyable value stored as its raw bytes.
    template <typename T>
    T read(std::string_view what) {
        static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>,
                      "read<T> copies raw bytes; read bools with readBool()");
        T value;
        std::memcpy(&value, take(sizeof(T), what).data(), sizeof(T));
        return value;
    }
    /// A one-byte boolean; any nonzero byte is true.
    bool readBool(std::string_view what) { return take(1, what)[0] != 0; }
    /// A string stored as u32 length + bytes. Lengths above `maxLength` are rejected before
    /// anything is allocated.
    std::string readString(std::string_view what, uint32_t maxLength = 1u << 20) {
        const uint32_t n = read<uint32_t>(what);
        if (n > maxLength) {
            fail(std::string(what) + " is " + std::to_string(n) + " bytes long (at most " +
                 std::to_string(maxLength) + " allowed)");
        }
        const auto s = take(n, what);
        return std::string(reinterpret_cast<const char*>(s.data()), s.size());
    }
    /// A count that must be at most what the remaining bytes can hold, at `minBytesEach`
    /// bytes per item: bounds every allocation by the size of the input.
    uint64_t checkedCount(uint64_t count, uint64_t minBytesEach, std::string_view what) const {
        if (minBytesEach > 0 && count > remaining() / minBytesEach) {
            fail(std::string(what) + " count " + std::to_string(count) +
                 " is more than the remaining data can hold");
        }
        return count;
    }

    [[noreturn]] void fail(const std::string& reason) const {
        throw IoError(std::string(mSource) + ": " + reason + " (at byte " + std::to_string(mPos) +
                      ")");
    }

private:
    std::span<const uint8_t> mBytes;
    size_t mPos = 0;
    std::string_view mSource;
};

/// Appends little-endian raw values to a byte vector.
class ByteWriter {
public:
    explicit ByteWriter(std::vector<uint8_t>& out) : mOut(&out) {}

    size_t pos() const { return mOut->size(); }
    std::vector<uint8_t>& buffer() { return *mOut; }

    void write(const void* data, size_t n) {
        const auto* p = static_cast<const uint8_t*>(data);
        mOut->insert(mOut->end(), p, p + n);
    }
    void write(std::span<const uint8_t> bytes) { write(bytes.data(), bytes.size()); }
    template <typename T>
    void put(const T& value) {
        static_assert(std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>,
                      "put<T> copies raw bytes; write bools with putBool()");
        write(&value, sizeof(T));
    }
    void putBool(bool b) { mOut->push_back(b ? 1 : 0); }
    void putString(std::string_view s) {
        put(uint32_t(s.size()));
        write(s.data(), s.size());
    }
    /// Overwrites sizeof(T) bytes at `pos` (which must already be written).
    template <typename T>
    void patch(size_t pos, const T& value) {
        std::memcpy(mOut->data() + pos, &value, sizeof(T));
    }

private:
    std::vector<uint8_t>* mOut;
};

}  // namespace vdb::io
