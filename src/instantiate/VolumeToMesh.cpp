// SPDX-License-Identifier: Apache-2.0
// Isosurface meshing for FloatGrid and DoubleGrid, instantiated once; the header declares these
// `extern template`. Also the type-erased entry point.

#include <vdb/tools/VolumeToMesh.h>

namespace vdb::tools {

template void volumeToMesh(const FloatGrid&, std::vector<Vec3s>&, std::vector<Vec3I>&,
                           std::vector<Vec4I>&, double, double, bool);
template void volumeToMesh(const DoubleGrid&, std::vector<Vec3s>&, std::vector<Vec3I>&,
                           std::vector<Vec4I>&, double, double, bool);
template void volumeToMesh(const FloatGrid&, std::vector<Vec3s>&, std::vector<Vec4I>&, double);
template void volumeToMesh(const DoubleGrid&, std::vector<Vec3s>&, std::vector<Vec4I>&, double);

void volumeToMesh(const GridBase& grid, std::vector<Vec3s>& points, std::vector<Vec3I>& triangles,
                  std::vector<Vec4I>& quads, double isovalue, double adaptivity,
                  bool relaxDisorientedTriangles) {
    if (const auto* g = dynamic_cast<const FloatGrid*>(&grid))
        return volumeToMesh(*g, points, triangles, quads, isovalue, adaptivity,
                            relaxDisorientedTriangles);
    if (const auto* g = dynamic_cast<const DoubleGrid*>(&grid))
        return volumeToMesh(*g, points, triangles, quads, isovalue, adaptivity,
                            relaxDisorientedTriangles);
    throw TypeError("volumeToMesh: grid \"" + grid.getName() + "\" has values of type " +
                    grid.valueType() + "; meshing needs a scalar grid of float or double values");
}

}  // namespace vdb::tools
