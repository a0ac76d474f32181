// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb demo`: the pipeline of the paper in one run. The torus-knot-helix of Fig. 8 from a
/// million spheres and a polygon mesh become level sets, their CSG union is written to a
/// `.vdb` file, meshed back to polygons in a PLY file and rendered to a PNG picture, each step
/// timed.

#include <vdb/meshio/MeshWriter.h>
#include <vdb/render/Camera.h>
#include <vdb/render/Renderer.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/VolumeToMesh.h>

#include "Commands.h"
#include "Geometry.h"
#include "PngWriter.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>

namespace vdb::app {
namespace {

/// A mesh the Debian package assimp-testmodels ships (the duck of the PLY test files).
constexpr const char* kShippedMesh = "/usr/share/assimp/models/PLY/Wuson.ply";

/// A torus of quads around the z axis (major radius R, minor r), for machines without the
/// shipped mesh.
meshio::Mesh torusMesh(float R, float r, uint32_t nu, uint32_t nv) {
    meshio::Mesh mesh;
    for (uint32_t i = 0; i < nu; ++i) {
        const double u = 2.0 * std::numbers::pi * i / nu;
        for (uint32_t j = 0; j < nv; ++j) {
            const double v = 2.0 * std::numbers::pi * j / nv;
            const double w = R + r * std::cos(v);
            mesh.points.emplace_back(float(w * std::cos(u)), float(w * std::sin(u)),
                                     float(r * std::sin(v)));
        }
    }
    for (uint32_t i = 0; i < nu; ++i)
        for (uint32_t j = 0; j < nv; ++j) {
            const uint32_t i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            mesh.quads.emplace_back(i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1);
        }
    return mesh;
}

/// Scales and moves the mesh so that its largest side is `size` and its box is centred at
/// `center`.
void fitMesh(meshio::Mesh& mesh, double size, const Vec3d& center) {
    const BBoxd box = meshBounds(mesh);
    const Vec3d extents = box.extents();
    const double largest = std::max({extents[0], extents[1], extents[2]});
    const double scale = largest > 0 ? size / largest : 1.0;
    const Vec3d middle = box.center();
    for (Vec3s& p : mesh.points)
        p = Vec3s((Vec3d(p) - middle) * scale + center);
}

}  // namespace

void addDemoCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string folder = ".";
        size_t spheres = 1'000'000;
        int resolution = 1024;
        std::string mesh;
        size_t width = 1280;
        size_t height = 960;
        double adaptivity = 0.5;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "demo",
        "The whole pipeline: spheres and a mesh to level sets, CSG, a .vdb file, a mesh and a "
        "PNG",
        true, [args, &ctx] {
            const Args& a = *args;
            namespace fs = std::filesystem;
            if (!fs::is_directory(a.folder))
                throw UsageError("output folder " + a.folder + " does not exist");
            const std::string vdbPath = (fs::path(a.folder) / "demo.vdb").string();
            const std::string pngPath = (fs::path(a.folder) / "demo.png").string();
            const std::string plyPath = (fs::path(a.folder) / "demo.ply").string();
            const auto start = std::chrono::steady_clock::now();
            const double voxelSize = 1.0 / a.resolution;
            const float halfWidth = 3.0f;
            checkMemoryEstimate(double(a.spheres) * (sizeof(Vec3s) + sizeof(float)) * 2.0 +
                                    double(a.width) * double(a.height) * 2.0 * sizeof(render::Rgba),
                                "the demo's spheres and picture");
            Report report(ctx);

            // 1. The torus-knot-helix (paper Fig. 8) in the unit box: spheres of radius 0.005,
            //    or two voxels where voxels are coarser, so that every sphere is resolved.
            const float radius = float(std::max(0.005, 2.0 * voxelSize));
            const tools::SphereList spheres =
                report.step("place " + withCommas(a.spheres) + " spheres along a torus-knot-helix",
                            [&] { return tools::torusKnotHelixSpheres(a.spheres, radius); });
            FloatGrid::Ptr helix = spheresToGrid(report, spheres, voxelSize, halfWidth);
            helix->setName("helix");
            report.json().key("grids").beginArray();
            const auto summary = [&](const GridBase& grid) {
                report.json().beginObject();
                reportGrid(report, grid);
                report.json().endObject();
            };
            summary(*helix);

            // 2. A polygon mesh, scaled to stand in the knot's hole.
            std::string meshName = a.mesh;
            if (meshName.empty() && fs::exists(kShippedMesh))
                meshName = kShippedMesh;
            meshio::Mesh mesh =
                meshName.empty()
                    ? report.step("make a torus mesh",
                                  [] { return torusMesh(1.0f, 0.35f, 512, 128); })
                    : report.step("read " + meshName, [&] { return meshio::readMesh(meshName); });
            if (!meshName.empty())  // files are y-up by convention; the scene is z-up
                for (Vec3s& p : mesh.points)
                    p = Vec3s(p[0], -p[2], p[1]);
            fitMesh(mesh, 0.5, Vec3d(0.5, 0.5, 0.5));
            FloatGrid::Ptr surface =
                meshToGrid(report, mesh, voxelSize, halfWidth, tools::MeshSign::Auto);
            surface->setName("mesh");
            summary(*surface);

            // 3. CSG union on whole branches (the inputs are kept for the file).
            FloatGrid::Ptr both = helix->deepCopy();
            both->setName("union");
            report.step("csg union", [&] {
                FloatGrid::Ptr tool = surface->deepCopy();
                tools::csgUnion(*both, *tool);
            });
            summary(*both);
            report.json().endArray();

            // 4. The union back to polygons.
            meshio::Mesh polygons;
            std::ostringstream meshLabel;
            meshLabel << "mesh the union (adaptivity " << a.adaptivity << ")";
            report.step(meshLabel.str(), [&] {
                tools::volumeToMesh(*both, polygons.points, polygons.triangles, polygons.quads, 0.0,
                                    a.adaptivity);
            });

            // 5. A picture of the union, made before anything is written.
            const CoordBBox bbox = both->evalActiveVoxelBoundingBox();
            const BBoxd worldBox = both->transform().indexToWorld(bbox);
            const auto camera = render::PerspectiveCamera::frame(
                worldBox, a.width, a.height, Vec3d(-0.45, -1.0, -0.75), 24.0, Vec3d(0, 0, 1));
            render::LevelSetRenderSettings settings;
            settings.lightDirection = Vec3d(0.3, 0.9, 0.7);
            settings.background = render::Rgba{0.06f, 0.07f, 0.09f, 1.0f};
            const render::Image image =
                report.step("ray-trace " + std::to_string(a.width) + "x" + std::to_string(a.height),
                            [&] { return render::renderLevelSet(*both, camera, settings); });

            // 6. The .vdb file (the three grids, blosc and active-mask compression), the union's
            //    mesh as PLY, and the PNG.
            writeGrids(vdbPath, {helix, surface, both},
                       io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK);
            report.note("  wrote " + vdbPath + " (" + bytesText(fs::file_size(vdbPath)) + ")");
            report.step("write " + plyPath, [&] { meshio::writeMesh(plyPath, polygons); });
            report.note("  wrote " + plyPath + " (" +
                        withCommas(polygons.quads.size() + polygons.triangles.size()) +
                        " polygons, " + bytesText(fs::file_size(plyPath)) + ")");
            report.step("write " + pngPath, [&] { writePng(pngPath, image); });

            const double total =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            report.note("demo done in " + secondsText(total) + ": " + vdbPath + ", " + plyPath +
                        ", " + pngPath);
            report.json()
                .key("spheres")
                .value(static_cast<uint64_t>(a.spheres))
                .key("resolution")
                .value(static_cast<int64_t>(a.resolution))
                .key("mesh")
                .value(meshName.empty() ? std::string("generated torus") : meshName)
                .key("activeVoxels")
                .value(static_cast<uint64_t>(both->activeVoxelCount()))
                .key("vdb")
                .value(vdbPath)
                .key("png")
                .value(pngPath)
                .key("ply")
                .value(plyPath)
                .key("polygons")
                .value(static_cast<uint64_t>(polygons.quads.size() + polygons.triangles.size()))
                .key("seconds")
                .value(total);
            report.finish();
        });
    cmd->add_option("-o,--output-dir", args->folder, "Folder for demo.vdb, demo.ply and demo.png")
        ->capture_default_str();
    cmd->add_option("--spheres", args->spheres, "Spheres along the torus-knot-helix")
        ->check(CLI::Range(size_t(1), size_t(20'000'000)))
        ->capture_default_str();
    cmd->add_option("--resolution", args->resolution, "Voxels across the unit box")
        ->check(CLI::Range(32, 8192))
        ->capture_default_str();
    cmd->add_option("--mesh", args->mesh,
                    std::string("Mesh file (default: ") + kShippedMesh +
                        " when installed, else a generated torus)");
    cmd->add_option("--adaptivity", args->adaptivity,
                    "Adaptivity of demo.ply, the union as polygons (0: a quad per surface voxel)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--width", args->width, "Picture width in pixels")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    cmd->add_option("--height", args->height, "Picture height in pixels")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    cmd->footer("Examples:\n  vdb demo -o /tmp\n  vdb demo --spheres 100000 --resolution 256");
}

}  // namespace vdb::app
