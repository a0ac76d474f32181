// SPDX-License-Identifier: Apache-2.0
/// @file
/// Ray<RealT>: the points eye + t * dir for t in [t0, t1], with the slab test against
/// axis-aligned boxes and conversion between index and world space.
///
/// @code
/// vdb::math::Ray<double> ray(vdb::Vec3d(0, 0, -10), vdb::Vec3d(0, 0, 1));
/// double t0, t1;
/// if (ray.intersects(vdb::BBoxd(vdb::Vec3d(-1), vdb::Vec3d(1)), t0, t1)) {
///     // the ray is inside the box for t in [t0, t1] = [9, 11]
/// }
/// auto indexRay = ray.worldToIndex(grid.transform());  // same points, index-space times
/// @endcode

#pragma once

#include <vdb/math/BBox.h>
#include <vdb/math/Math.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>

#include <limits>
#include <ostream>
#include <type_traits>
#include <utility>

namespace vdb {
namespace math {

/// The points eye() + t * dir() for t in [t0(), t1()].
///
/// The direction need not be unit length, and the constructor does not normalize it; invDir()
/// caches its componentwise reciprocal (infinite for zero components) for the slab test.
/// The default time span starts at Delta<RealT> (so that a ray cast from a surface does not
/// hit it at t = 0) and has no end (t1 = the largest RealT).
///
/// Threads: a plain value; concurrent const calls are safe.
template <typename RealT>
class Ray {
    static_assert(std::is_floating_point_v<RealT>, "a Ray has floating-point coordinates");

public:
    using RealType = RealT;
    using Vec3Type = Vec3<RealT>;
    using Vec3T = Vec3Type;
    using BBoxType = BBox<Vec3Type>;

    explicit Ray(const Vec3Type& eye = Vec3Type(0), const Vec3Type& dir = Vec3Type(1, 0, 0),
                 RealT t0 = Delta<RealT>::value(), RealT t1 = std::numeric_limits<RealT>::max())
        : mEye(eye), mDir(dir), mInvDir(RealT(1) / dir), mT0(t0), mT1(t1) {}

    const Vec3Type& eye() const { return mEye; }
    const Vec3Type& dir() const { return mDir; }
    /// The componentwise reciprocal of dir() (±infinity where dir() is zero).
    const Vec3Type& invDir() const { return mInvDir; }
    RealT t0() const { return mT0; }
    RealT t1() const { return mT1; }

    void setEye(const Vec3Type& eye) { mEye = eye; }
    void setDir(const Vec3Type& dir) {
        mDir = dir;
        mInvDir = RealT(1) / dir;
    }
    void setMinTime(RealT t0) { mT0 = t0; }
    void setMaxTime(RealT t1) { mT1 = t1; }
    void setTimes(RealT t0 = Delta<RealT>::value(), RealT t1 = std::numeric_limits<RealT>::max()) {
        mT0 = t0;
        mT1 = t1;
    }
    void reset(const Vec3Type& eye, const Vec3Type& dir, RealT t0 = Delta<RealT>::value(),
               RealT t1 = std::numeric_limits<RealT>::max()) {
        *this = Ray(eye, dir, t0, t1);
    }

    /// Returns the point at time `t`: eye + t * dir.
    Vec3Type operator()(RealT t) const { return mEye + mDir * t; }
    Vec3Type start() const { return (*this)(mT0); }
    Vec3Type end() const { return (*this)(mT1); }
    /// True when `t` lies in [t0, t1].
    bool test(RealT t) const { return mT0 <= t && t <= mT1; }
    /// True when the time span is longer than `eps`.
    bool valid(RealT eps = Delta<RealT>::value()) const { return mT0 + eps < mT1; }

    /// Slab test against the closed box `bbox`. On a hit, returns true with [t0, t1] the part
    /// of this ray's time span inside the box (t0 == t1 when it only touches the box);
    /// otherwise returns false and leaves t0 and t1 unspecified. Rays parallel to a slab and
    /// lying on its boundary count as inside it.
    bool intersects(const BBoxType& bbox, RealT& t0, RealT& t1) const;
    bool intersects(const BBoxType& bbox) const {
        RealT t0, t1;
        return intersects(bbox, t0, t1);
    }
    /// Shrinks the time span to the part inside `bbox` and returns true, or returns false and
    /// leaves the ray unchanged when it misses the box.
    bool clip(const BBoxType& bbox) {
        RealT t0, t1;
        if (!intersects(bbox, t0, t1))
            return false;
        mT0 = t0;
        mT1 = t1;
        return true;
    }

    /// Returns this world-space ray in the index space of `xform`: the eye and direction are
    /// mapped, the direction is then normalized, and the times are scaled so that every time
    /// names the image of the same point (an unbounded t1 stays unbounded).
    /// @throw ValueError for frustum transforms (the image of a ray is not a ray).
    Ray worldToIndex(const Transform& xform) const;
    /// Returns this index-space ray in world space; the inverse of worldToIndex().
    /// @throw ValueError for frustum transforms.
    Ray indexToWorld(const Transform& xform) const;

private:
    // Maps the ray through a linear map given as point and direction images.
    template <typename PointMapT, typename DirMapT>
    Ray mapped(const PointMapT& mapPoint, const DirMapT& mapDir) const;

    Vec3Type mEye, mDir, mInvDir;
    RealT mT0, mT1;
};

template <typename RealT>
std::ostream& operator<<(std::ostream& os, const Ray<RealT>& ray) {
    return os << "eye=" << ray.eye() << " dir=" << ray.dir() << " 1/dir=" << ray.invDir()
              << " t0=" << ray.t0() << " t1=" << ray.t1();
}

// ---- Implementation ---------------------------------------------------------------------------

template <typename RealT>
bool Ray<RealT>::intersects(const BBoxType& bbox, RealT& t0, RealT& t1) const {
    t0 = mT0;
    t1 = mT1;
    for (int i = 0; i < 3; ++i) {
        // Entry and exit times of slab i. A zero direction component gives ±infinity (the ray
        // is entirely inside or outside the slab), or NaN when the eye is on the slab's plane;
        // the comparisons below skip NaN, treating that slab as no constraint.
        RealT a = (bbox.min()[i] - mEye[i]) * mInvDir[i];
        RealT b = (bbox.max()[i] - mEye[i]) * mInvDir[i];
        if (a > b)
            std::swap(a, b);
        if (a > t0)
            t0 = a;
        if (b < t1)
            t1 = b;
        if (t0 > t1)
            return false;
    }
    return true;
}

template <typename RealT>
template <typename PointMapT, typename DirMapT>
Ray<RealT> Ray<RealT>::mapped(const PointMapT& mapPoint, const DirMapT& mapDir) const {
    const Vec3d dir = mapDir(Vec3d(mDir));
    const Vec3d eye = mapPoint(Vec3d(mEye));
    const double length = dir.length();
    // The point at time t maps to eye' + t * dir' = eye' + (t * length) * (dir' / length).
    // Clamping keeps the conversion back to RealT defined.
    const auto scaleTime = [length](RealT t) {
        using Limits = std::numeric_limits<RealT>;
        if (t == Limits::max())
            return t;
        return RealT(clamp(double(t) * length, double(Limits::lowest()), double(Limits::max())));
    };
    return Ray(Vec3Type(eye), Vec3Type(dir / length), scaleTime(mT0), scaleTime(mT1));
}

template <typename RealT>
Ray<RealT> Ray<RealT>::worldToIndex(const Transform& xform) const {
    if (!xform.isLinear())
        detail::frustumUnsupported("Ray::worldToIndex");
    return mapped([&](const Vec3d& p) { return xform.worldToIndex(p); },
                  [&](const Vec3d& v) { return xform.worldToIndexDirection(v); });
}

template <typename RealT>
Ray<RealT> Ray<RealT>::indexToWorld(const Transform& xform) const {
    if (!xform.isLinear())
        detail::frustumUnsupported("Ray::indexToWorld");
    return mapped([&](const Vec3d& p) { return xform.indexToWorld(p); },
                  [&](const Vec3d& v) { return xform.indexToWorldDirection(v); });
}

}  // namespace math
}  // namespace vdb
