// SPDX-License-Identifier: Apache-2.0
/// @file
/// DDA: the digital differential analyser (3D Bresenham walk) along a ray in index space over
/// the cells of one uniform lattice. tree/HierarchicalDDA.h walks a VDB tree as a multilevel
/// DDA built on it (paper section 4.7).
///
/// Index space is node-centred: voxel (i, j, k) is the unit cube [i, i+1) x [j, j+1) x [k, k+1),
/// so a point p lies in voxel floor(p).
///
/// Threads: a DDA is a plain value; concurrent const calls are safe.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Vec3.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>

namespace vdb::math {

namespace detail {

/// The index of the smallest of three times (the first of equal ones).
template <typename RealT>
inline int argMin3(const std::array<RealT, 3>& t) {
    const int ab = t[1] < t[0] ? 1 : 0;
    return t[2] < t[ab] ? 2 : ab;
}

}  // namespace detail

/// Walks, in order, the cells that a ray crosses in the lattice of aligned cubes of 2^Log2Dim
/// voxels (Amanatides and Woo): cell c covers [c, c + 2^Log2Dim) on each axis, with each
/// component of c a multiple of 2^Log2Dim.
///
/// After init(), voxel() is the cell that holds the ray's start, time() the time the walk
/// entered it and next() the time it leaves it; step() moves to the following cell.
/// Threads: a plain value; concurrent const calls are safe.
template <typename RealT, Index Log2Dim = 0>
class DDA {
    static_assert(std::is_floating_point_v<RealT>, "a DDA walks a floating-point ray");
    static_assert(Log2Dim < 31, "a DDA cell must be smaller than the index space");

public:
    static constexpr Int32 DIM = Int32(1) << Log2Dim;

    DDA() = default;
    explicit DDA(const Ray<RealT>& ray) { init(ray, ray.t0(), ray.t1()); }
    DDA(const Ray<RealT>& ray, RealT startTime, RealT maxTime) { init(ray, startTime, maxTime); }

    /// Starts the walk at the point ray(startTime); the walk ends after maxTime.
    void init(const Ray<RealT>& ray, RealT startTime, RealT maxTime);

    /// Moves to the next cell along the ray and returns true, or returns false (and stays) when
    /// that cell starts after maxTime().
    bool step() {
        const int a = nextAxis();
        const RealT t = mNext[a];
        if (t > mMaxTime)
            return false;
        mTime = t;
        mVoxel[a] += mStep[a];
        mNext[a] += mDelta[a];
        return true;
    }

    /// The origin (smallest corner) of the current cell.
    const Coord& voxel() const { return mVoxel; }
    /// The time the ray entered the current cell (the start time for the first cell).
    RealT time() const { return mTime; }
    /// The time the ray leaves the current cell.
    RealT next() const { return mNext[nextAxis()]; }
    RealT maxTime() const { return mMaxTime; }

private:
    int nextAxis() const { return detail::argMin3(mNext); }

    Coord mVoxel;
    std::array<Int32, 3> mStep{};
    std::array<RealT, 3> mNext{}, mDelta{};
    RealT mTime = 0, mMaxTime = 0;
};

namespace detail {

/// floor(x) for x already limited to the Int32 range, without a call into libm (the x86-64
/// baseline has no rounding instruction): truncate, then step down for negative fractions.
inline Int64 floorInRange(double x) {
    const Int64 i = Int64(x);
    return i - Int64(double(i) > x);
}

/// floor(x) limited to [lo, hi]; NaN gives lo.
inline Int32 floorClamped(double x, Int32 lo, Int32 hi) {
    if (!(x >= double(lo)))
        return lo;
    if (x >= double(hi))
        return hi;
    return Int32(floorInRange(x));
}

}  // namespace detail

// ---- Implementation ---------------------------------------------------------------------------

template <typename RealT, Index Log2Dim>
void DDA<RealT, Log2Dim>::init(const Ray<RealT>& ray, RealT startTime, RealT maxTime) {
    mTime = startTime;
    mMaxTime = maxTime;
    const Vec3<RealT> pos = ray(startTime);
    constexpr Int32 lo = std::numeric_limits<Int32>::min(), hi = std::numeric_limits<Int32>::max();
    mVoxel = Coord(detail::floorClamped(double(pos[0]), lo, hi),
                   detail::floorClamped(double(pos[1]), lo, hi),
                   detail::floorClamped(double(pos[2]), lo, hi))
                 .alignedDown(Log2Dim);
    for (int i = 0; i < 3; ++i) {
        const RealT d = ray.dir()[i], inv = ray.invDir()[i];
        if (d > RealT(0)) {
            mStep[i] = DIM;
            mDelta[i] = RealT(DIM) * inv;
            mNext[i] = startTime + (RealT(mVoxel[i]) + RealT(DIM) - pos[i]) * inv;
        } else if (d < RealT(0)) {
            mStep[i] = -DIM;
            mDelta[i] = -RealT(DIM) * inv;
            mNext[i] = startTime + (RealT(mVoxel[i]) - pos[i]) * inv;
        } else {
            mStep[i] = 0;
            mDelta[i] = std::numeric_limits<RealT>::max();
            mNext[i] = std::numeric_limits<RealT>::max();
        }
    }
}

}  // namespace vdb::math
