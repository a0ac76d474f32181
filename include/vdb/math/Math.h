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

/// Returns |x|; for unsigned types, x itself.
template <typename T>
constexpr T Abs(T x) {
    if constexpr (std::is_unsigned_v<T>) {
        return x;
    } else {
        return x < T(0) ? -x : x;
    }
}

/// True when `a` and `b` differ by at most `tolerance` (absolute). Integers compare exactly.
template <typename T>
constexpr bool isApproxEqual(T a, T b, T tolerance) {
    if constexpr (std::is_integral_v<T>) {
        return a == b;
    } else {
        return !(Abs(a - b) > tolerance);
    }
}
template <typename T>
constexpr bool isApproxEqual(T a, T b) {
    return isApproxEqual(a, b, Tolerance<T>::value());
}

/// True when `a` and `b` differ by at most `absTol`, or by at most `relTol` times the larger
/// magnitude. Use this for values far from 1, where an absolute tolerance means nothing.
template <typename T>
constexpr bool isRelOrApproxEqual(T a, T b, T absTol, T relTol) {
    const T diff = Abs(a - b);
    if (!(diff > absTol))
        return true;
    const T scale = Abs(a) > Abs(b) ? Abs(a) : Abs(b);
    return !(diff > relTol * scale);
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
