// SPDX-License-Identifier: Apache-2.0
/// @file
/// The analytic shapes of the volumeToMesh tests (sphere, torus, cube, two touching spheres, a
/// plate one voxel thick) in a 128^3 box, from the signed distances of LevelSetTestUtil.h;
/// narrow-band level sets sampled from them, and the mesh of a grid as a TestMesh. Shared by
/// the volumeToMesh, levelSetRebuild and OpenVDB compatibility tests.

#pragma once

#include <vdb/Grid.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/VolumeToMesh.h>

#include "LevelSetTestUtil.h"
#include "TestMeshes.h"

#include <algorithm>
#include <cmath>

namespace vdb::test {

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
                const double d = sdf(double(i), double(j), double(k));
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

inline double sdfAt(const Sdf& sdf, const Vec3d& p) {
    return sdf(p[0], p[1], p[2]);
}

/// The largest |sdf| over the points of `mesh`.
inline double largestDistance(const TestMesh& mesh, const Sdf& sdf) {
    double worst = 0.0;
    for (const Vec3s& p : mesh.points)
        worst = std::max(worst, std::abs(sdfAt(sdf, Vec3d(p))));
    return worst;
}

// ---- The shapes of the volumeToMesh tests, in the 128^3 box kBox128 ----

inline const CoordBBox kBox128(Coord(0), Coord(127));
inline const Sdf kSphere = sphereSdf(63.3, 64.1, 62.7, 40.0);
inline const Sdf kTorus = torusSdf(64.2, 63.7, 64.4, 36.0, 14.0);
/// A cube of edge 80.
inline const Sdf kCube = boxSdf(64.3, 63.8, 64.1, 40.0, 40.0, 40.0);
/// Two spheres of radius 30 that touch at one point.
inline const Sdf kTouchingSpheres = [](double x, double y, double z) {
    static const Sdf a = sphereSdf(34.2, 64.1, 63.8, 30.0), b = sphereSdf(94.2, 64.1, 63.8, 30.0);
    return std::min(a(x, y, z), b(x, y, z));
};
/// A plate 100 x 100 voxels and one voxel thick, centred on the plane z = 64.
inline const Sdf kPlate = boxSdf(64.3, 63.8, 64.0, 50.0, 50.0, 0.5);

}  // namespace vdb::test
