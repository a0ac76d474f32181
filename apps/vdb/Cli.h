// SPDX-License-Identifier: Apache-2.0
/// @file
/// What every subcommand of the `vdb` tool shares: the common options, reading and writing
/// `.vdb` files with clear errors, dispatch on the grid's value type, and Ctrl-C handling.

#pragma once

#include <vdb/GridTypes.h>
#include <vdb/io/File.h>
#include <vdb/math/BBox.h>

#include "Json.h"
#include "Progress.h"
#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::app {

/// A request that makes no sense (a bad option value, a grid of the wrong kind, a missing
/// input): reported as one line, exit status 2.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The options every subcommand takes and the state they set up, plus the subcommands
/// registered so far.
struct Context {
    int threads = 0;     ///< 0: every core
    bool quiet = false;  ///< no progress and no report lines
    bool json = false;   ///< figures as one JSON document on stdout

    struct Command {
        CLI::App* app;
        std::function<void()> run;
    };
    std::vector<Command> commands;
    std::unique_ptr<tbb::global_control> threadLimit;
    std::string maxMemory;  ///< --max-memory as given (empty: VDB_MAX_MEMORY, else 2 GB)
    uint64_t maxSteps = 0;  ///< --max-steps (0: the default of 100,000)

    /// Applies --threads and the limits of --max-memory and --max-steps; called once, before
    /// the chosen subcommand runs. Throws UsageError for a malformed size.
    void apply();
    /// Whether report lines go to stdout (neither --quiet nor --json).
    bool verbose() const { return !quiet && !json; }
};

/// Adds a subcommand with --threads and --quiet (and --json when it reports figures) and
/// registers `run` to be called when it is chosen.
CLI::App* addCommand(CLI::App& app, Context& ctx, std::string name, std::string description,
                     bool reportsFigures, std::function<void()> run);

/// A CLI11 check that a number is finite and above zero ("must be positive").
const CLI::Validator& positive();
/// A CLI11 check that a number (each number, for a list) is finite: not NaN, not infinite.
const CLI::Validator& finite();
/// A CLI11 check that a number is finite and within [lo, hi], naming the value and the range.
CLI::Validator finiteRange(double lo, double hi);

/// Adds --max-steps to a command whose work is a number of steps taken from its arguments.
void addStepLimitOption(CLI::App& cmd, Context& ctx);

/// The memory an operation may use: --max-memory (default 2 GB, or VDB_MAX_MEMORY), or less
/// where the system gives less (the memory available now, ulimit -v and -d, the cgroup's
/// limit).
double memoryLimit();
/// Throws UsageError when an operation estimated to need `bytes` of memory (any finite or
/// infinite estimate) is over memoryLimit(), naming `what`, the estimate with its unit and in
/// bytes, the limit, and how to raise it or what sets it.
void checkMemoryEstimate(double bytes, const std::string& what);
/// The memory of a float narrow-band level set whose surface has `areaVoxels` square voxels,
/// `halfWidth` voxels on each side: the leaves that cover the band, at about 2.2 kB each.
double levelSetBytes(double areaVoxels, double halfWidth);
/// Throws UsageError when an operation estimated to take `steps` steps is over the step
/// limit (--max-steps, default 100,000), naming `what` and the estimate.
void checkStepEstimate(double steps, const std::string& what);
/// Throws UsageError unless the index-space coordinate range [lo, hi] (in voxels) lies within
/// the 32-bit index space, naming `what` and the world-space values behind it.
void checkIndexRange(double lo, double hi, const std::string& what);

/// The largest spacing of float coordinates allowed where a command computes world positions
/// in single precision, as a fraction of the voxel size: 1/8, so that rounding moves a position
/// by at most 1/16 of a voxel (see docs/LIMITS.md).
inline constexpr double kFloatSpacingFraction = 1.0 / 8.0;
/// The spacing of float numbers at magnitude `x` (the distance to the next float up).
double floatSpacing(double x);
/// Throws UsageError when the world-space box `worldBox` (of `what`) reaches where float
/// coordinates are spaced more than kFloatSpacingFraction of `voxelSize` apart: a command that
/// holds positions there as floats would move them by a visible part of a voxel.
void checkFloatPrecision(const BBoxd& worldBox, double voxelSize, const std::string& what);
/// Throws UsageError when `grid` (the result of `what`) has no active value: no command writes
/// an empty result. `hint`, when given, says why it may be empty.
void requireNonEmpty(const GridBase& grid, const std::string& what, const std::string& hint = {});

/// Appends `name` in quotes to the comma-separated list `list`, with `detail` in parentheses
/// when given: `"density", "vel" (vec3s)`.
void appendQuoted(std::string& list, const std::string& name, const std::string& detail = {});

/// Formats a number with up to 6 significant digits ("0.0125", "1e-300", "2.5e+07").
std::string numberText(double value);
/// Formats a count with thousands separators ("794,720").
std::string withCommas(uint64_t n);
/// Formats a byte count ("3.28 MB"; decimal units, as file managers show them; "1.2e+20 B" for
/// counts beyond petabytes, "infinitely many bytes" for an infinite estimate).
std::string bytesText(double bytes);
/// Formats seconds ("0.12 s", "2 min 03 s").
std::string secondsText(double seconds);

/// What a command did: its timed steps (shown with a progress line while they run, then one
/// report line each) and, with --json, one JSON document of the steps and the command's own
/// figures, printed by finish().
class Report {
public:
    explicit Report(const Context& ctx);

    /// Runs `f()` (or `f(progress)` when it takes a Progress&) as the step `label`, and
    /// returns what it returns.
    template <typename F>
    decltype(auto) step(const std::string& label, F&& f, uint64_t total = 0) {
        Progress progress(progressWanted(mCtx.quiet), label, total);
        struct Record {
            Report& report;
            Progress& progress;
            const std::string& label;
            ~Record() {
                const double seconds = progress.finish();
                if (std::uncaught_exceptions() == 0)
                    report.recordStep(label, seconds);
            }
        } record{*this, progress, label};
        if constexpr (std::is_invocable_v<F, Progress&>)
            return f(progress);
        else
            return f();
    }

    /// A report line (printed unless --quiet or --json).
    void note(const std::string& text) const;
    /// The JSON document's top-level object, for the command's own keys.
    JsonWriter& json() { return mJson; }
    /// Prints the JSON document (with --json); call once, at the end.
    void finish();

private:
    void recordStep(const std::string& label, double seconds);

    const Context& mCtx;
    JsonWriter mJson;
    std::vector<std::pair<std::string, double>> mSteps;
};

/// The summary of a grid, the one every command reports: the line
/// `  grid "NAME" (TYPE): [BEFORE -> ]N active voxels in L leaves, M in memory` and the keys
/// name, valueType, [activeVoxelsBefore,] activeVoxels, leaves and memoryBytes in the JSON
/// object open in `report.json()`.
void reportGrid(Report& report, const GridBase& grid, std::optional<Index64> before = {});

/// Throws UsageError unless grids `a` (of file `pathA`) and `b` line up: transforms equal to a
/// relative 1e-6 (Transform::isApproxEqual), so a voxel size rounded through float on one side
/// still matches. The message names both transforms and what `operation` needs.
void requireMatchingTransforms(const GridBase& a, const std::string& pathA, const GridBase& b,
                               const std::string& pathB, const std::string& operation);

// ---- Files

/// Warns on stderr (unless quiet) when `file` (opened) has a format version newer than this
/// library knows: it is read as the newest known version, which may be wrong.
void warnAboutFileVersion(const io::File& file, const Context& ctx);

/// Reads every grid of the `.vdb` file `path`. Grids this library cannot read are skipped;
/// with `unsupported` they are listed there, else named in a warning unless quiet.
GridPtrVec readGrids(const std::string& path, const Context& ctx,
                     std::vector<io::UnsupportedGrid>* unsupported = nullptr);

/// The grids of `grids` named `name`, or all of them when `name` is empty. Throws UsageError
/// naming the file when nothing matches.
GridPtrVec selectGrids(const GridPtrVec& grids, const std::string& name, const std::string& path);

/// Checks, before any work starts, that `path` could be written (util::checkOutputFile):
/// throws UsageError with the reason otherwise. Creates nothing.
void checkOutputPath(const std::string& path);

/// Parses a --compression value ("none", "zip", "blosc", each with active-mask compression, or
/// "raw" for none at all) into COMPRESS_* flags.
uint32_t parseCompression(const std::string& name);

/// Writes `grids` to `path` (io::File, through util::OutputFile).
void writeGrids(const std::string& path, const GridPtrVec& grids, uint32_t compression);

/// The output options of commands that write a `.vdb` file.
struct OutputArgs {
    std::string path;
    std::string compression = "blosc";
    bool half = false;
};

/// Adds -o/--output (required), --compression and --half to `cmd`.
void addOutputOptions(CLI::App& cmd, OutputArgs& out);

/// Writes `grids` as `out` says (floats as halves with --half), as a timed report step.
void writeOutput(Report& report, const OutputArgs& out, const GridPtrVec& grids);

// ---- Read, edit, write

/// The input file and grid selection of a read-edit-write command.
struct EditArgs {
    std::string input;
    std::string grid;
    OutputArgs out;
};

/// Adds the input file, -g/--grid and the output options to `cmd`.
inline void addEditOptions(CLI::App& cmd, EditArgs& args) {
    cmd.add_option("input", args.input, "The .vdb file to read")->required();
    cmd.add_option("-g,--grid", args.grid, "Only this grid (default: every grid it applies to)");
    addOutputOptions(cmd, args.out);
}

/// Reads the input, calls `edit(report, grid)` on the selected grids (it returns whether it
/// applied to the grid), writes every grid. When no grid was edited, throws UsageError with
/// `noneEdited` (if given) before anything is written; so it does when an edit leaves a grid
/// that had active values with none (requireNonEmpty).
template <typename EditF>
void runEdit(const Context& ctx, const EditArgs& args, EditF&& edit,
             const std::string& noneEdited = {}) {
    checkOutputPath(args.out.path);
    Report report(ctx);
    const GridPtrVec grids =
        report.step("read " + args.input, [&] { return readGrids(args.input, ctx); });
    report.json().key("input").value(args.input).key("grids").beginArray();
    size_t edited = 0;
    for (const auto& grid : selectGrids(grids, args.grid, args.input)) {
        const Index64 before = grid->activeVoxelCount();
        if (!edit(report, grid))
            continue;
        ++edited;
        if (before > 0)
            requireNonEmpty(*grid, "grid \"" + grid->getName() + "\" of " + args.input);
        report.json().beginObject();
        reportGrid(report, *grid, before);
        report.json().endObject();
    }
    report.json().endArray();
    if (edited == 0 && !noneEdited.empty())
        throw UsageError(noneEdited);
    writeOutput(report, args.out, grids);
    report.finish();
}

/// Makes one grid and writes it: checks that the output can be written, calls `make(report)`
/// (a grid pointer; it may add its own keys to `report.json()`), names the grid `name` (unless
/// empty), refuses an empty result (requireNonEmpty, with `emptyHint`), reports the grid
/// (reportGrid) and writes it.
template <typename MakeF>
void runCreate(const Context& ctx, const OutputArgs& out, const std::string& name, MakeF&& make,
               const std::string& emptyHint = {}) {
    checkOutputPath(out.path);
    Report report(ctx);
    const GridBase::Ptr grid = make(report);
    if (!name.empty())
        grid->setName(name);
    requireNonEmpty(*grid, "grid \"" + grid->getName() + "\"", emptyHint);
    reportGrid(report, *grid);
    writeOutput(report, out, {grid});
    report.finish();
}

// ---- Frame sequences

/// A frame of a sequence: its number and the digits that write it in a file name.
struct FrameNumber {
    uint64_t number = 0;
    std::string digits;
};

/// The frame `number` of a sequence the tool makes itself (advect, enright): written with 4
/// digits at least ("0007").
FrameNumber madeFrame(uint64_t number);

/// The run of '#' in the file name (not the folders) of `path`: its offset in the file name and
/// its length, or nothing when there is none. Throws UsageError naming `what` for two runs.
std::optional<std::pair<size_t, size_t>> frameHashRun(const std::string& path,
                                                      const std::string& what);

/// The tool's one frame-number rule for the files it writes: `pattern` with the run of '#' in
/// its file name replaced by the frame's number, as `frame.digits` writes it for a single '#',
/// zero-padded to n digits for a run of n. Throws UsageError naming `option` when the file name
/// has no '#'.
std::string framePath(const std::string& pattern, const FrameNumber& frame,
                      const std::string& option);

// ---- Ctrl-C

/// Blocks SIGINT and SIGTERM in every thread and starts a thread that, on either signal,
/// removes the temporary files of outputs being written (util::removeOutputTemporaries) and
/// exits with status 128 + the signal. Call first thing in main, before any other thread
/// starts.
void installInterruptHandler();

// ---- Dispatch on value types

/// Calls `f(typedGrid)` when `grid` is one of `GridListT` (a TypeList of GridTypes.h); throws
/// UsageError with `message(grid)` otherwise.
template <typename GridListT, typename F, typename MessageF>
void withGridOf(const GridBase::Ptr& grid, F&& f, MessageF&& message) {
    if (!tryDispatchGrid<GridListT>(*grid, f))
        throw UsageError(message(*grid));
}

/// The start of the type errors below: `grid "NAME" has type TYPE`.
inline std::string gridHasType(const GridBase& grid) {
    return "grid \"" + grid.getName() + "\" has type " + grid.type();
}

/// Calls `f(typedGrid)` when `grid` is a FloatGrid or DoubleGrid (the grid types level set
/// tools take); throws UsageError naming the grid and its type otherwise.
template <typename F>
void withLevelSetGrid(const GridBase::Ptr& grid, F&& f) {
    withGridOf<RealGridTypes>(grid, f, [](const GridBase& g) {
        return gridHasType(g) + "; this command needs a float or double grid";
    });
}

/// Calls `f(typedGrid)` when `grid` is a FloatGrid, DoubleGrid, Vec3SGrid or Vec3DGrid (the
/// grid types of the value filters and of field extension); throws UsageError naming the grid,
/// its type and `takes` ("filters take") otherwise.
template <typename F>
void withRealGrid(const GridBase::Ptr& grid, const std::string& takes, F&& f) {
    withGridOf<FloatingPointGridTypes>(grid, f, [&](const GridBase& g) {
        return gridHasType(g) + "; " + takes + " float, double, vec3s and vec3d grids";
    });
}

/// Calls `f(typedGrid)` for any grid type the library holds; throws UsageError otherwise.
template <typename F>
void withAnyGrid(const GridBase::Ptr& grid, F&& f) {
    withGridOf<GridTypes>(grid, f, [](const GridBase& g) {
        return gridHasType(g) + ", which this command does not handle";
    });
}

}  // namespace vdb::app
