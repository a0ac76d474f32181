// SPDX-License-Identifier: Apache-2.0
/// @file
/// Reading polygon meshes from OBJ, PLY (ASCII and binary), STL (ASCII and binary) and OFF
/// files, for meshToLevelSet() (tools/MeshToVolume.h), the command-line tool and the tests.
///
/// This header belongs to the separate library target `vdb::meshio`, which parses files with
/// the Open Asset Import Library (assimp); the core library `vdb::vdb` does not depend on it,
/// and nothing of assimp shows in this header.
///
/// @code
/// const vdb::meshio::Mesh mesh = vdb::meshio::readMesh("bunny.ply");
/// auto xform = vdb::math::Transform::createLinearTransform(0.001);
/// auto grid = vdb::tools::meshToLevelSet<vdb::FloatGrid>(*xform, mesh.points, mesh.triangles,
///                                                       mesh.quads);
/// @endcode

#pragma once

#include <vdb/math/Vec3.h>

#include <string>
#include <vector>

namespace vdb::meshio {

/// A polygon mesh: points, triangles and quads indexing into `points`.
///
/// Invariants after readMesh(): at least one triangle or quad; every index is below
/// points.size(); every coordinate is finite. Degenerate faces (repeated or collinear
/// vertices) are kept as they are.
struct Mesh {
    std::vector<Vec3s> points;
    std::vector<Vec3I> triangles;
    std::vector<Vec4I> quads;
};

/// Reads the mesh in the file at `path`; the format is recognised by the file's contents and
/// extension (.obj, .ply, .stl, .off). Every mesh of the file goes into one Mesh, placed by the
/// transforms of the file's scene graph. Vertices at the same position are merged (STL stores
/// each triangle's corners separately; assimp splits files into several meshes that each hold
/// their copy of a shared vertex). Faces of more than
/// four vertices are split into a fan of triangles; points and lines are ignored.
/// @throw IoError when the file cannot be read, is empty or malformed (truncated, counts that
///        do not match the data, indices out of range), holds no face, or has a coordinate
///        that is not finite (NaN or infinite). The message names the file and the problem.
Mesh readMesh(const std::string& path);

}  // namespace vdb::meshio
