// SPDX-License-Identifier: Apache-2.0
/// @file
/// Compression of value arrays in `.vdb` files (paper appendix A; FORMAT.md 1.8 to 1.10).
///
/// A file chooses per grid a set of COMPRESS_* flags. Every node value array (internal node
/// tiles, leaf voxels) is then stored as:
/// - with COMPRESS_ACTIVE_MASK, a one-byte code saying how inactive values are rebuilt from at
///   most two stored values and a selection mask (the seven cases below), followed by the
///   active values only; otherwise code 6 and every value;
/// - the values through the chunk codec: raw bytes, a zlib stream (COMPRESS_ZIP) or a blosc
///   frame (COMPRESS_BLOSC), each with a 64-bit length whose sign marks a raw fallback;
/// - for grids saved as half floats, real components as IEEE binary16.
///
/// The writer picks the code exactly as OpenVDB 10 does, so files without ZIP or BLOSC are
/// byte-identical to OpenVDB's. The reader accepts any valid code, whatever chose it.

#pragma once

#include <vdb/Types.h>
#include <vdb/io/Codecs.h>
#include <vdb/io/Format.h>
#include <vdb/math/Half.h>
#include <vdb/math/Vec3.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace vdb::io {

/// Per-grid compression flags (OR-able), as stored in the grid's compression word.
inline constexpr uint32_t COMPRESS_NONE = 0;
inline constexpr uint32_t COMPRESS_ZIP = 0x1;
inline constexpr uint32_t COMPRESS_ACTIVE_MASK = 0x2;
inline constexpr uint32_t COMPRESS_BLOSC = 0x4;

/// "none", or the words "zip", "blosc", "active values" present in `flags`, joined by " + "
/// (the form of the `file_compression` metadata).
inline std::string compressionToString(uint32_t flags) {
    std::string s;
    auto add = [&](const char* word) {
        if (!s.empty())
            s += " + ";
        s += word;
    };
    if (flags & COMPRESS_ZIP)
        add("zip");
    if (flags & COMPRESS_BLOSC)
        add("blosc");
    if (flags & COMPRESS_ACTIVE_MASK)
        add("active values");
    return s.empty() ? "none" : s;
}

/// The per-node codes of mask compression (FORMAT.md 1.8): how inactive values are rebuilt.
enum class MaskCode : int8_t {
    NoMaskOrInactiveVals = 0,     // inactive = background
    NoMaskAndMinusBg = 1,         // inactive = -background
    NoMaskAndOneInactiveVal = 2,  // inactive = one stored value
    MaskAndNoInactiveVals = 3,    // selection ? background : -background
    MaskAndOneInactiveVal = 4,    // selection ? background : stored value
    MaskAndTwoInactiveVals = 5,   // selection ? second stored value : first stored value
    NoMaskAndAllVals = 6,         // every value stored
};

namespace detail {

/// The real components of value types stored as halves in half-float grids; 0 for types the
/// half flag leaves alone (integers, bool).
template <typename T>
inline constexpr int HALF_COMPONENTS = 0;
template <>
inline constexpr int HALF_COMPONENTS<float> = 1;
template <>
inline constexpr int HALF_COMPONENTS<double> = 1;
template <>
inline constexpr int HALF_COMPONENTS<Vec3s> = 3;
template <>
inline constexpr int HALF_COMPONENTS<Vec3d> = 3;

/// The real components of `n` values of T as one array (Vec3 is three packed components).
template <typename T>
auto* scalarsOf(T* v) {
    if constexpr (std::is_arithmetic_v<std::remove_const_t<T>>) {
        return v;
    } else {
        static_assert(sizeof(T) == 3 * sizeof(typename T::ValueType), "Vec3 must be packed");
        using S = std::conditional_t<std::is_const_v<T>, const typename T::ValueType,
                                     typename T::ValueType>;
        return reinterpret_cast<S*>(v);
    }
}

/// `v` rounded to half precision per real component (FORMAT.md 1.9); other types unchanged.
template <typename T>
T roundToHalf(const T& v) {
    if constexpr (HALF_COMPONENTS<T> == 1) {
        return T(math::roundToHalf(v));
    } else if constexpr (HALF_COMPONENTS<T> == 3) {
        T out = v;
        for (int i = 0; i < 3; ++i)
            out[i] = typename T::ValueType(math::roundToHalf(v[i]));
        return out;
    } else {
        return v;
    }
}

/// -v as the format defines it: arithmetic negation, logical NOT for bool.
template <typename T>
T negativeOf(const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
        return !v;
    } else if constexpr (std::is_integral_v<T>) {
        return T(std::make_unsigned_t<T>(0) - std::make_unsigned_t<T>(v));  // wraps at INT_MIN
    } else if constexpr (std::is_same_v<T, Vec3i>) {
        return Vec3i(negativeOf(v[0]), negativeOf(v[1]), negativeOf(v[2]));
    } else {
        return -v;
    }
}

/// Scratch space for one thread's encoding or decoding.
struct CodecScratch {
    std::vector<uint8_t> bytes;
    std::vector<uint8_t> values;  // raw storage for gathered values
};

/// Appends `raw` through the chunk codec of `flags` (FORMAT.md 1.10).
inline void writeChunk(ByteWriter& w, std::span<const uint8_t> raw, uint32_t flags) {
    if (flags & (COMPRESS_BLOSC | COMPRESS_ZIP)) {
        auto& out = w.buffer();
        const size_t lengthPos = out.size();
        w.put(int64_t(0));
        const size_t n = (flags & COMPRESS_BLOSC) ? bloscCompress(raw, out) : zipCompress(raw, out);
        // Blosc falls back to raw bytes only when it fails; zip whenever it does not shrink.
        const bool storeRaw = (flags & COMPRESS_BLOSC) ? n == 0 : n >= raw.size();
        if (storeRaw) {
            out.resize(lengthPos + sizeof(int64_t));
            w.patch(lengthPos, -int64_t(raw.size()));
            w.write(raw);
        } else {
            w.patch(lengthPos, int64_t(n));
        }
        return;
    }
    w.write(raw);
}

/// Reads exactly dst.size() bytes through the chunk codec of `flags` into `dst`.
inline void readChunk(ByteReader& r, std::span<uint8_t> dst, uint32_t flags) {
    if (!(flags & (COMPRESS_BLOSC | COMPRESS_ZIP))) {
        const auto src = r.take(dst.size(), "uncompressed values");
        if (!dst.empty())
            std::memcpy(dst.data(), src.data(), dst.size());
        return;
    }
    const int64_t length = r.read<int64_t>("chunk length");
    if (length <= 0) {
        if (length == std::numeric_limits<int64_t>::min() || uint64_t(-length) != dst.size()) {
            r.fail("raw chunk of " + std::to_string(length) + " bytes where " +
                   std::to_string(dst.size()) + " were expected");
        }
        const auto src = r.take(dst.size(), "raw chunk");
        if (!dst.empty())
            std::memcpy(dst.data(), src.data(), dst.size());
        return;
    }
    const auto src = r.take(uint64_t(length), "compressed chunk");
    try {
        if (flags & COMPRESS_BLOSC) {
            if (dst.empty()) {
                if (bloscDecompressedSize(src) != 0)
                    throw IoError("blosc frame is not empty");
                return;
            }
            bloscDecompress(src, dst);
        } else {
            zipDecompress(src, dst);
        }
    } catch (const IoError& e) {
        r.fail(std::string((flags & COMPRESS_BLOSC) ? "blosc" : "zip") + " chunk: " + e.what());
    }
}

/// Appends `n` values (as halves when `half` and the type is real) through the chunk codec.
template <typename ValueT>
void writeData(ByteWriter& w, const ValueT* values, size_t n, bool half, uint32_t flags,
               CodecScratch& scratch) {
    constexpr int C = HALF_COMPONENTS<ValueT>;
    if constexpr (C > 0) {
        if (half) {
            if (n == 0)
                return;  // a half array of no values writes nothing at all, not even a length
            auto& bytes = scratch.bytes;
            bytes.resize(n * C * sizeof(uint16_t));
            const auto* in = scalarsOf(values);
            for (size_t i = 0; i < n * C; ++i) {
                uint16_t h;
                if constexpr (std::is_same_v<std::remove_cvref_t<decltype(*in)>, double>)
                    h = math::doubleToHalfBits(in[i]);
                else
                    h = math::floatToHalfBits(in[i]);
                std::memcpy(bytes.data() + i * sizeof(uint16_t), &h, sizeof(uint16_t));
            }
            writeChunk(w, bytes, flags);
            return;
        }
    }
    writeChunk(w, {reinterpret_cast<const uint8_t*>(values), n * sizeof(ValueT)}, flags);
}

/// Reads `n` values written by writeData() into `out`.
template <typename ValueT>
void readData(ByteReader& r, ValueT* out, size_t n, bool half, uint32_t flags,
              CodecScratch& scratch) {
    constexpr int C = HALF_COMPONENTS<ValueT>;
    if constexpr (C > 0) {
        if (half) {
            if (n == 0)
                return;
            auto& bytes = scratch.bytes;
            bytes.resize(n * C * sizeof(uint16_t));
            readChunk(r, bytes, flags);
            auto* dst = scalarsOf(out);
            using S = std::remove_cvref_t<decltype(*dst)>;
            for (size_t i = 0; i < n * C; ++i) {
                uint16_t h;
                std::memcpy(&h, bytes.data() + i * sizeof(uint16_t), sizeof(uint16_t));
                dst[i] = S(math::halfBitsToFloat(h));
            }
            return;
        }
    }
    if constexpr (std::is_same_v<ValueT, bool>) {
        // Bytes other than 0 and 1 are not valid bools: read them as bytes first.
        auto& bytes = scratch.bytes;
        bytes.resize(n);
        readChunk(r, bytes, flags);
        for (size_t i = 0; i < n; ++i)
            out[i] = bytes[i] != 0;
    } else {
        readChunk(r, {reinterpret_cast<uint8_t*>(out), n * sizeof(ValueT)}, flags);
    }
}

/// Reads one raw value of ValueT (full width), as stored for backgrounds and inactive values.
template <typename ValueT>
ValueT readValue(ByteReader& r, std::string_view what) {
    if constexpr (std::is_same_v<ValueT, bool>)
        return r.readBool(what);
    else
        return r.read<ValueT>(what);
}
template <typename ValueT>
void writeValue(ByteWriter& w, const ValueT& v) {
    if constexpr (std::is_same_v<ValueT, bool>)
        w.putBool(v);
    else
        w.put(v);
}

/// What a writer records about one leaf's value array for the delayed-load table.
struct ArrayInfo {
    int8_t code = 6;
    uint64_t dataBytes = 0;  // bytes of the chunk (length prefix included), after the code etc.
};

/// Writes the value array of a node (FORMAT.md 1.8): `values` has MaskT::SIZE entries;
/// `childMask` marks the slots of an internal node that hold children (the format stores a
/// zero value there), null for leaves. `background` is the tree's full-precision background.
template <typename ValueT, typename MaskT>
ArrayInfo writeCompressedValues(ByteWriter& w, const ValueT* values, const MaskT& valueMask,
                                const MaskT* childMask, const ValueT& background, bool half,
                                uint32_t flags, CodecScratch& scratch) {
    constexpr Index COUNT = MaskT::SIZE;
    using Word = typename MaskT::Word;
    // The inactive slots (children excluded) of mask word `w`.
    const auto inactiveBits = [&](Index word) {
        Word bits = ~valueMask.words()[word];
        if (childMask)
            bits &= ~childMask->words()[word];
        return bits;
    };
    ArrayInfo info;
    // Up to three distinct inactive values (children excluded), compared with ==, as OpenVDB.
    ValueT inactive[2] = {background, background};
    int unique = 0;
    for (Index word = 0; word < MaskT::WORD_COUNT && unique < 3; ++word) {
        for (Word bits = inactiveBits(word); bits != 0 && unique < 3; bits &= bits - 1) {
            const ValueT& v = values[word * 64 + Index(std::countr_zero(bits))];
            if ((unique > 0 && v == inactive[0]) || (unique > 1 && v == inactive[1]))
                continue;
            if (unique < 2)
                inactive[unique] = v;
            ++unique;
        }
    }
    const ValueT minusBg = negativeOf(background);
    MaskCode code = MaskCode::NoMaskOrInactiveVals;
    if (unique == 1) {
        if (!(inactive[0] == background))
            code = inactive[0] == minusBg ? MaskCode::NoMaskAndMinusBg
                                          : MaskCode::NoMaskAndOneInactiveVal;
    } else if (unique == 2) {
        if (!(inactive[0] == background) && !(inactive[1] == background)) {
            code = MaskCode::MaskAndTwoInactiveVals;
        } else if (inactive[1] == background) {
            code = inactive[0] == minusBg ? MaskCode::MaskAndNoInactiveVals
                                          : MaskCode::MaskAndOneInactiveVal;
        } else {  // inactive[0] == background: the other value is stored, the mask selects bg
            std::swap(inactive[0], inactive[1]);
            code = inactive[0] == minusBg ? MaskCode::MaskAndNoInactiveVals
                                          : MaskCode::MaskAndOneInactiveVal;
        }
    } else if (unique > 2) {
        code = MaskCode::NoMaskAndAllVals;
    }
    // The delayed-load table records this code even when mask compression is off (as
    // OpenVDB does); the array itself then holds every value.
    if (!(flags & COMPRESS_ACTIVE_MASK)) {
        info.code = int8_t(code);
        w.put(int8_t(MaskCode::NoMaskAndAllVals));
        const size_t start = w.pos();
        writeData(w, values, COUNT, half, flags, scratch);
        info.dataBytes = w.pos() - start;
        return info;
    }
    info.code = int8_t(code);
    w.put(info.code);
    if (code == MaskCode::NoMaskAndOneInactiveVal || code == MaskCode::MaskAndOneInactiveVal ||
        code == MaskCode::MaskAndTwoInactiveVals) {
        writeValue(w, half ? roundToHalf(inactive[0]) : inactive[0]);
        if (code == MaskCode::MaskAndTwoInactiveVals)
            writeValue(w, half ? roundToHalf(inactive[1]) : inactive[1]);
    }
    if (code == MaskCode::NoMaskAndAllVals) {
        const size_t start = w.pos();
        writeData(w, values, COUNT, half, flags, scratch);
        info.dataBytes = w.pos() - start;
        return info;
    }
    if (code == MaskCode::MaskAndNoInactiveVals || code == MaskCode::MaskAndOneInactiveVal ||
        code == MaskCode::MaskAndTwoInactiveVals) {
        // Every slot off in the value mask, child slots (zero in `values`) included.
        Word selection[MaskT::WORD_COUNT];
        for (Index word = 0; word < MaskT::WORD_COUNT; ++word) {
            Word selected = 0;
            for (Word bits = ~valueMask.words()[word]; bits != 0; bits &= bits - 1) {
                const Index bit = Index(std::countr_zero(bits));
                if (values[word * 64 + bit] == inactive[1])
                    selected |= Word(1) << bit;
            }
            selection[word] = selected;
        }
        w.write(selection, sizeof(selection));
    }
    // The active values, in slot order: gathered straight into the output when they are
    // stored as they are.
    const Index active = valueMask.countOn();
    const bool direct = !(flags & (COMPRESS_BLOSC | COMPRESS_ZIP)) &&
                        !(HALF_COMPONENTS<ValueT> > 0 && half) && !std::is_same_v<ValueT, bool>;
    if (direct) {
        auto& out = w.buffer();
        const size_t start = out.size();
        out.resize(start + size_t(active) * sizeof(ValueT));
        uint8_t* dst = out.data() + start;
        for (Index n : valueMask.onBits()) {
            std::memcpy(dst, &values[n], sizeof(ValueT));
            dst += sizeof(ValueT);
        }
        info.dataBytes = out.size() - start;
        return info;
    }
    auto& store = scratch.values;
    store.resize(size_t(active) * sizeof(ValueT));
    auto* gathered = reinterpret_cast<ValueT*>(store.data());
    Index k = 0;
    for (Index n : valueMask.onBits())
        std::memcpy(static_cast<void*>(gathered + k++), &values[n], sizeof(ValueT));
    const size_t start = w.pos();
    writeData(w, gathered, active, half, flags, scratch);
    info.dataBytes = w.pos() - start;
    return info;
}

/// The part of a value array before its values (FORMAT.md 1.8): the code, the inactive values
/// it implies or stores, the selection mask, and how many values the chunk holds.
template <typename ValueT, typename MaskT>
struct ArrayHeader {
    MaskCode code = MaskCode::NoMaskAndAllVals;
    ValueT inactive0{}, inactive1{};
    MaskT selection;
    Index valueCount = 0;
    bool scattered = false;  // the chunk holds only the active values
};

/// Reads an array header. `count` is the array's length (the mask's size, or for files before
/// version 222 the number of non-child slots of an internal node); `background` is the
/// background as stored in the file; `hasCode` is false before version 222.
template <typename ValueT, typename MaskT>
ArrayHeader<ValueT, MaskT> readArrayHeader(ByteReader& r, Index count, const MaskT& valueMask,
                                           const ValueT& background, uint32_t flags, bool hasCode) {
    ArrayHeader<ValueT, MaskT> h;
    if (hasCode) {
        const int8_t code = r.read<int8_t>("mask compression code");
        if (code < 0 || code > 6)
            r.fail("invalid mask compression code " + std::to_string(int(code)));
        h.code = MaskCode(code);
    }
    h.inactive1 = background;
    h.inactive0 = h.code == MaskCode::NoMaskOrInactiveVals ? background : negativeOf(background);
    if (h.code == MaskCode::NoMaskAndOneInactiveVal || h.code == MaskCode::MaskAndOneInactiveVal ||
        h.code == MaskCode::MaskAndTwoInactiveVals) {
        h.inactive0 = readValue<ValueT>(r, "inactive value");
        if (h.code == MaskCode::MaskAndTwoInactiveVals)
            h.inactive1 = readValue<ValueT>(r, "second inactive value");
    }
    if (h.code == MaskCode::MaskAndNoInactiveVals || h.code == MaskCode::MaskAndOneInactiveVal ||
        h.code == MaskCode::MaskAndTwoInactiveVals) {
        const auto bytes =
            r.take(sizeof(typename MaskT::Word) * MaskT::WORD_COUNT, "selection mask");
        std::memcpy(h.selection.words(), bytes.data(), bytes.size());
    }
    const bool maskCompressed =
        (flags & COMPRESS_ACTIVE_MASK) && h.code != MaskCode::NoMaskAndAllVals;
    h.valueCount = maskCompressed ? valueMask.countOn() : count;
    h.scattered = maskCompressed && h.valueCount != count;
    return h;
}

/// Skips `n` values written by writeData() without decoding them.
template <typename ValueT>
void skipData(ByteReader& r, size_t n, bool half, uint32_t flags) {
    constexpr int C = HALF_COMPONENTS<ValueT>;
    const bool halves = C > 0 && half;
    if (halves && n == 0)
        return;
    if (flags & (COMPRESS_BLOSC | COMPRESS_ZIP)) {
        const int64_t length = r.read<int64_t>("chunk length");
        if (length == std::numeric_limits<int64_t>::min())
            r.fail("invalid chunk length");
        r.skip(uint64_t(length < 0 ? -length : length), "value chunk");
    } else {
        r.skip(halves ? n * C * sizeof(uint16_t) : n * sizeof(ValueT), "uncompressed values");
    }
}

/// Reads a value array written by writeCompressedValues() into `out` (`count` entries; see
/// readArrayHeader()).
template <typename ValueT, typename MaskT>
void readCompressedValues(ByteReader& r, ValueT* out, Index count, const MaskT& valueMask,
                          const ValueT& background, bool half, uint32_t flags, bool hasCode,
                          CodecScratch& scratch) {
    const auto h = readArrayHeader(r, count, valueMask, background, flags, hasCode);
    if (!h.scattered) {
        readData(r, out, h.valueCount, half, flags, scratch);
        return;
    }
    auto& store = scratch.values;
    store.resize(size_t(h.valueCount) * sizeof(ValueT));
    auto* active = reinterpret_cast<ValueT*>(store.data());
    readData(r, active, h.valueCount, half, flags, scratch);
    Index k = 0;
    for (Index i = 0; i < count; ++i) {
        if (valueMask.isOn(i))
            std::memcpy(static_cast<void*>(out + i), active + k++, sizeof(ValueT));
        else
            out[i] = h.selection.isOn(i) ? h.inactive1 : h.inactive0;
    }
}

}  // namespace detail
}  // namespace vdb::io
