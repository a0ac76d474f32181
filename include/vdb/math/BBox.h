// SPDX-License-Identifier: Apache-2.0
/// @file
/// BBox<Vec3T>, an axis-aligned box with real-valued corners (world space, or continuous index
/// space), and its alias BBoxd.

#pragma once

#include <vdb/math/Coord.h>
#include <vdb/math/Vec3.h>

#include <limits>
#include <ostream>
#include <type_traits>

namespace vdb {
namespace math {

/// The closed box [min(), max()] of real-valued points.
///
/// The box is empty when any component of min() exceeds the same component of max(). The
/// default box is empty (min = +largest, max = -largest), so that expand() from it yields the
/// point; a box with min() == max() holds exactly one point and is not empty.
///
/// The layout is the two corners, packed (BBoxd is the six doubles of a frustum map in a file).
/// Threads: a plain value; concurrent const calls are safe.
template <typename Vec3T>
class BBox {
public:
    using Vec3Type = Vec3T;
    using ValueType = typename Vec3T::ValueType;
    static_assert(std::is_floating_point_v<ValueType>, "a BBox has real-valued corners");

    constexpr BBox()
        : mMin(std::numeric_limits<ValueType>::max()),
          mMax(std::numeric_limits<ValueType>::lowest()) {}
    constexpr BBox(const Vec3T& min, const Vec3T& max) : mMin(min), mMax(max) {}
    /// The box spanned by the centers of the corner voxels of `b` (an empty `b` gives an empty
    /// box).
    constexpr explicit BBox(const CoordBBox& b) : BBox() {
        if (!b.empty())
            *this = BBox(Vec3T(b.min()), Vec3T(b.max()));
    }

    constexpr const Vec3T& min() const { return mMin; }
    constexpr const Vec3T& max() const { return mMax; }
    constexpr Vec3T& min() { return mMin; }
    constexpr Vec3T& max() { return mMax; }

    constexpr bool empty() const {
        return !(mMin[0] <= mMax[0] && mMin[1] <= mMax[1] && mMin[2] <= mMax[2]);
    }
    constexpr explicit operator bool() const { return !empty(); }
    constexpr void reset() { *this = BBox(); }

    /// Returns max() - min(): the edge lengths (zero when empty).
    constexpr Vec3T extents() const { return empty() ? Vec3T(0) : mMax - mMin; }
    /// Returns the midpoint of the box. @pre !empty()
    constexpr Vec3T center() const { return (mMin + mMax) * ValueType(0.5); }
    /// Returns the product of the extents (zero when empty).
    constexpr ValueType volume() const { return extents().product(); }

    /// True when `xyz` lies in the closed box.
    constexpr bool isInside(const Vec3T& xyz) const {
        return mMin[0] <= xyz[0] && xyz[0] <= mMax[0] && mMin[1] <= xyz[1] && xyz[1] <= mMax[1] &&
               mMin[2] <= xyz[2] && xyz[2] <= mMax[2];
    }
    /// True when `b` lies entirely inside this box.
    constexpr bool isInside(const BBox& b) const { return isInside(b.mMin) && isInside(b.mMax); }
    /// True when the two closed boxes share at least one point (touching faces count).
    constexpr bool hasOverlap(const BBox& b) const {
        return mMin[0] <= b.mMax[0] && b.mMin[0] <= mMax[0] && mMin[1] <= b.mMax[1] &&
               b.mMin[1] <= mMax[1] && mMin[2] <= b.mMax[2] && b.mMin[2] <= mMax[2];
    }

    /// Grows the box to hold `xyz`.
    constexpr void expand(const Vec3T& xyz) {
        mMin = Vec3T::minComponent(mMin, xyz);
        mMax = Vec3T::maxComponent(mMax, xyz);
    }
    /// Grows the box to hold `b`.
    constexpr void expand(const BBox& b) {
        if (b.empty())
            return;
        expand(b.mMin);
        expand(b.mMax);
    }
    /// Grows the box by `padding` on every side.
    constexpr void expand(ValueType padding) {
        mMin -= padding;
        mMax += padding;
    }
    /// Shrinks this box to its intersection with `b` (empty when they do not overlap).
    constexpr void intersect(const BBox& b) {
        mMin = Vec3T::maxComponent(mMin, b.mMin);
        mMax = Vec3T::minComponent(mMax, b.mMax);
    }
    constexpr void translate(const Vec3T& t) {
        mMin += t;
        mMax += t;
    }

    constexpr bool operator==(const BBox&) const = default;

private:
    Vec3T mMin, mMax;
};

template <typename Vec3T>
std::ostream& operator<<(std::ostream& os, const BBox<Vec3T>& b) {
    return os << b.min() << " -> " << b.max();
}

using BBoxd = BBox<Vec3d>;
using BBoxs = BBox<Vec3s>;

static_assert(sizeof(BBoxd) == 48 && std::is_trivially_copyable_v<BBoxd>);

}  // namespace math

using math::BBox;
using math::BBoxd;

}  // namespace vdb
