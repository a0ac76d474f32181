// SPDX-License-Identifier: Apache-2.0
// The level set simulation benchmark of the paper's Table III (Museth 2013, section 5.2): this
// library against OpenVDB 10 on the same Enright sphere, in one process.
//
// One step, as in Table III: one advection step in the Enright field at t = 0 with TVD-RK3 and
// HJ-WENO5, then the rebuild of the narrow band (dilation by one, three renormalisation steps
// with HJ-WENO5 and TVD-RK1 at CFL 0.3, trimming, pruning). Both libraries advect from t = 0 to
// t = 1e-4, shorter than one CFL-limited step at every resolution used here, so each takes
// exactly one step of the same dt. Both use OpenVDB's CFL number for TVD-RK3, 1/sqrt(3) (it
// does not limit that step, but sets the step count of the full period). This library samples
// the Enright field three times per step (start and end speeds, velocities at the middle of
// the step), OpenVDB once (velocities at the start): that cost is part of the timed step.
//
// Inputs: the Enright sphere (radius 0.15 at (0.35, 0.35, 0.35), voxel size 1/resolution,
// narrow band of half width 5 voxels, values in world units), inserted voxel by voxel from the
// same list into both libraries and flood-filled by each library's signedFloodFill.
//
// Each measurement copies the input grid (not timed), times the construction of the advection
// object and the step, and compares the results (active voxel counts and the largest value
// difference); the median of the repetitions is reported. "1 thread" runs under
// tbb::global_control with one thread for both libraries; "all" uses every core.
//
// --enright RES also runs the whole Enright test (one full period, t = 0 to 3) at RES^3 in both
// libraries with the same schemes and reports the volume loss, each library's final grid
// measured by the same smeared-Heaviside volume (vdb::tools::smearedHeavisideVolume). With
// --enright-frames N it runs the test a second time in N equal intervals (one advect call per
// interval, as a caller writing N frames would): OpenVDB sizes each step by the speed at its
// start and keeps that velocity for the whole step, so where Enright's field vanishes
// (t = 1.5) it takes a few long steps; intervals bound every step of both libraries alike.
//
// The floor of a step: the same arithmetic in a plain loop, with no tree and no band to keep.
// A dense block with as many voxels as the band (plus a halo of 3) goes through the step's six
// stages (three of TVD-RK3 advection with a constant velocity, three of renormalisation), each
// stage the HJ-WENO5 differences of every voxel along its three axes (math::weno5, six per
// voxel) and its update (upwind advection, or Godunov's norm and the sign-weighted step), in
// loops along z that the compiler vectorizes, threaded over x like the step.
//
// With --markdown FILE the program also writes its results as Markdown tables to FILE and one
// overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_levelset [--res 256,512,1024] [--reps 3] [--threads 1,all] [--enright 0]
//                           [--enright-frames 0] [--markdown FILE]

#include <vdb/math/FiniteDifference.h>
#include <vdb/tools/EnrightTest.h>
#include <vdb/tools/LevelSetAdvect.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/VelocityFields.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetAdvect.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace {

using vdb::bench::BandVoxel;
using Clock = std::chrono::steady_clock;

constexpr double kStepEnd = 1e-4;  // one step at t = 0 (below the CFL step up to 2048^3)

// ---- Library tags ----

struct Vdb {
    using GridType = vdb::FloatGrid;
    using Field = vdb::tools::EnrightField<float>;

    static GridType::Ptr build(const std::vector<BandVoxel>& band, int res) {
        const float dx = 1.0f / float(res);
        auto grid = GridType::create(float(vdb::bench::EnrightSphere::kHalfWidth) * dx);
        grid->setTransform(vdb::math::Transform::createLinearTransform(dx));
        grid->setGridClass(vdb::GRID_LEVEL_SET);
        auto acc = grid->getAccessor();
        for (const BandVoxel& v : band)
            acc.setValue(vdb::Coord(v.x, v.y, v.z), v.value * dx);
        vdb::tools::signedFloodFill(grid->tree());
        return grid;
    }
    static GridType::Ptr copy(const GridType& g) { return g.deepCopy(); }
    static size_t advect(GridType& grid, double t0, double t1) {
        const Field field;
        vdb::tools::LevelSetAdvection<GridType, Field> advection(grid, field);
        advection.setSpatialScheme(vdb::math::HJWENO5_BIAS);
        advection.setTemporalScheme(vdb::math::TVD_RK3);
        advection.setTrackerSpatialScheme(vdb::math::HJWENO5_BIAS);
        advection.setTrackerTemporalScheme(vdb::math::TVD_RK1);
        advection.setNormCount(3);
        advection.setCFL(float(1.0 / std::sqrt(3.0)));  // OpenVDB's fixed CFL for TVD-RK3
        return advection.advect(t0, t1);
    }
    static uint64_t activeVoxels(const GridType& g) { return g.activeVoxelCount(); }
};

struct OpenVdb {
    using GridType = openvdb::FloatGrid;
    using Field = openvdb::tools::EnrightField<float>;

    static GridType::Ptr build(const std::vector<BandVoxel>& band, int res) {
        const float dx = 1.0f / float(res);
        auto grid = GridType::create(float(vdb::bench::EnrightSphere::kHalfWidth) * dx);
        grid->setTransform(openvdb::math::Transform::createLinearTransform(dx));
        grid->setGridClass(openvdb::GRID_LEVEL_SET);
        auto acc = grid->getAccessor();
        for (const BandVoxel& v : band)
            acc.setValue(openvdb::Coord(v.x, v.y, v.z), v.value * dx);
        openvdb::tools::signedFloodFill(grid->tree());
        return grid;
    }
    static GridType::Ptr copy(const GridType& g) { return g.deepCopy(); }
    static size_t advect(GridType& grid, double t0, double t1) {
        const Field field;
        openvdb::tools::LevelSetAdvection<GridType, Field> advection(grid, field);
        advection.setSpatialScheme(openvdb::math::HJWENO5_BIAS);
        advection.setTemporalScheme(openvdb::math::TVD_RK3);
        advection.setTrackerSpatialScheme(openvdb::math::HJWENO5_BIAS);
        advection.setTrackerTemporalScheme(openvdb::math::TVD_RK1);
        advection.setNormCount(3);
        return advection.advect(t0, t1);
    }
    static uint64_t activeVoxels(const GridType& g) { return g.activeVoxelCount(); }
};

/// Copies the active voxels of an OpenVDB level set into a grid of this library (then flood
/// filled), so that both results are measured by the same code.
vdb::FloatGrid::Ptr toVdb(const openvdb::FloatGrid& in) {
    auto out = vdb::FloatGrid::create(in.background());
    out->setTransform(vdb::math::Transform::createLinearTransform(in.voxelSize()[0]));
    auto acc = out->getAccessor();
    for (auto it = in.cbeginValueOn(); it; ++it) {
        const openvdb::Coord& c = it.getCoord();
        acc.setValue(vdb::Coord(c[0], c[1], c[2]), *it);
    }
    vdb::tools::signedFloodFill(out->tree());
    return out;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// CPU seconds used by the process so far (all threads).
double cpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Timing {
    double medianMs = 0;
    double medianCpuMs = 0;  // process CPU time: on a shared machine, the work itself
    size_t steps = 0;
    typename Vdb::GridType::Ptr result;  // this library's view of the last result
};

template <typename Lib>
Timing timeStep(const typename Lib::GridType& input, int reps) {
    std::vector<double> ms, cpu;
    Timing timing;
    for (int r = 0; r < reps; ++r) {
        auto grid = Lib::copy(input);
        vdb::bench::releaseFreeMemory();
        const double cpu0 = cpuSeconds();
        const auto start = Clock::now();
        timing.steps = Lib::advect(*grid, 0.0, kStepEnd);
        const auto stop = Clock::now();
        cpu.push_back(1e3 * (cpuSeconds() - cpu0));
        ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
        if (r + 1 == reps) {
            if constexpr (std::is_same_v<Lib, Vdb>) {
                timing.result = grid;
            } else {
                timing.result = toVdb(*grid);
            }
        }
    }
    timing.medianMs = median(ms);
    timing.medianCpuMs = median(cpu);
    return timing;
}

/// The largest |a - b| over the voxels active in either grid.
/// The floor of one step over `voxels` band voxels (see the file comment): the median of `reps`
/// runs, in milliseconds, with the threads tbb may use.
double stepFloorMs(uint64_t voxels, int reps) {
    const int n = int(std::ceil(std::cbrt(double(voxels)))) + 6;  // the block with its halo
    const size_t count = size_t(n) * size_t(n) * size_t(n);
    std::vector<float> phi(count), next(count);
    const auto at = [n](int i, int j, int k) {
        return (size_t(i) * size_t(n) + size_t(j)) * size_t(n) + size_t(k);
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k)  // a sphere's distance, in voxels
                phi[at(i, j, k)] =
                    std::sqrt(float((i - n / 2) * (i - n / 2) + (j - n / 2) * (j - n / 2) +
                                    (k - n / 2) * (k - n / 2))) -
                    float(n) / 3.0f;
    next = phi;
    const float dt = 0.3f, vx = 0.5f, vy = -0.25f, vz = 0.125f;
    // One stage: the one-sided HJ-WENO5 derivatives of every interior voxel along its three axes,
    // then the update.
    const auto stage = [&](bool renormalise) {
        tbb::parallel_for(tbb::blocked_range<int>(3, n - 3), [&](const tbb::blocked_range<int>& r) {
            const size_t strides[3] = {size_t(n) * size_t(n), size_t(n), 1};
            const size_t len = size_t(n);
            std::vector<float> dm(3 * len), dp(3 * len);
            for (int i = r.begin(); i < r.end(); ++i)
                for (int j = 3; j < n - 3; ++j) {
                    const float* row = phi.data() + at(i, j, 0);
                    // The derivatives of the row along each axis, one loop per axis over z.
                    for (int a = 0; a < 3; ++a) {
                        const size_t s = strides[a];
                        float* m = dm.data() + size_t(a) * len;
                        float* p = dp.data() + size_t(a) * len;
                        for (int k = 3; k < n - 3; ++k) {
                            const float* c = row + k;
                            const float line[7] = {c[-3 * ptrdiff_t(s)],
                                                   c[-2 * ptrdiff_t(s)],
                                                   c[-ptrdiff_t(s)],
                                                   c[0],
                                                   c[s],
                                                   c[2 * s],
                                                   c[3 * s]};
                            vdb::math::biasedDifferences<vdb::math::HJWENO5_BIAS>(line, m[k], p[k]);
                        }
                    }
                    float* out = next.data() + at(i, j, 0);
                    const float *mx = dm.data(), *my = mx + len, *mz = my + len;
                    const float *px = dp.data(), *py = px + len, *pz = py + len;
                    for (int k = 3; k < n - 3; ++k) {
                        const float v = row[k];
                        if (renormalise) {
                            const float g2 = vdb::math::godunovNormSqrd(v > 0.0f, mx[k], px[k],
                                                                        my[k], py[k], mz[k], pz[k]);
                            const float sign = v / std::sqrt(v * v + g2);
                            out[k] = v - dt * sign * (std::sqrt(g2) - 1.0f);
                        } else {
                            out[k] = v - dt * (vx * vdb::math::upwind(vx, mx[k], px[k]) +
                                               vy * vdb::math::upwind(vy, my[k], py[k]) +
                                               vz * vdb::math::upwind(vz, mz[k], pz[k]));
                        }
                    }
                }
        });
        phi.swap(next);
    };
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) {
        const auto start = Clock::now();
        for (int s = 0; s < 6; ++s)
            stage(s >= 3);
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
    return median(ms);
}

double maxDifference(const vdb::FloatGrid& a, const vdb::FloatGrid& b) {
    double worst = 0.0;
    auto accA = a.getConstAccessor();
    auto accB = b.getConstAccessor();
    for (auto it = a.cbeginValueOn(); it; ++it)
        worst = std::max(worst, double(std::abs(*it - accB.getValue(it.getCoord()))));
    for (auto it = b.cbeginValueOn(); it; ++it)
        worst = std::max(worst, double(std::abs(*it - accA.getValue(it.getCoord()))));
    return worst;
}

/// The full-period Enright test in one library: returns the final grid (this library's view),
/// the steps and the seconds.
template <typename Lib>
vdb::FloatGrid::Ptr fullPeriod(const typename Lib::GridType& input, int intervals, size_t& steps,
                               double& seconds) {
    auto grid = Lib::copy(input);
    const double period = vdb::tools::EnrightField<float>::PERIOD;
    const auto start = Clock::now();
    steps = 0;
    for (int i = 0; i < intervals; ++i)
        steps += Lib::advect(*grid, period * i / intervals, period * (i + 1) / intervals);
    seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if constexpr (std::is_same_v<Lib, Vdb>) {
        return grid;
    } else {
        return toVdb(*grid);
    }
}

// ---- Markdown report ----

using vdb::bench::fmt;

/// The target of the Table III step: at most 0.8 times OpenVDB's time.
constexpr double kTarget = 0.8;

/// Milliseconds as the tables show them: whole numbers, one decimal below 100 ms.
std::string msText(double ms) {
    return fmt(ms, ms < 100.0 ? 1 : 0);
}

/// How far the two libraries' results of one resolution lie apart, worst over its runs.
struct Agreement {
    int res = 0;
    double maxDiffVoxels = 0.0;
    uint64_t activeOurs = 0, activeTheirs = 0;  // of the run whose counts differ most
    double activeDiff = -1.0;                   // relative, of that run
    size_t stepsOurs = 0, stepsTheirs = 0;

    void add(const Timing& a, const Timing& b, double diffVoxels) {
        maxDiffVoxels = std::max(maxDiffVoxels, diffVoxels);
        const uint64_t na = a.result->activeVoxelCount(), nb = b.result->activeVoxelCount();
        const double rel = double(na > nb ? na - nb : nb - na) / double(std::max<uint64_t>(1, nb));
        if (rel > activeDiff) {
            activeDiff = rel;
            activeOurs = na;
            activeTheirs = nb;
        }
        stepsOurs = std::max(stepsOurs, a.steps);
        stepsTheirs = std::max(stepsTheirs, b.steps);
    }

    vdb::bench::MarkdownReport::Row row() const {
        char diff[32];
        std::snprintf(diff, sizeof diff, "%.2g", maxDiffVoxels);
        return {std::to_string(res),
                std::to_string(stepsOurs) + " / " + std::to_string(stepsTheirs),
                fmt(double(activeOurs), 0) + " / " + fmt(double(activeTheirs), 0),
                fmt(100.0 * activeDiff, 3) + "%", diff};
    }
};

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> resolutions{256, 512, 1024};
    std::vector<std::string> threads{"1", "all"};
    int reps = 3, enright = 0, enrightFrames = 0;
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_levelset [--res 256,512,1024] [--reps 3] "
        "[--threads 1,all] [--enright 0] [--enright-frames 0] "
        "[--markdown FILE]");
    // --enright 0 and --enright-frames 0 turn the Enright runs off.
    options.numbers("--res", resolutions)
        .number("--reps", reps)
        .list("--threads", threads)
        .number("--enright", enright, 0)
        .number("--enright-frames", enrightFrames, 0)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    openvdb::initialize();

    std::printf(
        "# vdb_bench_levelset: Table III step (advect RK3/HJ-WENO5 at t=0, rebuild with 3 "
        "renormalisations RK1/HJ-WENO5 CFL 0.3), medians of %d runs, milliseconds; "
        "ratio = vdb / openvdb\n",
        reps);
    std::printf("%5s %10s %7s %9s %9s %6s %9s %9s %6s  %s\n", "res", "active", "threads", "vdb",
                "openvdb", "ratio", "vdb cpu", "ovdb cpu", "ratio", "results");
    vdb::bench::MarkdownReport report;
    std::vector<vdb::bench::MarkdownReport::Row> stepRows, agreementRows;
    vdb::bench::RatioRange wallRatios, cpuRatios;
    for (const int res : resolutions) {
        const auto band = vdb::bench::makeEnrightBand(res);
        const auto ours = Vdb::build(band, res);
        const auto theirs = OpenVdb::build(band, res);
        Agreement agreement;
        agreement.res = res;
        for (const std::string& t : threads) {
            const int n = options.threadCount(t);
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
            const Timing a = timeStep<Vdb>(*ours, reps);
            const Timing b = timeStep<OpenVdb>(*theirs, reps);
            const double floorMs = stepFloorMs(Vdb::activeVoxels(*ours), reps);
            const double diffVoxels = maxDifference(*a.result, *b.result) * res;
            std::printf(
                "%5d %10llu %7d %9.1f %9.1f %6.2f %9.1f %9.1f %6.2f  steps %zu/%zu, active "
                "after %llu/%llu, max |vdb - openvdb| %.2g voxels; floor %.1f ms\n",
                res, (unsigned long long)Vdb::activeVoxels(*ours), n, a.medianMs, b.medianMs,
                a.medianMs / b.medianMs, a.medianCpuMs, b.medianCpuMs,
                a.medianCpuMs / b.medianCpuMs, a.steps, b.steps,
                (unsigned long long)a.result->activeVoxelCount(),
                (unsigned long long)b.result->activeVoxelCount(), diffVoxels, floorMs);
            std::fflush(stdout);
            agreement.add(a, b, diffVoxels);
            wallRatios.add(a.medianMs / b.medianMs);
            cpuRatios.add(a.medianCpuMs / b.medianCpuMs);
            stepRows.push_back({std::to_string(res), fmt(double(Vdb::activeVoxels(*ours)), 0),
                                std::to_string(n), msText(a.medianMs), msText(b.medianMs),
                                vdb::bench::ratioCell(a.medianMs / b.medianMs, kTarget),
                                msText(a.medianCpuMs), msText(b.medianCpuMs),
                                vdb::bench::ratioCell(a.medianCpuMs / b.medianCpuMs, kTarget),
                                msText(floorMs), fmt(a.medianMs / floorMs, 1)});
        }
        if (!threads.empty())
            agreementRows.push_back(agreement.row());
    }
    report.paragraph("**Table III step.** Medians of " + std::to_string(reps) +
                     (reps == 1 ? " run" : " runs") +
                     ", milliseconds; ratio = vdb / OpenVDB, in bold where it meets the target "
                     "of 0.8; " +
                     std::to_string(cores) + " hardware threads.");
    report.table({"R", "active voxels", "threads", "vdb ms", "OpenVDB ms", "ratio", "vdb CPU ms",
                  "OpenVDB CPU ms", "CPU ratio", "floor ms", "vdb / floor"},
                 stepRows);
    report.paragraph(
        "Floor: the step's arithmetic in a plain loop, with no tree and no band to keep: a dense "
        "block with as many voxels as the band goes through the six stages (three of TVD-RK3 "
        "advection with a constant velocity, three of renormalisation), each the HJ-WENO5 "
        "differences of every voxel along three axes and its update, threaded like the step.");
    report.paragraph(
        "**Agreement** of the two results after the step, worst over the runs of each R: steps "
        "taken, active voxels, and the largest value difference over the voxels active in "
        "either.");
    report.table({"R", "steps vdb / OpenVDB", "active voxels vdb / OpenVDB", "difference",
                  "max value difference (voxels)"},
                 agreementRows);
    // The status line: both ranges, judged on wall-clock time as the paper's Table III is.
    std::string status = wallRatios.status("step", kTarget);
    status.insert(std::string("step ").size() + wallRatios.text().size(),
                  " wall, " + cpuRatios.text() + " CPU");
    report.status(status);

    if (enright > 0) {
        const auto band = vdb::bench::makeEnrightBand(enright);
        const auto ours = Vdb::build(band, enright);
        const auto theirs = OpenVdb::build(band, enright);
        const double v0 = vdb::tools::smearedHeavisideVolume(*ours);
        std::printf("# Enright test, full period at %d^3, %d threads, initial volume %.6g\n",
                    enright, cores, v0);
        std::printf("%-8s %9s %6s %9s %12s %10s\n", "library", "intervals", "steps", "seconds",
                    "volume", "loss %");
        using Row = vdb::bench::MarkdownReport::Row;
        std::vector<Row> rows;
        std::string status;
        std::vector<int> intervalCounts{1};
        if (enrightFrames > 1)
            intervalCounts.push_back(enrightFrames);
        for (const int intervals : intervalCounts) {
            size_t stepsA = 0, stepsB = 0;
            double secA = 0, secB = 0;
            const auto a = fullPeriod<Vdb>(*ours, intervals, stepsA, secA);
            const auto b = fullPeriod<OpenVdb>(*theirs, intervals, stepsB, secB);
            const double va = vdb::tools::smearedHeavisideVolume(*a);
            const double vb = vdb::tools::smearedHeavisideVolume(*b);
            const double lossA = 100.0 * (v0 - va) / v0, lossB = 100.0 * (v0 - vb) / v0;
            std::printf("%-8s %9d %6zu %9.1f %12.6g %10.3f\n", "vdb", intervals, stepsA, secA, va,
                        lossA);
            std::printf("%-8s %9d %6zu %9.1f %12.6g %10.3f\n", "openvdb", intervals, stepsB, secB,
                        vb, lossB);
            const auto row = [&](const char* library, size_t steps, double seconds, double v,
                                 double loss) {
                char text[32];
                std::snprintf(text, sizeof text, "%.6g", v);
                return Row{library, fmt(double(intervals), 0), fmt(loss, 2) + "%",
                           text,    fmt(double(steps), 0),     fmt(seconds, 1)};
            };
            rows.push_back(row("vdb", stepsA, secA, va, lossA));
            rows.push_back(row("OpenVDB 10", stepsB, secB, vb, lossB));
            status += std::string(status.empty() ? "" : ", ") + fmt(lossA, 2) + "% / " +
                      fmt(lossB, 2) + "%" +
                      (intervals > 1 ? " in " + std::to_string(intervals) + " intervals" : "");
        }
        char volume[32];
        std::snprintf(volume, sizeof volume, "%.6g", v0);
        report.paragraph("**Volume loss, full period** (t = 0 to 3) at " + std::to_string(enright) +
                         "^3, " + std::to_string(cores) + " threads, initial volume " + volume +
                         "; intervals: the number of advect calls that cover the period:");
        report.table({"library", "intervals", "volume loss after t = 3", "final volume", "steps",
                      "time (s)"},
                     rows);
        report.status("Enright " + std::to_string(enright) + "^3 volume loss vdb / OpenVDB " +
                      status);
    }
    std::printf("# machine: %u hardware threads\n", std::thread::hardware_concurrency());
    if (!markdownPath.empty() && !report.write(markdownPath))
        return 1;
    return 0;
}
