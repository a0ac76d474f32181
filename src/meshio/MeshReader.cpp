// SPDX-License-Identifier: Apache-2.0
// Mesh import through assimp (library target vdb::meshio).

#include <vdb/Exceptions.h>
#include <vdb/meshio/MeshReader.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <sstream>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vdb::meshio {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw IoError("readMesh: " + path + ": " + what);
}

// ---- Structure checks for the text formats that assimp reads leniently ----
//
// assimp's ASCII PLY and OFF readers accept files whose counts do not match their data, that
// stop early, or whose faces name vertices that do not exist (reading defaults or dropping the
// faces), and its PLY reader reserves memory for the counts its header declares. These checks
// walk such files once, by their own counts, before assimp parses them, and refuse counts the
// bytes of the file cannot hold.

/// The numbers of one line, or false when a token is not a number.
bool parseNumbers(const std::string& line, std::vector<double>& out) {
    out.clear();
    std::istringstream in(line);
    std::string token;
    while (in >> token) {
        char* end = nullptr;
        const double v = std::strtod(token.c_str(), &end);
        // The whole token: a NUL byte inside it ends strtod's string early.
        if (end == token.c_str() || end != token.c_str() + token.size())
            return false;
        out.push_back(v);
    }
    return true;
}

/// Reads the next line that is neither empty nor a comment (`comment` starts it).
bool nextDataLine(std::istream& in, std::string& line, const char* comment) {
    while (std::getline(in, line)) {
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line.compare(first, std::strlen(comment), comment) == 0)
            continue;
        return true;
    }
    return false;
}

/// Checks the vertex coordinates and face indices of one face record: `n` then n indices.
void checkFace(const std::string& path, const std::vector<double>& v, size_t at,
               uint64_t vertexCount, uint64_t face) {
    // The count is compared as a double before it becomes an integer: no conversion overflows.
    if (v.size() <= at || !(v[at] >= 0) || v[at] != std::floor(v[at]) ||
        !(v[at] <= double(v.size() - at - 1)))
        fail(path, "face " + std::to_string(face) + " is malformed");
    // assimp's OFF reader crashes on a face without vertices; no format gives it a meaning.
    if (v[at] < 1)
        fail(path, "face " + std::to_string(face) + " has no vertices");
    for (size_t k = 0; k < size_t(v[at]); ++k) {
        const double index = v[at + 1 + k];
        if (!(index >= 0 && index < double(vertexCount)) || index != std::floor(index)) {
            fail(path, "face " + std::to_string(face) + " uses vertex " + std::to_string(index) +
                           " of " + std::to_string(vertexCount));
        }
    }
}

void checkVertex(const std::string& path, const std::vector<double>& v, size_t count,
                 uint64_t vertex) {
    if (v.size() < count)
        fail(path, "vertex " + std::to_string(vertex) + " has too few values");
    for (size_t k = 0; k < 3 && k < v.size(); ++k) {
        if (!std::isfinite(v[k]))
            fail(path, "vertex " + std::to_string(vertex) + " has a coordinate that is not finite");
    }
}

/// Fails unless `count` records of at least `recordBytes` bytes each fit in the `bytesLeft`
/// bytes the file has after its header, so that no reader allocates for records the file
/// cannot hold.
void checkCount(const std::string& path, uint64_t count, uint64_t recordBytes, uint64_t bytesLeft,
                const std::string& what) {
    if (recordBytes > 0 && count > bytesLeft / recordBytes) {
        fail(path, "the header declares " + std::to_string(count) + " " + what + " of at least " +
                       std::to_string(recordBytes) + " bytes each, but only " +
                       std::to_string(bytesLeft) + " bytes follow it");
    }
}

/// OFF: "OFF", then vertex, face and edge counts, the vertices, the faces.
void checkOff(const std::string& path, std::istream& in, uint64_t fileSize) {
    std::string line;
    std::vector<double> v;
    nextDataLine(in, line, "#");  // the OFF keyword, possibly followed by the counts
    const size_t key = line.find("OFF");
    std::string rest = key == std::string::npos ? line : line.substr(key + 3);
    if (!parseNumbers(rest, v) || v.empty()) {
        if (!nextDataLine(in, line, "#") || !parseNumbers(line, v))
            fail(path, "the OFF header has no counts");
    }
    if (v.size() < 2 || !(v[0] >= 0 && v[0] < 1.8e19) || !(v[1] >= 0 && v[1] < 1.8e19))
        fail(path, "the OFF header has no valid vertex and face counts");
    const uint64_t vertices = uint64_t(v[0]), faces = uint64_t(v[1]);
    // A vertex takes at least "0 0 0\n", a face "0\n".
    const uint64_t left =
        fileSize - std::min<uint64_t>(fileSize, uint64_t(std::max<std::streamoff>(0, in.tellg())));
    checkCount(path, vertices, 6, left, "vertices");
    checkCount(path, faces, 2, left - std::min(left, vertices * 6), "faces");
    for (uint64_t n = 0; n < vertices; ++n) {
        if (!nextDataLine(in, line, "#") || !parseNumbers(line, v))
            fail(path, "the file ends after " + std::to_string(n) + " of " +
                           std::to_string(vertices) + " vertices");
        checkVertex(path, v, 3, n);
    }
    for (uint64_t n = 0; n < faces; ++n) {
        if (!nextDataLine(in, line, "#") || !parseNumbers(line, v))
            fail(path, "the file ends after " + std::to_string(n) + " of " + std::to_string(faces) +
                           " faces");
        checkFace(path, v, 0, vertices, n);
    }
}

/// OBJ: every vertex record "v x y z [w]" has numeric, finite coordinates (assimp's OBJ reader
/// turns a token that is not a number, "nan" included, into 0).
void checkObj(const std::string& path, std::istream& in) {
    std::string line;
    std::vector<double> v;
    uint64_t vertex = 0;
    while (std::getline(in, line)) {
        const size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line.compare(first, 2, "v ") != 0)
            continue;
        if (!parseNumbers(line.substr(first + 2), v) || v.size() < 3)
            fail(path, "vertex " + std::to_string(vertex) + " is malformed");
        checkVertex(path, v, 3, vertex);
        ++vertex;
    }
}

/// The size in bytes of a PLY scalar type, 0 for an unknown name.
uint64_t plyTypeBytes(const std::string& type) {
    for (const auto& [name, bytes] : {std::pair<const char*, uint64_t>{"char", 1},
                                      {"int8", 1},
                                      {"uchar", 1},
                                      {"uint8", 1},
                                      {"short", 2},
                                      {"int16", 2},
                                      {"ushort", 2},
                                      {"uint16", 2},
                                      {"int", 4},
                                      {"int32", 4},
                                      {"uint", 4},
                                      {"uint32", 4},
                                      {"float", 4},
                                      {"float32", 4},
                                      {"double", 8},
                                      {"float64", 8}}) {
        if (type == name)
            return bytes;
    }
    return 0;
}

/// True when `token` is a decimal count (digits only).
bool isCount(const std::string& token) {
    return !token.empty() && token.size() <= 19 &&
           std::all_of(token.begin(), token.end(), [](unsigned char c) { return std::isdigit(c); });
}

/// True for the PLY scalar types a list count can take.
bool isPlyIntegerType(const std::string& type) {
    return plyTypeBytes(type) != 0 && type.find("float") == std::string::npos && type != "double";
}

/// PLY: the header is "ply", "format <ascii|binary_little_endian|binary_big_endian> 1.0", then
/// elements ("element <name> <count>") each followed by its properties ("property <type>
/// <name>" or "property list <count type> <type> <name>"), comments and "end_header". Lines of
/// free text between the format and the first element are allowed (Blender 2.4 wrote its
/// comment that way); any other line, and any control character but tabs and carriage returns,
/// is refused, since assimp's header parser can loop on them.
/// The header's elements must fit in the bytes after it (in binary, each record takes at least
/// its scalars and list counts; in ASCII, at least two characters per property); in ASCII, each
/// record is a line with its properties in order.
void checkPly(const std::string& path, std::istream& in, uint64_t fileSize) {
    struct Element {
        std::string name;
        uint64_t count = 0;
        uint64_t minBytes = 0;     // binary: the record's size with every list empty
        std::vector<bool> isList;  // per property
        int indexList = -1;        // the vertex_indices / vertex_index list of faces
    };
    std::vector<Element> elements;
    std::string line, format;
    uint64_t vertexCount = 0;
    std::vector<std::string> words;
    for (int lineNumber = 1;; ++lineNumber) {
        if (!std::getline(in, line))
            fail(path, "the PLY header has no end_header");
        if (lineNumber == 1)
            continue;  // "ply", checked by the caller
        if (std::any_of(line.begin(), line.end(),
                        [](unsigned char c) { return c < 0x20 && c != '\t' && c != '\r'; }))
            fail(path,
                 "PLY header line " + std::to_string(lineNumber) + " holds a control character");
        words.clear();
        std::istringstream tokens(line);
        for (std::string word; tokens >> word;)
            words.push_back(word);
        const std::string keyword = words.empty() ? std::string() : words[0];
        const auto malformed = [&](const std::string& what) {
            fail(path, "PLY header line " + std::to_string(lineNumber) + ": " + what);
        };
        if (lineNumber == 2) {
            if (words.size() != 3 || keyword != "format" ||
                (words[1] != "ascii" && words[1] != "binary_little_endian" &&
                 words[1] != "binary_big_endian") ||
                words[2] != "1.0")
                malformed("not \"format ascii|binary_little_endian|binary_big_endian 1.0\"");
            format = words[1];
        } else if (keyword == "end_header") {
            if (words.size() != 1)
                malformed("end_header is followed by more text");
            break;
        } else if (keyword == "comment" || keyword == "obj_info") {
            continue;
        } else if (keyword == "element") {
            if (words.size() != 3 || !isCount(words[2]))
                malformed("not \"element <name> <count>\"");
            Element e;
            e.name = words[1];
            e.count = std::stoull(words[2]);
            for (const Element& other : elements) {
                if (other.name == e.name)
                    malformed("a second element " + e.name);
            }
            if (e.name == "vertex")
                vertexCount = e.count;
            elements.push_back(e);
        } else if (keyword == "property") {
            if (elements.empty())
                malformed("a property comes before any element");
            const bool list = words.size() > 1 && words[1] == "list";
            if (list ? (words.size() != 5 || !isPlyIntegerType(words[2]) ||
                        plyTypeBytes(words[3]) == 0)
                     : (words.size() != 3 || plyTypeBytes(words[1]) == 0))
                malformed(
                    "not \"property <type> <name>\" or \"property list <count type> "
                    "<type> <name>\" with PLY types");
            const std::string& name = words.back();
            auto& e = elements.back();
            if (list && (name == "vertex_indices" || name == "vertex_index"))
                e.indexList = int(e.isList.size());
            e.isList.push_back(list);
            e.minBytes += plyTypeBytes(words[list ? 2 : 1]);
        } else if (!elements.empty() || keyword == "format" || keyword == "ply") {
            malformed("not a comment, element, property or end_header");
        }
    }
    const bool ascii = format == "ascii";
    uint64_t left =
        fileSize - std::min<uint64_t>(fileSize, uint64_t(std::max<std::streamoff>(0, in.tellg())));
    for (const Element& e : elements) {
        const uint64_t bytes = ascii ? 2 * std::max<uint64_t>(1, e.isList.size()) : e.minBytes;
        checkCount(path, e.count, bytes, left, e.name + " records");
        left -= e.count * bytes;
    }
    if (!ascii)
        return;
    std::vector<double> v;
    for (const Element& e : elements) {
        for (uint64_t n = 0; n < e.count; ++n) {
            if (!nextDataLine(in, line, "comment") || !parseNumbers(line, v)) {
                fail(path, "the file ends after " + std::to_string(n) + " of " +
                               std::to_string(e.count) + " " + e.name + " records");
            }
            // Walk the properties: a scalar takes one value, a list its count and items.
            size_t at = 0;
            for (size_t p = 0; p < e.isList.size(); ++p) {
                if (at >= v.size())
                    fail(path, e.name + " " + std::to_string(n) + " has too few values");
                if (int(p) == e.indexList && e.name == "face")
                    checkFace(path, v, at, vertexCount, n);
                at +=
                    e.isList[p] ? 1 + size_t(std::min(std::max(0.0, v[at]), double(v.size()))) : 1;
            }
            if (at != v.size()) {
                fail(path, e.name + " " + std::to_string(n) + " has " + std::to_string(v.size()) +
                               " values where the header gives " + std::to_string(at));
            }
            if (e.name == "vertex")
                checkVertex(path, v, 3, n);
        }
    }
}

/// Fails when a vertex of the scene, as the file gives it, has a coordinate that is not finite
/// (before post-processing, which could merge it into a finite one).
void checkFinite(const std::string& path, const aiScene& scene) {
    uint64_t vertex = 0;
    for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
        const aiMesh* mesh = scene.mMeshes[m];
        if (!mesh || !mesh->mVertices)
            continue;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v, ++vertex) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                fail(path, "vertex " + std::to_string(vertex) +
                               " has a coordinate that is not finite (" + std::to_string(p.x) +
                               ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
            }
        }
    }
}

/// Appends the faces of `mesh`, its vertices moved by `xform`, to `out`.
void appendMesh(const std::string& path, const aiMesh& mesh, const aiMatrix4x4& xform, Mesh& out) {
    const size_t base = out.points.size();
    if (base + mesh.mNumVertices >= size_t(0xFFFFFFFFu))
        fail(path, "too many vertices");
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        const aiVector3D p = xform * mesh.mVertices[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            fail(path, "vertex " + std::to_string(v) + " has a coordinate that is not finite");
        out.points.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        for (unsigned k = 0; k < face.mNumIndices; ++k) {
            if (face.mIndices[k] >= mesh.mNumVertices) {
                fail(path, "face " + std::to_string(f) + " uses vertex " +
                               std::to_string(face.mIndices[k]) + " of " +
                               std::to_string(mesh.mNumVertices));
            }
        }
        const auto at = [&](unsigned k) { return Index32(base + face.mIndices[k]); };
        if (face.mNumIndices == 3) {
            out.triangles.emplace_back(at(0), at(1), at(2));
        } else if (face.mNumIndices == 4) {
            out.quads.emplace_back(at(0), at(1), at(2), at(3));
        } else {
            for (unsigned k = 2; k < face.mNumIndices; ++k)
                out.triangles.emplace_back(at(0), at(k - 1), at(k));
        }
    }
}

void appendNode(const std::string& path, const aiScene& scene, const aiNode& node,
                const aiMatrix4x4& parent, Mesh& out, unsigned depth) {
    if (depth > 1024)
        fail(path, "the scene graph is too deep");
    const aiMatrix4x4 xform = parent * node.mTransformation;
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
        if (node.mMeshes[m] >= scene.mNumMeshes)
            fail(path, "a node names a mesh that does not exist");
        appendMesh(path, *scene.mMeshes[node.mMeshes[m]], xform, out);
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c)
        appendNode(path, scene, *node.mChildren[c], xform, out, depth + 1);
}

/// Merges the points of `mesh` that lie at the same position (-0 and +0 alike): assimp merges
/// identical vertices within each of its meshes, but a file's vertex shared by faces that it
/// splits into several meshes (triangles and polygons, OBJ groups) arrives once per mesh.
void weldPoints(Mesh& mesh) {
    struct Key {
        float x, y, z;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            const auto bits = [](float f) {
                uint32_t u = 0;
                f += 0.0f;  // -0 becomes +0
                std::memcpy(&u, &f, sizeof u);
                return size_t(u);
            };
            return (bits(k.x) * 73856093u) ^ (bits(k.y) * 19349663u) ^ (bits(k.z) * 83492791u);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> first;
    first.reserve(mesh.points.size());
    std::vector<uint32_t> remap(mesh.points.size());
    std::vector<Vec3s> welded;
    welded.reserve(mesh.points.size());
    for (size_t i = 0; i < mesh.points.size(); ++i) {
        const Vec3s& p = mesh.points[i];
        const auto [it, fresh] = first.try_emplace(Key{p[0], p[1], p[2]}, uint32_t(welded.size()));
        if (fresh)
            welded.push_back(p);
        remap[i] = it->second;
    }
    if (welded.size() == mesh.points.size())
        return;
    mesh.points = std::move(welded);
    for (Vec3I& t : mesh.triangles)
        t = Vec3I(remap[t[0]], remap[t[1]], remap[t[2]]);
    for (Vec4I& q : mesh.quads)
        q = Vec4I(remap[q[0]], remap[q[1]], remap[q[2]], remap[q[3]]);
}

}  // namespace

Mesh readMesh(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::is_regular_file(status))
        fail(path, "no such file");
    if (std::filesystem::file_size(path, ec) == 0 || ec)
        fail(path, "the file is empty");

    const uint64_t fileSize = std::filesystem::file_size(path, ec);
    {
        std::ifstream in(path, std::ios::binary);
        // assimp chooses its PLY reader by the extension or by "ply" in any case anywhere in
        // the first 200 bytes (nulls skipped), and that reader trusts what follows: such a
        // file must be a PLY file with its magic line, and is checked as one.
        std::string head(200, '\0');
        in.read(head.data(), std::streamsize(head.size()));
        head.resize(size_t(in.gcount()));
        in.clear();
        in.seekg(0);
        std::string ext = std::filesystem::path(path).extension().string();
        const auto lower = [](std::string text) {
            std::transform(text.begin(), text.end(), text.begin(),
                           [](unsigned char c) { return char(std::tolower(c)); });
            return text;
        };
        ext = lower(ext);
        std::string folded = lower(head);
        std::erase(folded, '\0');
        const bool plyMagic = head.rfind("ply\n", 0) == 0 || head.rfind("ply\r\n", 0) == 0;
        const bool otherFormat = ext == ".obj" || ext == ".stl" || ext == ".off";
        if (plyMagic || ext == ".ply" ||
            (!otherFormat && folded.find("ply") != std::string::npos)) {
            if (!plyMagic)
                fail(path, "not a PLY file: its first line is not \"ply\"");
            checkPly(path, in, fileSize);
        } else if (ext == ".off" ||
                   (head.find("OFF") != std::string::npos && head.find("OFF") < 4)) {
            checkOff(path, in, fileSize);
        } else if (ext == ".obj") {
            checkObj(path, in);
        }
    }

    Assimp::Importer importer;
    // Points and lines are dropped; polygons keep their vertex counts (no triangulation).
    // Only positions matter: without normals, colours and texture coordinates, the corners
    // STL stores per triangle merge into shared vertices.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                                aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                    aiComponent_COLORS | aiComponent_TEXCOORDS);
    // The vertices are checked as the file gives them, then merged.
    const aiScene* scene = nullptr;
    try {
        scene = importer.ReadFile(path, 0);
        if (scene)
            checkFinite(path, *scene);
        if (scene) {
            scene = importer.ApplyPostProcessing(
                aiProcess_RemoveComponent | aiProcess_JoinIdenticalVertices |
                aiProcess_ValidateDataStructure | aiProcess_SortByPType);
        }
    } catch (const std::bad_alloc&) {
        fail(path, "out of memory while reading it");
    }
    if (!scene) {
        const std::string why = importer.GetErrorString();
        fail(path, why.empty() ? "not a mesh file assimp can read" : why);
    }
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        fail(path, "the file is incomplete");

    Mesh out;
    if (scene->mRootNode)
        appendNode(path, *scene, *scene->mRootNode, aiMatrix4x4(), out, 0);
    if (out.triangles.empty() && out.quads.empty())
        fail(path, "the file holds no faces");
    weldPoints(out);
    return out;
}

}  // namespace vdb::meshio
