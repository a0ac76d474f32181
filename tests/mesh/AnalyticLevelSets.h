// SPDX-License-Identifier: Apache-2.0
/// @file
/// Analytic signed distance functions in index space (sphere, torus, box, two touching
/// spheres) on a 128^3 box, narrow-band level sets sampled from them, and the mesh of a grid
/// as a TestMesh. Shared by the volumeToMesh tests and their OpenVDB compatibility test.

#pragma once

#include <vdb/Grid.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/VolumeToMesh.h>

#include "TestMeshes.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace vdb::test {

using Sdf = std::function<double(const Vec3d&)>;

/// A narrow-band level set of `sdf` (index space): exact distances within `halfWidth` voxels
/// over `box`, then the signed flood fill for the rest.
template <typename GridT = FloatGrid>
typename GridT::Ptr levelSetOf(const Sdf& sdf, const CoordBBox& box, double halfWidth = 3.0) {
    using ValueT = typename GridT::ValueType;
    auto grid = GridT::create(ValueT(halfWidth));
    grid->setGridClass(GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const double d = sdf(Vec3d(Coord(i, j, k)));
                if (std::abs(d) < halfWidth)
                    acc.setValue(Coord(i, j, k), ValueT(d));
            }
    tools::signedFloodFill(grid->tree());
    return grid;
}

template <typename GridT>
TestMesh meshOf(const GridT& grid, double isovalue = 0.0, double adaptivity = 0.0,
                bool relax = true) {
    TestMesh mesh;
    tools::volumeToMesh(grid, mesh.points, mesh.triangles, mesh.quads, isovalue, adaptivity, relax);
    return mesh;
}

/// The largest |sdf| over the points of `mesh`.
inline double largestDistance(const TestMesh& mesh, const Sdf& sdf) {
    double worst = 0.0;
    for (const Vec3s& p : mesh.points)
        worst = std::max(worst, std::abs(sdf(Vec3d(p))));
    return worst;
}

inline const CoordBBox kBox128(Coord(0), Coord(127));

inline double sphereSdf(const Vec3d& p) {
    return (p - Vec3d(63.3, 64.1, 62.7)).length() - 40.0;
}
inline double torusSdf(const Vec3d& x) {
    const Vec3d p = x - Vec3d(64.2, 63.7, 64.4);
    const double q = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 36.0;
    return std::sqrt(q * q + p[2] * p[2]) - 14.0;
}
inline double boxSdf(const Vec3d& p, const Vec3d& center, const Vec3d& half) {
    const Vec3d q =
        Vec3d(std::abs(p[0] - center[0]), std::abs(p[1] - center[1]), std::abs(p[2] - center[2])) -
        half;
    return Vec3d::maxComponent(q, Vec3d(0.0)).length() + std::min(q.maxComponent(), 0.0);
}
/// The cube of edge 80 in the middle of the 128^3 box.
inline double cubeSdf(const Vec3d& p) {
    return boxSdf(p, Vec3d(64.3, 63.8, 64.1), Vec3d(40.0));
}
inline double touchingSpheresSdf(const Vec3d& p) {
    return std::min((p - Vec3d(34.2, 64.1, 63.8)).length() - 30.0,
                    (p - Vec3d(94.2, 64.1, 63.8)).length() - 30.0);
}

}  // namespace vdb::test
