// SPDX-License-Identifier: Apache-2.0
// Isosurface meshing benchmark: tools::volumeToMesh of this library against OpenVDB 10's
// volumeToMesh on the same grids, in one process.
//
//   enright:RES   the Enright sphere (radius 0.15 at (0.35, 0.35, 0.35) in the unit box) at
//                 voxel size 1/RES: the band voxels of BenchCommon.h (half width 5), inserted
//                 into both libraries' trees and signed by each library's flood fill
//   wuson:RES     Wuson.ply of the Debian package assimp-testmodels, scan-converted by this
//                 library at a bounding resolution of RES (voxel size = longest side / RES,
//                 half width 3, signs by winding numbers: the mesh is open), then copied voxel
//                 for voxel and tile for tile into an OpenVDB grid
//
// Each grid is meshed at every adaptivity (--adaptivity 0,0.5) and thread count (--threads
// 1,all; tbb::global_control limits both libraries alike), `reps` times each; the median time
// is reported with the ratio ours / OpenVDB, the polygon counts of both (quads + triangles) and
// the polygons per second.
//
// With --markdown FILE the program also writes its results as a Markdown table to FILE and
// one overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_volumetomesh [--cases enright:512,wuson:512,...] [--adaptivity 0,0.5]
//                               [--reps 5] [--threads 1,all] [--markdown FILE]

#include <vdb/meshio/MeshReader.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/VolumeToMesh.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using vdb::bench::fmt;
using vdb::bench::splitList;

constexpr const char* kWuson = "/usr/share/assimp/models/PLY/Wuson.ply";
/// The target of the issue: at most 0.7 times OpenVDB's time.
constexpr double kTarget = 0.7;

// ---- Inputs ----

/// The Enright sphere's band in both libraries, each signed by its own flood fill.
std::pair<vdb::FloatGrid::Ptr, openvdb::FloatGrid::Ptr> enright(int res) {
    const auto band = vdb::bench::makeEnrightBand(res);
    const float background = float(vdb::bench::EnrightSphere::kHalfWidth);
    auto ours = vdb::FloatGrid::create(background);
    auto theirs = openvdb::FloatGrid::create(background);
    ours->setGridClass(vdb::GRID_LEVEL_SET);
    theirs->setGridClass(openvdb::GRID_LEVEL_SET);
    auto acc = ours->getAccessor();
    auto theirAcc = theirs->getAccessor();
    for (const auto& v : band) {
        acc.setValue(vdb::Coord(v.x, v.y, v.z), v.value);
        theirAcc.setValue(openvdb::Coord(v.x, v.y, v.z), v.value);
    }
    vdb::tools::signedFloodFill(ours->tree());
    openvdb::tools::signedFloodFill(theirs->tree());
    return {ours, theirs};
}

/// The same grid in OpenVDB: every leaf's values and active states, and every tile.
openvdb::FloatGrid::Ptr copyToOpenVdb(const vdb::FloatGrid& grid) {
    auto out = openvdb::FloatGrid::create(grid.background());
    out->setGridClass(openvdb::GRID_LEVEL_SET);
    auto& tree = out->tree();
    for (const auto& leaf : grid.tree().leaves()) {
        const vdb::Coord& o = leaf.origin();
        auto* copy = tree.touchLeaf(openvdb::Coord(o[0], o[1], o[2]));
        std::memcpy(copy->buffer().data(), &leaf.getValue(vdb::Index(0)),
                    sizeof(float) * leaf.NUM_VALUES);
        for (vdb::Index n = 0; n < leaf.NUM_VALUES; ++n)
            copy->setActiveState(n, leaf.isValueOn(n));
    }
    for (auto it = grid.cbeginValueAll(); it; ++it) {
        if (!it.isTileValue())
            continue;
        vdb::CoordBBox box;
        it.getBoundingBox(box);
        tree.fill(openvdb::CoordBBox(openvdb::Coord(box.min()[0], box.min()[1], box.min()[2]),
                                     openvdb::Coord(box.max()[0], box.max()[1], box.max()[2])),
                  *it, it.isValueOn());
    }
    return out;
}

/// Wuson.ply as a level set of ours (winding-number signs) and its copy in OpenVDB.
std::pair<vdb::FloatGrid::Ptr, openvdb::FloatGrid::Ptr> wuson(int res) {
    const vdb::meshio::Mesh mesh = vdb::meshio::readMesh(kWuson);
    vdb::Vec3d lo(std::numeric_limits<double>::max()), hi(-lo[0]);
    for (const auto& p : mesh.points) {
        lo = vdb::Vec3d::minComponent(lo, vdb::Vec3d(p));
        hi = vdb::Vec3d::maxComponent(hi, vdb::Vec3d(p));
    }
    const auto xform = vdb::math::Transform::createLinearTransform((hi - lo).maxComponent() / res);
    vdb::tools::MeshToVolumeOptions options;
    options.sign = vdb::tools::MeshSign::WindingNumber;
    auto ours = vdb::tools::meshToVolume<vdb::FloatGrid>(*xform, mesh.points, mesh.triangles,
                                                         mesh.quads, options);
    auto theirs = copyToOpenVdb(*ours);
    theirs->setTransform(openvdb::math::Transform::createLinearTransform(xform->voxelSize()[0]));
    return {ours, theirs};
}

// ---- Timing ----

/// The median of `reps` runs of `op` in milliseconds; `op` returns its polygon count.
double medianMs(int reps, const std::function<size_t()>& op, size_t& polygons) {
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) {
        const auto start = Clock::now();
        polygons = op();
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
    std::nth_element(ms.begin(), ms.begin() + ptrdiff_t(ms.size() / 2), ms.end());
    const double upper = ms[ms.size() / 2];
    if (ms.size() % 2)
        return upper;
    return 0.5 * (upper + *std::max_element(ms.begin(), ms.begin() + ptrdiff_t(ms.size() / 2)));
}

/// One row of the report table. Not inlined: GCC 12, inlining fmt() into main, warns of an
/// impossible overlap in its string copies (-Wrestrict).
[[gnu::noinline]] vdb::bench::MarkdownReport::Row tableRow(const std::string& input,
                                                           const std::string& adaptivity,
                                                           int threads, double msOurs,
                                                           double msTheirs, size_t polysOurs,
                                                           size_t polysTheirs) {
    const auto both = [](const std::string& ours, const std::string& theirs) {
        std::string cell = ours;
        cell += " / ";
        cell += theirs;
        return cell;
    };
    return {input,
            adaptivity,
            std::to_string(threads),
            fmt(msOurs, 1),
            fmt(msTheirs, 1),
            vdb::bench::ratioCell(msOurs / msTheirs, kTarget),
            both(fmt(double(polysOurs), 0), fmt(double(polysTheirs), 0)),
            both(fmt(double(polysOurs) / msOurs / 1e3, 2),
                 fmt(double(polysTheirs) / msTheirs / 1e3, 2))};
}

size_t ourMesh(const vdb::FloatGrid& grid, double adaptivity) {
    std::vector<vdb::Vec3s> points;
    std::vector<vdb::Vec3I> triangles;
    std::vector<vdb::Vec4I> quads;
    vdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, adaptivity);
    return triangles.size() + quads.size();
}

size_t theirMesh(const openvdb::FloatGrid& grid, double adaptivity) {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, adaptivity);
    return triangles.size() + quads.size();
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> cases{"enright:512", "enright:1024", "wuson:512", "wuson:1024"};
    std::vector<std::string> adaptivities{"0", "0.5"};
    std::vector<std::string> threads{"1", "all"};
    int reps = 5;
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_volumetomesh [--cases enright:RES,wuson:RES,...] "
        "[--adaptivity 0,0.5] [--reps 5] [--threads 1,all] "
        "[--markdown FILE]");
    options.list("--cases", cases)
        .list("--adaptivity", adaptivities)
        .list("--threads", threads)
        .number("--reps", reps)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    openvdb::initialize();
    vdb::bench::keepHeapOnFree();
    std::printf(
        "# vdb_bench_volumetomesh: medians of %d runs, milliseconds; ratio = vdb / "
        "openvdb\n",
        reps);
    std::printf("%-14s %10s %7s %10s %10s %6s %20s %16s\n", "input", "adaptivity", "threads", "vdb",
                "openvdb", "ratio", "polygons vdb/ovdb", "Mpolygons/s");
    std::vector<vdb::bench::MarkdownReport::Row> rows;
    vdb::bench::RatioRange uniform, adaptive;
    for (const std::string& c : cases) {
        const auto parts = splitList(c, ':');
        if (parts.size() != 2 || (parts[0] != "enright" && parts[0] != "wuson"))
            options.fail("bad case " + c);
        const int res = int(options.toNumber(parts[1], "resolution"));
        const auto [ours, theirs] = parts[0] == "enright" ? enright(res) : wuson(res);
        char inputText[64];
        std::snprintf(inputText, sizeof inputText, "%s %d^3",
                      parts[0] == "enright" ? "Enright sphere" : "Wuson.ply", res);
        const std::string input = inputText;
        bool firstOfCase = true;
        for (const std::string& a : adaptivities) {
            const double adaptivity = std::strtod(a.c_str(), nullptr);
            for (const std::string& t : threads) {
                const int n = options.threadCount(t);
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
                size_t polysOurs = 0, polysTheirs = 0;
                const double msOurs = medianMs(
                    reps, [&] { return ourMesh(*ours, adaptivity); }, polysOurs);
                const double msTheirs = medianMs(
                    reps, [&] { return theirMesh(*theirs, adaptivity); }, polysTheirs);
                const double ratio = msOurs / msTheirs;
                (adaptivity > 0 ? adaptive : uniform).add(ratio);
                const double rateOurs = double(polysOurs) / msOurs / 1e3;
                const double rateTheirs = double(polysTheirs) / msTheirs / 1e3;
                std::printf("%-14s %10s %7d %10.1f %10.1f %6.2f %9zu/%-10zu %7.2f/%-7.2f\n",
                            input.c_str(), a.c_str(), n, msOurs, msTheirs, ratio, polysOurs,
                            polysTheirs, rateOurs, rateTheirs);
                std::fflush(stdout);
                rows.push_back(tableRow(firstOfCase ? input : "", a, n, msOurs, msTheirs, polysOurs,
                                        polysTheirs));
                firstOfCase = false;
            }
        }
    }
    std::printf("# machine: %d hardware threads\n", cores);
    if (markdownPath.empty())
        return 0;
    vdb::bench::MarkdownReport md;
    char line[256];
    std::snprintf(line, sizeof line,
                  "Medians of %d runs in milliseconds; ratio = vdb / OpenVDB, in bold where it "
                  "meets the target (at most %.2f). The machine has %d hardware threads.",
                  reps, kTarget, cores);
    md.paragraph(line);
    md.table({"input", "adaptivity", "threads", "vdb ms", "OpenVDB ms", "ratio",
              "polygons vdb / OpenVDB", "Mpolygons/s vdb / OpenVDB"},
             rows);
    md.status(uniform.status("adaptivity 0", kTarget));
    md.status(adaptive.status("adaptive", kTarget));
    return md.write(markdownPath) ? 0 : 1;
}
