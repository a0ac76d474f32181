// SPDX-License-Identifier: Apache-2.0
// Mesh import (vdb::meshio): tiny files of every format written at test time, read back and
// compared with the mesh they were written from; malformed files each give an IoError (counts
// the file cannot hold before anything is allocated for them, coordinates that are not finite
// in every format); a cube read from OBJ converts to the same level set as the cube in memory;
// the real meshes of the Debian package assimp-testmodels (skipped when it is not installed)
// read alike in every format, and their level sets, with the default signs, agree with the
// brute-force generalized winding number (tests/support/TestMeshes.h) away from their open edges.

#include <vdb/meshio/MeshReader.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/vdb.h>

#include "GridContents.h"
#include "TestMeshes.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace vdb::meshio {
namespace {

std::string writeFile(const std::string& name, const std::string& bytes) {
    const std::string path = test::tempPath("vdb-meshio-", name);
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

/// A unit tetrahedron, counter-clockwise seen from outside.
const std::vector<Vec3s> kTetPoints = {Vec3s(0, 0, 0), Vec3s(1, 0, 0), Vec3s(0, 1, 0),
                                       Vec3s(0, 0, 1)};
const std::vector<Vec3I> kTetFaces = {Vec3I(0, 2, 1), Vec3I(0, 1, 3), Vec3I(0, 3, 2),
                                      Vec3I(1, 2, 3)};

template <typename T>
void append(std::string& out, const T& value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

std::string tetObj() {
    std::ostringstream s;
    for (const Vec3s& p : kTetPoints)
        s << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const Vec3I& f : kTetFaces)
        s << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
    return s.str();
}

std::string tetPlyAscii(int declaredVertices = 4) {
    std::ostringstream s;
    s << "ply\nformat ascii 1.0\nelement vertex " << declaredVertices
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
         "property list uchar int vertex_indices\nend_header\n";
    for (const Vec3s& p : kTetPoints)
        s << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const Vec3I& f : kTetFaces)
        s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
    return s.str();
}

std::string tetPlyBinary() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nelement face 4\n"
        "property list uchar int vertex_indices\nend_header\n";
    for (const Vec3s& p : kTetPoints)
        for (int k = 0; k < 3; ++k)
            append(s, p[k]);
    for (const Vec3I& f : kTetFaces) {
        append(s, uint8_t(3));
        for (int k = 0; k < 3; ++k)
            append(s, int32_t(f[k]));
    }
    return s;
}

Vec3s faceNormal(const Vec3I& f) {
    const Vec3s a = kTetPoints[f[0]], b = kTetPoints[f[1]], c = kTetPoints[f[2]];
    return (b - a).cross(c - a).unitSafe();
}

std::string tetStlAscii() {
    std::ostringstream s;
    s << "solid tet\n";
    for (const Vec3I& f : kTetFaces) {
        const Vec3s n = faceNormal(f);
        s << " facet normal " << n[0] << ' ' << n[1] << ' ' << n[2] << "\n  outer loop\n";
        for (int k = 0; k < 3; ++k) {
            const Vec3s& p = kTetPoints[f[k]];
            s << "   vertex " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
        }
        s << "  endloop\n endfacet\n";
    }
    s << "endsolid tet\n";
    return s.str();
}

std::string tetStlBinary(uint32_t declaredTriangles = 4) {
    std::string s(80, ' ');
    append(s, declaredTriangles);
    for (const Vec3I& f : kTetFaces) {
        const Vec3s n = faceNormal(f);
        for (int k = 0; k < 3; ++k)
            append(s, n[k]);
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k)
                append(s, kTetPoints[f[v]][k]);
        append(s, uint16_t(0));
    }
    return s;
}

std::string tetOff(int declaredVertices = 4) {
    std::ostringstream s;
    s << "OFF\n" << declaredVertices << " 4 6\n";
    for (const Vec3s& p : kTetPoints)
        s << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const Vec3I& f : kTetFaces)
        s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
    return s.str();
}

/// The faces of a mesh as sets of point triples, independent of vertex numbering.
std::set<std::tuple<float, float, float, float, float, float, float, float, float>> faceSet(
    const std::vector<Vec3s>& points, const std::vector<Vec3I>& faces) {
    std::set<std::tuple<float, float, float, float, float, float, float, float, float>> out;
    for (const Vec3I& f : faces) {
        // Rotate so that the smallest point comes first (keeps the orientation).
        int first = 0;
        for (int k = 1; k < 3; ++k) {
            const Vec3s& p = points[f[k]];
            const Vec3s& q = points[f[first]];
            if (std::make_tuple(p[0], p[1], p[2]) < std::make_tuple(q[0], q[1], q[2]))
                first = k;
        }
        const Vec3s& a = points[f[first]];
        const Vec3s& b = points[f[(first + 1) % 3]];
        const Vec3s& c = points[f[(first + 2) % 3]];
        out.emplace(a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]);
    }
    return out;
}

class MeshReaderFormats : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(MeshReaderFormats, ReadsTheTetrahedronBack) {
    const auto& [name, bytes] = GetParam();
    const Mesh mesh = readMesh(writeFile(name, bytes));
    EXPECT_EQ(mesh.points.size(), 4u) << "identical vertices are merged";
    EXPECT_TRUE(mesh.quads.empty());
    EXPECT_EQ(faceSet(mesh.points, mesh.triangles), faceSet(kTetPoints, kTetFaces));
}

INSTANTIATE_TEST_SUITE_P(
    AllFormats, MeshReaderFormats,
    ::testing::Values(std::make_pair(std::string("tet.obj"), tetObj()),
                      std::make_pair(std::string("tet-ascii.ply"), tetPlyAscii()),
                      std::make_pair(std::string("tet-binary.ply"), tetPlyBinary()),
                      std::make_pair(std::string("tet-ascii.stl"), tetStlAscii()),
                      std::make_pair(std::string("tet-binary.stl"), tetStlBinary()),
                      std::make_pair(std::string("tet.off"), tetOff())),
    [](const auto& info) {
        std::string n = info.param.first;
        std::replace_if(
            n.begin(), n.end(), [](char c) { return !std::isalnum(c); }, '_');
        return n;
    });

TEST(MeshReader, ObjQuadsStayQuadsAndPolygonsBecomeFans) {
    const Mesh mesh = readMesh(writeFile("polys.obj",
                                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n"
                                         "f 1 2 3 4\nf 1 2 3 4 5\nf 1 2 3\n"));
    EXPECT_EQ(mesh.quads.size(), 1u);
    EXPECT_EQ(mesh.triangles.size(), 4u);  // the pentagon's three and the triangle
}

TEST(MeshReader, DegenerateTrianglesAreTolerated) {
    const Mesh mesh =
        readMesh(writeFile("degenerate.obj", tetObj() + "v 2 0 0\nf 1 2 5\nf 1 1 2\n"));
    EXPECT_EQ(mesh.triangles.size(), 6u);
    const auto xform = math::Transform::createLinearTransform(0.1);
    EXPECT_NO_THROW(tools::meshToLevelSet<FloatGrid>(*xform, mesh.points, mesh.triangles));
}

TEST(MeshReader, CubeFromObjConvertsLikeTheCubeInMemory) {
    const test::TestMesh cube = test::makeCubeMesh(Vec3d(-0.52, -0.49, -0.47), 1.0, 3, true);
    std::ostringstream s;
    s.precision(9);
    for (const Vec3s& p : cube.points)
        s << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const Vec4I& q : cube.quads)
        s << "f " << q[0] + 1 << ' ' << q[1] + 1 << ' ' << q[2] + 1 << ' ' << q[3] + 1 << '\n';
    const Mesh mesh = readMesh(writeFile("cube.obj", s.str()));
    EXPECT_EQ(mesh.points.size(), cube.points.size());
    EXPECT_EQ(mesh.quads.size(), cube.quads.size());
    const auto xform = math::Transform::createLinearTransform(0.05);
    const auto a = tools::meshToLevelSet<FloatGrid>(*xform, cube.points, {}, cube.quads);
    const auto b =
        tools::meshToLevelSet<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads);
    ASSERT_EQ(a->activeVoxelCount(), b->activeVoxelCount());
    for (auto it = a->tree().cbeginValueOn(); it; ++it)
        ASSERT_EQ(b->tree().getValue(it.getCoord()), *it) << it.getCoord();
}

/// Reading the file at `path` must throw an IoError whose message names the file.
::testing::AssertionResult rejectsFile(const std::string& path) {
    try {
        const Mesh mesh = readMesh(path);
        return ::testing::AssertionFailure()
               << path << " was accepted: " << mesh.points.size() << " points, "
               << mesh.triangles.size() << " triangles, " << mesh.quads.size() << " quads";
    } catch (const IoError& e) {
        if (std::string(e.what()).find(path) == std::string::npos)
            return ::testing::AssertionFailure() << "message without the path: " << e.what();
        return ::testing::AssertionSuccess() << e.what();
    }
}

/// Reading `bytes` as `name` must throw an IoError whose message names the file.
::testing::AssertionResult rejects(const std::string& name, const std::string& bytes) {
    return rejectsFile(writeFile(name, bytes));
}

TEST(MeshReader, MissingAndEmptyFilesThrow) {
    EXPECT_THROW(readMesh(test::tempPath("vdb-meshio-", "does-not-exist.obj")), IoError);
    EXPECT_TRUE(rejects("empty.obj", ""));
    EXPECT_TRUE(rejects("empty.stl", ""));
    EXPECT_TRUE(rejects("no-faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"));
    EXPECT_TRUE(rejects("garbage.ply", "this is not a mesh\n"));
}

TEST(MeshReader, PlyHeadersWithoutTheMagicLineThrow) {
    // A file that assimp would hand to its PLY reader (by the extension, or by "ply" in any
    // case near the start) must begin with the line "ply". The first of these, a mangled
    // binary header, crashed assimp's reader.
    const std::string mangled = std::string("plY\nformat binary_litt/le_endian 1.0\n") +
                                "element vertex 4\nproperty float x\npro\x15perty Aloat y\n" +
                                "property float?" + std::string(7, '\0') + "w" +
                                std::string(1, '\0') + "y\nformat binarSt13runtime_" +
                                std::string(3, '\0') + "\x03";
    EXPECT_TRUE(rejects("mangled.ply", mangled));
    EXPECT_TRUE(rejects("mangled.dat", mangled));
    EXPECT_TRUE(rejects("leading-space.ply", " " + tetPlyAscii()));
    EXPECT_TRUE(rejects("upper-case.ply", "PLY" + tetPlyAscii().substr(3)));
    // A valid PLY file under another name is still read.
    EXPECT_EQ(readMesh(writeFile("tet.dat", tetPlyAscii())).triangles.size(), 4u);
}

TEST(MeshReader, TruncatedFilesThrow) {
    const std::string stl = tetStlBinary();
    EXPECT_TRUE(rejects("truncated.stl", stl.substr(0, stl.size() - 30)));
    const std::string ply = tetPlyBinary();
    EXPECT_TRUE(rejects("truncated.ply", ply.substr(0, ply.size() - 7)));
    const std::string ascii = tetPlyAscii();
    EXPECT_TRUE(rejects("truncated-ascii.ply", ascii.substr(0, ascii.size() - 12)));
    EXPECT_TRUE(rejects("truncated.off", tetOff().substr(0, 40)));
}

TEST(MeshReader, WrongCountsThrow) {
    EXPECT_TRUE(rejects("count.stl", tetStlBinary(/*declaredTriangles=*/9)));
    EXPECT_TRUE(rejects("count.ply", tetPlyAscii(/*declaredVertices=*/7)));
    EXPECT_TRUE(rejects("count.off", tetOff(/*declaredVertices=*/9)));
    // Without the OFF keyword, the first line's counts are still checked (assimp's reader
    // would reserve memory for them).
    EXPECT_TRUE(rejects("no-keyword.off", std::string(55, '7') + "0 1 0\n0 0 1\n1 2 3\n"));
    // A face whose vertex count is beyond any integer type.
    std::string off = tetOff();
    off.replace(off.rfind("3 1 2 3"), 7, "6666666666666666666666666666666666666666666666663 1 2 3");
    EXPECT_TRUE(rejects("huge-face.off", off));
    // A second list on the faces whose count no integer type holds (and the line cannot back).
    std::string ply = tetPlyAscii();
    ply.replace(ply.find("end_header"), 10, "property list uchar float texcoord\nend_header");
    for (size_t at = ply.find("\n3 ", ply.find("end_header")); at != std::string::npos;
         at = ply.find("\n3 ", at + 1)) {
        const size_t end = ply.find('\n', at + 1);
        ply.insert(end == std::string::npos ? ply.size() : end, " 8.9e73 0.5");
    }
    EXPECT_TRUE(rejects("huge-list.ply", ply));
    // A face without vertices (followed by more lines, it crashed assimp's OFF reader).
    EXPECT_TRUE(
        rejects("empty-face.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 1 0\n0 0 1\n"));
}

TEST(MeshReader, OutOfRangeIndicesThrow) {
    EXPECT_TRUE(rejects("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"));
    std::string ply = tetPlyAscii();
    ply.replace(ply.rfind("3 1 2 3"), 7, "3 1 2 9");
    EXPECT_TRUE(rejects("index.ply", ply));
    std::string off = tetOff();
    off.replace(off.rfind("3 1 2 3"), 7, "3 1 2 8");
    EXPECT_TRUE(rejects("index.off", off));
}

/// True when reading `bytes` as `name` throws an IoError whose message names the file and
/// holds every one of `words`.
::testing::AssertionResult rejectsWith(const std::string& name, const std::string& bytes,
                                       const std::vector<std::string>& words) {
    const std::string path = writeFile(name, bytes);
    try {
        readMesh(path);
        return ::testing::AssertionFailure() << name << " was accepted";
    } catch (const IoError& e) {
        const std::string what = e.what();
        std::vector<std::string> needles = words;
        needles.push_back(path);
        for (const std::string& w : needles) {
            if (what.find(w) == std::string::npos)
                return ::testing::AssertionFailure() << "no '" << w << "' in: " << what;
        }
        return ::testing::AssertionSuccess() << what;
    }
}

TEST(MeshReader, MalformedPlyHeadersThrow) {
    // Each of these header lines made assimp's PLY reader loop without end (found by the fuzz
    // target); each is refused before assimp sees the file, with the line it is on.
    const std::string ply = tetPlyAscii();
    const auto withLine = [&](const std::string& before, const std::string& line) {
        std::string text = ply;
        text.insert(text.find(before), line + "\n");
        return text;
    };
    EXPECT_TRUE(rejectsWith("count-word.ply", withLine("end_header", "element vertexar int"),
                            {"header line 9", "element <name> <count>"}));
    EXPECT_TRUE(rejectsWith("format-again.ply", withLine("end_header", "format ascii 1.0"),
                            {"header line 9"}));
    EXPECT_TRUE(
        rejectsWith("stray-word.ply", withLine("element face", "propces"), {"header line 7"}));
    // Free text before the first element is allowed, but not with control characters.
    EXPECT_TRUE(rejectsWith("nul-text.ply",
                            withLine("element vertex", std::string("properuint1\0\0ex", 15)),
                            {"header line 3", "control character"}));
    EXPECT_TRUE(rejectsWith("soh-comment.ply", withLine("element face", "comment \x01"),
                            {"control character"}));
    // Other malformed lines: no format line, an unknown format, a second element of one name,
    // a property of an unknown type or with a floating-point list count, a count with a sign.
    std::string noFormat = ply;
    noFormat.erase(noFormat.find("format ascii 1.0\n"), 17);
    EXPECT_TRUE(rejectsWith("no-format.ply", noFormat, {"header line 2"}));
    std::string badFormat = ply;
    badFormat.replace(badFormat.find("ascii"), 5, "text");
    EXPECT_TRUE(rejectsWith("bad-format.ply", badFormat, {"header line 2"}));
    EXPECT_TRUE(rejectsWith("two-vertex.ply", withLine("element face", "element vertex 0"),
                            {"a second element vertex"}));
    EXPECT_TRUE(rejects("float96.ply", withLine("element face", "property float96 w")));
    std::string floatCount = ply;
    floatCount.replace(floatCount.find("list uchar"), 10, "list float");
    EXPECT_TRUE(rejects("float-count.ply", floatCount));
    std::string signedCount = ply;
    signedCount.replace(signedCount.find("vertex 4"), 8, "vertex +4");
    EXPECT_TRUE(rejects("signed-count.ply", signedCount));
    // Comments anywhere, and a line of free text before the first element (as Blender 2.4
    // wrote its comment; PLY/Wuson.ply has one), are read.
    std::string annotated = withLine("end_header", "comment last");
    annotated.insert(annotated.find("element face"), "obj_info scanned\n");
    annotated.insert(annotated.find("element vertex"), "Created by an exporter\n");
    EXPECT_EQ(readMesh(writeFile("annotated.ply", annotated)).triangles.size(), 4u);
}

TEST(MeshReader, NulBytesInAsciiRecordsThrowBeforeAssimpReadsThem) {
    // A NUL byte inside a number of an ASCII PLY record: assimp's reader refused the file but
    // leaked; the record check must refuse it first.
    std::string nul = tetPlyAscii();
    nul.insert(nul.find("end_header\n") + 11 + 5, std::string("\0J", 2));
    EXPECT_TRUE(rejectsWith("nul.ply", nul, {"vertex record"}));
}

TEST(MeshReader, CountsBeyondWhatTheFileHoldsThrowBeforeAllocating) {
    // Binary PLY: 10^8 vertices of 12 bytes, 10^8 faces of at least 1 byte, 4e9 vertices.
    const std::string header = "ply\nformat binary_little_endian 1.0\n";
    const std::string vertexProps = "property float x\nproperty float y\nproperty float z\n";
    const std::string faceProps = "property list uchar int vertex_indices\n";
    std::string ply = header + "element vertex 100000000\n" + vertexProps + "element face 1\n" +
                      faceProps + "end_header\n";
    ply.resize(180, '\0');
    EXPECT_TRUE(rejectsWith("many-vertices.ply", ply, {"100000000 vertex", "12 bytes"}));
    std::string faces = header + "element vertex 3\n" + vertexProps + "element face 100000000\n" +
                        faceProps + "end_header\n";
    faces.resize(faces.size() + 36 + 20, '\0');
    EXPECT_TRUE(rejectsWith("many-faces.ply", faces, {"100000000 face", "1 byte", "20 bytes"}));
    std::string huge = header + "element vertex 4000000000\n" + vertexProps + "element face 1\n" +
                       faceProps + "end_header\n";
    huge.resize(huge.size() + 40, '\0');
    EXPECT_TRUE(rejectsWith("huge.ply", huge, {"4000000000 vertex", "40 bytes"}));
    // ASCII PLY and OFF: at least two characters per value.
    std::string ascii = tetPlyAscii();
    ascii.replace(ascii.find("element vertex 4"), 16, "element vertex 1000000000");
    EXPECT_TRUE(rejectsWith("many-vertices-ascii.ply", ascii, {"1000000000 vertex"}));
    EXPECT_TRUE(rejectsWith("many.off", "OFF\n2000000000 1 0\n0 0 0\n", {"2000000000 vertices"}));
    EXPECT_TRUE(rejectsWith("many-faces.off", "OFF\n3 900000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                            {"900000000 faces"}));
}

TEST(MeshReader, NonFiniteCoordinatesThrow) {
    EXPECT_TRUE(rejects("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_TRUE(rejects("nan-z.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_TRUE(rejects("word.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n"));
    std::string ply = tetPlyAscii();
    ply.replace(ply.find("end_header\n0 0 0") + 11, 5, "0 inf 0");
    EXPECT_TRUE(rejects("inf.ply", ply));
    std::string stl = tetStlBinary();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(stl.data() + 84 + 12 + 4, &nan, 4);  // first triangle, first vertex, y
    EXPECT_TRUE(rejects("nan.stl", stl));
    // A triangle whose corners are all NaN (which merging identical vertices would hide).
    std::string allNan = tetStlBinary();
    for (int k = 0; k < 9; ++k)
        std::memcpy(allNan.data() + 84 + 3 * 50 + 12 + 4 * k, &nan, 4);
    EXPECT_TRUE(rejectsWith("all-nan.stl", allNan, {"not finite", "nan"}));
    std::string asciiStl = tetStlAscii();
    asciiStl.replace(asciiStl.find("vertex 1 0 0"), 12, "vertex 1 0 1e999");
    EXPECT_TRUE(rejectsWith("inf-ascii.stl", asciiStl, {"not finite", "inf"}));
    std::string off = tetOff();
    off.replace(off.find("\n1 0 0\n"), 7, "\n1 nan 0\n");
    EXPECT_TRUE(rejects("nan.off", off));
    std::string binaryPly = tetPlyBinary();
    std::memcpy(binaryPly.data() + binaryPly.find("end_header\n") + 11 + 4, &nan, 4);
    EXPECT_TRUE(rejectsWith("nan-binary.ply", binaryPly, {"not finite"}));
}

// ---- Real meshes of the Debian package assimp-testmodels ----

/// The path of a model of assimp-testmodels, or "" when the package is not installed.
std::string model(const std::string& relative) {
    const std::string path = "/usr/share/assimp/models/" + relative;
    return std::filesystem::exists(path) ? path : std::string();
}

#define VDB_MODEL_OR_SKIP(var, relative)     \
    const std::string var = model(relative); \
    if (var.empty())                         \
    GTEST_SKIP() << relative << " not found (package assimp-testmodels)"

/// The bounding box of a mesh's points.
std::pair<Vec3d, Vec3d> bounds(const Mesh& mesh) {
    Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec3s& p : mesh.points) {
        lo = Vec3d::minComponent(lo, Vec3d(p));
        hi = Vec3d::maxComponent(hi, Vec3d(p));
    }
    return {lo, hi};
}

TEST(MeshReaderModels, CubeOffIsEightPointsAndSixQuads) {
    VDB_MODEL_OR_SKIP(path, "OFF/Cube.off");
    const Mesh mesh = readMesh(path);
    EXPECT_EQ(mesh.points.size(), 8u);
    EXPECT_EQ(mesh.quads.size() * 2 + mesh.triangles.size(), 12u);
    const auto [lo, hi] = bounds(mesh);
    EXPECT_EQ(lo, Vec3d(-0.5));
    EXPECT_EQ(hi, Vec3d(0.5));
}

TEST(MeshReaderModels, WusonReadsAlikeFromPlyOffAndStl) {
    VDB_MODEL_OR_SKIP(ply, "PLY/Wuson.ply");
    VDB_MODEL_OR_SKIP(off, "OFF/Wuson.off");
    VDB_MODEL_OR_SKIP(stl, "STL/Wuson.stl");
    const Mesh a = readMesh(ply), b = readMesh(off), c = readMesh(stl);
    const auto triangles = [](const Mesh& m) { return m.triangles.size() + 2 * m.quads.size(); };
    EXPECT_GT(triangles(a), 1000u);
    EXPECT_EQ(triangles(a), triangles(b));
    EXPECT_EQ(triangles(a), triangles(c));
    const auto [loA, hiA] = bounds(a);
    for (const Mesh* m : {&b, &c}) {
        const auto [lo, hi] = bounds(*m);
        EXPECT_LT((lo - loA).length() + (hi - hiA).length(), 1e-3 * (hiA - loA).length())
            << lo << hi << " vs " << loA << hiA;
    }
}

TEST(MeshReaderModels, StlPlyAndOffOfWusonHaveTheSameEdges) {
    // STL stores every triangle's corners apart: after welding, its edges are those of the
    // indexed formats.
    std::vector<tools::MeshToVolumeReport> reports;
    for (const char* name : {"PLY/Wuson.ply", "OFF/Wuson.off", "STL/Wuson.stl"}) {
        VDB_MODEL_OR_SKIP(path, name);
        const Mesh mesh = readMesh(path);
        const auto xform = math::Transform::createLinearTransform(0.05);
        tools::MeshToVolumeReport report;
        tools::meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads, {},
                                       &report);
        EXPECT_EQ(report.sign, tools::MeshSign::WindingNumber) << name;
        EXPECT_EQ(report.boundaryEdges, 412u) << name;
        EXPECT_EQ(report.nonManifoldEdges + report.misorientedEdges, 0u) << name;
        reports.push_back(report);
    }
    EXPECT_EQ(reports[0].holes, reports[2].holes);
}

/// The level set of a model of assimp-testmodels at a bounding resolution of 64 voxels, with
/// the default signs, against the brute-force generalized winding number at about 1,200 points
/// (band and box) more than half a voxel from the surface and three voxels from an open edge.
::testing::AssertionResult modelMatchesTheWindingNumber(const std::string& path,
                                                        tools::MeshSign expected) {
    const Mesh mesh = readMesh(path);
    const auto [lo, hi] = bounds(mesh);
    const Vec3d extent = hi - lo;
    const double dx = std::max({extent[0], extent[1], extent[2]}) / 64;
    const auto xform = math::Transform::createLinearTransform(dx);
    tools::MeshToVolumeReport report;
    const auto grid = tools::meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles,
                                                     mesh.quads, {}, &report);
    if (report.sign != expected)
        return ::testing::AssertionFailure() << path << ": another sign mode was chosen";
    const test::OracleMesh oracle =
        test::toIndexSpace(test::TestMesh{mesh.points, mesh.triangles, mesh.quads}, dx);
    const auto acc = grid->getConstAccessor();
    const test::SignTally tally = test::compareSigns(
        oracle, test::signSamples(*grid, oracle, 31, 5), 0.5, 3.0,
        [&](const Vec3d& p) { return acc.getValue(math::floorToCoord(p + 0.5)) < 0.0f; },
        [&](const Vec3d& p) { return oracle.insideByWinding(p); });
    if (tally.checked < 600 || tally.wrong > 0) {
        return ::testing::AssertionFailure()
               << path << ": " << tally.wrong << " of " << tally.checked << " signs differ";
    }
    return ::testing::AssertionSuccess();
}

// Holes (Wuson: 412 boundary edges), faces turned the wrong way and non-manifold edges
// (spider, from OBJ and binary STL), holes and non-manifold edges in several objects with
// points shared between them (regr01), an STL of a sphere with a hole, an STL with
// non-manifold edges.
class MeshReaderDefectiveModels : public ::testing::TestWithParam<std::string> {};

TEST_P(MeshReaderDefectiveModels, MatchTheWindingNumberAwayFromTheirOpenEdges) {
    VDB_MODEL_OR_SKIP(path, GetParam());
    EXPECT_TRUE(modelMatchesTheWindingNumber(path, tools::MeshSign::WindingNumber));
}

INSTANTIATE_TEST_SUITE_P(AssimpTestModels, MeshReaderDefectiveModels,
                         ::testing::Values("PLY/Wuson.ply", "OBJ/spider.obj", "OBJ/regr01.obj",
                                           "STL/Spider_binary.stl", "STL/sphereWithHole.stl",
                                           "STL/3DSMaxExport.STL"),
                         [](const auto& info) {
                             std::string n = info.param;
                             std::replace_if(
                                 n.begin(), n.end(), [](char c) { return !std::isalnum(c); }, '_');
                             return n;
                         });

TEST(MeshReaderModels, ClosedModelsAreSignedByFloodFill) {
    for (const char* name : {"OFF/Cube.off", "PLY/cube_binary.ply", "OBJ/box.obj"}) {
        VDB_MODEL_OR_SKIP(path, name);
        EXPECT_TRUE(modelMatchesTheWindingNumber(path, tools::MeshSign::FloodFill));
    }
}

TEST(MeshReaderModels, InvalidOffThrows) {
    VDB_MODEL_OR_SKIP(path, "OFF/invalid.off");
    EXPECT_TRUE(rejectsFile(path));
}

TEST(MeshReaderModels, SphereWithHoleSignsByWindingNumbers) {
    VDB_MODEL_OR_SKIP(path, "STL/sphereWithHole.stl");
    const Mesh mesh = readMesh(path);
    const auto [lo, hi] = bounds(mesh);
    const Vec3d center = 0.5 * (lo + hi), extent = hi - lo;
    const double dx = extent[0] / 48;
    const auto xform = math::Transform::createLinearTransform(dx);
    tools::MeshToVolumeOptions options;
    options.sign = tools::MeshSign::WindingNumber;
    const auto grid =
        tools::meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads, options);
    // The default picks the same.
    EXPECT_TRUE(test::sameContents(
        grid->tree(),
        tools::meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads)->tree()));
    const auto valueAt = [&](const Vec3d& world) {
        return grid->tree().getValue(xform->worldToIndexCellCentered(world));
    };
    // Deep inside, and well outside on every axis, far from the hole.
    EXPECT_LT(valueAt(center), 0.0f);
    for (int axis = 0; axis < 3; ++axis) {
        Vec3d out = center;
        out[axis] = hi[axis] + 0.25 * extent[axis];
        EXPECT_GT(valueAt(out), 0.0f) << out;
        out[axis] = lo[axis] - 0.25 * extent[axis];
        EXPECT_GT(valueAt(out), 0.0f) << out;
    }
    // Inside near the sides, a quarter of the way in.
    for (int axis = 0; axis < 3; ++axis) {
        Vec3d in = center;
        in[axis] = lo[axis] + 0.25 * extent[axis];
        EXPECT_LT(valueAt(in), 0.0f) << in;
        in[axis] = hi[axis] - 0.25 * extent[axis];
        EXPECT_LT(valueAt(in), 0.0f) << in;
    }
}

}  // namespace
}  // namespace vdb::meshio
