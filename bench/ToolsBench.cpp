// SPDX-License-Identifier: Apache-2.0
// The topology tool benchmarks of the paper's Tables VII-IX (Museth 2013, sections 4 and 5):
// this library against OpenVDB 10 on the same level sets, in one process.
//
//   dilate      dilateActiveValues by one, face neighbours (Table VII)
//   erode       erodeActiveValues by one, face neighbours
//   brute       dilation by one done the naive way: every active voxel's six neighbours
//               activated by random insertion through an accessor (Table VII's ~17x)
//   floodfill   signedFloodFill of a narrow band whose inactive values are all +background
//               (Table VIII)
//   union, intersection, difference
//               csgUnion / csgIntersection / csgDifference of the Enright sphere and a torus
//               that cuts through it (Table IX), pruned afterwards as both libraries default to
//   union-copy, intersection-copy, difference-copy
//               csgUnionCopy / csgIntersectionCopy / csgDifferenceCopy of the same inputs: a
//               new tree, both inputs left intact
//
// Inputs: the Enright sphere (radius 0.15 at (0.35, 0.35, 0.35) of the unit box) and a torus
// (major radius 0.15, minor radius 0.05, centred at (0.45, 0.35, 0.35), axis z) at voxel size
// 1/resolution, narrow bands of half width 5 voxels, values in voxel units. Both libraries
// insert the same band voxels and flood-fill them with their own signedFloodFill.
//
// Each measurement copies the input tree (not timed), times the operation alone, and checks
// the result against the other library's (active voxel count and leaf count); the median of
// the repetitions is reported. "1 thread" runs under tbb::global_control with one thread for
// both libraries; "all" uses every core the machine has. The process runs with glibc's
// trimming of the heap inside free() off (bench::keepHeapOnFree) for both libraries: with it,
// operations that free many nodes (CSG intersection and difference at 2048^3) took up to 7
// times longer in a run after the smaller resolutions than alone, from some 18,000 extra brk()
// calls, depending on the heap that earlier measurements left.
//
// The floor of each measurement is the time to copy its result's leaf bytes (the values and
// the value mask of every leaf) once with memcpy between two buffers already in memory: the
// memory traffic of writing the whole result. It bounds the copy forms and the flood fill from
// below; dilation, erosion and in-place CSG change masks and some leaves only, so for them it is
// a reference, not a bound.
//
// With --markdown FILE the program also writes its results as Markdown tables to FILE and one
// overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_tools [--res 512,1024,2048] [--reps 5] [--ops dilate,erode,...]
//                        [--threads 1,all] [--markdown FILE]

#include <vdb/tools/Composite.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using vdb::bench::BandVoxel;
using vdb::bench::splitList;

constexpr double kHalfWidth = 5.0;                // narrow band half width in voxels
constexpr float kBackground = float(kHalfWidth);  // values are in voxel units

// ---- Inputs (library-neutral) ----

/// The band voxels of the torus with major radius 0.15 and minor radius 0.05 (unit box),
/// centred at (0.45, 0.35, 0.35) with its axis along z, at `resolution`.
std::vector<BandVoxel> makeTorusBand(int resolution) {
    const double cx = 0.45 * resolution, cy = 0.35 * resolution, cz = 0.35 * resolution;
    const double major = 0.15 * resolution, minor = 0.05 * resolution;
    const double outer = minor + kHalfWidth;
    const int xLo = int(std::floor(cx - major - outer)) - 1;
    const int xHi = int(std::ceil(cx + major + outer)) + 1;
    const int yLo = int(std::floor(cy - major - outer)) - 1;
    const int yHi = int(std::ceil(cy + major + outer)) + 1;
    std::vector<BandVoxel> band;
    for (int i = xLo; i <= xHi; ++i) {
        for (int j = yLo; j <= yHi; ++j) {
            const double radial = std::hypot(i - cx, j - cy) - major;
            const double rest = outer * outer - radial * radial;
            if (rest < 0.0)
                continue;
            const double reach = std::sqrt(rest);
            for (int k = int(std::floor(cz - reach)); k <= int(std::ceil(cz + reach)); ++k) {
                const double dist = std::hypot(radial, k - cz) - minor;
                if (std::abs(dist) < kHalfWidth)
                    band.push_back({i, j, k, float(dist)});
            }
        }
    }
    return band;
}

// ---- Library tags: one tree type and the operations under test ----

struct Vdb {
    static constexpr const char* kName = "vdb";
    using TreeType = vdb::FloatTree;
    using CoordType = vdb::Coord;
    using Accessor = vdb::tree::ValueAccessor<TreeType>;

    static void dilate(TreeType& t) { vdb::tools::dilateActiveValues(t, 1, vdb::tools::NN_FACE); }
    static void erode(TreeType& t) { vdb::tools::erodeActiveValues(t, 1, vdb::tools::NN_FACE); }
    static void floodFill(TreeType& t) { vdb::tools::signedFloodFill(t); }
    static void csgUnion(TreeType& a, TreeType& b) { vdb::tools::csgUnion(a, b); }
    static void csgIntersection(TreeType& a, TreeType& b) { vdb::tools::csgIntersection(a, b); }
    static void csgDifference(TreeType& a, TreeType& b) { vdb::tools::csgDifference(a, b); }
    static auto csgUnionCopy(const TreeType& a, const TreeType& b) {
        return vdb::tools::csgUnionCopy(a, b);
    }
    static auto csgIntersectionCopy(const TreeType& a, const TreeType& b) {
        return vdb::tools::csgIntersectionCopy(a, b);
    }
    static auto csgDifferenceCopy(const TreeType& a, const TreeType& b) {
        return vdb::tools::csgDifferenceCopy(a, b);
    }
};

struct OpenVdb {
    static constexpr const char* kName = "openvdb";
    using TreeType = openvdb::FloatTree;
    using CoordType = openvdb::Coord;
    using Accessor = openvdb::tree::ValueAccessor<TreeType>;

    static void dilate(TreeType& t) {
        openvdb::tools::dilateActiveValues(t, 1, openvdb::tools::NN_FACE);
    }
    static void erode(TreeType& t) {
        openvdb::tools::erodeActiveValues(t, 1, openvdb::tools::NN_FACE);
    }
    static void floodFill(TreeType& t) { openvdb::tools::signedFloodFill(t); }
    static void csgUnion(TreeType& a, TreeType& b) { openvdb::tools::csgUnion(a, b); }
    static void csgIntersection(TreeType& a, TreeType& b) { openvdb::tools::csgIntersection(a, b); }
    static void csgDifference(TreeType& a, TreeType& b) { openvdb::tools::csgDifference(a, b); }
    static auto csgUnionCopy(const TreeType& a, const TreeType& b) {
        return openvdb::tools::csgUnionCopy(a, b);
    }
    static auto csgIntersectionCopy(const TreeType& a, const TreeType& b) {
        return openvdb::tools::csgIntersectionCopy(a, b);
    }
    static auto csgDifferenceCopy(const TreeType& a, const TreeType& b) {
        return openvdb::tools::csgDifferenceCopy(a, b);
    }
};

template <typename Lib>
std::unique_ptr<typename Lib::TreeType> buildBand(const std::vector<BandVoxel>& band) {
    auto tree = std::make_unique<typename Lib::TreeType>(kBackground);
    typename Lib::Accessor acc(*tree);
    for (const BandVoxel& v : band)
        acc.setValue(typename Lib::CoordType(v.x, v.y, v.z), v.value);
    return tree;
}

/// One library's inputs at one resolution.
template <typename Lib>
struct Inputs {
    std::unique_ptr<typename Lib::TreeType> sphereBand;  // band only: inactive values +bg
    std::unique_ptr<typename Lib::TreeType> sphere;      // the band, flood-filled
    std::unique_ptr<typename Lib::TreeType> torus;       // likewise

    Inputs(const std::vector<BandVoxel>& sphereVoxels, const std::vector<BandVoxel>& torusVoxels)
        : sphereBand(buildBand<Lib>(sphereVoxels)),
          sphere(std::make_unique<typename Lib::TreeType>(*sphereBand)),
          torus(buildBand<Lib>(torusVoxels)) {
        Lib::floodFill(*sphere);
        Lib::floodFill(*torus);
    }
};

// ---- Timing ----

using Clock = std::chrono::steady_clock;

/// What one run of an operation left behind, compared between the libraries.
struct Outcome {
    uint64_t activeVoxels = 0;
    uint64_t leaves = 0;
    bool operator==(const Outcome&) const = default;
};

template <typename TreeT>
Outcome outcomeOf(const TreeT& tree) {
    return {uint64_t(tree.activeVoxelCount()), uint64_t(tree.leafCount())};
}

/// Whether the two libraries agree. OpenVDB's CSG copy forms build their result from the
/// leaves and a signed flood fill rather than by its in-place rules, and keep some uniform
/// leaves that its in-place forms (and ours, in both forms) prune into tiles: for those only
/// the active voxels are compared.
bool isCopyForm(const std::string& op) {
    return op.ends_with("-copy");
}
bool sameResult(const std::string& op, const Outcome& ours, const Outcome& theirs) {
    return isCopyForm(op) ? ours.activeVoxels == theirs.activeVoxels : ours == theirs;
}

struct Timing {
    double medianMs = 0;
    Outcome outcome;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Runs `op(a, b)` on fresh copies of `a` and `b` (b may be null) `reps` times. An operation
/// that returns a new tree (the CSG copy forms) is judged by that tree, which is freed after
/// the clock stops; any other by what it left in `a`.
template <typename TreeT, typename Op>
Timing timeOp(const TreeT& a, const TreeT* b, int reps, Op op) {
    std::vector<double> ms;
    Timing timing;
    for (int r = 0; r < reps; ++r) {
        auto ca = std::make_unique<TreeT>(a);
        auto cb = b ? std::make_unique<TreeT>(*b) : nullptr;
        vdb::bench::releaseFreeMemory();
        if constexpr (std::is_void_v<decltype(op(*ca, cb.get()))>) {
            const auto start = Clock::now();
            op(*ca, cb.get());
            const auto stop = Clock::now();
            ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
            timing.outcome = outcomeOf(*ca);
        } else {
            const auto start = Clock::now();
            auto result = op(*ca, cb.get());
            const auto stop = Clock::now();
            ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
            timing.outcome = outcomeOf(*result);
        }
    }
    timing.medianMs = median(ms);
    return timing;
}

/// The median time of copying `leaves` leaves' values and value masks once with memcpy, between
/// two buffers touched beforehand; memoised, since every operation at one resolution asks.
double copyFloorMs(uint64_t leaves, int reps) {
    static std::map<uint64_t, double> known;
    if (leaves == 0)
        return 0.0;
    if (const auto it = known.find(leaves); it != known.end())
        return it->second;
    using LeafT = vdb::FloatTree::LeafNodeType;
    const size_t bytes =
        size_t(leaves) * (sizeof(float) * LeafT::NUM_VALUES + LeafT::NUM_VALUES / 8);
    std::vector<char> from(bytes, 1), to(bytes, 2);
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) {
        const auto start = Clock::now();
        std::memcpy(to.data(), from.data(), bytes);
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
        from[size_t(r) % bytes] = to[bytes / 2];  // the copies are not dead stores
    }
    return known[leaves] = median(ms);
}

/// Naive dilation by one: list the active voxels, then activate each one's six face
/// neighbours through an accessor, one random insertion at a time.
template <typename Lib>
void bruteForceDilate(typename Lib::TreeType& tree) {
    using CoordT = typename Lib::CoordType;
    std::vector<CoordT> active;
    active.reserve(size_t(tree.activeVoxelCount()));
    for (auto it = tree.cbeginValueOn(); it; ++it)
        active.push_back(it.getCoord());
    typename Lib::Accessor acc(tree);
    for (const CoordT& c : active) {
        acc.setValueOn(c.offsetBy(-1, 0, 0));
        acc.setValueOn(c.offsetBy(1, 0, 0));
        acc.setValueOn(c.offsetBy(0, -1, 0));
        acc.setValueOn(c.offsetBy(0, 1, 0));
        acc.setValueOn(c.offsetBy(0, 0, -1));
        acc.setValueOn(c.offsetBy(0, 0, 1));
    }
}

template <typename Lib>
Timing run(const std::string& op, const Inputs<Lib>& in, int reps) {
    using TreeT = typename Lib::TreeType;
    if (op == "dilate")
        return timeOp(*in.sphere, (const TreeT*)nullptr, reps,
                      [](TreeT& a, TreeT*) { Lib::dilate(a); });
    if (op == "erode")
        return timeOp(*in.sphere, (const TreeT*)nullptr, reps,
                      [](TreeT& a, TreeT*) { Lib::erode(a); });
    if (op == "brute")
        return timeOp(*in.sphere, (const TreeT*)nullptr, reps,
                      [](TreeT& a, TreeT*) { bruteForceDilate<Lib>(a); });
    if (op == "floodfill")
        return timeOp(*in.sphereBand, (const TreeT*)nullptr, reps,
                      [](TreeT& a, TreeT*) { Lib::floodFill(a); });
    if (op == "union")
        return timeOp(*in.sphere, in.torus.get(), reps,
                      [](TreeT& a, TreeT* b) { Lib::csgUnion(a, *b); });
    if (op == "intersection")
        return timeOp(*in.sphere, in.torus.get(), reps,
                      [](TreeT& a, TreeT* b) { Lib::csgIntersection(a, *b); });
    if (op == "difference")
        return timeOp(*in.sphere, in.torus.get(), reps,
                      [](TreeT& a, TreeT* b) { Lib::csgDifference(a, *b); });
    if (op == "union-copy")
        return timeOp(*in.sphere, in.torus.get(), reps,
                      [](TreeT& a, TreeT* b) { return Lib::csgUnionCopy(a, *b); });
    if (op == "intersection-copy")
        return timeOp(*in.sphere, in.torus.get(), reps,
                      [](TreeT& a, TreeT* b) { return Lib::csgIntersectionCopy(a, *b); });
    if (op == "difference-copy")
        return timeOp(*in.sphere, in.torus.get(), reps,
                      [](TreeT& a, TreeT* b) { return Lib::csgDifferenceCopy(a, *b); });
    std::fprintf(stderr, "unknown operation '%s'\n", op.c_str());
    std::exit(2);
}

// ---- Command line ----

// ---- Markdown report ----

using vdb::bench::fmt;

/// Ratios at most this are in bold in the report.
constexpr double kGoodRatio = 0.8;

/// One printed row, kept for the report.
struct Measurement {
    std::string op;
    int res = 0;
    int threads = 0;
    Timing ours, theirs;
    double floorMs = 0;  // copyFloorMs() of our result's leaves
};

/// The operation's name in the report, and the group of its overview range ("" for the
/// brute-force baseline, which is no tool of either library).
std::pair<std::string, std::string> describe(const std::string& op) {
    if (op == "dilate")
        return {"dilate by 1 (face)", "dilate/erode"};
    if (op == "erode")
        return {"erode by 1 (face)", "dilate/erode"};
    if (op == "brute")
        return {"brute-force dilation (random insert)", ""};
    if (op == "floodfill")
        return {"signed flood fill", "flood fill"};
    if (isCopyForm(op))
        return {"CSG " + op.substr(0, op.size() - 5) + ", copy form", "CSG copy"};
    return {"CSG " + op, "CSG"};
}

/// The tables of docs/BENCHMARKS.md: every measurement grouped by operation (in the order of
/// --ops), then resolution and thread count; then the brute-force dilation against each
/// library's mask dilation. The overview line gives the ranges of the ratios.
vdb::bench::MarkdownReport report(const std::vector<Measurement>& measured,
                                  const std::vector<std::string>& ops, int reps, int cores) {
    std::vector<Measurement> sorted = measured;
    const auto rank = [&](const Measurement& m) {
        return std::find(ops.begin(), ops.end(), m.op) - ops.begin();
    };
    std::stable_sort(sorted.begin(), sorted.end(),
                     [&](const Measurement& a, const Measurement& b) { return rank(a) < rank(b); });

    vdb::bench::MarkdownReport md;
    std::vector<vdb::bench::MarkdownReport::Row> rows;
    vdb::bench::RatioRange all;
    std::vector<std::pair<std::string, vdb::bench::RatioRange>> groups;
    bool differ = false;
    for (size_t i = 0; i < sorted.size(); ++i) {
        const Measurement& m = sorted[i];
        const Measurement* prev = i ? &sorted[i - 1] : nullptr;
        const auto described = describe(m.op);
        const std::string& name = described.first;
        const std::string& group = described.second;
        const double ratio = m.ours.medianMs / m.theirs.medianMs;
        // The operation is named on the first row of its group, the result on the first row of
        // each resolution and wherever it changes.
        const bool newOp = !prev || prev->op != m.op;
        const bool newResult = newOp || prev->res != m.res || prev->ours.outcome != m.ours.outcome;
        std::string result;
        if (!sameResult(m.op, m.ours.outcome, m.theirs.outcome)) {
            differ = true;
            result = "**differ:** " + fmt(double(m.ours.outcome.activeVoxels), 0) + " / " +
                     fmt(double(m.theirs.outcome.activeVoxels), 0);
        } else if (newResult) {
            result = fmt(double(m.ours.outcome.activeVoxels), 0);
        }
        rows.push_back({newOp ? name : "", std::to_string(m.res), std::to_string(m.threads),
                        fmt(m.ours.medianMs, 2), fmt(m.theirs.medianMs, 2),
                        vdb::bench::ratioCell(ratio, kGoodRatio), fmt(m.floorMs, 2),
                        m.floorMs > 0.0 ? fmt(m.ours.medianMs / m.floorMs, 1) : "n/a", result});
        if (group.empty())
            continue;
        all.add(ratio);
        auto it = std::find_if(groups.begin(), groups.end(),
                               [&](const auto& g) { return g.first == group; });
        if (it == groups.end())
            it = groups.insert(groups.end(), {group, vdb::bench::RatioRange()});
        it->second.add(ratio);
    }

    // Brute force against mask dilation, each library against itself, at the thread count the
    // brute force ran with.
    std::vector<vdb::bench::MarkdownReport::Row> bruteRows;
    for (const Measurement& brute : sorted) {
        if (brute.op != "brute")
            continue;
        for (const Measurement& mask : sorted) {
            if (mask.op == "dilate" && mask.res == brute.res && mask.threads == brute.threads)
                bruteRows.push_back({std::to_string(brute.res), std::to_string(brute.threads),
                                     fmt(brute.ours.medianMs / mask.ours.medianMs, 1),
                                     fmt(brute.theirs.medianMs / mask.theirs.medianMs, 1)});
        }
    }

    const std::string protocol =
        reps > 1 ? "Medians of " + std::to_string(reps) + " runs" : "One run per figure";
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s in milliseconds; ratio = vdb / OpenVDB, in bold where it is at most %.2f. "
                  "The machine has %d hardware threads.",
                  protocol.c_str(), kGoodRatio, cores);
    md.paragraph(line);
    md.table({"operation", "res", "threads", "vdb ms", "OpenVDB ms", "ratio", "floor ms",
              "vdb / floor", "active voxels after"},
             rows);
    md.paragraph(
        "Floor: the time to copy the result's leaf bytes (every leaf's values and value mask) "
        "once with `memcpy` between two buffers already in memory, the memory traffic of "
        "writing the whole result. It bounds the copy forms and the flood fill from below; "
        "dilation, erosion and in-place CSG change masks and some leaves only, so for them it "
        "is a reference, not a bound.");
    if (differ)
        md.paragraph(
            "**The libraries' results differ where marked (active voxels vdb / OpenVDB).**");
    if (std::any_of(ops.begin(), ops.end(), isCopyForm))
        md.paragraph(
            "The copy forms (`csgUnionCopy`, `csgIntersectionCopy`, `csgDifferenceCopy`) leave "
            "both inputs intact and return a new tree; each library's copy form against the "
            "other's. They are compared by their active voxels only: OpenVDB builds its copy "
            "from the leaves and a signed flood fill, which keeps a few uniform leaves that its "
            "in-place forms, and ours in both forms, prune into tiles.");
    if (!bruteRows.empty()) {
        md.paragraph(
            "Brute-force dilation (random insertion) against mask dilation "
            "(`dilateActiveValues`): the time of the one over the time of the other, each "
            "library against itself.");
        md.table({"res", "threads", "vdb brute force / vdb dilation",
                  "OpenVDB brute force / OpenVDB dilation"},
                 bruteRows);
    }

    md.status(all.text() + " over all operations");
    std::string ranges;
    for (const auto& [group, range] : groups)
        ranges += (ranges.empty() ? "" : ", ") + range.status(group);
    if (!ranges.empty())
        md.status(ranges);
    if (differ)
        md.status("results differ");
    return md;
}

}  // namespace

int main(int argc, char** argv) {
    vdb::bench::keepHeapOnFree();
    std::vector<int> resolutions{512, 1024, 2048};
    int reps = 5;
    std::vector<std::string> ops{
        "dilate",       "erode",      "brute",      "floodfill",         "union",
        "intersection", "difference", "union-copy", "intersection-copy", "difference-copy"};
    std::vector<std::string> threads{"1", "all"};
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_tools [--res 512,1024,2048] [--reps 5] "
        "[--ops dilate,erode,brute,floodfill,union,intersection,difference,"
        "union-copy,intersection-copy,difference-copy] [--threads 1,all] [--markdown FILE]");
    options.numbers("--res", resolutions)
        .number("--reps", reps)
        .list("--ops", ops)
        .list("--threads", threads)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));

    openvdb::initialize();
    std::printf("# vdb_bench_tools: medians of %d runs, milliseconds; ratio = vdb / openvdb\n",
                reps);
    std::printf("%-13s %5s %7s %12s %12s %6s  %s\n", "operation", "res", "threads", "vdb",
                "openvdb", "ratio", "results");
    bool allMatch = true;
    std::vector<Measurement> measured;
    for (const int res : resolutions) {
        const auto sphereVoxels = vdb::bench::makeEnrightBand(res);
        const auto torusVoxels = makeTorusBand(res);
        const Inputs<Vdb> ours(sphereVoxels, torusVoxels);
        const Inputs<OpenVdb> theirs(sphereVoxels, torusVoxels);
        for (const std::string& op : ops) {
            for (const std::string& t : threads) {
                // The naive dilation is one serial loop; timing it with more threads says
                // nothing new.
                if (op == "brute" && t != threads.front())
                    continue;
                const int n = options.threadCount(t);
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(n));
                const Timing a = run<Vdb>(op, ours, reps);
                const Timing b = run<OpenVdb>(op, theirs, reps);
                const bool match = sameResult(op, a.outcome, b.outcome);
                allMatch = allMatch && match;
                measured.push_back({op, res, n, a, b, copyFloorMs(a.outcome.leaves, reps)});
                std::printf("%-13s %5d %7d %12.2f %12.2f %6.2f  %s (%llu active, %llu leaves)\n",
                            op.c_str(), res, n, a.medianMs, b.medianMs, a.medianMs / b.medianMs,
                            match ? "same" : "DIFFERENT",
                            (unsigned long long)a.outcome.activeVoxels,
                            (unsigned long long)a.outcome.leaves);
                if (!(a.outcome == b.outcome))
                    std::printf("%-13s %5s %7s %12s %12s %6s  openvdb: %llu active, %llu leaves\n",
                                "", "", "", "", "", "", (unsigned long long)b.outcome.activeVoxels,
                                (unsigned long long)b.outcome.leaves);
                std::fflush(stdout);
            }
        }
    }
    std::printf("# machine: %u hardware threads\n", std::thread::hardware_concurrency());
    if (!markdownPath.empty() && !report(measured, ops, reps, cores).write(markdownPath))
        return 1;
    return allMatch ? 0 : 1;
}
