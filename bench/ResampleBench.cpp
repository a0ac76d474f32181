// SPDX-License-Identifier: Apache-2.0
// Resampling and dense copy benchmark: tools::resampleToMatch, copyToDense and copyFromDense of
// this library against OpenVDB 10's, on the same grids in one process.
//
//   resample   the Enright sphere (radius 0.15 at (0.35, 0.35, 0.35) in the unit box) at voxel
//              size 1/RES, the band voxels of BenchCommon.h (half width 5) inserted into both
//              libraries' trees, resampled with the box sampler to half the resolution, to
//              double the resolution, and to a rotated transform (30 degrees about z, then 20
//              about x, same voxel size): once as a level set (both libraries rebuild the band
//              through a mesh) and once as a fog volume with the same values (both sample
//              every output voxel; GridTransformer's path)
//   dense      copyToDense of the Enright grid at resolution DENSE into a DENSE^3 array of
//              floats (LayoutZYX), and copyFromDense of that array into an empty grid
//              (tolerance 0)
//
// Every operation runs at each thread count (--threads 1,2; tbb::global_control limits both
// libraries alike), `reps` times; the median time is reported with the ratio ours / OpenVDB.
//
// With --markdown FILE the program also writes its results as a Markdown table to FILE and
// one overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_resample [--res 1024] [--dense 512] [--reps 3] [--threads 1,2]
//                           [--markdown FILE]

// OpenVDB 10's GridResampler hands tbb::parallel_reduce an iterator range that does not model
// oneTBB's C++20 range concept; with the constraints on, its tile pass does not compile.
#define __TBB_USE_CONSTRAINTS 0

#include <vdb/tools/Dense.h>
#include <vdb/tools/GridTransformer.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/GridTransformer.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using vdb::bench::splitList;

/// The target of the issue: at most 0.8 times OpenVDB's time.
constexpr double kTarget = 0.8;

/// The Enright sphere's band in both libraries (values in world units), as a level set signed
/// by each library's flood fill, or as a fog volume of the same values.
std::pair<vdb::FloatGrid::Ptr, openvdb::FloatGrid::Ptr> enright(int res, bool levelSet) {
    const auto band = vdb::bench::makeEnrightBand(res);
    const float dx = 1.0f / float(res);
    const float background = float(vdb::bench::EnrightSphere::kHalfWidth) * dx;
    auto ours = vdb::FloatGrid::create(background);
    auto theirs = openvdb::FloatGrid::create(background);
    ours->setTransform(vdb::math::Transform::createLinearTransform(dx));
    theirs->setTransform(openvdb::math::Transform::createLinearTransform(dx));
    ours->setGridClass(levelSet ? vdb::GRID_LEVEL_SET : vdb::GRID_FOG_VOLUME);
    theirs->setGridClass(levelSet ? openvdb::GRID_LEVEL_SET : openvdb::GRID_FOG_VOLUME);
    auto acc = ours->getAccessor();
    auto theirAcc = theirs->getAccessor();
    for (const auto& v : band) {
        acc.setValue(vdb::Coord(v.x, v.y, v.z), v.value * dx);
        theirAcc.setValue(openvdb::Coord(v.x, v.y, v.z), v.value * dx);
    }
    if (levelSet) {
        vdb::tools::signedFloodFill(ours->tree());
        openvdb::tools::signedFloodFill(theirs->tree());
    }
    return {ours, theirs};
}

/// The target transforms, as matrices of world from index: half and double resolution, and
/// rotated at the same voxel size.
vdb::Mat4R target(const std::string& name, double dx) {
    if (name == "half")
        return vdb::Mat4R::scale(vdb::Vec3R(2.0 * dx));
    if (name == "double")
        return vdb::Mat4R::scale(vdb::Vec3R(0.5 * dx));
    vdb::Mat4R m = vdb::Mat4R::scale(vdb::Vec3R(dx));
    m.postRotate(vdb::math::Axis::Z, 30.0 * M_PI / 180.0);
    m.postRotate(vdb::math::Axis::X, 20.0 * M_PI / 180.0);
    return m;
}

openvdb::Mat4R toOvdb(const vdb::Mat4R& m) {
    openvdb::Mat4R r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            r(i, j) = m(i, j);
    return r;
}

/// The median of `reps` runs of `op` in milliseconds; `op` returns a count to report.
double medianMs(int reps, const std::function<uint64_t()>& op, uint64_t& count) {
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) {
        const auto start = Clock::now();
        count = op();
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
    return vdb::bench::median(ms);
}

/// One row of the report table (numbers formatted with snprintf: GCC 12, inlining
/// bench::fmt() here, warns of an impossible overlap in its string copies, -Wrestrict).
[[gnu::noinline]] vdb::bench::MarkdownReport::Row tableRow(const std::string& op,
                                                           const std::string& input, int threads,
                                                           double msOurs, double msTheirs,
                                                           uint64_t countOurs,
                                                           uint64_t countTheirs) {
    char ours[32], theirs[32], counts[64];
    std::snprintf(ours, sizeof ours, "%.1f", msOurs);
    std::snprintf(theirs, sizeof theirs, "%.1f", msTheirs);
    std::snprintf(counts, sizeof counts, "%llu / %llu", static_cast<unsigned long long>(countOurs),
                  static_cast<unsigned long long>(countTheirs));
    return {op,    input,  std::to_string(threads),
            ours,  theirs, vdb::bench::ratioCell(msOurs / msTheirs, kTarget),
            counts};
}

}  // namespace

int main(int argc, char** argv) {
    int res = 1024, dense = 512, reps = 3;
    std::vector<std::string> threads{"1", "2"};
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_resample [--res 1024] [--dense 512] [--reps 3] "
        "[--threads 1,2] [--markdown FILE]");
    options.number("--res", res)
        .number("--dense", dense)
        .list("--threads", threads)
        .number("--reps", reps)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    openvdb::initialize();
    vdb::bench::keepHeapOnFree();
    std::printf("# vdb_bench_resample: medians of %d runs, milliseconds; ratio = vdb / openvdb\n",
                reps);
    std::printf("%-22s %-28s %7s %10s %10s %6s %24s\n", "operation", "input", "threads", "vdb",
                "openvdb", "ratio", "active voxels vdb/ovdb");
    std::vector<vdb::bench::MarkdownReport::Row> rows;
    vdb::bench::RatioRange resampleLs, resampleFog, copies;
    const auto run = [&](const std::string& op, const std::string& input,
                         const std::function<uint64_t()>& ours,
                         const std::function<uint64_t()>& theirs, vdb::bench::RatioRange& range) {
        bool first = true;
        for (const std::string& t : threads) {
            const int n = options.threadCount(t);
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
            uint64_t countOurs = 0, countTheirs = 0;
            const double msOurs = medianMs(reps, ours, countOurs);
            const double msTheirs = medianMs(reps, theirs, countTheirs);
            range.add(msOurs / msTheirs);
            std::printf("%-22s %-28s %7d %10.1f %10.1f %6.2f %11llu/%-12llu\n", op.c_str(),
                        input.c_str(), n, msOurs, msTheirs, msOurs / msTheirs,
                        static_cast<unsigned long long>(countOurs),
                        static_cast<unsigned long long>(countTheirs));
            std::fflush(stdout);
            rows.push_back(tableRow(first ? op : "", first ? input : "", n, msOurs, msTheirs,
                                    countOurs, countTheirs));
            first = false;
        }
    };

    // ---- resampleToMatch
    for (const bool levelSet : {true, false}) {
        const auto [ours, theirs] = enright(res, levelSet);
        const double dx = 1.0 / res;
        for (const std::string name : {"half", "double", "rotated"}) {
            const vdb::Mat4R m = target(name, dx);
            char input[96];
            std::snprintf(input, sizeof input, "Enright %d^3 %s, %s", res,
                          levelSet ? "level set" : "fog", name.c_str());
            run(
                "resampleToMatch", input,
                [&, m] {
                    auto out = vdb::FloatGrid::create();
                    out->setTransform(vdb::math::Transform::createLinearTransform(m));
                    vdb::tools::resampleToMatch<vdb::tools::BoxSampler>(*ours, *out);
                    return uint64_t(out->activeVoxelCount());
                },
                [&, m] {
                    auto out = openvdb::FloatGrid::create();
                    out->setTransform(openvdb::math::Transform::createLinearTransform(toOvdb(m)));
                    openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*theirs, *out);
                    return uint64_t(out->activeVoxelCount());
                },
                levelSet ? resampleLs : resampleFog);
        }
    }

    // ---- Dense copies
    {
        const auto [ours, theirs] = enright(dense, false);
        const vdb::CoordBBox box(vdb::Coord(0), vdb::Coord(dense - 1));
        const openvdb::CoordBBox theirBox(openvdb::Coord(0), openvdb::Coord(dense - 1));
        vdb::tools::Dense<float, vdb::tools::LayoutZYX> ourDense(box);
        openvdb::tools::Dense<float, openvdb::tools::LayoutZYX> theirDense(theirBox);
        char input[64];
        std::snprintf(input, sizeof input, "Enright %d^3 into %d^3", dense, dense);
        run(
            "copyToDense", input,
            [&] {
                vdb::tools::copyToDense(*ours, ourDense);
                return uint64_t(ours->activeVoxelCount());
            },
            [&] {
                openvdb::tools::copyToDense(*theirs, theirDense);
                return uint64_t(theirs->activeVoxelCount());
            },
            copies);
        vdb::tools::copyToDense(*ours, ourDense);
        openvdb::tools::copyToDense(*theirs, theirDense);
        std::snprintf(input, sizeof input, "%d^3 array", dense);
        run(
            "copyFromDense", input,
            [&] {
                auto grid = vdb::FloatGrid::create(ours->background());
                vdb::tools::copyFromDense(ourDense, *grid, 0.0f);
                return uint64_t(grid->activeVoxelCount());
            },
            [&] {
                auto grid = openvdb::FloatGrid::create(theirs->background());
                openvdb::tools::copyFromDense(theirDense, *grid, 0.0f);
                return uint64_t(grid->activeVoxelCount());
            },
            copies);
    }
    std::printf("# machine: %d hardware threads\n", cores);
    if (markdownPath.empty())
        return 0;
    vdb::bench::MarkdownReport md;
    md.paragraph(vdb::bench::mediansNote(reps, kTarget, cores));
    md.table({"operation", "input", "threads", "vdb ms", "OpenVDB ms", "ratio",
              "active voxels vdb / OpenVDB"},
             rows);
    md.status(resampleLs.status("level sets", kTarget));
    md.status(resampleFog.status("fog", kTarget));
    md.status(copies.status("dense copies", kTarget));
    return md.write(markdownPath) ? 0 : 1;
}
