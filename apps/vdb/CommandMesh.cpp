// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb mesh IN -o OUT.vdb`: a polygon mesh (OBJ, PLY, STL, OFF) to a narrow-band level set.

#include "Commands.h"
#include "Geometry.h"

#include <cmath>
#include <string>
#include <utility>

namespace vdb::app {
namespace {

double meshArea(const meshio::Mesh& mesh) {
    const auto triangleArea = [&](uint32_t a, uint32_t b, uint32_t c) {
        const Vec3d p(mesh.points[a]), q(mesh.points[b]), r(mesh.points[c]);
        return 0.5 * (q - p).cross(r - p).length();
    };
    double area = 0.0;
    for (const Vec3I& t : mesh.triangles)
        area += triangleArea(t[0], t[1], t[2]);
    for (const Vec4I& q : mesh.quads)
        area += triangleArea(q[0], q[1], q[2]) + triangleArea(q[0], q[2], q[3]);
    return area;
}

/// The --sign names, in the order of tools::MeshSign.
constexpr std::pair<const char*, tools::MeshSign> kSignNames[] = {
    {"auto", tools::MeshSign::Auto},
    {"flood", tools::MeshSign::FloodFill},
    {"winding", tools::MeshSign::WindingNumber},
    {"robust", tools::MeshSign::WindingNumber},  // the earlier name of "winding"
    {"unsigned", tools::MeshSign::Unsigned},
};

tools::MeshSign signByName(const std::string& name) {
    for (const auto& [n, sign] : kSignNames) {
        if (name == n)
            return sign;
    }
    throw UsageError("unknown --sign " + name);
}

const char* signName(tools::MeshSign sign) {
    for (const auto& [n, s] : kSignNames) {
        if (s == sign)
            return n;
    }
    return "auto";
}

/// "12 boundary edges, 3 non-manifold edges" for the counts that are not 0, or "".
std::string edgeDefects(const tools::MeshToVolumeReport& r) {
    std::string text;
    const auto add = [&](size_t n, const char* what) {
        if (n > 0)
            text += (text.empty() ? "" : ", ") + withCommas(n) + " " + what;
    };
    add(r.boundaryEdges, r.boundaryEdges == 1 ? "boundary edge" : "boundary edges");
    add(r.nonManifoldEdges, r.nonManifoldEdges == 1 ? "non-manifold edge" : "non-manifold edges");
    add(r.misorientedEdges, r.misorientedEdges == 1
                                ? "edge between faces of opposite orientation"
                                : "edges between faces of opposite orientation");
    return text;
}

/// Why the converter signed the mesh the way it did, in a line.
std::string signReason(tools::MeshSign asked, const tools::MeshToVolumeReport& r) {
    if (r.sign == tools::MeshSign::Unsigned)
        return "unsigned distances (asked for)";
    std::string mesh;
    const std::string defects = edgeDefects(r);
    if (r.holes == 0) {
        mesh = defects.empty() ? "mesh is closed and consistently oriented"
                               : "mesh is closed (" + defects + ")";
    } else {
        mesh = withCommas(r.holes) + (r.holes == 1 ? " open loop" : " open loops") + " (" +
               defects + ")";
    }
    if (r.flippedFaces > 0) {
        mesh += ", " + withCommas(r.flippedFaces) +
                (r.flippedFaces == 1 ? " face turned to agree with its neighbours"
                                     : " faces turned to agree with their neighbours");
    }
    if (r.mergedPoints > 0)
        mesh += ", " + withCommas(r.mergedPoints) + " coincident points welded";
    const char* method = r.sign == tools::MeshSign::FloodFill
                             ? (r.holes == 0 ? "flood fill" : "flood fill by crossing parity")
                             : (r.holes == 0 ? "winding numbers (exact crossing counts)"
                                             : "winding numbers near the holes");
    return mesh + ": " + method + (asked == tools::MeshSign::Auto ? "" : " (asked for)");
}

}  // namespace

void reportMesh(Report& report, const meshio::Mesh& mesh) {
    report.note("  " + withCommas(mesh.points.size()) + " points, " +
                withCommas(mesh.triangles.size()) + " triangles, " + withCommas(mesh.quads.size()) +
                " quads");
    report.json()
        .key("points")
        .value(static_cast<uint64_t>(mesh.points.size()))
        .key("triangles")
        .value(static_cast<uint64_t>(mesh.triangles.size()))
        .key("quads")
        .value(static_cast<uint64_t>(mesh.quads.size()));
}

BBoxd meshBounds(const meshio::Mesh& mesh) {
    BBoxd box;
    for (const Vec3s& p : mesh.points)
        box.expand(Vec3d(p));
    return box;
}

FloatGrid::Ptr meshToGrid(Report& report, const meshio::Mesh& mesh, double voxelSize,
                          float halfWidth, tools::MeshSign sign, tools::MeshToVolumeReport* found) {
    // Band voxels: about the area in voxels times the band's width, each ~5 bytes in the
    // grid plus the converter's per-voxel scratch; the interior is filled with tiles.
    const double area = meshArea(mesh) / (voxelSize * voxelSize);
    checkMemoryEstimate(24.0 * area * 2.0 * double(halfWidth), "this mesh at this voxel size");
    // Mesh points are held as floats.
    checkFloatPrecision(meshBounds(mesh), voxelSize, "the box of this mesh");
    const auto xform = math::Transform::createLinearTransform(voxelSize);
    tools::MeshToVolumeOptions options;
    options.exteriorBandWidth = halfWidth;
    options.interiorBandWidth = halfWidth;
    options.sign = sign;
    return report.step(
        "scan-convert " + withCommas(mesh.triangles.size() + mesh.quads.size()) + " faces", [&] {
            return tools::meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads,
                                                  options, found);
        });
}

void addMeshCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string input;
        OutputArgs out;
        double voxelSize = 0;
        int resolution = 0;
        float halfWidth = 3.0f;
        std::string sign = "auto";
        std::string name = "surface";
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "mesh", "Convert a polygon mesh (OBJ, PLY, STL, OFF) to a narrow-band level set",
        true, [args, &ctx] {
            Args& a = *args;
            if (a.voxelSize <= 0 && a.resolution <= 0)
                throw UsageError("give --voxel-size or --resolution");
            runCreate(
                ctx, a.out, a.name,
                [&](Report& report) {
                    const meshio::Mesh mesh =
                        report.step("read " + a.input, [&] { return meshio::readMesh(a.input); });
                    const BBoxd box = meshBounds(mesh);
                    const double extent =
                        std::max({box.extents()[0], box.extents()[1], box.extents()[2]});
                    double voxelSize = a.voxelSize;
                    if (a.resolution > 0) {
                        if (!(extent > 0))
                            throw UsageError(a.input +
                                             " is flat in every direction; give --voxel-size");
                        voxelSize = extent / a.resolution;
                    }
                    for (int i = 0; i < 3; ++i)
                        checkIndexRange(box.min()[i] / voxelSize - a.halfWidth,
                                        box.max()[i] / voxelSize + a.halfWidth,
                                        a.input + " at voxel size " + numberText(voxelSize));
                    reportMesh(report, mesh);
                    report.note("  voxel size " + numberText(voxelSize) + " (" +
                                std::to_string(int(std::ceil(extent / voxelSize))) +
                                " voxels across the largest side)");
                    const tools::MeshSign sign = signByName(a.sign);
                    tools::MeshToVolumeReport found;
                    FloatGrid::Ptr grid =
                        meshToGrid(report, mesh, voxelSize, a.halfWidth, sign, &found);
                    const std::string reason = signReason(sign, found);
                    report.note("  signs: " + reason);
                    report.json()
                        .key("voxelSize")
                        .value(voxelSize)
                        .key("sign")
                        .value(signName(found.sign))
                        .key("signReason")
                        .value(reason)
                        .key("mergedPoints")
                        .value(static_cast<uint64_t>(found.mergedPoints))
                        .key("boundaryEdges")
                        .value(static_cast<uint64_t>(found.boundaryEdges))
                        .key("nonManifoldEdges")
                        .value(static_cast<uint64_t>(found.nonManifoldEdges))
                        .key("misorientedEdges")
                        .value(static_cast<uint64_t>(found.misorientedEdges))
                        .key("flippedFaces")
                        .value(static_cast<uint64_t>(found.flippedFaces))
                        .key("holes")
                        .value(static_cast<uint64_t>(found.holes));
                    return grid;
                },
                "the mesh has no faces, or none the voxels resolve");
        });
    cmd->add_option("input", args->input, "The mesh file (.obj, .ply, .stl or .off)")->required();
    addOutputOptions(*cmd, args->out);
    auto* size = cmd->add_option("-s,--voxel-size", args->voxelSize, "Voxel edge in world units")
                     ->check(positive());
    auto* res = cmd->add_option("-r,--resolution", args->resolution,
                                "Instead: voxels across the mesh's largest side")
                    ->check(CLI::Range(1, 1 << 16));
    size->excludes(res);
    res->excludes(size);
    cmd->add_option("-w,--half-width", args->halfWidth, "Half the band width, in voxels")
        ->check(finiteRange(1.0, 1000.0))
        ->capture_default_str();
    cmd->add_option("--sign", args->sign,
                    "auto: chosen from the mesh's edges (flood for closed meshes, winding "
                    "otherwise); flood: closed meshes (crossing counts and flood fill); "
                    "winding: generalized winding numbers of the faces as given (meshes with "
                    "holes; robust is another name for it); unsigned: distances without sign")
        ->check(CLI::IsMember({"auto", "flood", "winding", "robust", "unsigned"}))
        ->capture_default_str();
    cmd->add_option("-n,--name", args->name, "Grid name")->capture_default_str();
    cmd->footer(
        "Examples:\n  vdb mesh bunny.ply -o bunny.vdb --resolution 512\n"
        "  vdb mesh scan.stl -o scan.vdb --voxel-size 0.5 --half-width 4 --json");
}

}  // namespace vdb::app
