// SPDX-License-Identifier: Apache-2.0
// Ray marching of the paper's section 4.7: rays per second of level set intersection (hit
// point and normal) of this library's LevelSetRayIntersector against OpenVDB 10's, on the same
// level sets and the same rays, in one process.
//
//   sphere   the Enright sphere at resolution R (radius 0.15 at (0.35, 0.35, 0.35) of the unit
//            box, voxel size 1/R, half width 5), made by each library's createLevelSetSphere
//            (they produce the same voxels)
//   torus    a torus (major radius 0.15, minor 0.06, centred at (0.5, 0.5, 0.5), axis tilted
//            by 30 degrees about x): the same narrow band voxels inserted into both trees and
//            flood-filled by each library's signedFloodFill
//   wuson    Wuson.ply of the Debian package assimp-testmodels (read with vdb::meshio),
//            converted once by this library's meshToVolume at a bounding resolution of R (the
//            voxel size is the longest edge of the mesh's bounding box over R), half width 5,
//            with winding-number signs: the mesh has holes (edges with one face), and the
//            scanline signs of meshToLevelSet would leave inside regions that meet the outside
//            without a band, which this library's intersector reports as hits and OpenVDB's
//            skips. Its leaves and tiles are copied value by value into an OpenVDB grid, so
//            that both libraries march identical data. A default scene where that file is
//            installed.
//
// Rays: one per pixel centre of a W x H perspective image (40 degree field of view) framing the
// level set's active bounding box, looking along (-1, -0.6, -0.8); the same world-space rays
// go to both libraries. A pass intersects every ray, in rows split among oneTBB tasks (each task
// with its own copy of the intersector). Passes of the two libraries alternate; the medians of
// the passes are reported as rays per wall-clock second and per CPU second of the process
// (the latter is what a loaded machine distorts least). Both libraries' hits are compared:
// pixels hit by one and not the other, and the largest distance between hit points hit by both
// (in voxels, so that the measure is the same for every scene). A second row per case times
// the whole renderers on the same camera: this library's renderLevelSet (diffuse shading, one
// light) against OpenVDB's tools::rayTrace (LevelSetRayTracer with a DiffuseShader, one sample
// a pixel), in pixels per second.
//
// With --fog-samples DIR and --vdb-tool PATH the program also compares fog volume rendering,
// tool against tool: this library's `vdb render` against OpenVDB's `vdb_render` on the .vdb
// files of DIR (bench/FogToolComparison.h), --fog-reps runs each at --fog-size, keeping the
// last pictures in --fog-pictures DIR. --scenes none skips the level set part.
//
// With --markdown FILE the program also writes its results as Markdown tables to FILE and one
// overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// With --write-scenes DIR the program only writes DIR/level-set.vdb (a level set: the union
// of the sphere and the torus) and DIR/fog.vdb (a fog volume made from it), which
// scripts/render-docs renders with `vdb render` into the pictures of docs/.
//
// Usage: vdb_bench_render [--res 512,1024] [--size 1024x1024] [--reps 5]
//                         [--scenes sphere,torus,wuson|none] [--threads 1,all] [--markdown FILE]
//                         [--fog-samples DIR --vdb-tool PATH [--vdb-render PATH]
//                          [--fog-size 960x720] [--fog-reps 3] [--fog-pictures DIR]]
//                         [--write-scenes DIR]

#include <vdb/io/File.h>
#include <vdb/math/Transform.h>
#include <vdb/render/Camera.h>
#include <vdb/render/Renderer.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/RayIntersector.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/vdb.h>

#ifdef VDB_BENCH_MESHIO
#include <vdb/meshio/MeshReader.h>
#endif

#include "BenchCommon.h"
#include "FogToolComparison.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/RayIntersector.h>
#include <openvdb/tools/RayTracer.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace {

constexpr float kHalfWidth = 5.0f;

// ---- Inputs (library-neutral) ----

using vdb::bench::BandVoxel;  // here with values in world units

/// The narrow band of the tilted torus described in the file comment, at `resolution`.
std::vector<BandVoxel> makeTorusBand(int resolution) {
    const double c = 0.5 * resolution, major = 0.15 * resolution, minor = 0.06 * resolution;
    const double ca = std::cos(std::numbers::pi / 6), sa = std::sin(std::numbers::pi / 6);
    const double reach = major + minor + kHalfWidth + 2;
    const int lo = int(std::floor(c - reach)), hi = int(std::ceil(c + reach));
    std::vector<BandVoxel> band;
    for (int i = lo; i <= hi; ++i)
        for (int j = lo; j <= hi; ++j)
            for (int k = lo; k <= hi; ++k) {
                // Rotate into the torus frame (about x by 30 degrees).
                const double x = i - c, y = ca * (j - c) + sa * (k - c),
                             z = -sa * (j - c) + ca * (k - c);
                const double d = std::hypot(std::hypot(x, y) - major, z) - minor;
                if (std::abs(d) < kHalfWidth)
                    band.push_back({i, j, k, float(d / resolution)});
            }
    return band;
}

struct WorldRay {
    double eye[3], dir[3];
};

#ifdef VDB_BENCH_MESHIO
constexpr const char* kWuson = "/usr/share/assimp/models/PLY/Wuson.ply";
#endif

/// Why the wuson scene cannot run here, or "" when it can: it needs vdb::meshio at build time
/// and Wuson.ply (package assimp-testmodels) at run time.
std::string wusonMissing() {
#ifdef VDB_BENCH_MESHIO
    std::error_code ec;
    if (std::filesystem::is_regular_file(kWuson, ec))
        return "";
    return std::string(kWuson) + " not found (package assimp-testmodels)";
#else
    return "built without vdb::meshio (assimp)";
#endif
}

// ---- Library tags ----

struct Vdb {
    static constexpr const char* kName = "vdb";
    using GridT = vdb::FloatGrid;
    using Intersector = vdb::tools::LevelSetRayIntersector<GridT>;
    using Vec3 = vdb::Vec3d;
    using RayT = vdb::math::Ray<double>;
    static GridT::Ptr sphere(int res) {
        return vdb::tools::createLevelSetSphere<GridT>(0.15f, vdb::Vec3f(0.35f), 1.0f / res,
                                                       kHalfWidth);
    }
    static GridT::Ptr fromBand(const std::vector<BandVoxel>& band, int res) {
        auto grid = GridT::create(kHalfWidth / res);
        grid->setTransform(vdb::math::Transform::createLinearTransform(1.0 / res));
        grid->setGridClass(vdb::GRID_LEVEL_SET);
        auto acc = grid->getAccessor();
        for (const BandVoxel& v : band)
            acc.setValue(vdb::Coord(v.x, v.y, v.z), v.value);
        vdb::tools::signedFloodFill(grid->tree());
        return grid;
    }
    /// Wuson.ply converted by meshToVolume at a bounding resolution of `res`, half width
    /// kHalfWidth, signed by winding numbers (see the file comment); `triangles` receives the
    /// mesh's triangle count (a quad counts as two).
    /// @pre wusonMissing() is empty
    static GridT::Ptr wuson(int res, size_t& triangles) {
#ifdef VDB_BENCH_MESHIO
        const vdb::meshio::Mesh mesh = vdb::meshio::readMesh(kWuson);
        Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (const auto& p : mesh.points) {
            lo = Vec3::minComponent(lo, Vec3(p));
            hi = Vec3::maxComponent(hi, Vec3(p));
        }
        const Vec3 extent = hi - lo;
        const auto xform = vdb::math::Transform::createLinearTransform(
            std::max({extent[0], extent[1], extent[2]}) / res);
        triangles = mesh.triangles.size() + 2 * mesh.quads.size();
        vdb::tools::MeshToVolumeOptions options;
        options.exteriorBandWidth = options.interiorBandWidth = kHalfWidth;
        options.sign = vdb::tools::MeshSign::WindingNumber;
        return vdb::tools::meshToVolume<GridT>(*xform, mesh.points, mesh.triangles, mesh.quads,
                                               options);
#else
        (void)res;
        triangles = 0;
        return nullptr;
#endif
    }
    static RayT ray(const WorldRay& r) {
        return RayT(Vec3(r.eye[0], r.eye[1], r.eye[2]), Vec3(r.dir[0], r.dir[1], r.dir[2]));
    }
};

struct OpenVdb {
    static constexpr const char* kName = "openvdb";
    using GridT = openvdb::FloatGrid;
    using Intersector = openvdb::tools::LevelSetRayIntersector<GridT>;
    using Vec3 = openvdb::Vec3d;
    using RayT = openvdb::math::Ray<double>;
    static GridT::Ptr sphere(int res) {
        return openvdb::tools::createLevelSetSphere<GridT>(0.15f, openvdb::Vec3f(0.35f), 1.0f / res,
                                                           kHalfWidth);
    }
    static GridT::Ptr fromBand(const std::vector<BandVoxel>& band, int res) {
        auto grid = GridT::create(kHalfWidth / res);
        grid->setTransform(openvdb::math::Transform::createLinearTransform(1.0 / res));
        grid->setGridClass(openvdb::GRID_LEVEL_SET);
        auto acc = grid->getAccessor();
        for (const BandVoxel& v : band)
            acc.setValue(openvdb::Coord(v.x, v.y, v.z), v.value);
        openvdb::tools::signedFloodFill(grid->tree());
        return grid;
    }
    /// A copy of `ours`, leaf by leaf and tile by tile: the same values and active states, the
    /// same background and voxel size, grid class level set.
    /// @pre ours' transform is a uniform scale, as Vdb::wuson() makes it
    static GridT::Ptr copyOf(const Vdb::GridT& ours) {
        using OurLeaf = Vdb::GridT::TreeType::LeafNodeType;
        using TheirLeaf = GridT::TreeType::LeafNodeType;
        // Both leaves store voxel (i, j, k) at offset (i * 8 + j) * 8 + k.
        static_assert(OurLeaf::DIM == TheirLeaf::DIM && OurLeaf::NUM_VALUES == TheirLeaf::SIZE,
                      "The two libraries' float leaves must have the same shape.");
        auto grid = GridT::create(ours.background());
        grid->setTransform(openvdb::math::Transform::createLinearTransform(ours.voxelSize()[0]));
        grid->setGridClass(openvdb::GRID_LEVEL_SET);
        auto& tree = grid->tree();
        const auto coord = [](const vdb::Coord& c) { return openvdb::Coord(c.x(), c.y(), c.z()); };
        for (const OurLeaf& leaf : ours.tree().leaves()) {
            TheirLeaf* copy = tree.touchLeaf(coord(leaf.origin()));
            for (openvdb::Index n = 0; n < TheirLeaf::SIZE; ++n) {
                copy->setValueOnly(n, leaf.getValue(n));
                copy->setActiveState(n, leaf.isValueOn(n));
            }
        }
        // A fill of exactly a tile's region makes a tile of the same size in OpenVDB's tree.
        for (auto it = ours.tree().cbeginValueAll(); it; ++it) {
            if (!it.isTileValue())
                continue;
            vdb::CoordBBox box;
            it.getBoundingBox(box);
            tree.fill(openvdb::CoordBBox(coord(box.min()), coord(box.max())), *it, it.isValueOn());
        }
        return grid;
    }
    static RayT ray(const WorldRay& r) {
        return RayT(Vec3(r.eye[0], r.eye[1], r.eye[2]), Vec3(r.dir[0], r.dir[1], r.dir[2]));
    }
};

// ---- Timing ----

using Clock = std::chrono::steady_clock;

using vdb::bench::median;

/// The hits of one pass: per pixel, whether the ray hit and where (world space).
struct Hits {
    std::vector<uint8_t> hit;
    std::vector<double> xyz, normal;  // 3 per pixel
    uint64_t count() const { return uint64_t(std::count(hit.begin(), hit.end(), uint8_t(1))); }
};

/// Seconds of CPU time used by the whole process (every thread).
double cpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Wall-clock and CPU seconds of one pass.
struct PassTime {
    double wall = 0, cpu = 0;
};

/// One pass of `prototype`'s library over all rays, in rows split among oneTBB tasks.
template <typename Lib>
PassTime runPass(const typename Lib::Intersector& prototype, const std::vector<WorldRay>& rays,
                 size_t width, Hits& hits) {
    hits.hit.assign(rays.size(), 0);
    hits.xyz.assign(rays.size() * 3, 0.0);
    hits.normal.assign(rays.size() * 3, 0.0);
    const size_t height = rays.size() / width;
    const double cpu0 = cpuSeconds();
    const auto start = Clock::now();
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, height, 4), [&](const tbb::blocked_range<size_t>& rows) {
            typename Lib::Intersector intersector(prototype);
            typename Lib::Vec3 xyz, normal;
            for (size_t y = rows.begin(); y < rows.end(); ++y)
                for (size_t x = 0; x < width; ++x) {
                    const size_t p = y * width + x;
                    const bool hit = intersector.intersectsWS(Lib::ray(rays[p]), xyz, normal);
                    hits.hit[p] = hit;
                    if (!hit)
                        continue;
                    for (int i = 0; i < 3; ++i) {
                        hits.xyz[3 * p + size_t(i)] = xyz[i];
                        hits.normal[3 * p + size_t(i)] = normal[i];
                    }
                }
        });
    PassTime t;
    t.wall = std::chrono::duration<double>(Clock::now() - start).count();
    t.cpu = cpuSeconds() - cpu0;
    return t;
}

/// Rays through the pixel centres of a width x height image framing `worldBox`.
std::vector<WorldRay> makeRays(const vdb::BBoxd& worldBox, size_t width, size_t height) {
    const auto camera =
        vdb::render::PerspectiveCamera::frame(worldBox, width, height, vdb::Vec3d(-1, -0.6, -0.8));
    std::vector<WorldRay> rays(width * height);
    for (size_t y = 0; y < height; ++y)
        for (size_t x = 0; x < width; ++x) {
            const auto r = camera.ray(double(x) + 0.5, double(y) + 0.5);
            WorldRay& w = rays[y * width + x];
            for (int i = 0; i < 3; ++i) {
                w.eye[i] = r.eye()[size_t(i)];
                w.dir[i] = r.dir()[size_t(i)];
            }
        }
    return rays;
}

// ---- Whole renderers ----

/// Pixels per second of the two renderers (ours: renderLevelSet, diffuse shading with one light;
/// OpenVDB: tools::rayTrace, its LevelSetRayTracer with a DiffuseShader, one sample a pixel)
/// for the same pinhole camera, and how many pixels each found on the surface.
struct RenderRow {
    double wallA = 0, wallB = 0;
    size_t hitsA = 0, hitsB = 0;
};

RenderRow timeRenderers(const Vdb::GridT& ours, const OpenVdb::GridT& theirs, const vdb::BBoxd& box,
                        size_t width, size_t height, int reps) {
    const double fov = 40.0;
    const auto camera =
        vdb::render::PerspectiveCamera::frame(box, width, height, vdb::Vec3d(-1, -0.6, -0.8), fov);
    // OpenVDB's camera takes the horizontal aperture over the focal length.
    openvdb::tools::Film film(width, height);
    const double focal = 50.0,
                 aperture = 2.0 * focal * camera.tanHalfFov() * double(width) / double(height);
    const vdb::Vec3d pos = camera.position(), centre = box.center();
    openvdb::tools::PerspectiveCamera ovdbCamera(
        film, openvdb::Vec3R(0.0), openvdb::Vec3R(pos[0], pos[1], pos[2]), focal, aperture);
    ovdbCamera.lookAt(openvdb::Vec3R(centre[0], centre[1], centre[2]));
    const openvdb::tools::DiffuseShader<openvdb::tools::Film::RGBA> shader;
    vdb::render::LevelSetRenderSettings settings;
    std::vector<double> wallA, wallB;
    RenderRow row;
    for (int r = 0; r < reps; ++r) {
        auto start = Clock::now();
        const vdb::render::Image image = vdb::render::renderLevelSet(ours, camera, settings);
        wallA.push_back(std::chrono::duration<double>(Clock::now() - start).count());
        film.fill(openvdb::tools::Film::RGBA(0.0f));  // misses stay black
        start = Clock::now();
        openvdb::tools::rayTrace(theirs, shader, ovdbCamera, 1, 0, true);
        wallB.push_back(std::chrono::duration<double>(Clock::now() - start).count());
        if (r == 0) {
            const auto bytes = image.toRgba8(false);
            for (size_t p = 0; p < width * height; ++p)
                row.hitsA += bytes[4 * p] || bytes[4 * p + 1] || bytes[4 * p + 2];
            for (size_t y = 0; y < height; ++y)
                for (size_t x = 0; x < width; ++x) {
                    const auto& c = film.pixel(x, y);  // a shaded hit has colour |n . d|
                    row.hitsB += c.r > 0.0f || c.g > 0.0f || c.b > 0.0f;
                }
        }
    }
    row.wallA = median(wallA);
    row.wallB = median(wallB);
    return row;
}

// ---- Pictures ----

/// A fog volume from a level set: density 1 inside (tiles stay tiles), falling to 0 across the
/// band, modulated by a few sines so that the shadows have something to show.
vdb::FloatGrid::Ptr fogFromLevelSet(const vdb::FloatGrid& ls) {
    auto fog = vdb::FloatGrid::create(0.0f);
    fog->setTransform(ls.transform().copy());
    fog->setGridClass(vdb::GRID_FOG_VOLUME);
    const float bg = ls.background();
    auto acc = fog->getAccessor();
    for (auto it = ls.tree().cbeginValueAll(); it; ++it) {
        const float phi = *it;
        if (!(phi < 0.0f))
            continue;
        if (it.isTileValue()) {
            vdb::CoordBBox box;
            it.getBoundingBox(box);
            fog->tree().fill(box, 1.0f, true);
            continue;
        }
        const vdb::Coord ijk = it.getCoord();
        const double n = 0.75 + 0.25 * std::sin(0.21 * ijk.x()) * std::sin(0.17 * ijk.y() + 1.0) *
                                    std::sin(0.23 * ijk.z() + 2.0);
        acc.setValue(ijk, float(std::min(1.0, double(-phi / bg)) * n));
    }
    return fog;
}

/// Writes DIR/level-set.vdb (the union of a sphere and a torus at resolution 384) and
/// DIR/fog.vdb (a fog volume made from it), the scenes of the pictures in docs/.
int writeScenes(const std::string& dir) {
    const int res = 384;
    auto ls = vdb::tools::createLevelSetSphere<vdb::FloatGrid>(0.15f, vdb::Vec3f(0.35f), 1.0f / res,
                                                               3.0f);
    auto torus = Vdb::fromBand(makeTorusBand(res), res);
    vdb::tools::csgUnion(*ls, *torus);
    ls->setName("surface");
    vdb::io::File(dir + "/level-set.vdb").write(vdb::GridPtrVec{ls});
    auto fog = fogFromLevelSet(*ls);
    fog->setName("density");
    vdb::io::File(dir + "/fog.vdb").write(vdb::GridPtrVec{fog});
    std::printf("# wrote %s/level-set.vdb and %s/fog.vdb\n", dir.c_str(), dir.c_str());
    return 0;
}

// ---- Command line ----

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> resolutions{1024};
    int reps = 5;
    size_t width = 1024, height = 1024;
    std::vector<std::string> scenes{"sphere", "torus", "wuson"}, threads{"1", "all"};
    std::string scenesDir, markdownPath;
    vdb::bench::FogToolOptions fog;
    fog.pictures = "fog-pictures";
    vdb::bench::Options options(
        "vdb_bench_render [--res 512,1024] [--size 1024x1024] [--reps 5] "
        "[--scenes sphere,torus,wuson|none] [--threads 1,all] [--markdown FILE] "
        "[--fog-samples DIR --vdb-tool PATH [--vdb-render PATH] [--fog-size WxH] "
        "[--fog-reps N] [--fog-pictures DIR]] [--write-scenes DIR]");
    options.numbers("--res", resolutions)
        .size("--size", width, height)
        .number("--reps", reps)
        .list("--scenes", scenes)
        .list("--threads", threads)
        .text("--markdown", markdownPath)
        .text("--write-scenes", scenesDir)
        .text("--fog-samples", fog.samples)
        .text("--vdb-tool", fog.vdbTool)
        .text("--vdb-render", fog.vdbRender)
        .text("--fog-pictures", fog.pictures)
        .number("--fog-reps", fog.reps)
        .size("--fog-size", fog.width, fog.height);
    options.parse(argc, argv);
    if (!scenesDir.empty()) {
        try {
            return writeScenes(scenesDir);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s\n", e.what());
            return 1;
        }
    }

    openvdb::initialize();
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    std::string resText;
    for (const int r : resolutions)
        resText += (resText.empty() ? "" : ", ") + std::to_string(r);
    std::printf(
        "# vdb_bench_render: level set rays (hit point and normal), %zux%zu rays, "
        "resolution %s, medians of %d passes; ratio = vdb / openvdb in rays/s\n",
        width, height, resText.c_str(), reps);
    std::printf("# Mrays/s per wall-clock second, then per CPU second (all threads together)\n");
    std::printf("%-7s %7s %9s %9s %6s %9s %9s %6s  %s\n", "scene", "threads", "vdb", "openvdb",
                "ratio", "vdb cpu", "ovdb cpu", "ratio",
                "hits (differing pixels, worst distance in voxels)");
    // The target: at least 1.25 times OpenVDB's rays per second.
    constexpr double kTarget = 1.25;
    using vdb::bench::fmt;
    using vdb::bench::ratioCell;
    using Row = vdb::bench::MarkdownReport::Row;
    std::vector<Row> rows, checks;
    std::vector<std::string> notes;
    vdb::bench::RatioRange intersectionRatios, rendererRatios;
    const auto pair = [](uint64_t a, uint64_t b) {
        return a == b ? fmt(double(a), 0) : fmt(double(a), 0) + " / " + fmt(double(b), 0);
    };
    bool agree = true;
    for (const int res : resolutions)
        for (const std::string& scene : scenes) {
            Vdb::GridT::Ptr ours;
            OpenVdb::GridT::Ptr theirs;
            std::string label = scene;
            if (scene == "sphere") {
                ours = Vdb::sphere(res);
                theirs = OpenVdb::sphere(res);
            } else if (scene == "torus") {
                const auto band = makeTorusBand(res);
                ours = Vdb::fromBand(band, res);
                theirs = OpenVdb::fromBand(band, res);
            } else if (scene == "wuson") {
                const std::string missing = wusonMissing();
                if (!missing.empty()) {
                    std::printf("# scene wuson skipped: %s\n", missing.c_str());
                    notes.push_back("Scene wuson skipped: " + missing + ".");
                    continue;
                }
                size_t triangles = 0;
                const auto start = Clock::now();
                try {
                    ours = Vdb::wuson(res, triangles);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "%s\n", e.what());
                    return 1;
                }
                const auto converted = Clock::now();
                theirs = OpenVdb::copyOf(*ours);
                const double convertS = std::chrono::duration<double>(converted - start).count();
                const double copyS =
                    std::chrono::duration<double>(Clock::now() - converted).count();
                if (theirs->activeVoxelCount() != ours->activeVoxelCount() ||
                    theirs->tree().leafCount() != ours->tree().leafCount()) {
                    std::fprintf(stderr,
                                 "the OpenVDB copy of the wuson level set differs from it\n");
                    return 1;
                }
                label = "Wuson.ply";
                std::printf(
                    "# wuson: Wuson.ply, %zu triangles, voxel size %g, %llu active voxels in "
                    "both grids (conversion %.1f s, copy %.1f s)\n",
                    triangles, ours->voxelSize()[0], (unsigned long long)ours->activeVoxelCount(),
                    convertS, copyS);
                notes.push_back(
                    "Wuson.ply: " + fmt(double(triangles), 0) +
                    " triangles, converted by this library's meshToVolume (winding-number "
                    "signs) at bounding resolution " +
                    std::to_string(res) + ", half width " + fmt(kHalfWidth, 0) + " (" +
                    fmt(double(ours->activeVoxelCount()), 0) +
                    " active voxels) and copied into an OpenVDB grid.");
            } else {
                options.fail("unknown scene " + scene);
            }
            const double voxelSize = ours->voxelSize()[0];
            const vdb::BBoxd box =
                ours->transform().indexToWorld(ours->evalActiveVoxelBoundingBox());
            const auto rays = makeRays(box, width, height);
            std::vector<Row> intersectionRows, rendererRows;
            std::string firstHits;
            for (const std::string& t : threads) {
                const int n = options.threadCount(t);
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
                // The two libraries alternate, pass by pass, so that load from other processes on
                // the machine falls on both alike.
                const Vdb::Intersector protoA(*ours);
                const OpenVdb::Intersector protoB(*theirs);
                Hits a, b;
                std::vector<double> wallA, wallB, cpuA, cpuB;
                for (int r = 0; r < reps; ++r) {
                    const PassTime ta = runPass<Vdb>(protoA, rays, width, a);
                    const PassTime tb = runPass<OpenVdb>(protoB, rays, width, b);
                    wallA.push_back(ta.wall);
                    wallB.push_back(tb.wall);
                    cpuA.push_back(ta.cpu);
                    cpuB.push_back(tb.cpu);
                }
                const double sa = median(wallA), sb = median(wallB);
                const double ca = median(cpuA), cb = median(cpuB);
                size_t differ = 0;
                double worst = 0.0;
                for (size_t p = 0; p < rays.size(); ++p) {
                    if (a.hit[p] != b.hit[p]) {
                        ++differ;
                        continue;
                    }
                    if (!a.hit[p])
                        continue;
                    double d2 = 0.0;
                    for (int i = 0; i < 3; ++i)
                        d2 += std::pow(a.xyz[3 * p + size_t(i)] - b.xyz[3 * p + size_t(i)], 2);
                    worst = std::max(worst, std::sqrt(d2) / voxelSize);
                }
                // Pixels on the silhouette may differ; more than 0.1% would mean a real difference.
                agree = agree && differ <= rays.size() / 1000;
                const double ra = double(rays.size()) / sa / 1e6,
                             rb = double(rays.size()) / sb / 1e6;
                const double rca = double(rays.size()) / ca / 1e6;
                const double rcb = double(rays.size()) / cb / 1e6;
                std::printf(
                    "%-7s %7d %9.3f %9.3f %6.2f %9.3f %9.3f %6.2f  %llu vs %llu (%zu, %.3f)\n",
                    scene.c_str(), n, ra, rb, ra / rb, rca, rcb, rca / rcb,
                    (unsigned long long)a.count(), (unsigned long long)b.count(), differ, worst);
                const RenderRow rr = timeRenderers(*ours, *theirs, box, width, height, reps);
                const double pa = double(rays.size()) / rr.wallA / 1e6;
                const double pb = double(rays.size()) / rr.wallB / 1e6;
                std::printf(
                    "%-7s %7d %9.3f %9.3f %6.2f  (renderers, Mpixels/s; surface pixels %zu "
                    "vs %zu)\n",
                    scene.c_str(), n, pa, pb, pa / pb, rr.hitsA, rr.hitsB);
                std::fflush(stdout);

                // The report: intersection rows, then renderer rows, the scene named on the first
                // of each, the hit count only where it changes.
                const bool first = intersectionRows.empty();
                const std::string hits = pair(a.count(), b.count());
                intersectionRows.push_back(
                    {first ? label + ", intersection" : "", std::to_string(res), std::to_string(n),
                     fmt(ra, 3), fmt(rb, 3), ratioCell(ra / rb, kTarget, true), fmt(rca, 3),
                     fmt(rcb, 3), ratioCell(rca / rcb, kTarget, true),
                     first || hits != firstHits ? hits : ""});
                if (first)
                    firstHits = hits;
                rendererRows.push_back({first ? label + ", renderer" : "", std::to_string(res),
                                        std::to_string(n), fmt(pa, 3), fmt(pb, 3),
                                        ratioCell(pa / pb, kTarget, true), "", "", "", ""});
                checks.push_back({label, std::to_string(res), std::to_string(n),
                                  fmt(double(a.count()), 0) + " / " + fmt(double(b.count()), 0),
                                  fmt(double(differ), 0), fmt(worst, 3),
                                  fmt(double(rr.hitsA), 0) + " / " + fmt(double(rr.hitsB), 0)});
                intersectionRatios.add(ra / rb);
                rendererRatios.add(pa / pb);
            }
            rows.insert(rows.end(), intersectionRows.begin(), intersectionRows.end());
            rows.insert(rows.end(), rendererRows.begin(), rendererRows.end());
        }
    // Fog volumes, tool against tool (its own tables, after the level set ones).
    constexpr double kFogTarget = 0.8;  // at most 0.8 of vdb_render's time
    vdb::bench::MarkdownReport fogMd;
    vdb::bench::RatioRange fogRatios;
    bool fogOk = true;
    const bool fogRun = !fog.samples.empty();
    if (fogRun) {
        if (fog.vdbTool.empty())
            options.fail("--fog-samples needs --vdb-tool");
        fogOk = vdb::bench::compareFogTools(fog, fogMd, fogRatios, kFogTarget);
    }
    std::printf("# machine: %u hardware threads\n", std::thread::hardware_concurrency());
    if (markdownPath.empty())
        return agree && fogOk ? 0 : 1;

    vdb::bench::MarkdownReport md;
    char line[512];
    if (!rows.empty()) {
        std::snprintf(
            line, sizeof line,
            "%zux%zu rays, resolution %s, medians of %d passes. Intersection rows: million "
            "rays per wall-clock second and per CPU second of the process (all threads "
            "together); renderer rows: million pixels per wall-clock second of whole "
            "pictures. Ratio = vdb / OpenVDB, in bold where it reaches the target (at "
            "least %.2f). The machine has %d hardware threads.",
            width, height, resText.c_str(), reps, kTarget, cores);
        md.paragraph(line);
        md.table({"scene", "res", "threads", "vdb Mrays/s", "OpenVDB Mrays/s", "ratio",
                  "vdb Mrays/CPU s", "OpenVDB Mrays/CPU s", "ratio (CPU)", "hit pixels"},
                 rows);
        for (const std::string& note : notes)
            md.paragraph(note);
        md.paragraph(
            "Hits of the intersection passes compared pixel by pixel: pixels hit by one "
            "library only, and the largest distance between the two hit points of a pixel "
            "hit by both, in voxels; then the surface pixels of the two renderers.");
        md.table({"scene", "res", "threads", "hit pixels vdb / OpenVDB", "pixels hit by one only",
                  "max hit-point distance (voxels)", "renderer surface pixels vdb / OpenVDB"},
                 checks);
        if (!agree)
            md.paragraph("**More than 0.1 % of the pixels were hit by one library only.**");
    }

    // One overview line: both ranges, and whether every ratio reaches the target.
    vdb::bench::RatioRange all = intersectionRatios;
    all.add(rendererRatios.min());
    all.add(rendererRatios.max());
    std::snprintf(line, sizeof line, "intersection %s, renderer %s",
                  intersectionRatios.text().c_str(), rendererRatios.text().c_str());
    std::string status = line;
    if (!all.empty()) {
        std::snprintf(line, sizeof line, " (target >= %.2f: %s)", kTarget,
                      all.min() >= kTarget ? "met" : "not met");
        status += line;
    }
    if (!rows.empty())
        md.status(status);
    if (!agree)
        md.status("hits differ");
    if (fogRun) {
        md.paragraph(fogMd.text());
        md.status(fogRatios.status("fog vs vdb_render", kFogTarget));
        if (!fogOk)
            md.status("a fog render failed");
    }
    if (!md.write(markdownPath))
        return 1;
    return agree && fogOk ? 0 : 1;
}
