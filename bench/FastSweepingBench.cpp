// SPDX-License-Identifier: Apache-2.0
// Fast sweeping benchmark: tools::fogToSdf and tools::dilateSdf of this library against
// OpenVDB 10's tools/FastSweeping.h on the same grids, in one process.
//
//   input at RES   the Enright sphere (radius 0.15 at (0.35, 0.35, 0.35) in the unit box) at
//                  voxel size 1/RES, made by each library's createLevelSetSphere (half width
//                  3); the fog volume is each library's sdfToFogVolume of it (interior tiles
//                  of density 1, a ramp over the inner band)
//   fogToSdf       fogToSdf(fog, 0.5): every interior voxel gets its distance
//   dilateSdf:N    dilateSdf(levelSet, N): the band widened by N voxels (NN_FACE)
//
// Every operation runs at every thread count (--threads 1,2; tbb::global_control limits both
// libraries alike), `reps` times each; the median time is reported with the ratio
// ours / OpenVDB and both libraries' active voxel counts of the result.
//
// With --markdown FILE the program also writes its results as a Markdown table to FILE and
// one overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_fastsweep [--res 256,512] [--dilation 10] [--reps 5] [--threads 1,2]
//                            [--markdown FILE]

#include <vdb/tools/FastSweeping.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/LevelSetUtil.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace {

using vdb::bench::fmt;

/// The target: at most 0.8 times OpenVDB's time.
constexpr double kTarget = 0.8;

/// One row of the report table. Not inlined: GCC 12, inlining fmt() into main, warns of an
/// impossible overlap in its string copies (-Wrestrict).
[[gnu::noinline]] vdb::bench::MarkdownReport::Row tableRow(const std::string& input,
                                                           const std::string& op, int threads,
                                                           double msOurs, double msTheirs,
                                                           uint64_t voxelsOurs,
                                                           uint64_t voxelsTheirs) {
    return {input,
            op,
            std::to_string(threads),
            fmt(msOurs, 1),
            fmt(msTheirs, 1),
            vdb::bench::ratioCell(msOurs / msTheirs, kTarget),
            fmt(double(voxelsOurs), 0) + " / " + fmt(double(voxelsTheirs), 0)};
}

/// Timings of one operation: every run in milliseconds, and the result's active voxel count.
struct Runs {
    std::vector<double> ms;
    uint64_t voxels = 0;

    /// The median (the mean of the two middle runs for an even count).
    double median() const {
        std::vector<double> sorted = ms;
        std::sort(sorted.begin(), sorted.end());
        const size_t n = sorted.size();
        return n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    }
};

/// Runs `op` (which returns the result's active voxel count) `reps` times.
Runs timeRuns(int reps, const std::function<uint64_t()>& op) {
    Runs runs;
    for (int r = 0; r < reps; ++r) {
        const auto start = std::chrono::steady_clock::now();
        runs.voxels = op();
        runs.ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count());
    }
    return runs;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> resolutions{256, 512};
    std::vector<std::string> threads{"1", "2"};
    int dilation = 10;
    int reps = 5;
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_fastsweep [--res 256,512] [--dilation 10] [--reps 5] "
        "[--threads 1,2] [--markdown FILE]");
    options.numbers("--res", resolutions)
        .list("--threads", threads)
        .number("--dilation", dilation)
        .number("--reps", reps)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    openvdb::initialize();
    vdb::bench::keepHeapOnFree();
    std::printf("# vdb_bench_fastsweep: medians of %d runs, milliseconds; ratio = vdb / openvdb\n",
                reps);
    std::printf("%-10s %-14s %7s %10s %10s %6s %24s\n", "input", "operation", "threads", "vdb",
                "openvdb", "ratio", "active voxels vdb/ovdb");
    std::vector<vdb::bench::MarkdownReport::Row> rows;
    vdb::bench::RatioRange fogRatios, dilateRatios;
    const std::string dilateName = "dilateSdf(" + std::to_string(dilation) + ")";
    for (const int res : resolutions) {
        const double dx = 1.0 / res;
        const auto ours =
            vdb::tools::createLevelSetSphere<vdb::FloatGrid>(0.15, vdb::Vec3d(0.35), dx, 3.0);
        const auto theirs = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
            0.15f, openvdb::Vec3f(0.35f), float(dx), 3.0f);
        auto ourFog = ours->deepCopy();
        vdb::tools::sdfToFogVolume(*ourFog);
        auto theirFog = theirs->deepCopy();
        openvdb::tools::sdfToFogVolume(*theirFog);
        const std::string input = "Enright " + std::to_string(res) + "^3";
        struct Op {
            std::string name;
            std::function<uint64_t()> ours, theirs;
            vdb::bench::RatioRange* ratios;
        };
        const Op ops[] = {
            {"fogToSdf",
             [&] { return uint64_t(vdb::tools::fogToSdf(*ourFog, 0.5f)->activeVoxelCount()); },
             [&] {
                 return uint64_t(openvdb::tools::fogToSdf(*theirFog, 0.5f)->activeVoxelCount());
             },
             &fogRatios},
            {dilateName,
             [&] { return uint64_t(vdb::tools::dilateSdf(*ours, dilation)->activeVoxelCount()); },
             [&] {
                 return uint64_t(openvdb::tools::dilateSdf(*theirs, dilation)->activeVoxelCount());
             },
             &dilateRatios}};
        bool firstOfInput = true;
        for (const Op& op : ops) {
            for (const std::string& t : threads) {
                const int n = options.threadCount(t);
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
                const Runs a = timeRuns(reps, op.ours);
                const Runs b = timeRuns(reps, op.theirs);
                const double ratio = a.median() / b.median();
                op.ratios->add(ratio);
                std::printf("%-10s %-14s %7d %10.1f %10.1f %6.2f %11llu/%-12llu\n", input.c_str(),
                            op.name.c_str(), n, a.median(), b.median(), ratio,
                            static_cast<unsigned long long>(a.voxels),
                            static_cast<unsigned long long>(b.voxels));
                std::fflush(stdout);
                rows.push_back(tableRow(firstOfInput ? input : "", op.name, n, a.median(),
                                        b.median(), a.voxels, b.voxels));
                firstOfInput = false;
            }
        }
    }
    std::printf("# machine: %d hardware threads\n", cores);
    if (markdownPath.empty())
        return 0;
    vdb::bench::MarkdownReport md;
    md.paragraph("Medians of " + std::to_string(reps) +
                 " runs in milliseconds; ratio = vdb / OpenVDB, in bold at or below the target " +
                 std::to_string(kTarget).substr(0, 4) + ". The machine has " +
                 std::to_string(cores) + " hardware threads.");
    md.table({"input", "operation", "threads", "vdb ms", "OpenVDB ms", "ratio",
              "active voxels vdb / OpenVDB"},
             rows);
    md.status(fogRatios.status("fogToSdf", kTarget));
    md.status(dilateRatios.status(dilateName, kTarget));
    return md.write(markdownPath) ? 0 : 1;
}
