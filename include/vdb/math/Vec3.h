// SPDX-License-Identifier: Apache-2.0
/// @file
/// Vec3<T>, a three-component vector (positions, directions, voxel values of vector grids,
/// triangle indices), and Vec4<T>, a four-component tuple (quad indices).

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>

#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <ostream>
#include <type_traits>

namespace vdb {
namespace math {

/// A vector of three `T` components, x at index 0.
///
/// The layout is exactly three packed `T` values (standard layout, trivially copyable), so
/// arrays of Vec3 are written to and read from files byte for byte. A default-constructed
/// vector is zero.
///
/// Arithmetic is componentwise; a scalar operand on either side acts on every component.
/// length(), normalize() and unit() exist only for floating-point `T`.
///
/// Threads: a plain value; concurrent const calls are safe.
template <typename T>
class Vec3 {
    static_assert(std::is_arithmetic_v<T>, "a Vec3 holds arithmetic components");

public:
    using ValueType = T;
    using value_type = T;
    static constexpr int size = 3;

    constexpr Vec3() = default;
    /// Every component `s`.
    constexpr explicit Vec3(T s) : mVec{s, s, s} {}
    constexpr Vec3(T x, T y, T z) : mVec{x, y, z} {}
    /// Converts each component with static_cast.
    template <typename U>
    constexpr explicit Vec3(const Vec3<U>& v)
        : mVec{static_cast<T>(v[0]), static_cast<T>(v[1]), static_cast<T>(v[2])} {}
    /// The index-space point `ijk`, each component converted with static_cast.
    constexpr explicit Vec3(const Coord& ijk)
        : mVec{static_cast<T>(ijk[0]), static_cast<T>(ijk[1]), static_cast<T>(ijk[2])} {}

    static constexpr Vec3 zero() { return Vec3(T(0)); }
    static constexpr Vec3 ones() { return Vec3(T(1)); }

    constexpr T x() const { return mVec[0]; }
    constexpr T y() const { return mVec[1]; }
    constexpr T z() const { return mVec[2]; }
    constexpr T& x() { return mVec[0]; }
    constexpr T& y() { return mVec[1]; }
    constexpr T& z() { return mVec[2]; }
    constexpr T operator[](size_t i) const { return mVec[i]; }
    constexpr T& operator[](size_t i) { return mVec[i]; }
    constexpr const T* data() const { return mVec.data(); }
    constexpr T* data() { return mVec.data(); }

    // ---- Componentwise arithmetic
    constexpr Vec3 operator-() const { return Vec3(-mVec[0], -mVec[1], -mVec[2]); }
    constexpr Vec3& operator+=(const Vec3& v) { return *this = *this + v; }
    constexpr Vec3& operator-=(const Vec3& v) { return *this = *this - v; }
    constexpr Vec3& operator*=(const Vec3& v) { return *this = *this * v; }
    constexpr Vec3& operator/=(const Vec3& v) { return *this = *this / v; }
    constexpr Vec3& operator+=(T s) { return *this = *this + s; }
    constexpr Vec3& operator-=(T s) { return *this = *this - s; }
    constexpr Vec3& operator*=(T s) { return *this = *this * s; }
    constexpr Vec3& operator/=(T s) { return *this = *this / s; }

    friend constexpr Vec3 operator+(const Vec3& a, const Vec3& b) {
        return Vec3(a[0] + b[0], a[1] + b[1], a[2] + b[2]);
    }
    friend constexpr Vec3 operator-(const Vec3& a, const Vec3& b) {
        return Vec3(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    }
    friend constexpr Vec3 operator*(const Vec3& a, const Vec3& b) {
        return Vec3(a[0] * b[0], a[1] * b[1], a[2] * b[2]);
    }
    friend constexpr Vec3 operator/(const Vec3& a, const Vec3& b) {
        return Vec3(a[0] / b[0], a[1] / b[1], a[2] / b[2]);
    }
    friend constexpr Vec3 operator+(const Vec3& a, T s) {
        return Vec3(a[0] + s, a[1] + s, a[2] + s);
    }
    friend constexpr Vec3 operator-(const Vec3& a, T s) {
        return Vec3(a[0] - s, a[1] - s, a[2] - s);
    }
    friend constexpr Vec3 operator*(const Vec3& a, T s) {
        return Vec3(a[0] * s, a[1] * s, a[2] * s);
    }
    friend constexpr Vec3 operator/(const Vec3& a, T s) {
        return Vec3(a[0] / s, a[1] / s, a[2] / s);
    }
    friend constexpr Vec3 operator+(T s, const Vec3& a) { return a + s; }
    friend constexpr Vec3 operator-(T s, const Vec3& a) {
        return Vec3(s - a[0], s - a[1], s - a[2]);
    }
    friend constexpr Vec3 operator*(T s, const Vec3& a) { return a * s; }
    friend constexpr Vec3 operator/(T s, const Vec3& a) {
        return Vec3(s / a[0], s / a[1], s / a[2]);
    }

    constexpr bool operator==(const Vec3&) const = default;

    // ---- Products and norms
    constexpr T dot(const Vec3& v) const {
        return mVec[0] * v[0] + mVec[1] * v[1] + mVec[2] * v[2];
    }
    constexpr Vec3 cross(const Vec3& v) const {
        return Vec3(mVec[1] * v[2] - mVec[2] * v[1], mVec[2] * v[0] - mVec[0] * v[2],
                    mVec[0] * v[1] - mVec[1] * v[0]);
    }
    constexpr T lengthSqr() const { return dot(*this); }
    T length() const requires std::floating_point<T> { return std::sqrt(lengthSqr()); }

    /// Scales this vector to unit length and returns true, or leaves it unchanged and returns
    /// false when its length is at most `eps`.
    bool normalize(T eps = Tolerance<T>::value()) requires std::floating_point<T> {
        const T len = length();
        if (!(len > eps))
            return false;
        *this /= len;
        return true;
    }
    /// Returns this vector scaled to unit length.
    /// @throw ValueError when the length is at most `eps`.
    Vec3 unit(T eps = Tolerance<T>::value()) const requires std::floating_point<T> {
        Vec3 v(*this);
        if (!v.normalize(eps))
            throw ValueError("Vec3::unit: cannot normalize a zero vector");
        return v;
    }
    /// Returns this vector scaled to unit length, or the zero vector when its length is at
    /// most `eps`.
    Vec3 unitSafe(T eps = Tolerance<T>::value()) const requires std::floating_point<T> {
        Vec3 v(*this);
        return v.normalize(eps) ? v : zero();
    }

    constexpr T sum() const { return mVec[0] + mVec[1] + mVec[2]; }
    constexpr T product() const { return mVec[0] * mVec[1] * mVec[2]; }

    // ---- Componentwise minimum and maximum (named as on Coord)
    static constexpr Vec3 minComponent(const Vec3& a, const Vec3& b) {
        return Vec3(b[0] < a[0] ? b[0] : a[0], b[1] < a[1] ? b[1] : a[1],
                    b[2] < a[2] ? b[2] : a[2]);
    }
    static constexpr Vec3 maxComponent(const Vec3& a, const Vec3& b) {
        return Vec3(a[0] < b[0] ? b[0] : a[0], a[1] < b[1] ? b[1] : a[1],
                    a[2] < b[2] ? b[2] : a[2]);
    }
    /// Returns the smallest (largest) of the three components.
    constexpr T minComponent() const {
        const T m = mVec[1] < mVec[0] ? mVec[1] : mVec[0];
        return mVec[2] < m ? mVec[2] : m;
    }
    constexpr T maxComponent() const {
        const T m = mVec[0] < mVec[1] ? mVec[1] : mVec[0];
        return m < mVec[2] ? mVec[2] : m;
    }

private:
    std::array<T, 3> mVec{};
};

/// True when every component of `a` is within `tolerance` of the same component of `b`.
template <typename T>
constexpr bool isApproxEqual(const Vec3<T>& a, const Vec3<T>& b, T tolerance) {
    return isApproxEqual(a[0], b[0], tolerance) && isApproxEqual(a[1], b[1], tolerance) &&
           isApproxEqual(a[2], b[2], tolerance);
}
/// Componentwise tolerance: component i compares with `tolerance[i]`.
template <typename T>
constexpr bool isApproxEqual(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& tolerance) {
    return isApproxEqual(a[0], b[0], tolerance[0]) && isApproxEqual(a[1], b[1], tolerance[1]) &&
           isApproxEqual(a[2], b[2], tolerance[2]);
}
/// OpenVDB's default comparison of vectors: each component within 1e-7, absolutely or relative
/// to the larger magnitude (exact for integer components).
template <typename T>
constexpr bool isApproxEqual(const Vec3<T>& a, const Vec3<T>& b) {
    const T eps = std::is_integral_v<T> ? T(0) : static_cast<T>(1e-7);
    return isRelOrApproxEqual(a[0], b[0], eps, eps) && isRelOrApproxEqual(a[1], b[1], eps, eps) &&
           isRelOrApproxEqual(a[2], b[2], eps, eps);
}

/// Componentwise absolute value.
template <typename T>
constexpr Vec3<T> Abs(const Vec3<T>& v) {
    return Vec3<T>(Abs(v[0]), Abs(v[1]), Abs(v[2]));
}

/// Returns the index-space coordinate holding `xyz` when voxels are unit cells with their
/// corners on integers: componentwise floor, saturated to the Int32 range.
template <typename T>
inline Coord floorToCoord(const Vec3<T>& xyz) {
    if constexpr (std::is_integral_v<T>) {
        return Coord(Int32(xyz[0]), Int32(xyz[1]), Int32(xyz[2]));
    } else {
        return Coord(floorToInt32(xyz[0]), floorToInt32(xyz[1]), floorToInt32(xyz[2]));
    }
}
/// Returns the index-space coordinate nearest to `xyz` (halves round up), saturated to the
/// Int32 range.
template <typename T>
inline Coord roundToCoord(const Vec3<T>& xyz) {
    if constexpr (std::is_integral_v<T>) {
        return Coord(Int32(xyz[0]), Int32(xyz[1]), Int32(xyz[2]));
    } else {
        return Coord(roundToInt32(xyz[0]), roundToInt32(xyz[1]), roundToInt32(xyz[2]));
    }
}

template <typename T>
std::ostream& operator<<(std::ostream& os, const Vec3<T>& v) {
    // Unary + prints 8-bit components as numbers, not characters.
    return os << '[' << +v[0] << ", " << +v[1] << ", " << +v[2] << ']';
}

/// A tuple of four `T` components: the vertex indices of a quad (Vec4I), or a homogeneous
/// point. Packed like Vec3: standard layout, trivially copyable, zero when default-constructed.
template <typename T>
class Vec4 {
    static_assert(std::is_arithmetic_v<T>, "a Vec4 holds arithmetic components");

public:
    using ValueType = T;
    using value_type = T;
    static constexpr int size = 4;

    constexpr Vec4() = default;
    constexpr explicit Vec4(T s) : mVec{s, s, s, s} {}
    constexpr Vec4(T x, T y, T z, T w) : mVec{x, y, z, w} {}
    template <typename U>
    constexpr explicit Vec4(const Vec4<U>& v)
        : mVec{static_cast<T>(v[0]), static_cast<T>(v[1]), static_cast<T>(v[2]),
               static_cast<T>(v[3])} {}

    constexpr T x() const { return mVec[0]; }
    constexpr T y() const { return mVec[1]; }
    constexpr T z() const { return mVec[2]; }
    constexpr T w() const { return mVec[3]; }
    constexpr T& x() { return mVec[0]; }
    constexpr T& y() { return mVec[1]; }
    constexpr T& z() { return mVec[2]; }
    constexpr T& w() { return mVec[3]; }
    constexpr T operator[](size_t i) const { return mVec[i]; }
    constexpr T& operator[](size_t i) { return mVec[i]; }
    constexpr const T* data() const { return mVec.data(); }
    constexpr T* data() { return mVec.data(); }

    constexpr bool operator==(const Vec4&) const = default;

private:
    std::array<T, 4> mVec{};
};

template <typename T>
std::ostream& operator<<(std::ostream& os, const Vec4<T>& v) {
    return os << '[' << +v[0] << ", " << +v[1] << ", " << +v[2] << ", " << +v[3] << ']';
}

using Vec3s = Vec3<float>;
using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;
using Vec3R = Vec3<double>;  ///< OpenVDB's name for the vector of its tools' parameters
using Vec3i = Vec3<Int32>;
using Vec3I = Vec3<Index32>;
using Vec4s = Vec4<float>;
using Vec4d = Vec4<double>;
using Vec4i = Vec4<Int32>;
using Vec4I = Vec4<Index32>;

// The file format stores these packed; any padding would corrupt files.
static_assert(sizeof(Vec3s) == 12 && sizeof(Vec3d) == 24 && sizeof(Vec3i) == 12);
static_assert(sizeof(Vec4I) == 16);
static_assert(std::is_standard_layout_v<Vec3d> && std::is_trivially_copyable_v<Vec3d>);
static_assert(std::is_standard_layout_v<Vec3s> && std::is_trivially_copyable_v<Vec3s>);
static_assert(std::is_standard_layout_v<Vec4I> && std::is_trivially_copyable_v<Vec4I>);

}  // namespace math

using math::Vec3;
using math::Vec3d;
using math::Vec3f;
using math::Vec3I;
using math::Vec3i;
using math::Vec3R;
using math::Vec3s;
using math::Vec4;
using math::Vec4d;
using math::Vec4I;
using math::Vec4i;
using math::Vec4s;

}  // namespace vdb
