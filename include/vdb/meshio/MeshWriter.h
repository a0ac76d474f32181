// SPDX-License-Identifier: Apache-2.0
/// @file
/// Writing polygon meshes to OBJ, PLY (binary) and STL (binary) files, for the meshes of
/// volumeToMesh() (tools/VolumeToMesh.h), the command-line tool and the tests.
///
/// Like MeshReader.h, this header belongs to the library target `vdb::meshio`, which encodes
/// files with the Open Asset Import Library (assimp); nothing of assimp shows here.
///
/// Files follow their formats' convention: faces wind counter-clockwise seen from outside, and
/// STL's facet normals point outward. volumeToMesh() keeps OpenVDB's opposite winding, so by
/// default writeMesh() reverses every face; a Mesh read from a file (readMesh()) already winds
/// the files' way and is written with Winding::CounterClockwise.
///
/// @code
/// vdb::meshio::Mesh mesh;
/// vdb::tools::volumeToMesh(*grid, mesh.points, mesh.triangles, mesh.quads);
/// vdb::meshio::writeMesh("surface.ply", mesh);  // reversed to the files' winding
/// @endcode

#pragma once

#include <vdb/meshio/MeshReader.h>

#include <string>

namespace vdb::meshio {

/// Which way the faces of a Mesh wind, seen from outside.
enum class Winding {
    Clockwise,         ///< volumeToMesh()'s (OpenVDB's) convention: right-hand normals inward
    CounterClockwise,  ///< the mesh files' convention and readMesh()'s: normals outward
};

/// The mesh file formats writeMesh() writes.
enum class MeshFormat {
    Obj,  ///< Wavefront OBJ, text: points, per-vertex normals, triangles and quads
    Ply,  ///< Stanford PLY, binary little-endian: points, per-vertex normals, polygons
    Stl,  ///< STL, binary: triangles (quads split) with outward facet normals
};

/// The format named by the extension of `path`: .obj, .ply or .stl, in any case.
/// @throw IoError naming the path when the extension is none of these.
MeshFormat meshFormatOf(const std::string& path);

/// Writes `mesh`, whose faces wind as `winding` says, to `path` in the format of its
/// extension (see MeshFormat), faces counter-clockwise seen from outside. Per-vertex normals
/// are the area-weighted means of the outward normals of the faces around each point. A mesh
/// without faces gives a valid file without points or faces.
///
/// The file is replaced as the `.vdb` writer replaces one: the whole file is encoded first,
/// written to a temporary file in the same folder and renamed over `path` when complete, so
/// that a failed or interrupted write leaves the old file (or nothing) behind. A symbolic link
/// is followed and its target replaced; an existing file keeps its permission bits; a device or
/// FIFO is written directly.
/// @throw ValueError when a face uses a point that does not exist or a point is not finite.
/// @throw IoError when the extension is not a known format or the file cannot be written; the
///        message names the file.
void writeMesh(const std::string& path, const Mesh& mesh, Winding winding = Winding::Clockwise);

}  // namespace vdb::meshio
