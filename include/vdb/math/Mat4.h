// SPDX-License-Identifier: Apache-2.0
/// @file
/// Mat4<T>, a 4x4 matrix in OpenVDB's row-vector convention (p' = p * M, translation in the
/// last row), stored row-major exactly as the .vdb format writes it.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <ostream>
#include <type_traits>

namespace vdb {
namespace math {

/// A 4x4 matrix of `T`, acting on row vectors: a point p maps to [p 1] * M.
///
/// Element (r, c) lives at data()[4 * r + c], so the 16 values are the row-major order of the
/// file format. An affine matrix has last column (0, 0, 0, 1)^T and its translation in
/// elements 12, 13 and 14 (the last row). Composition reads left to right: `A * B` applies A
/// first, then B.
///
/// A default-constructed matrix is zero; use identity() for the identity.
/// Threads: a plain value; concurrent const calls are safe.
template <typename T>
class Mat4 {
    static_assert(std::is_floating_point_v<T>, "a Mat4 holds floating-point elements");

public:
    using ValueType = T;
    using value_type = T;
    using Vec3Type = Vec3<T>;

    constexpr Mat4() = default;
    /// The matrix with rows (a00 a01 a02 a03), (a10 …), (a20 …), (a30 …).
    constexpr Mat4(T a00, T a01, T a02, T a03, T a10, T a11, T a12, T a13, T a20, T a21, T a22,
                   T a23, T a30, T a31, T a32, T a33)
        : mM{a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23, a30, a31, a32, a33} {}
    /// Converts each element with static_cast.
    template <typename U>
    constexpr explicit Mat4(const Mat4<U>& m) {
        for (size_t i = 0; i < 16; ++i)
            mM[i] = static_cast<T>(m.data()[i]);
    }

    /// The matrix whose 16 elements, in row-major order, are `values[0..15]`.
    static constexpr Mat4 fromRowMajor(const T* values) {
        Mat4 m;
        for (size_t i = 0; i < 16; ++i)
            m.mM[i] = values[i];
        return m;
    }

    static constexpr Mat4 zero() { return Mat4(); }
    static constexpr Mat4 identity() {
        return Mat4(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1);
    }
    /// The affine matrix that moves every point by `t`.
    static constexpr Mat4 translation(const Vec3Type& t) {
        Mat4 m = identity();
        m.setTranslation(t);
        return m;
    }
    /// The matrix that scales axis i by `s[i]`.
    static constexpr Mat4 scale(const Vec3Type& s) {
        return Mat4(s[0], 0, 0, 0, 0, s[1], 0, 0, 0, 0, s[2], 0, 0, 0, 0, 1);
    }
    /// The right-handed rotation by `radians` about a coordinate axis (counterclockwise when
    /// the axis points at the viewer): rotation(Axis::Z, pi/2) maps (1, 0, 0) to (0, 1, 0).
    static Mat4 rotation(Axis axis, T radians);
    /// The right-handed rotation by `radians` about `axis`, which need not be unit length.
    /// @throw ValueError when `axis` is zero.
    static Mat4 rotation(const Vec3Type& axis, T radians);

    // ---- Elements
    constexpr T operator()(int r, int c) const { return mM[size_t(4 * r + c)]; }
    constexpr T& operator()(int r, int c) { return mM[size_t(4 * r + c)]; }
    /// Row `r` as a pointer, so that `m[r][c]` reads element (r, c).
    constexpr const T* operator[](int r) const { return mM.data() + 4 * r; }
    constexpr T* operator[](int r) { return mM.data() + 4 * r; }
    /// The 16 elements in row-major order.
    constexpr const T* data() const { return mM.data(); }
    constexpr T* data() { return mM.data(); }

    /// The translation of an affine matrix: elements (3, 0), (3, 1), (3, 2).
    constexpr Vec3Type getTranslation() const { return Vec3Type(mM[12], mM[13], mM[14]); }
    constexpr void setTranslation(const Vec3Type& t) {
        mM[12] = t[0];
        mM[13] = t[1];
        mM[14] = t[2];
    }

    // ---- Tests
    /// True when the last column is exactly (0, 0, 0, 1)^T.
    constexpr bool isAffine() const {
        return mM[3] == T(0) && mM[7] == T(0) && mM[11] == T(0) && mM[15] == T(1);
    }
    constexpr bool isIdentity() const { return *this == identity(); }
    constexpr bool operator==(const Mat4&) const = default;

    // ---- Algebra
    friend constexpr Mat4 operator*(const Mat4& a, const Mat4& b) {
        Mat4 m;
        for (int r = 0; r < 4; ++r) {
            for (int c = 0; c < 4; ++c) {
                m(r, c) =
                    a(r, 0) * b(0, c) + a(r, 1) * b(1, c) + a(r, 2) * b(2, c) + a(r, 3) * b(3, c);
            }
        }
        return m;
    }
    constexpr Mat4& operator*=(const Mat4& b) { return *this = *this * b; }

    constexpr Mat4 transpose() const;
    /// Returns the determinant, by cofactor expansion (exact for small integer matrices).
    constexpr T determinant() const;
    /// Returns the determinant of the upper-left 3x3 block (the linear part of an affine map).
    constexpr T determinant3() const;
    /// Returns the inverse. Affine matrices are inverted as affine maps (the 3x3 block, then
    /// the translation), which stays accurate when the translation dwarfs the scale.
    /// @throw ValueError when the matrix is singular to working precision (its determinant is
    /// below 64 epsilon times the product of its row lengths) or holds non-finite values.
    Mat4 inverse() const;

    // ---- Applying the matrix to row vectors
    /// Returns the image of the point `p`: [p 1] * M, ignoring the last column.
    constexpr Vec3Type transformPoint(const Vec3Type& p) const {
        return Vec3Type(p[0] * mM[0] + p[1] * mM[4] + p[2] * mM[8] + mM[12],
                        p[0] * mM[1] + p[1] * mM[5] + p[2] * mM[9] + mM[13],
                        p[0] * mM[2] + p[1] * mM[6] + p[2] * mM[10] + mM[14]);
    }
    /// Returns the image of the direction `v`: [v 0] * M (no translation).
    constexpr Vec3Type transformDirection(const Vec3Type& v) const {
        return Vec3Type(v[0] * mM[0] + v[1] * mM[4] + v[2] * mM[8],
                        v[0] * mM[1] + v[1] * mM[5] + v[2] * mM[9],
                        v[0] * mM[2] + v[1] * mM[6] + v[2] * mM[10]);
    }

    // ---- Composition in place; "pre" acts before this matrix, "post" after it
    constexpr Mat4& preMult(const Mat4& m) { return *this = m * *this; }
    constexpr Mat4& postMult(const Mat4& m) { return *this = *this * m; }
    constexpr Mat4& preTranslate(const Vec3Type& t) { return preMult(translation(t)); }
    constexpr Mat4& postTranslate(const Vec3Type& t) { return postMult(translation(t)); }
    constexpr Mat4& preScale(const Vec3Type& s) { return preMult(scale(s)); }
    constexpr Mat4& postScale(const Vec3Type& s) { return postMult(scale(s)); }
    Mat4& preRotate(Axis axis, T radians) { return preMult(rotation(axis, radians)); }
    Mat4& postRotate(Axis axis, T radians) { return postMult(rotation(axis, radians)); }

private:
    std::array<T, 16> mM{};  // row-major: element (r, c) at 4 * r + c
};

/// True when every element of `a` is within `tolerance` of the same element of `b`.
template <typename T>
constexpr bool isApproxEqual(const Mat4<T>& a, const Mat4<T>& b, T tolerance) {
    for (int i = 0; i < 16; ++i) {
        if (!isApproxEqual(a.data()[i], b.data()[i], tolerance))
            return false;
    }
    return true;
}

/// Prints the four rows, each in brackets.
template <typename T>
std::ostream& operator<<(std::ostream& os, const Mat4<T>& m) {
    os << '[';
    for (int r = 0; r < 4; ++r) {
        os << (r ? ", [" : "[") << m(r, 0) << ", " << m(r, 1) << ", " << m(r, 2) << ", " << m(r, 3)
           << ']';
    }
    return os << ']';
}

using Mat4s = Mat4<float>;
using Mat4d = Mat4<double>;
using Mat4R = Mat4<double>;  ///< OpenVDB's name for the matrix of its tools' parameters

// The file format stores 16 packed doubles (mat4d, AffineMap) or floats (mat4s).
static_assert(sizeof(Mat4d) == 128 && sizeof(Mat4s) == 64);
static_assert(std::is_standard_layout_v<Mat4d> && std::is_trivially_copyable_v<Mat4d>);

// ---- Implementation ---------------------------------------------------------------------------

template <typename T>
Mat4<T> Mat4<T>::rotation(Axis axis, T radians) {
    const T c = std::cos(radians), s = std::sin(radians);
    // Row-vector convention: row i is the image of axis i.
    switch (axis) {
        case Axis::X:
            return Mat4(1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, 0, 0, 0, 1);
        case Axis::Y:
            return Mat4(c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, 0, 0, 0, 1);
        case Axis::Z:
            break;
    }
    return Mat4(c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1);
}

template <typename T>
Mat4<T> Mat4<T>::rotation(const Vec3Type& axis, T radians) {
    const Vec3Type a = axis.unit();
    const T c = std::cos(radians), s = std::sin(radians), t = T(1) - c;
    // Rodrigues' formula, transposed for row vectors: row i is the image of axis i.
    return Mat4(t * a[0] * a[0] + c, t * a[0] * a[1] + s * a[2], t * a[0] * a[2] - s * a[1], 0,
                t * a[0] * a[1] - s * a[2], t * a[1] * a[1] + c, t * a[1] * a[2] + s * a[0], 0,
                t * a[0] * a[2] + s * a[1], t * a[1] * a[2] - s * a[0], t * a[2] * a[2] + c, 0, 0,
                0, 0, 1);
}

template <typename T>
constexpr Mat4<T> Mat4<T>::transpose() const {
    Mat4 m;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c)
            m(c, r) = (*this)(r, c);
    }
    return m;
}

namespace detail {

/// The twelve 2x2 minors of a 4x4 matrix that the Laplace expansion along the first two rows
/// uses: s* from rows 0-1, c* from rows 2-3.
template <typename T>
struct Mat4Minors {
    T s0, s1, s2, s3, s4, s5, c0, c1, c2, c3, c4, c5;

    constexpr explicit Mat4Minors(const Mat4<T>& m)
        : s0(m(0, 0) * m(1, 1) - m(1, 0) * m(0, 1)),
          s1(m(0, 0) * m(1, 2) - m(1, 0) * m(0, 2)),
          s2(m(0, 0) * m(1, 3) - m(1, 0) * m(0, 3)),
          s3(m(0, 1) * m(1, 2) - m(1, 1) * m(0, 2)),
          s4(m(0, 1) * m(1, 3) - m(1, 1) * m(0, 3)),
          s5(m(0, 2) * m(1, 3) - m(1, 2) * m(0, 3)),
          c0(m(2, 0) * m(3, 1) - m(3, 0) * m(2, 1)),
          c1(m(2, 0) * m(3, 2) - m(3, 0) * m(2, 2)),
          c2(m(2, 0) * m(3, 3) - m(3, 0) * m(2, 3)),
          c3(m(2, 1) * m(3, 2) - m(3, 1) * m(2, 2)),
          c4(m(2, 1) * m(3, 3) - m(3, 1) * m(2, 3)),
          c5(m(2, 2) * m(3, 3) - m(3, 2) * m(2, 3)) {}

    constexpr T determinant() const {
        return s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
    }
};

/// Length of row `r` of the upper-left `n` x `n` block.
template <typename T>
T rowLength(const Mat4<T>& m, int r, int n) {
    T sum = 0;
    for (int c = 0; c < n; ++c)
        sum += m(r, c) * m(r, c);
    return std::sqrt(sum);
}

/// True when `det` is too small, relative to the rows it came from, to trust its inverse;
/// Hadamard's inequality bounds |det| by the product of the row lengths.
template <typename T>
bool isSingular(const Mat4<T>& m, int n, T det) {
    T bound = 1;
    for (int r = 0; r < n; ++r)
        bound *= rowLength(m, r, n);
    const T tolerance = T(64) * std::numeric_limits<T>::epsilon() * bound;
    return !(std::abs(det) > tolerance) || !std::isfinite(bound) || !std::isfinite(det);
}

}  // namespace detail

template <typename T>
constexpr T Mat4<T>::determinant() const {
    return detail::Mat4Minors<T>(*this).determinant();
}

template <typename T>
constexpr T Mat4<T>::determinant3() const {
    const Mat4& m = *this;
    return m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) +
           m(0, 1) * (m(1, 2) * m(2, 0) - m(1, 0) * m(2, 2)) +
           m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
}

template <typename T>
Mat4<T> Mat4<T>::inverse() const {
    const Mat4& m = *this;
    Mat4 inv;
    if (isAffine()) {
        // Invert the 3x3 block by its adjugate: inv(r, c) = cofactor(c, r) / det.
        const T det = determinant3();
        if (detail::isSingular(m, 3, det)) {
            throw ValueError("Mat4::inverse: the matrix is singular or not finite");
        }
        const T k = T(1) / det;
        inv(0, 0) = k * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1));
        inv(1, 0) = k * (m(1, 2) * m(2, 0) - m(1, 0) * m(2, 2));
        inv(2, 0) = k * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
        inv(0, 1) = k * (m(0, 2) * m(2, 1) - m(0, 1) * m(2, 2));
        inv(1, 1) = k * (m(0, 0) * m(2, 2) - m(0, 2) * m(2, 0));
        inv(2, 1) = k * (m(0, 1) * m(2, 0) - m(0, 0) * m(2, 1));
        inv(0, 2) = k * (m(0, 1) * m(1, 2) - m(0, 2) * m(1, 1));
        inv(1, 2) = k * (m(0, 2) * m(1, 0) - m(0, 0) * m(1, 2));
        inv(2, 2) = k * (m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0));
        // The inverse translation is -t * inverse(block).
        inv.setTranslation(-inv.transformDirection(getTranslation()));
        inv(3, 3) = 1;
        return inv;
    }

    // General case: adjugate from the 2x2 minors of rows 0-1 and rows 2-3.
    const detail::Mat4Minors<T> n(m);
    const T det = n.determinant();
    if (detail::isSingular(m, 4, det)) {
        throw ValueError("Mat4::inverse: the matrix is singular or not finite");
    }
    const T k = T(1) / det;
    inv(0, 0) = k * (m(1, 1) * n.c5 - m(1, 2) * n.c4 + m(1, 3) * n.c3);
    inv(0, 1) = k * (-m(0, 1) * n.c5 + m(0, 2) * n.c4 - m(0, 3) * n.c3);
    inv(0, 2) = k * (m(3, 1) * n.s5 - m(3, 2) * n.s4 + m(3, 3) * n.s3);
    inv(0, 3) = k * (-m(2, 1) * n.s5 + m(2, 2) * n.s4 - m(2, 3) * n.s3);
    inv(1, 0) = k * (-m(1, 0) * n.c5 + m(1, 2) * n.c2 - m(1, 3) * n.c1);
    inv(1, 1) = k * (m(0, 0) * n.c5 - m(0, 2) * n.c2 + m(0, 3) * n.c1);
    inv(1, 2) = k * (-m(3, 0) * n.s5 + m(3, 2) * n.s2 - m(3, 3) * n.s1);
    inv(1, 3) = k * (m(2, 0) * n.s5 - m(2, 2) * n.s2 + m(2, 3) * n.s1);
    inv(2, 0) = k * (m(1, 0) * n.c4 - m(1, 1) * n.c2 + m(1, 3) * n.c0);
    inv(2, 1) = k * (-m(0, 0) * n.c4 + m(0, 1) * n.c2 - m(0, 3) * n.c0);
    inv(2, 2) = k * (m(3, 0) * n.s4 - m(3, 1) * n.s2 + m(3, 3) * n.s0);
    inv(2, 3) = k * (-m(2, 0) * n.s4 + m(2, 1) * n.s2 - m(2, 3) * n.s0);
    inv(3, 0) = k * (-m(1, 0) * n.c3 + m(1, 1) * n.c1 - m(1, 2) * n.c0);
    inv(3, 1) = k * (m(0, 0) * n.c3 - m(0, 1) * n.c1 + m(0, 2) * n.c0);
    inv(3, 2) = k * (-m(3, 0) * n.s3 + m(3, 1) * n.s1 - m(3, 2) * n.s0);
    inv(3, 3) = k * (m(2, 0) * n.s3 - m(2, 1) * n.s1 + m(2, 2) * n.s0);
    return inv;
}

}  // namespace math

using math::Mat4;
using math::Mat4d;
using math::Mat4R;
using math::Mat4s;

}  // namespace vdb
