// SPDX-License-Identifier: Apache-2.0
/// @file
/// Coord, a signed 32-bit index-space coordinate, and CoordBBox, an inclusive box of them.

#pragma once

#include <vdb/Types.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <ostream>

namespace vdb {
namespace math {

/// A point of the integer index-space lattice: three signed 32-bit components.
///
/// Every key and offset in a VDB tree is derived from a Coord by bit operations, so negative
/// components need no special handling (two's complement does the work).
class Coord {
public:
    using ValueType = Int32;

    constexpr Coord() = default;
    constexpr explicit Coord(Int32 xyz) : mVec{xyz, xyz, xyz} {}
    constexpr Coord(Int32 x, Int32 y, Int32 z) : mVec{x, y, z} {}

    constexpr Int32 x() const { return mVec[0]; }
    constexpr Int32 y() const { return mVec[1]; }
    constexpr Int32 z() const { return mVec[2]; }
    constexpr Int32& x() { return mVec[0]; }
    constexpr Int32& y() { return mVec[1]; }
    constexpr Int32& z() { return mVec[2]; }
    constexpr Int32 operator[](size_t i) const { return mVec[i]; }
    constexpr Int32& operator[](size_t i) { return mVec[i]; }
    constexpr const Int32* data() const { return mVec.data(); }

    constexpr Coord& reset(Int32 x, Int32 y, Int32 z) {
        mVec = {x, y, z};
        return *this;
    }

    /// Returns this coordinate moved by (dx, dy, dz).
    constexpr Coord offsetBy(Int32 dx, Int32 dy, Int32 dz) const {
        return Coord(wrapAdd(mVec[0], dx), wrapAdd(mVec[1], dy), wrapAdd(mVec[2], dz));
    }
    constexpr Coord offsetBy(Int32 d) const { return offsetBy(d, d, d); }

    /// Moves this coordinate by (dx, dy, dz) in place.
    constexpr Coord& offset(Int32 dx, Int32 dy, Int32 dz) { return *this = offsetBy(dx, dy, dz); }

    /// Clears the low bits of every component: the origin of the aligned block of 2^log2
    /// voxels per axis that holds this coordinate.
    constexpr Coord alignedDown(Index log2) const {
        const Int32 m = ~((Int32(1) << log2) - 1);
        return Coord(mVec[0] & m, mVec[1] & m, mVec[2] & m);
    }

    constexpr Coord operator+(const Coord& o) const { return offsetBy(o[0], o[1], o[2]); }
    constexpr Coord operator-(const Coord& o) const {
        return Coord(wrapSub(mVec[0], o[0]), wrapSub(mVec[1], o[1]), wrapSub(mVec[2], o[2]));
    }
    constexpr Coord operator-() const { return Coord() - *this; }
    constexpr Coord& operator+=(const Coord& o) { return *this = *this + o; }
    constexpr Coord& operator-=(const Coord& o) { return *this = *this - o; }
    constexpr Coord operator&(Int32 m) const {
        return Coord(mVec[0] & m, mVec[1] & m, mVec[2] & m);
    }
    constexpr Coord operator<<(Index n) const {
        return Coord(Int32(Index(mVec[0]) << n), Int32(Index(mVec[1]) << n),
                     Int32(Index(mVec[2]) << n));
    }
    constexpr Coord operator>>(Index n) const {
        return Coord(mVec[0] >> n, mVec[1] >> n, mVec[2] >> n);
    }

    constexpr bool operator==(const Coord& o) const {
        // One test instead of three branches: equal iff no bit differs.
        return ((mVec[0] ^ o.mVec[0]) | (mVec[1] ^ o.mVec[1]) | (mVec[2] ^ o.mVec[2])) == 0;
    }

    /// Lexicographic order on (x, y, z); the order of OpenVDB's root table and file layout.
    constexpr bool operator<(const Coord& o) const {
        return mVec[0] != o[0] ? mVec[0] < o[0] : mVec[1] != o[1] ? mVec[1] < o[1] : mVec[2] < o[2];
    }
    constexpr bool operator>(const Coord& o) const { return o < *this; }
    constexpr bool operator<=(const Coord& o) const { return !(o < *this); }
    constexpr bool operator>=(const Coord& o) const { return !(*this < o); }

    /// Componentwise minimum and maximum.
    static constexpr Coord minComponent(const Coord& a, const Coord& b) {
        return Coord(std::min(a[0], b[0]), std::min(a[1], b[1]), std::min(a[2], b[2]));
    }
    static constexpr Coord maxComponent(const Coord& a, const Coord& b) {
        return Coord(std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2]));
    }
    constexpr Int32 minComponent() const { return std::min({mVec[0], mVec[1], mVec[2]}); }
    constexpr Int32 maxComponent() const { return std::max({mVec[0], mVec[1], mVec[2]}); }

    static constexpr Coord min() { return Coord(std::numeric_limits<Int32>::min()); }
    static constexpr Coord max() { return Coord(std::numeric_limits<Int32>::max()); }

    /// A 32-bit hash of the coordinate (Teschner et al.'s large-prime XOR, as the paper's root
    /// table uses); callers keep the low bits.
    constexpr uint32_t hash() const {
        return (uint32_t(mVec[0]) * 73856093u) ^ (uint32_t(mVec[1]) * 19349663u) ^
               (uint32_t(mVec[2]) * 83492791u);
    }

private:
    // Two's-complement wrap-around, without signed-overflow UB.
    static constexpr Int32 wrapAdd(Int32 a, Int32 b) { return Int32(uint32_t(a) + uint32_t(b)); }
    static constexpr Int32 wrapSub(Int32 a, Int32 b) { return Int32(uint32_t(a) - uint32_t(b)); }

    std::array<Int32, 3> mVec{0, 0, 0};
};

inline std::ostream& operator<<(std::ostream& os, const Coord& ijk) {
    return os << '[' << ijk[0] << ", " << ijk[1] << ", " << ijk[2] << ']';
}

/// An axis-aligned box of index-space coordinates, both corners inclusive.
///
/// A box is empty when any component of min() exceeds the same component of max(); the default
/// box is empty (min = +INT_MAX, max = -INT_MAX) so that expand() from it yields the point.
class CoordBBox {
public:
    constexpr CoordBBox() : mMin(Coord::max()), mMax(Coord::min()) {}
    constexpr CoordBBox(const Coord& min, const Coord& max) : mMin(min), mMax(max) {}
    constexpr CoordBBox(Int32 xMin, Int32 yMin, Int32 zMin, Int32 xMax, Int32 yMax, Int32 zMax)
        : mMin(xMin, yMin, zMin), mMax(xMax, yMax, zMax) {}

    /// The box of `dim` voxels per axis whose smallest corner is `min`.
    static constexpr CoordBBox createCube(const Coord& min, Int32 dim) {
        return CoordBBox(min, min.offsetBy(dim - 1));
    }
    /// The largest representable box.
    static constexpr CoordBBox inf() { return CoordBBox(Coord::min(), Coord::max()); }

    constexpr const Coord& min() const { return mMin; }
    constexpr const Coord& max() const { return mMax; }
    constexpr Coord& min() { return mMin; }
    constexpr Coord& max() { return mMax; }

    constexpr bool empty() const {
        return mMin[0] > mMax[0] || mMin[1] > mMax[1] || mMin[2] > mMax[2];
    }
    constexpr explicit operator bool() const { return !empty(); }
    constexpr void reset() { *this = CoordBBox(); }
    constexpr void reset(const Coord& min, const Coord& max) {
        mMin = min;
        mMax = max;
    }

    /// Number of voxels along each axis (as signed 64-bit, so the full 32-bit range fits).
    constexpr std::array<Int64, 3> extents() const {
        if (empty())
            return {0, 0, 0};
        return {Int64(mMax[0]) - mMin[0] + 1, Int64(mMax[1]) - mMin[1] + 1,
                Int64(mMax[2]) - mMin[2] + 1};
    }
    /// Number of voxels along each axis as a Coord. @pre each extent fits in 32 bits.
    constexpr Coord dim() const {
        const auto e = extents();
        return Coord(Int32(e[0]), Int32(e[1]), Int32(e[2]));
    }
    /// Number of voxels in the box (0 when empty). Boxes of 2^64 voxels or more wrap modulo
    /// 2^64 (only boxes spanning the full 32-bit range on every axis come close).
    constexpr Index64 volume() const {
        const auto e = extents();
        return Index64(e[0]) * Index64(e[1]) * Index64(e[2]);
    }

    constexpr bool isInside(const Coord& ijk) const {
        return mMin[0] <= ijk[0] && ijk[0] <= mMax[0] && mMin[1] <= ijk[1] && ijk[1] <= mMax[1] &&
               mMin[2] <= ijk[2] && ijk[2] <= mMax[2];
    }
    /// True when `b` lies entirely inside this box.
    constexpr bool isInside(const CoordBBox& b) const {
        return isInside(b.mMin) && isInside(b.mMax);
    }
    constexpr bool hasOverlap(const CoordBBox& b) const {
        return mMin[0] <= b.mMax[0] && b.mMin[0] <= mMax[0] && mMin[1] <= b.mMax[1] &&
               b.mMin[1] <= mMax[1] && mMin[2] <= b.mMax[2] && b.mMin[2] <= mMax[2];
    }

    /// Grows the box to hold `ijk`.
    constexpr void expand(const Coord& ijk) {
        mMin = Coord::minComponent(mMin, ijk);
        mMax = Coord::maxComponent(mMax, ijk);
    }
    /// Grows the box to hold `b`.
    constexpr void expand(const CoordBBox& b) {
        if (b.empty())
            return;
        mMin = Coord::minComponent(mMin, b.mMin);
        mMax = Coord::maxComponent(mMax, b.mMax);
    }
    /// Grows the box by `padding` voxels on every side.
    constexpr void expand(Int32 padding) {
        mMin = mMin.offsetBy(-padding);
        mMax = mMax.offsetBy(padding);
    }
    /// Shrinks this box to its intersection with `b`.
    constexpr void intersect(const CoordBBox& b) {
        mMin = Coord::maxComponent(mMin, b.mMin);
        mMax = Coord::minComponent(mMax, b.mMax);
    }
    constexpr void translate(const Coord& t) {
        mMin += t;
        mMax += t;
    }

    constexpr bool operator==(const CoordBBox& o) const = default;

private:
    Coord mMin, mMax;
};

inline std::ostream& operator<<(std::ostream& os, const CoordBBox& b) {
    return os << b.min() << " -> " << b.max();
}

}  // namespace math

using math::Coord;
using math::CoordBBox;

}  // namespace vdb

template <>
struct std::hash<vdb::math::Coord> {
    size_t operator()(const vdb::math::Coord& ijk) const noexcept { return ijk.hash(); }
};
