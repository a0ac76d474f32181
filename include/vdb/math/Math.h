// SPDX-License-Identifier: Apache-2.0
/// @file
/// Small scalar helpers shared by the math types: tolerances, approximate comparison, clamping,
/// signs and powers, saturating float-to-int conversion, and zeroVal<T>().

#pragma once

#include <vdb/Types.h>

#include <cmath>
#include <limits>
#include <type_traits>

namespace vdb::math {

/// A coordinate axis, used to pick a rotation axis or a vector component.
enum class Axis { X = 0, Y = 1, Z = 2 };

/// Returns the zero of `T`: its value-initialized state (0, false, a zero vector).
template <typename T>
constexpr T zeroVal() {
    return T{};
}

/// Default absolute tolerance of isApproxEqual() and isApproxZero() for `T`.
template <typename T>
struct Tolerance {
    static constexpr T value() { return T(0); }
};
template <>
struct Tolerance<float> {
    static constexpr float value() { return 1e-8f; }
};
template <>
struct Tolerance<double> {
    static constexpr double value() { return 1e-15; }
};

/// A small positive step for `T`: the default start time of a Ray (so that a ray leaving a
/// surface does not hit it again at t = 0).
template <typename T>
struct Delta {
    static constexpr T value() { return T(0); }
};
template <>
struct Delta<float> {
    static constexpr float value() { return 1e-5f; }
};
template <>
struct Delta<double> {
    static constexpr double value() { return 1e-9; }
};

/// Returns |x|; for unsigned types, x itself. @pre for signed integers, x is not the type's
/// minimum (whose magnitude it cannot hold): use absDiff() for distances.
template <typename T>
constexpr T Abs(T x) {
    if constexpr (std::is_unsigned_v<T>) {
        return x;
    } else {
        return x < T(0) ? -x : x;
    }
}

/// The distance |a - b| between two values of `T`, without overflow: for integers it is
/// computed and returned in the unsigned type of the same width (two int32 values of opposite
/// sign near +-2^31 are 2^32 - 1 apart, which fits), for floating-point types in `T` (infinite
/// when the difference overflows), for bool 0 or 1.
template <typename T>
constexpr auto absDiff(T a, T b) {
    static_assert(std::is_arithmetic_v<T>, "absDiff takes an arithmetic type");
    if constexpr (std::is_same_v<T, bool>) {
        return a != b;
    } else if constexpr (std::is_integral_v<T>) {
        using U = std::make_unsigned_t<T>;
        return a < b ? U(U(b) - U(a)) : U(U(a) - U(b));
    } else {
        return Abs(a - b);
    }
}

/// True when |a - b| <= `tolerance`: the one tolerance comparison of the library (node
/// isConstant(), prune, background tiles, composites). Equal values are always equal, whatever
/// the tolerance; otherwise a negative tolerance matches nothing. Integers compare their exact
/// distance (no overflow at the extremes of the type), bools compare exactly, and NaN is
/// approximately equal to nothing (a node holding NaN among other values is never constant, so
/// no value is lost to a tile).
template <typename T>
requires std::is_arithmetic_v<T>
constexpr bool isApproxEqual(T a, T b, T tolerance) {
    if constexpr (std::is_same_v<T, bool>) {
        return a == b;
    } else if constexpr (std::is_integral_v<T>) {
        using U = std::make_unsigned_t<T>;
        return a == b || (tolerance >= T(0) && absDiff(a, b) <= U(tolerance));
    } else {
        // Both tests always (no short circuit): loops over values vectorise without branches.
        return (a == b) | (absDiff(a, b) <= tolerance);
    }
}
/// As above with the default tolerance of `T` (OpenVDB's: 1e-8 for float, 1e-15 for double,
/// exact for integers and bools).
template <typename T>
requires std::is_arithmetic_v<T>
constexpr bool isApproxEqual(T a, T b) {
    return isApproxEqual(a, b, Tolerance<T>::value());
}

/// True when `a` and `b` differ by at most `absTol`, or by at most `relTol` times the larger
/// magnitude. Use this for values far from 1, where an absolute tolerance means nothing. NaN is
/// equal to nothing; integers compare their exact distance.
template <typename T>
requires std::is_arithmetic_v<T>
constexpr bool isRelOrApproxEqual(T a, T b, T absTol, T relTol) {
    if (isApproxEqual(a, b, absTol))
        return true;
    if constexpr (std::is_integral_v<T>) {
        const double x = a < T(0) ? -double(a) : double(a), y = b < T(0) ? -double(b) : double(b);
        return double(absDiff(a, b)) <= double(relTol) * (x > y ? x : y);
    } else {
        const T scale = Abs(a) > Abs(b) ? Abs(a) : Abs(b);
        return absDiff(a, b) <= relTol * scale;
    }
}

/// Three-way comparison of `hi - lo` with `c`, as exact numbers for integer types (no
/// overflow; types of up to 32 bits, the components of vector values) and as `T` arithmetic
/// for floating-point types: negative, zero or positive as `hi - lo` is below, equal to or
/// above `c`. NaN compares as equal.
template <typename T>
requires std::is_arithmetic_v<T>
constexpr int compareDifference(T lo, T hi, T c) {
    if constexpr (std::is_integral_v<T>) {
        static_assert(sizeof(T) <= 4, "compareDifference: integer types of at most 32 bits");
        const Int64 d = Int64(hi) - Int64(lo);
        return (d > Int64(c)) - (d < Int64(c));
    } else {
        const T d = hi - lo;
        return (d > c) - (d < c);
    }
}

/// True when `x` is exactly zero.
template <typename T>
constexpr bool isZero(T x) {
    return x == T(0);
}
/// True when |x| is at most `tolerance`.
template <typename T>
constexpr bool isApproxZero(T x, T tolerance = Tolerance<T>::value()) {
    return !(Abs(x) > tolerance);
}

/// Returns `x` limited to [lo, hi]. @pre lo <= hi
template <typename T>
constexpr T clamp(T x, T lo, T hi) {
    return x < lo ? lo : (hi < x ? hi : x);
}
/// Returns `x` limited to [0, 1].
template <typename T>
constexpr T clamp01(T x) {
    return clamp(x, T(0), T(1));
}

/// Returns -1, 0 or 1 as `x` is negative, zero or positive.
template <typename T>
constexpr int Sign(T x) {
    return (T(0) < x) - (x < T(0));
}

template <typename T>
constexpr T Pow2(T x) {
    return x * x;
}
template <typename T>
constexpr T Pow3(T x) {
    return x * x * x;
}

/// Returns floor(x) as an Int32, saturated to [INT32_MIN, INT32_MAX]; NaN gives 0.
/// Unlike a plain cast, this is defined for every input.
template <typename RealT>
inline Int32 floorToInt32(RealT x) {
    static_assert(std::is_floating_point_v<RealT>, "floorToInt32 takes a floating-point value");
    constexpr RealT lo = RealT(std::numeric_limits<Int32>::min());
    constexpr RealT hi = RealT(2147483648.0);  // 2^31, the first value that does not fit
    if (!(x == x))
        return 0;
    if (x < lo)
        return std::numeric_limits<Int32>::min();
    if (x >= hi)
        return std::numeric_limits<Int32>::max();
    return static_cast<Int32>(std::floor(x));
}

/// Returns x rounded to the nearest Int32, halves rounding up (floor(x + 0.5)), saturated like
/// floorToInt32().
template <typename RealT>
inline Int32 roundToInt32(RealT x) {
    return floorToInt32(x + RealT(0.5));
}

}  // namespace vdb::math
