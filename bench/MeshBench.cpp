// SPDX-License-Identifier: Apache-2.0
// Geometry to level set benchmarks (Museth 2013, section 4.5, appendix B, Fig. 8): this
// library against OpenVDB 10 on the same inputs, in one process.
//
//   mesh        meshToLevelSet, half width 3, both libraries with their default signs (here
//               MeshSign::Auto, which picks flood fill for closed meshes and winding numbers
//               for the others; the signs column says which), at a bounding resolution: the
//               voxel size is the longest edge of the mesh's bounding box over `res`. Meshes:
//               a generated latitude-longitude sphere or torus with about the given number of
//               triangles (shape:res:triangles), or a model of the Debian package
//               assimp-testmodels read with vdb::meshio (PATH:res, PATH relative to
//               /usr/share/assimp/models, e.g. PLY/Wuson.ply:512; wuson:res is PLY/Wuson.ply)
//   particles   the torus-knot-helix of Fig. 8: N spheres along the curve
//               (tools::torusKnotHelixSpheres, radii 0.00375-0.005 in the unit box) rasterized
//               as the union of their distance fields (ParticlesToLevelSet), half width 3, at
//               voxel size 1/res (res:count)
//
// Each case runs both libraries `reps` times; the median is reported with the ratio ours /
// OpenVDB, and the active voxel counts of both results. "1 thread" runs under
// tbb::global_control with one thread for both libraries; "all" uses every core.
//
// With --markdown FILE the program also writes its results as a Markdown table to FILE and
// one overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_mesh [--cases sphere:256:10000,PLY/Wuson.ply:512,...]
//                       [--particles 1024:100000,...] [--reps 3] [--threads 1,all]
//                       [--markdown FILE]

#include <vdb/meshio/MeshReader.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/ParticlesToLevelSet.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include "TestMeshes.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Runs `op` `reps` times and returns the median in milliseconds; `op` returns the active
/// voxel count of what it built (reported, and kept out of the optimiser's reach).
double timeMs(int reps, const std::function<uint64_t()>& op, uint64_t& active) {
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) {
        const auto start = Clock::now();
        active = op();
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
    return median(ms);
}

// ---- Inputs ----

constexpr const char* kModels = "/usr/share/assimp/models/";

/// True for a case's first part that names a model file rather than a generated shape.
bool isModel(const std::string& shape) {
    return shape == "wuson" || shape.find('.') != std::string::npos;
}

/// A generated closed mesh (`shape` with about `triangles` triangles in the unit box), or a
/// model of assimp-testmodels.
vdb::test::TestMesh makeMesh(const std::string& shape, int triangles) {
    if (shape == "sphere") {
        // 2 * segments * (rings - 1) triangles with segments = 2 * rings.
        const int rings = std::max(3, int(std::lround(std::sqrt(triangles / 4.0))));
        return vdb::test::makeSphereMesh(vdb::Vec3d(0.5), 0.4, rings, 2 * rings);
    }
    if (shape == "torus") {
        // 2 * around * tube triangles with around = 3 * tube.
        const int tube = std::max(3, int(std::lround(std::sqrt(triangles / 6.0))));
        return vdb::test::makeTorusMesh(vdb::Vec3d(0.5), 0.3, 0.1, 3 * tube, tube);
    }
    if (isModel(shape)) {
        const std::string path =
            std::string(kModels) + (shape == "wuson" ? std::string("PLY/Wuson.ply") : shape);
        try {
            const vdb::meshio::Mesh read = vdb::meshio::readMesh(path);
            return {read.points, read.triangles, read.quads};
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s\n", e.what());
            std::exit(2);
        }
    }
    std::fprintf(stderr, "unknown mesh shape '%s' (sphere, torus or a model path)\n",
                 shape.c_str());
    std::exit(2);
}

/// The voxel size that gives `mesh` a bounding resolution of `res` voxels.
double voxelSizeFor(const vdb::test::TestMesh& mesh, int res) {
    vdb::Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const auto& p : mesh.points) {
        lo = vdb::Vec3d::minComponent(lo, vdb::Vec3d(p));
        hi = vdb::Vec3d::maxComponent(hi, vdb::Vec3d(p));
    }
    const vdb::Vec3d extent = hi - lo;
    return std::max({extent[0], extent[1], extent[2]}) / res;
}

uint64_t vdbMesh(const vdb::test::TestMesh& mesh, double voxelSize) {
    const auto xform = vdb::math::Transform::createLinearTransform(voxelSize);
    return vdb::tools::meshToLevelSet<vdb::FloatGrid>(*xform, mesh.points, mesh.triangles,
                                                      mesh.quads, 3.0f)
        ->activeVoxelCount();
}

/// How this library's default signs the mesh: "flood" for a closed mesh, "winding (N open
/// loops)" otherwise (MeshToVolumeReport of one conversion at a coarse voxel size).
std::string signsOf(const vdb::test::TestMesh& mesh, double voxelSize) {
    const auto xform = vdb::math::Transform::createLinearTransform(voxelSize);
    vdb::tools::MeshToVolumeReport report;
    vdb::tools::meshToVolume<vdb::FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads, {},
                                             &report);
    if (report.sign == vdb::tools::MeshSign::FloodFill)
        return "flood";
    return "winding (" + std::to_string(report.holes) +
           (report.holes == 1 ? " open loop)" : " open loops)");
}

struct OpenVdbMesh {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    explicit OpenVdbMesh(const vdb::test::TestMesh& mesh) {
        for (const auto& p : mesh.points)
            points.emplace_back(p[0], p[1], p[2]);
        for (const auto& t : mesh.triangles)
            triangles.emplace_back(t[0], t[1], t[2]);
        for (const auto& q : mesh.quads)
            quads.emplace_back(q[0], q[1], q[2], q[3]);
    }
};

uint64_t openvdbMesh(const OpenVdbMesh& mesh, double voxelSize) {
    const auto xform = openvdb::math::Transform::createLinearTransform(voxelSize);
    return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, mesh.points, mesh.triangles,
                                                              mesh.quads, 3.0f)
        ->activeVoxelCount();
}

/// The particle list interface OpenVDB's ParticlesToLevelSet reads.
struct OpenVdbParticles {
    using PosType = openvdb::Vec3R;
    std::vector<openvdb::Vec3R> positions;
    std::vector<double> radii;
    size_t size() const { return positions.size(); }
    void getPos(size_t n, openvdb::Vec3R& xyz) const { xyz = positions[n]; }
    void getPosRad(size_t n, openvdb::Vec3R& xyz, openvdb::Real& rad) const {
        xyz = positions[n];
        rad = radii[n];
    }
};

uint64_t vdbParticles(const vdb::tools::SphereList& spheres, int res) {
    auto grid = vdb::FloatGrid::create(float(3.0 / res));
    grid->setTransform(vdb::math::Transform::createLinearTransform(1.0 / res));
    grid->setGridClass(vdb::GRID_LEVEL_SET);
    vdb::tools::ParticlesToLevelSet<vdb::FloatGrid> raster(*grid);
    raster.rasterizeSpheres(spheres.positions, spheres.radii);
    raster.finalize();
    return grid->activeVoxelCount();
}

uint64_t openvdbParticles(const OpenVdbParticles& spheres, int res) {
    auto grid = openvdb::createLevelSet<openvdb::FloatGrid>(1.0 / res, 3.0);
    openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
    raster.rasterizeSpheres(spheres);
    raster.finalize(true);
    return grid->activeVoxelCount();
}

// ---- Command line ----

using vdb::bench::splitList;

void printRow(const char* what, const std::string& input, int res, int threads, double ours,
              double theirs, uint64_t activeOurs, uint64_t activeTheirs) {
    std::printf("%-9s %-24s %5d %7d %10.1f %10.1f %6.2f  %llu / %llu active\n", what, input.c_str(),
                res, threads, ours, theirs, ours / theirs, (unsigned long long)activeOurs,
                (unsigned long long)activeTheirs);
    std::fflush(stdout);
}

// ---- Markdown report ----

using vdb::bench::fmt;

/// The target of both tools: at most 0.8 times OpenVDB's time.
constexpr double kTarget = 0.8;

/// "1e5" for a count of the form d * 10^k (k >= 3), as the particle cases are named;
/// "12,345" otherwise.
std::string countText(uint64_t count) {
    int exponent = 0;
    uint64_t digit = count;
    while (digit >= 10 && digit % 10 == 0) {
        digit /= 10;
        ++exponent;
    }
    if (digit < 10 && exponent >= 3)
        return std::to_string(digit) + "e" + std::to_string(exponent);
    return fmt(double(count), 0);
}

/// The rows of one case, one per thread count: the tool, input and active voxel counts are
/// named on the first row only (later rows repeat the counts only where they differ).
class CaseRows {
public:
    CaseRows(std::string tool, std::string input, std::string signs, int res)
        : mTool(std::move(tool)), mInput(std::move(input)), mSigns(std::move(signs)), mRes(res) {}

    void add(int threads, double ours, double theirs, uint64_t activeOurs, uint64_t activeTheirs,
             std::vector<vdb::bench::MarkdownReport::Row>& rows) {
        const bool first = mFirst;
        const bool sameActive =
            !first && activeOurs == mActiveOurs && activeTheirs == mActiveTheirs;
        if (first) {
            mActiveOurs = activeOurs;
            mActiveTheirs = activeTheirs;
            mFirst = false;
        }
        rows.push_back(
            {first ? mTool : "", first ? mInput : "", first ? mSigns : "", std::to_string(mRes),
             std::to_string(threads), fmt(ours, 1), fmt(theirs, 1),
             vdb::bench::ratioCell(ours / theirs, mTool == "mesh" ? kTarget : 0.0),
             sameActive ? "" : fmt(double(activeOurs), 0) + " / " + fmt(double(activeTheirs), 0)});
    }

private:
    std::string mTool, mInput, mSigns;
    int mRes;
    bool mFirst = true;
    uint64_t mActiveOurs = 0, mActiveTheirs = 0;
};

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> cases{"sphere:256:10000",
                                   "torus:256:100000",
                                   "sphere:512:100000",
                                   "torus:512:1000000",
                                   "sphere:1024:1000000",
                                   "PLY/Wuson.ply:512",
                                   "PLY/Wuson.ply:1024",
                                   "OBJ/spider.obj:512",
                                   "OBJ/spider.obj:1024",
                                   "OBJ/regr01.obj:512",
                                   "OBJ/regr01.obj:1024",
                                   "STL/sphereWithHole.stl:512",
                                   "STL/sphereWithHole.stl:1024",
                                   "STL/Spider_binary.stl:512"};
    std::vector<std::string> particles{"1024:100000", "1024:1000000"};
    int reps = 3;
    std::vector<std::string> threads{"1", "all"};
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_mesh [--cases shape:res:triangles,wuson:res,...] "
        "[--particles res:count,...] [--reps 3] [--threads 1,all] "
        "[--markdown FILE]");
    options.list("--cases", cases)
        .list("--particles", particles)
        .number("--reps", reps)
        .list("--threads", threads)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    constexpr long MANY = std::numeric_limits<int>::max();
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    openvdb::initialize();
    std::printf("# vdb_bench_mesh: medians of %d runs, milliseconds; ratio = vdb / openvdb\n",
                reps);
    std::printf("%-9s %-24s %5s %7s %10s %10s %6s  %s\n", "tool", "input", "res", "threads", "vdb",
                "openvdb", "ratio", "active voxels vdb / openvdb");
    std::vector<vdb::bench::MarkdownReport::Row> rows;
    vdb::bench::RatioRange meshRatios, particleRatios;
    for (const std::string& c : cases) {
        const auto parts = splitList(c, ':');
        if (parts.size() != (parts.empty() || !isModel(parts[0]) ? 3u : 2u))
            options.fail("bad case " + c);
        const int res = int(options.toNumber(parts[1], "resolution"));
        const auto mesh = makeMesh(
            parts[0], parts.size() > 2 ? int(options.toNumber(parts[2], "triangles", 1, MANY)) : 0);
        const double voxelSize = voxelSizeFor(mesh, res);
        const OpenVdbMesh theirMesh(mesh);
        const size_t triangles = mesh.triangles.size() + 2 * mesh.quads.size();
        const std::string name = parts[0] == "wuson"
                                     ? std::string("Wuson.ply")
                                     : parts[0].substr(parts[0].find_last_of('/') + 1);
        const std::string input = name + " " + std::to_string(triangles);
        CaseRows caseRows("mesh", name + ", " + fmt(double(triangles), 0) + " triangles",
                          signsOf(mesh, voxelSizeFor(mesh, 64)), res);
        for (const std::string& t : threads) {
            const int n = options.threadCount(t);
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
            uint64_t a = 0, b = 0;
            const double ours = timeMs(
                reps, [&] { return vdbMesh(mesh, voxelSize); }, a);
            const double theirs = timeMs(
                reps, [&] { return openvdbMesh(theirMesh, voxelSize); }, b);
            printRow("mesh", input, res, n, ours, theirs, a, b);
            caseRows.add(n, ours, theirs, a, b, rows);
            meshRatios.add(ours / theirs);
        }
    }
    for (const std::string& c : particles) {
        const auto parts = splitList(c, ':');
        if (parts.size() != 2)
            options.fail("bad particle case " + c);
        const int res = int(options.toNumber(parts[0], "resolution"));
        const size_t count = size_t(options.toNumber(parts[1], "particle count", 1, MANY));
        const auto spheres = vdb::tools::torusKnotHelixSpheres(count);
        OpenVdbParticles theirs;
        for (size_t n = 0; n < count; ++n) {
            const auto& p = spheres.positions[n];
            theirs.positions.emplace_back(p[0], p[1], p[2]);
            theirs.radii.push_back(spheres.radii[n]);
        }
        CaseRows caseRows("particles", "torus-knot-helix, " + countText(count) + " spheres", "",
                          res);
        for (const std::string& t : threads) {
            const int n = options.threadCount(t);
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
            uint64_t a = 0, b = 0;
            const double ours = timeMs(
                reps, [&] { return vdbParticles(spheres, res); }, a);
            const double other = timeMs(
                reps, [&] { return openvdbParticles(theirs, res); }, b);
            printRow("particles", "tkh " + std::to_string(count), res, n, ours, other, a, b);
            caseRows.add(n, ours, other, a, b, rows);
            particleRatios.add(ours / other);
        }
    }
    std::printf("# machine: %u hardware threads\n", std::thread::hardware_concurrency());
    if (markdownPath.empty())
        return 0;

    vdb::bench::MarkdownReport md;
    char line[256];
    std::snprintf(line, sizeof line,
                  "Medians of %d runs in milliseconds; ratio = vdb / OpenVDB, in bold where a "
                  "mesh conversion meets its target (at most %.2f; particles have none). The "
                  "machine has %d hardware threads.",
                  reps, kTarget, cores);
    md.paragraph(line);
    md.table({"tool", "input", "signs", "res", "threads", "vdb ms", "OpenVDB ms", "ratio",
              "active voxels vdb / OpenVDB"},
             rows);
    md.status(meshRatios.status("mesh", kTarget));
    md.status(particleRatios.status("particles (no target)"));
    return md.write(markdownPath) ? 0 : 1;
}
