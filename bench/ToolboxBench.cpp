// SPDX-License-Identifier: Apache-2.0
// The level set and volume toolbox against OpenVDB 10 on the same grids, in one process:
// filters, differential operators, measures and the fog conversion.
//
//   ls-mean, ls-gaussian, ls-median, ls-curvature, ls-laplacian, ls-offset
//               LevelSetFilter on the Enright sphere: mean(1), gaussian(1), median(1),
//               meanCurvature(), laplacian(), offset(-1 voxel), each with its band rebuild
//   gradient, laplacian, curvature
//               gradient, laplacian, meanCurvature of the Enright sphere
//   fog         sdfToFogVolume of the Enright sphere
//   area-volume LevelSetMeasure::area() and volume() of the Enright sphere (one pass)
//   genus       LevelSetMeasure::totMeanCurvature() and eulerCharacteristic() (the curvature
//               pass)
//   mean, gaussian, median, offset
//               Filter on the density of smoke.vdb (the sample files): mean(1), gaussian(1),
//               median(1), offset(0.1)
//   fog-gradient, fog-laplacian
//               gradient and laplacian of that density
//   divergence, curl, magnitude, normalize
//               of the velocity of vel_VDB_bound_v02.vdb (a vec3s grid of 1M voxels)
//
// The Enright sphere (radius 0.15 at (0.35, 0.35, 0.35) of the unit box) is a level set in
// world units at voxel size 1/resolution, half width 5 voxels, flood filled, the same voxels
// and values in both libraries. The sample files are read by each library's own reader,
// without delayed loading (else the first operation on a copy would time the decompression).
//
// Each measurement copies the input grid (not timed), times the operation alone, and compares
// the result with the other library's: the active voxel count, and for the measures the
// numbers (relative 1e-4). The median of the repetitions is reported. "1 thread" runs under
// tbb::global_control with one thread for both libraries; "all" uses every core.
//
// With --markdown FILE the program also writes its results as Markdown tables to FILE and one
// overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_toolbox [--res 512,1024] [--measure-res 1024] [--reps 3]
//                          [--ops ls-mean,...] [--threads 1,all] [--samples DIR]
//                          [--markdown FILE]

#include <vdb/io/File.h>
#include <vdb/tools/Filter.h>
#include <vdb/tools/GridOperators.h>
#include <vdb/tools/LevelSetFilter.h>
#include <vdb/tools/LevelSetMeasure.h>
#include <vdb/tools/LevelSetUtil.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Filter.h>
#include <openvdb/tools/GridOperators.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace {

using vdb::bench::BandVoxel;
using vdb::bench::EnrightSphere;

// ---- What a run leaves, compared between the libraries ----

struct Outcome {
    uint64_t activeVoxels = 0;
    double a = 0, b = 0;  // the measures' numbers (0 for the other operations)

    bool matches(const Outcome& o) const {
        const auto near = [](double x, double y) {
            return std::abs(x - y) <= 1e-4 * std::max(std::abs(x), std::abs(y));
        };
        return activeVoxels == o.activeVoxels && near(a, o.a) && near(b, o.b);
    }
};

// ---- Library tags: grid types, inputs and the operations under test ----

/// The outcome of an operator's result, which `keep` holds until after the timing (so that
/// freeing it is not timed).
template <typename PtrT>
Outcome kept(std::shared_ptr<void>& keep, const PtrT& result) {
    keep = result;
    return {uint64_t(result->activeVoxelCount())};
}

struct Vdb {
    using FloatGrid = vdb::FloatGrid;
    using Vec3SGrid = vdb::Vec3SGrid;

    static FloatGrid::Ptr levelSet(const std::vector<BandVoxel>& band, int res) {
        const double dx = 1.0 / res;
        auto grid = FloatGrid::create(float(EnrightSphere::kHalfWidth * dx));
        grid->setTransform(vdb::math::Transform::createLinearTransform(dx));
        grid->setGridClass(vdb::GRID_LEVEL_SET);
        vdb::tree::ValueAccessor<vdb::FloatTree> acc(grid->tree());
        for (const BandVoxel& v : band)
            acc.setValue(vdb::Coord(v.x, v.y, v.z), float(v.value * dx));
        vdb::tools::signedFloodFill(grid->tree());
        return grid;
    }
    template <typename GridT>
    static typename GridT::Ptr read(const std::string& file, const std::string& name) {
        vdb::io::File in(file);
        in.open(false);  // every value in memory: the timings measure the tools, not loading
        auto grid = vdb::gridPtrCast<GridT>(in.readGrid(name));
        if (!grid) {
            std::fprintf(stderr, "%s: no grid \"%s\" of the expected type\n", file.c_str(),
                         name.c_str());
            std::exit(2);
        }
        return grid;
    }
    template <typename GridT>
    static typename GridT::Ptr copy(const GridT& g) {
        return g.deepCopy();
    }
    template <typename GridT>
    static Outcome outcome(const GridT& g) {
        return {uint64_t(g.activeVoxelCount())};
    }

    static Outcome run(const std::string& op, FloatGrid& g, std::shared_ptr<void>& keep) {
        using LsFilter = vdb::tools::LevelSetFilter<FloatGrid>;
        if (op == "ls-mean")
            return LsFilter(g).mean(1), outcome(g);
        if (op == "ls-gaussian")
            return LsFilter(g).gaussian(1), outcome(g);
        if (op == "ls-median")
            return LsFilter(g).median(1), outcome(g);
        if (op == "ls-curvature")
            return LsFilter(g).meanCurvature(), outcome(g);
        if (op == "ls-laplacian")
            return LsFilter(g).laplacian(), outcome(g);
        if (op == "ls-offset")
            return LsFilter(g).offset(-float(g.voxelSize()[0])), outcome(g);
        if (op == "gradient" || op == "fog-gradient")
            return kept(keep, vdb::tools::gradient(g));
        if (op == "laplacian" || op == "fog-laplacian")
            return kept(keep, vdb::tools::laplacian(g));
        if (op == "curvature")
            return kept(keep, vdb::tools::meanCurvature(g));
        if (op == "fog")
            return vdb::tools::sdfToFogVolume(g), outcome(g);
        if (op == "area-volume") {
            vdb::tools::LevelSetMeasure<FloatGrid> m(g);
            const double area = m.area();
            return {0, area, m.volume()};
        }
        if (op == "genus") {
            vdb::tools::LevelSetMeasure<FloatGrid> m(g);
            const double h = m.totMeanCurvature();
            return {0, h, double(m.eulerCharacteristic())};
        }
        using ValueFilter = vdb::tools::Filter<FloatGrid>;
        if (op == "mean")
            return ValueFilter(g).mean(1, 1), outcome(g);
        if (op == "gaussian")
            return ValueFilter(g).gaussian(1, 1), outcome(g);
        if (op == "median")
            return ValueFilter(g).median(1, 1), outcome(g);
        if (op == "offset")
            return ValueFilter(g).offset(0.1f), outcome(g);
        return unknown(op);
    }
    static Outcome run(const std::string& op, Vec3SGrid& g, std::shared_ptr<void>& keep) {
        if (op == "divergence")
            return kept(keep, vdb::tools::divergence(g));
        if (op == "curl")
            return kept(keep, vdb::tools::curl(g));
        if (op == "magnitude")
            return kept(keep, vdb::tools::magnitude(g));
        if (op == "normalize")
            return kept(keep, vdb::tools::normalize(g));
        return unknown(op);
    }
    [[noreturn]] static Outcome unknown(const std::string& op) {
        std::fprintf(stderr, "unknown operation '%s'\n", op.c_str());
        std::exit(2);
    }
};

struct OpenVdb {
    using FloatGrid = openvdb::FloatGrid;
    using Vec3SGrid = openvdb::Vec3SGrid;

    static FloatGrid::Ptr levelSet(const std::vector<BandVoxel>& band, int res) {
        const double dx = 1.0 / res;
        auto grid = FloatGrid::create(float(EnrightSphere::kHalfWidth * dx));
        grid->setTransform(openvdb::math::Transform::createLinearTransform(dx));
        grid->setGridClass(openvdb::GRID_LEVEL_SET);
        openvdb::tree::ValueAccessor<openvdb::FloatTree> acc(grid->tree());
        for (const BandVoxel& v : band)
            acc.setValue(openvdb::Coord(v.x, v.y, v.z), float(v.value * dx));
        openvdb::tools::signedFloodFill(grid->tree());
        return grid;
    }
    template <typename GridT>
    static typename GridT::Ptr read(const std::string& file, const std::string& name) {
        openvdb::io::File in(file);
        in.open(false);
        auto grid = openvdb::gridPtrCast<GridT>(in.readGrid(name));
        if (!grid) {
            std::fprintf(stderr, "%s: no grid \"%s\" of the expected type\n", file.c_str(),
                         name.c_str());
            std::exit(2);
        }
        return grid;
    }
    template <typename GridT>
    static typename GridT::Ptr copy(const GridT& g) {
        return g.deepCopy();
    }
    template <typename GridT>
    static Outcome outcome(const GridT& g) {
        return {uint64_t(g.activeVoxelCount())};
    }

    static Outcome run(const std::string& op, FloatGrid& g, std::shared_ptr<void>& keep) {
        using LsFilter = openvdb::tools::LevelSetFilter<FloatGrid>;
        if (op == "ls-mean")
            return LsFilter(g).mean(1), outcome(g);
        if (op == "ls-gaussian")
            return LsFilter(g).gaussian(1), outcome(g);
        if (op == "ls-median")
            return LsFilter(g).median(1), outcome(g);
        if (op == "ls-curvature")
            return LsFilter(g).meanCurvature(), outcome(g);
        if (op == "ls-laplacian")
            return LsFilter(g).laplacian(), outcome(g);
        if (op == "ls-offset")
            return LsFilter(g).offset(-float(g.voxelSize()[0])), outcome(g);
        if (op == "gradient" || op == "fog-gradient")
            return kept(keep, openvdb::tools::gradient(g));
        if (op == "laplacian" || op == "fog-laplacian")
            return kept(keep, openvdb::tools::laplacian(g));
        if (op == "curvature")
            return kept(keep, openvdb::tools::meanCurvature(g));
        if (op == "fog")
            return openvdb::tools::sdfToFogVolume(g), outcome(g);
        if (op == "area-volume") {
            openvdb::tools::LevelSetMeasure<FloatGrid> m(g);
            const double area = m.area();
            return {0, area, m.volume()};
        }
        if (op == "genus") {
            openvdb::tools::LevelSetMeasure<FloatGrid> m(g);
            const double h = m.totMeanCurvature();
            return {0, h, double(m.eulerCharacteristic())};
        }
        using ValueFilter = openvdb::tools::Filter<FloatGrid>;
        if (op == "mean")
            return ValueFilter(g).mean(1, 1), outcome(g);
        if (op == "gaussian")
            return ValueFilter(g).gaussian(1, 1), outcome(g);
        if (op == "median")
            return ValueFilter(g).median(1, 1), outcome(g);
        if (op == "offset")
            return ValueFilter(g).offset(0.1f), outcome(g);
        return Vdb::unknown(op);
    }
    static Outcome run(const std::string& op, Vec3SGrid& g, std::shared_ptr<void>& keep) {
        if (op == "divergence")
            return kept(keep, openvdb::tools::divergence(g));
        if (op == "curl")
            return kept(keep, openvdb::tools::curl(g));
        if (op == "magnitude")
            return kept(keep, openvdb::tools::magnitude(g));
        if (op == "normalize")
            return kept(keep, openvdb::tools::normalize(g));
        return Vdb::unknown(op);
    }
};

/// Which input an operation takes.
enum class Input { Sphere, Density, Velocity };

Input inputOf(const std::string& op) {
    if (op == "mean" || op == "gaussian" || op == "median" || op == "offset" ||
        op == "fog-gradient" || op == "fog-laplacian")
        return Input::Density;
    if (op == "divergence" || op == "curl" || op == "magnitude" || op == "normalize")
        return Input::Velocity;
    return Input::Sphere;
}

bool isMeasure(const std::string& op) {
    return op == "area-volume" || op == "genus";
}

// ---- Timing ----

using Clock = std::chrono::steady_clock;

struct Timing {
    double medianMs = 0;
    Outcome outcome;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Runs `op` on a fresh copy of `input` `reps` times. Freeing the copy and the result is not
/// timed.
template <typename Lib, typename GridT>
Timing timeOp(const std::string& op, const GridT& input, int reps) {
    std::vector<double> ms;
    Timing timing;
    for (int r = 0; r < reps; ++r) {
        auto grid = Lib::copy(input);
        std::shared_ptr<void> result;
        vdb::bench::releaseFreeMemory();
        const auto start = Clock::now();
        timing.outcome = Lib::run(op, *grid, result);
        const auto stop = Clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
    }
    timing.medianMs = median(ms);
    return timing;
}

/// One library's inputs.
template <typename Lib>
struct Inputs {
    typename Lib::FloatGrid::Ptr sphere, density;
    typename Lib::Vec3SGrid::Ptr velocity;
};

template <typename Lib>
Timing run(const std::string& op, const Inputs<Lib>& in, int reps) {
    switch (inputOf(op)) {
        case Input::Density:
            return timeOp<Lib>(op, *in.density, reps);
        case Input::Velocity:
            return timeOp<Lib>(op, *in.velocity, reps);
        default:
            return timeOp<Lib>(op, *in.sphere, reps);
    }
}

// ---- Command line ----

// ---- Markdown report ----

using vdb::bench::fmt;

/// Ratios at most this are in bold in the report.
constexpr double kGoodRatio = 0.8;

struct Measurement {
    std::string op;
    std::string input;  // "512^3 sphere", "smoke.vdb density", ...
    int threads = 0;
    Timing ours, theirs;
};

std::string describe(const std::string& op) {
    if (op.rfind("ls-", 0) == 0)
        return "LevelSetFilter " + op.substr(3);
    if (op == "area-volume")
        return "LevelSetMeasure area + volume";
    if (op == "genus")
        return "LevelSetMeasure curvatures + genus";
    if (op == "fog")
        return "sdfToFogVolume";
    if (op == "mean" || op == "gaussian" || op == "median" || op == "offset")
        return "Filter " + op;
    if (op == "fog-gradient")
        return "gradient";
    if (op == "fog-laplacian")
        return "laplacian";
    if (op == "curvature")
        return "meanCurvature";
    return op;
}

vdb::bench::MarkdownReport report(std::vector<Measurement> measured,
                                  const std::vector<std::string>& ops, int reps, int cores) {
    // Grouped by operation, in the order of --ops.
    const auto rank = [&](const Measurement& m) {
        return std::find(ops.begin(), ops.end(), m.op) - ops.begin();
    };
    std::stable_sort(measured.begin(), measured.end(),
                     [&](const Measurement& a, const Measurement& b) { return rank(a) < rank(b); });
    vdb::bench::MarkdownReport md;
    std::vector<vdb::bench::MarkdownReport::Row> rows;
    vdb::bench::RatioRange all, filters, operators, measures;
    bool differ = false;
    for (size_t i = 0; i < measured.size(); ++i) {
        const Measurement& m = measured[i];
        const Measurement* prev = i ? &measured[i - 1] : nullptr;
        const double ratio = m.ours.medianMs / m.theirs.medianMs;
        const bool newOp = !prev || prev->op != m.op;
        const bool newInput = newOp || prev->input != m.input;
        std::string result;
        if (!m.ours.outcome.matches(m.theirs.outcome)) {
            differ = true;
            result = "**differ**";
        } else if (isMeasure(m.op)) {
            result = fmt(m.ours.outcome.a, 4) + ", " + fmt(m.ours.outcome.b, 4);
        } else if (newInput) {
            result = fmt(double(m.ours.outcome.activeVoxels), 0);
        }
        rows.push_back({newOp ? describe(m.op) : "", newInput ? m.input : "",
                        std::to_string(m.threads), fmt(m.ours.medianMs, 1),
                        fmt(m.theirs.medianMs, 1), vdb::bench::ratioCell(ratio, kGoodRatio),
                        result});
        all.add(ratio);
        if (isMeasure(m.op))
            measures.add(ratio);
        else if (m.op.rfind("ls-", 0) == 0 || describe(m.op).rfind("Filter", 0) == 0)
            filters.add(ratio);
        else
            operators.add(ratio);
    }
    const std::string protocol =
        reps > 1 ? "Medians of " + std::to_string(reps) + " runs" : "One run per figure";
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s in milliseconds; ratio = vdb / OpenVDB, in bold where it is at most %.2f. "
                  "The result column gives the active voxels of the result (for the measures: "
                  "area and volume, or total mean curvature and Euler characteristic, in world "
                  "units). The machine has %d hardware threads.",
                  protocol.c_str(), kGoodRatio, cores);
    md.paragraph(line);
    md.table({"operation", "input", "threads", "vdb ms", "OpenVDB ms", "ratio", "result"}, rows);
    if (differ)
        md.paragraph("**The libraries' results differ where marked.**");
    md.status(all.text() + " over all operations");
    md.status(filters.status("filters") + ", " + operators.status("operators") + ", " +
              measures.status("measures"));
    if (differ)
        md.status("results differ");
    return md;
}

}  // namespace

int main(int argc, char** argv) {
    vdb::bench::keepHeapOnFree();
    std::vector<int> resolutions{512, 1024};
    int measureRes = 1024;
    int reps = 3;
    std::vector<std::string> ops{
        "ls-mean",    "ls-gaussian", "ls-median", "ls-curvature", "ls-laplacian", "ls-offset",
        "gradient",   "laplacian",   "curvature", "fog",          "area-volume",  "genus",
        "mean",       "gaussian",    "median",    "offset",       "fog-gradient", "fog-laplacian",
        "divergence", "curl",        "magnitude", "normalize"};
    std::vector<std::string> threads{"1", "all"};
    std::string samples = VDB_SAMPLES_DIR;
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_toolbox [--res 512,1024] [--measure-res 1024] "
        "[--reps 3] [--ops ls-mean,...] [--threads 1,all] "
        "[--samples DIR] [--markdown FILE]");
    options.numbers("--res", resolutions)
        .number("--measure-res", measureRes)
        .number("--reps", reps)
        .list("--ops", ops)
        .list("--threads", threads)
        .text("--samples", samples)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    openvdb::initialize();

    // The file inputs, read once by each library.
    const std::string smoke = samples + "/smoke.vdb", vel = samples + "/vel_VDB_bound_v02.vdb";
    const bool needsDensity = std::any_of(ops.begin(), ops.end(), [](const std::string& op) {
        return inputOf(op) == Input::Density;
    });
    const bool needsVelocity = std::any_of(ops.begin(), ops.end(), [](const std::string& op) {
        return inputOf(op) == Input::Velocity;
    });
    Inputs<Vdb> ours;
    Inputs<OpenVdb> theirs;
    if (needsDensity) {
        ours.density = Vdb::read<vdb::FloatGrid>(smoke, "density");
        theirs.density = OpenVdb::read<openvdb::FloatGrid>(smoke, "density");
    }
    if (needsVelocity) {
        ours.velocity = Vdb::read<vdb::Vec3SGrid>(vel, "vel");
        theirs.velocity = OpenVdb::read<openvdb::Vec3SGrid>(vel, "vel");
    }

    std::printf("# vdb_bench_toolbox: medians of %d runs, milliseconds; ratio = vdb / openvdb\n",
                reps);
    std::printf("%-14s %-20s %7s %10s %10s %6s  %s\n", "operation", "input", "threads", "vdb",
                "openvdb", "ratio", "results");
    bool allMatch = true;
    std::vector<Measurement> measured;
    const auto measure = [&](const std::string& op, const std::string& input) {
        for (const std::string& t : threads) {
            const int n = options.threadCount(t);
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
            const Timing a = run<Vdb>(op, ours, reps);
            const Timing b = run<OpenVdb>(op, theirs, reps);
            const bool match = a.outcome.matches(b.outcome);
            allMatch = allMatch && match;
            measured.push_back({op, input, n, a, b});
            std::printf("%-14s %-20s %7d %10.1f %10.1f %6.2f  %s (%llu active; %.6g, %.6g)\n",
                        op.c_str(), input.c_str(), n, a.medianMs, b.medianMs,
                        a.medianMs / b.medianMs, match ? "same" : "DIFFERENT",
                        (unsigned long long)a.outcome.activeVoxels, a.outcome.a, a.outcome.b);
            if (!match)
                std::printf("%-14s %-20s %7s %10s %10s %6s  openvdb: %llu active; %.6g, %.6g\n", "",
                            "", "", "", "", "", (unsigned long long)b.outcome.activeVoxels,
                            b.outcome.a, b.outcome.b);
            std::fflush(stdout);
        }
    };
    // Sphere operations per resolution (measures only at --measure-res), then the file inputs.
    std::vector<int> sphereRes = resolutions;
    if (std::find(sphereRes.begin(), sphereRes.end(), measureRes) == sphereRes.end())
        sphereRes.push_back(measureRes);
    for (const int res : sphereRes) {
        const auto band = vdb::bench::makeEnrightBand(res);
        ours.sphere = Vdb::levelSet(band, res);
        theirs.sphere = OpenVdb::levelSet(band, res);
        const std::string input = std::to_string(res) + "^3 sphere";
        const bool filterRes =
            std::find(resolutions.begin(), resolutions.end(), res) != resolutions.end();
        for (const std::string& op : ops) {
            if (inputOf(op) != Input::Sphere)
                continue;
            if (isMeasure(op) ? res != measureRes : !filterRes)
                continue;
            measure(op, input);
        }
    }
    ours.sphere.reset();
    theirs.sphere.reset();
    for (const std::string& op : ops) {
        if (inputOf(op) == Input::Density)
            measure(op, "smoke.vdb density");
        else if (inputOf(op) == Input::Velocity)
            measure(op, "vel_VDB_bound vel");
    }
    std::printf("# machine: %u hardware threads\n", std::thread::hardware_concurrency());
    if (!markdownPath.empty() && !report(measured, ops, reps, cores).write(markdownPath))
        return 1;
    return allMatch ? 0 : 1;
}
