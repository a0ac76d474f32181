// SPDX-License-Identifier: Apache-2.0
/// @file
/// IEEE 754 binary16 ("half") conversion, as the .vdb format uses it for grids saved as half.
///
/// Half values travel as their 16 bit patterns (`uint16_t`); there is no half arithmetic type.
/// floatToHalfBits() rounds to nearest, ties to even, exactly as Imath's `half` and numpy's
/// float16 do, so files agree bit for bit with OpenVDB:
///   - finite values of magnitude >= 65520 (the midpoint between the largest half, 65504, and
///     the next power of two) become infinity of the same sign;
///   - magnitudes below 2^-14 become subnormal halves (steps of 2^-24), down to a signed zero;
///   - NaN stays NaN with its sign, quieted, keeping the top bits of its payload.
///
/// Doubles are converted to float first and then to half, as OpenVDB does. That double rounding
/// can differ from rounding a double straight to half in the last bit, and files must match
/// OpenVDB's, not the single-rounding result.
///
/// Cost: a handful of integer operations and one float addition per value, with selects instead
/// of branches so that the bulk loops vectorize. The code assumes the default floating-point
/// environment (round to nearest).
/// Threads: pure functions; safe everywhere.
///
/// @code
/// const uint16_t h = vdb::math::floatToHalfBits(0.1f);   // 0x2e66
/// const float back = vdb::math::halfBitsToFloat(h);      // 0.0999755859375f
/// @endcode

#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

namespace vdb::math {

/// Returns the binary16 bit pattern nearest to `f` (ties to even); see the file comment.
constexpr uint16_t floatToHalfBits(float f);

/// Returns the float equal to the binary16 bit pattern `h` (exact: every half is a float).
constexpr float halfBitsToFloat(uint16_t h);

/// Returns `f` rounded to the nearest value a half can hold, as a float.
constexpr float roundToHalf(float f) {
    return halfBitsToFloat(floatToHalfBits(f));
}

/// Returns the half bit pattern of `d`, converted to float first (see the file comment).
constexpr uint16_t doubleToHalfBits(double d) {
    return floatToHalfBits(static_cast<float>(d));
}

/// Returns `d` rounded through float to half precision, as a double.
constexpr double roundToHalf(double d) {
    return halfBitsToFloat(doubleToHalfBits(d));
}

/// Converts `n` floats from `in` to half bit patterns in `out`. The ranges may not overlap.
inline void floatsToHalf(const float* in, uint16_t* out, size_t n);

/// Converts `n` half bit patterns from `in` to floats in `out`. The ranges may not overlap.
inline void halfToFloats(const uint16_t* in, float* out, size_t n);

// ---- Implementation ---------------------------------------------------------------------------

constexpr uint16_t floatToHalfBits(float f) {
    const uint32_t x = std::bit_cast<uint32_t>(f);
    const uint32_t sign = (x >> 16) & 0x8000u;
    const uint32_t a = x & 0x7fffffffu;  // |f|

    // Normal halves: move the exponent bias from 127 to 15 (adding -112 << 23 modulo 2^32),
    // then drop 13 mantissa bits. Adding 0xfff plus the lowest kept bit rounds to nearest with
    // ties to even, and a carry out of the mantissa correctly bumps the exponent.
    const uint32_t normal = (a + 0xc8000fffu + ((a >> 13) & 1u)) >> 13;

    // Subnormal halves are multiples of 2^-24. Adding 0.5f puts |f| where a float's spacing is
    // exactly 2^-24, so the hardware's own ties-to-even rounding picks the half mantissa; the
    // count of 2^-24 steps is then the difference of the bit patterns. A result of 0x400 is the
    // smallest normal half, which is also the right encoding.
    const uint32_t subnormal =
        std::bit_cast<uint32_t>(std::bit_cast<float>(a) + 0.5f) - 0x3f000000u;

    // NaN: keep the top 10 payload bits and set the quiet bit, so that a payload living only in
    // the low float bits still gives a NaN rather than infinity.
    const uint32_t nan = 0x7e00u | ((a >> 13) & 0x3ffu);

    uint32_t h = a < 0x38800000u ? subnormal : normal;  // 0x38800000 = 2^-14
    h = a >= 0x477ff000u ? 0x7c00u : h;                 // 0x477ff000 = 65520: overflow to inf
    h = a > 0x7f800000u ? nan : h;
    return static_cast<uint16_t>(sign | h);
}

constexpr float halfBitsToFloat(uint16_t h) {
    const uint32_t sign = static_cast<uint32_t>(h & 0x8000u) << 16;
    const uint32_t a = h & 0x7fffu;

    // Normal: rebias the exponent from 15 to 127 (+112 << 23) and widen the mantissa.
    const uint32_t normal = (a << 13) + 0x38000000u;
    // Infinity and NaN: all-ones exponent, mantissa (and so the quiet bit) carried over.
    const uint32_t infNan = (a << 13) | 0x7f800000u;
    // Subnormal and zero: mantissa * 2^-24, exact in float.
    const uint32_t subnormal = std::bit_cast<uint32_t>(static_cast<float>(a) * 0x1p-24f);

    uint32_t bits = a >= 0x7c00u ? infNan : normal;
    bits = a < 0x0400u ? subnormal : bits;
    return std::bit_cast<float>(sign | bits);
}

inline void floatsToHalf(const float* in, uint16_t* out, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        out[i] = floatToHalfBits(in[i]);
    }
}

inline void halfToFloats(const uint16_t* in, float* out, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        out[i] = halfBitsToFloat(in[i]);
    }
}

}  // namespace vdb::math
