// SPDX-License-Identifier: Apache-2.0
/// @file
/// A slab test of a ray against one cube: the oracle of the DDA tests, which compare the cells
/// a walk reports with the cubes the ray meets one by one.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Ray.h>

namespace vdb::test {

/// The time span [a, b] during which `ray` (restricted to [t0, t1]) lies in the closed cube of
/// edge `dim` at `origin`; false when it misses. With `shrink` > 0 the cube is first shrunk by
/// that much on every side, so that rays along its faces do not count.
inline bool rayCubeOverlap(const math::Ray<double>& ray, double t0, double t1, const Coord& origin,
                           Int64 dim, double& a, double& b, double shrink = 0.0) {
    const math::Vec3d lo(origin);
    const math::BBoxd cube(lo + shrink, lo + (double(dim) - shrink));
    const math::Ray<double> r(ray.eye(), ray.dir(), t0, t1);
    return r.intersects(cube, a, b);
}

}  // namespace vdb::test
