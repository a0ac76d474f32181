// SPDX-License-Identifier: Apache-2.0
// Mesh export through assimp (library target vdb::meshio).

#include <vdb/Exceptions.h>
#include <vdb/meshio/MeshWriter.h>
#include <vdb/util/OutputFile.h>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace vdb::meshio {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw IoError("writeMesh: " + path + ": " + what);
}

/// Replaces the file at `path` with `size` bytes at `data` through util::OutputFile (an atomic
/// replace of a regular file, links written through, devices and FIFOs written directly).
void writeFileReplacing(const std::string& path, const uint8_t* data, size_t size) {
    try {
        util::writeOutputFile(path, [&](util::OutputFile& out) { out.write(data, size); });
    } catch (const IoError& e) {
        throw IoError(std::string("writeMesh: ") + e.what());  // it names the path
    }
}

/// The mesh as one assimp mesh, faces counter-clockwise seen from outside. For STL every
/// triangle gets its own three corners, whose normals are the facet's normal (assimp's STL
/// exporter writes the mean of a facet's vertex normals); otherwise points are shared and carry
/// the area-weighted mean normal of their faces.
std::unique_ptr<aiScene> buildScene(const Mesh& mesh, Winding winding, MeshFormat format) {
    const bool reverse = winding == Winding::Clockwise;
    // Faces as index lists, in the files' winding.
    std::vector<std::array<uint32_t, 4>> faces;  // a triangle's fourth index is ~0
    faces.reserve(mesh.triangles.size() + mesh.quads.size());
    constexpr uint32_t none = ~uint32_t(0);
    // Reversed faces keep their first corner, so a quad keeps its (0, 2) diagonal.
    for (const Vec3I& t : mesh.triangles)
        faces.push_back(reverse ? std::array<uint32_t, 4>{t[0], t[2], t[1], none}
                                : std::array<uint32_t, 4>{t[0], t[1], t[2], none});
    for (const Vec4I& q : mesh.quads) {
        if (format == MeshFormat::Stl) {
            // Split along the (0, 2) diagonal, as meshToVolume() does.
            const Vec3I a(q[0], q[1], q[2]), b(q[0], q[2], q[3]);
            for (const Vec3I& t : {a, b})
                faces.push_back(reverse ? std::array<uint32_t, 4>{t[0], t[2], t[1], none}
                                        : std::array<uint32_t, 4>{t[0], t[1], t[2], none});
        } else {
            faces.push_back(reverse ? std::array<uint32_t, 4>{q[0], q[3], q[2], q[1]}
                                    : std::array<uint32_t, 4>{q[0], q[1], q[2], q[3]});
        }
    }
    const auto corners = [](const std::array<uint32_t, 4>& f) { return f[3] == none ? 3u : 4u; };
    // A face's outward normal, scaled by twice its area (quads: the mean of their two halves).
    const auto faceNormal = [&](const std::array<uint32_t, 4>& f) {
        const Vec3d a(mesh.points[f[0]]), b(mesh.points[f[1]]), c(mesh.points[f[2]]);
        Vec3d n = (b - a).cross(c - a);
        if (f[3] != none)
            n += (c - a).cross(Vec3d(mesh.points[f[3]]) - a);
        return n;
    };

    auto scene = std::make_unique<aiScene>();
    scene->mRootNode = new aiNode();
    scene->mMaterials = new aiMaterial* [1] { new aiMaterial() };
    scene->mNumMaterials = 1;
    scene->mMeshes = new aiMesh* [1] { new aiMesh() };
    scene->mNumMeshes = 1;
    scene->mRootNode->mMeshes = new unsigned[1]{0};
    scene->mRootNode->mNumMeshes = 1;
    aiMesh& out = *scene->mMeshes[0];
    out.mMaterialIndex = 0;
    out.mPrimitiveTypes = aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON;
    out.mFaces = new aiFace[faces.size()];
    out.mNumFaces = unsigned(faces.size());
    const auto toAi = [](const Vec3d& v) {
        return aiVector3D(ai_real(v[0]), ai_real(v[1]), ai_real(v[2]));
    };

    if (format == MeshFormat::Stl) {
        out.mNumVertices = unsigned(3 * faces.size());
        out.mVertices = new aiVector3D[out.mNumVertices];
        out.mNormals = new aiVector3D[out.mNumVertices];
        for (size_t f = 0; f < faces.size(); ++f) {
            const Vec3d n = faceNormal(faces[f]).unitSafe();
            aiFace& face = out.mFaces[f];
            face.mNumIndices = 3;
            face.mIndices = new unsigned[3];
            for (unsigned k = 0; k < 3; ++k) {
                const unsigned v = unsigned(3 * f + k);
                out.mVertices[v] = toAi(Vec3d(mesh.points[faces[f][k]]));
                out.mNormals[v] = toAi(n);
                face.mIndices[k] = v;
            }
        }
        return scene;
    }

    std::vector<Vec3d> normals(mesh.points.size(), Vec3d(0.0));
    for (const auto& f : faces) {
        const Vec3d n = faceNormal(f);
        for (unsigned k = 0; k < corners(f); ++k)
            normals[f[k]] += n;
    }
    out.mNumVertices = unsigned(mesh.points.size());
    out.mVertices = new aiVector3D[out.mNumVertices];
    out.mNormals = new aiVector3D[out.mNumVertices];
    for (size_t v = 0; v < mesh.points.size(); ++v) {
        out.mVertices[v] = toAi(Vec3d(mesh.points[v]));
        out.mNormals[v] = toAi(normals[v].unitSafe());
    }
    for (size_t f = 0; f < faces.size(); ++f) {
        aiFace& face = out.mFaces[f];
        face.mNumIndices = corners(faces[f]);
        face.mIndices = new unsigned[face.mNumIndices];
        for (unsigned k = 0; k < face.mNumIndices; ++k)
            face.mIndices[k] = faces[f][k];
    }
    return scene;
}

/// A valid file of `format` without points or faces (assimp's PLY exporter refuses to write
/// one).
std::string emptyFile(MeshFormat format) {
    switch (format) {
        case MeshFormat::Obj:
            return "# empty mesh\n";
        case MeshFormat::Ply:
            return "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
                   "property float y\nproperty float z\nelement face 0\n"
                   "property list uchar int vertex_index\nend_header\n";
        case MeshFormat::Stl:
            return std::string(84, '\0');  // an 80-byte header and a triangle count of 0
    }
    return {};
}

}  // namespace

MeshFormat meshFormatOf(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".obj")
        return MeshFormat::Obj;
    if (ext == ".ply")
        return MeshFormat::Ply;
    if (ext == ".stl")
        return MeshFormat::Stl;
    fail(path, "unknown mesh format \"" + ext + "\" (use .obj, .ply or .stl)");
}

void writeMesh(const std::string& path, const Mesh& mesh, Winding winding) {
    const MeshFormat format = meshFormatOf(path);
    if (mesh.points.size() >= size_t(0xFFFFFFFFu))
        throw ValueError("writeMesh: " + path + ": too many points");
    for (size_t v = 0; v < mesh.points.size(); ++v) {
        const Vec3s& p = mesh.points[v];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw ValueError("writeMesh: " + path + ": point " + std::to_string(v) +
                             " is not finite");
    }
    const auto check = [&](uint32_t index, size_t face) {
        if (index >= mesh.points.size())
            throw ValueError("writeMesh: " + path + ": face " + std::to_string(face) +
                             " uses point " + std::to_string(index) + " of " +
                             std::to_string(mesh.points.size()));
    };
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k)
            check(mesh.triangles[f][k], f);
    for (size_t f = 0; f < mesh.quads.size(); ++f)
        for (int k = 0; k < 4; ++k)
            check(mesh.quads[f][k], mesh.triangles.size() + f);

    if (mesh.triangles.empty() && mesh.quads.empty()) {
        const std::string bytes = emptyFile(format);
        writeFileReplacing(path, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
        return;
    }
    const std::unique_ptr<aiScene> scene = buildScene(mesh, winding, format);
    const char* id = format == MeshFormat::Obj   ? "objnomtl"
                     : format == MeshFormat::Ply ? "plyb"
                                                 : "stlb";
    Assimp::Exporter exporter;
    const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), id, 0);
    if (!blob)
        fail(path, std::string("cannot encode the mesh: ") + exporter.GetErrorString());
    writeFileReplacing(path, static_cast<const uint8_t*>(blob->data), blob->size);
}

}  // namespace vdb::meshio
