// SPDX-License-Identifier: Apache-2.0

#include "Cli.h"

#include <vdb/Exceptions.h>
#include <vdb/io/Format.h>
#include <vdb/util/OutputFile.h>

#include <dirent.h>
#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace vdb::app {

namespace {

// The limits of this run (one command per process), set by Context::apply().
constexpr double kDefaultMaxMemory = 2e9;
constexpr uint64_t kDefaultMaxSteps = 100'000;
double sMaxMemory = kDefaultMaxMemory;
uint64_t sMaxSteps = kDefaultMaxSteps;

/// Parses "2G", "512MB", "1.5GiB", "3000000000": a positive size in bytes (K, M, G, T are
/// powers of 1000, Ki, Mi, Gi, Ti of 1024; a trailing B is optional).
double parseByteSize(const std::string& text, const std::string& source) {
    size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    std::string unit = text.substr(used);
    if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b'))
        unit.pop_back();
    const std::pair<const char*, double> units[] = {{"", 1},
                                                    {"K", 1e3},
                                                    {"k", 1e3},
                                                    {"M", 1e6},
                                                    {"G", 1e9},
                                                    {"T", 1e12},
                                                    {"Ki", 1024.0},
                                                    {"Mi", 1048576.0},
                                                    {"Gi", 1073741824.0},
                                                    {"Ti", 1099511627776.0}};
    for (const auto& [name, factor] : units) {
        if (used > 0 && unit == name && std::isfinite(value) && value > 0)
            return value * factor;
    }
    throw UsageError(source + " must be a positive size such as 4G, 512M or 3000000000, not \"" +
                     text + "\"");
}

}  // namespace

void Context::apply() {
    if (threads > 0)
        threadLimit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    if (!maxMemory.empty()) {
        sMaxMemory = parseByteSize(maxMemory, "--max-memory");
    } else if (const char* env = std::getenv("VDB_MAX_MEMORY"); env && *env) {
        sMaxMemory = parseByteSize(env, "VDB_MAX_MEMORY");
    }
    if (maxSteps > 0)
        sMaxSteps = maxSteps;
}

namespace {

/// The memory this process can get from the system, and what sets that limit: the smallest of
/// the memory available on the machine (MemAvailable, else the physical memory), the
/// address-space and data-segment limits (ulimit -v, -d), and the memory limit of its cgroup
/// (v2 or v1).
std::pair<double, std::string> systemMemoryLimit() {
    double limit = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                   static_cast<double>(::sysconf(_SC_PAGESIZE));
    std::string why = "the physical memory of this machine";
    const auto lower = [&](double bytes, const char* reason) {
        if (bytes > 0 && (limit <= 0 || bytes < limit)) {
            limit = bytes;
            why = reason;
        }
    };
    const auto readNumber = [](const std::string& path, const char* key) {
        std::FILE* f = std::fopen(path.c_str(), "r");
        if (!f)
            return -1.0;
        char line[256];
        double value = -1.0;
        while (std::fgets(line, sizeof line, f)) {
            const size_t n = std::strlen(key);
            if (std::strncmp(line, key, n) == 0) {
                char* end = nullptr;
                const double v = std::strtod(line + n, &end);
                if (end != line + n)
                    value = v;
                break;
            }
        }
        std::fclose(f);
        return value;
    };
    lower(readNumber("/proc/meminfo", "MemAvailable:") * 1024.0,
          "the memory available on this machine now");
    for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit rl{};
        if (::getrlimit(resource, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
            lower(static_cast<double>(rl.rlim_cur), resource == RLIMIT_AS
                                                        ? "the address-space limit (ulimit -v)"
                                                        : "the data-segment limit (ulimit -d)");
    }
    // This process's cgroup: "0::/path" (v2) or "N:memory:/path" (v1).
    std::FILE* f = std::fopen("/proc/self/cgroup", "r");
    if (f) {
        char line[512];
        while (std::fgets(line, sizeof line, f)) {
            std::string entry(line);
            if (!entry.empty() && entry.back() == '\n')
                entry.pop_back();
            const size_t colon = entry.find(':'), colon2 = entry.find(':', colon + 1);
            if (colon == std::string::npos || colon2 == std::string::npos)
                continue;
            const std::string controllers = entry.substr(colon + 1, colon2 - colon - 1);
            const std::string path = entry.substr(colon2 + 1);
            if (controllers.empty())
                lower(readNumber("/sys/fs/cgroup" + path + "/memory.max", ""),
                      "the memory limit of this process's cgroup");
            else if (controllers == "memory")
                lower(readNumber("/sys/fs/cgroup/memory" + path + "/memory.limit_in_bytes", ""),
                      "the memory limit of this process's cgroup");
        }
        std::fclose(f);
    }
    return {limit, why};
}

}  // namespace

double memoryLimit() {
    const double system = systemMemoryLimit().first;
    return system > 0 ? std::min(sMaxMemory, system) : sMaxMemory;
}

void checkMemoryEstimate(double bytes, const std::string& what) {
    const auto [system, why] = systemMemoryLimit();
    const bool bySystem = system > 0 && system <= sMaxMemory;
    const double limit = bySystem ? system : sMaxMemory;
    if (bytes <= limit)
        return;
    // "5.37 GB (5,368,709,120 bytes[, note])"
    const auto amount = [](double b, const std::string& note) {
        std::vector<std::string> parts;
        if (b < 1e18)
            parts.push_back(withCommas(uint64_t(b)) + " bytes");
        if (!note.empty())
            parts.push_back(note);
        std::string text = bytesText(b);
        for (size_t i = 0; i < parts.size(); ++i)
            text += (i == 0 ? " (" : ", ") + parts[i];
        return parts.empty() ? text : text + ")";
    };
    throw UsageError(
        what + " would need about " + amount(bytes, "") + " of memory, over the limit of " +
        amount(limit, bySystem ? why : "raise it with --max-memory SIZE or VDB_MAX_MEMORY"));
}

double levelSetBytes(double areaVoxels, double halfWidth) {
    // The band's leaves form a shell about 2 halfWidth + 7 voxels thick (leaves straddle it),
    // 512 voxels each; at least one leaf.
    const double leaves = std::max(1.0, areaVoxels * (2.0 * halfWidth + 7.0) / 512.0);
    return leaves * double(sizeof(FloatTree::LeafNodeType) + 512 * sizeof(float));
}

void checkStepEstimate(double steps, const std::string& what) {
    if (steps <= double(sMaxSteps))
        return;
    char estimate[32];
    std::snprintf(estimate, sizeof estimate, steps < 1e15 ? "%.0f" : "%.2g", steps);
    throw UsageError(what + " would take about " +
                     (steps < 1e15 ? withCommas(uint64_t(steps)) : std::string(estimate)) +
                     " steps, over the limit of " + withCommas(sMaxSteps) +
                     " (raise it with --max-steps N)");
}

void checkIndexRange(double lo, double hi, const std::string& what) {
    constexpr double kMax = 2147483647.0;
    if (lo >= -kMax && hi <= kMax)
        return;
    char range[96];
    std::snprintf(range, sizeof range, "%.4g to %.4g", lo, hi);
    throw UsageError(what + " spans index coordinates " + range +
                     " voxels, beyond the index space of -2^31 to 2^31 - 1 voxels (use a "
                     "larger voxel size, or move the data towards the origin)");
}

void addStepLimitOption(CLI::App& cmd, Context& ctx) {
    cmd.add_option("--max-steps", ctx.maxSteps,
                   "Refuse work estimated to take more steps than this (default 100,000)")
        ->check(CLI::Range(uint64_t(1), uint64_t(1) << 40));
}

CLI::App* addCommand(CLI::App& app, Context& ctx, std::string name, std::string description,
                     bool reportsFigures, std::function<void()> run) {
    CLI::App* cmd = app.add_subcommand(std::move(name), std::move(description));
    cmd->add_option("--threads", ctx.threads, "Worker threads (default: every core)")
        ->check(CLI::Range(1, 4096));
    cmd->add_flag("-q,--quiet", ctx.quiet, "No progress display and no report lines");
    cmd->add_option("--max-memory", ctx.maxMemory,
                    "Refuse work estimated to need more memory than this, e.g. 8G (default: "
                    "VDB_MAX_MEMORY, else 2G)");
    if (reportsFigures)
        cmd->add_flag("--json", ctx.json, "Print the figures as one JSON document");
    ctx.commands.push_back({cmd, std::move(run)});
    return cmd;
}

namespace {

/// The number in `text`, or an error message in `error`.
bool parseNumber(const std::string& text, double& value, std::string& error) {
    if (!CLI::detail::lexical_cast(text, value)) {
        error = "\"" + text + "\" is not a number";
        return false;
    }
    if (!std::isfinite(value)) {
        error = "must be a finite number, not " + text;
        return false;
    }
    return true;
}

}  // namespace

const CLI::Validator& positive() {
    static const CLI::Validator check(
        [](const std::string& text) -> std::string {
            double value = 0;
            std::string error;
            if (!parseNumber(text, value, error))
                return error;
            return value > 0 ? "" : "must be a positive number, not " + text;
        },
        "POSITIVE");
    return check;
}

const CLI::Validator& finite() {
    static const CLI::Validator check(
        [](const std::string& text) -> std::string {
            double value = 0;
            std::string error;
            return parseNumber(text, value, error) ? "" : error;
        },
        "FINITE");
    return check;
}

CLI::Validator finiteRange(double lo, double hi) {
    char range[64];
    std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
    return CLI::Validator(
        [lo, hi, bounds = std::string(range)](const std::string& text) -> std::string {
            double value = 0;
            std::string error;
            if (parseNumber(text, value, error) && value >= lo && value <= hi)
                return "";
            return "must be a finite number within " + bounds + ", not " + text;
        },
        std::string("NUMBER in ") + range);
}

double floatSpacing(double x) {
    const float f = float(std::abs(x));
    return double(std::nextafter(f, std::numeric_limits<float>::infinity())) - double(f);
}

void checkFloatPrecision(const BBoxd& worldBox, double voxelSize, const std::string& what) {
    double reach = 0.0;
    for (int a = 0; a < 3; ++a)
        reach = std::max({reach, std::abs(worldBox.min()[a]), std::abs(worldBox.max()[a])});
    const double spacing = floatSpacing(reach);
    if (spacing <= kFloatSpacingFraction * voxelSize)
        return;
    throw UsageError(what + " reaches " + numberText(reach) +
                     " world units from the origin, where float coordinates are " +
                     numberText(spacing) + " apart: more than 1/8 of the voxel size " +
                     numberText(voxelSize) +
                     " (use a larger voxel size, or move the data towards the origin)");
}

void requireNonEmpty(const GridBase& grid, const std::string& what, const std::string& hint) {
    if (grid.activeVoxelCount() > 0)
        return;
    throw UsageError(what + " would have no active values" +
                     (hint.empty() ? "" : " (" + hint + ")") + ": an empty result is not written");
}

void reportGrid(Report& report, const GridBase& grid, std::optional<Index64> before) {
    const Index64 active = grid.activeVoxelCount();
    const Index64 leaves = grid.leafCount();
    const double memory = double(grid.memUsage());
    report.note("  grid \"" + grid.getName() + "\" (" + grid.valueType() +
                "): " + (before ? withCommas(*before) + " -> " : std::string()) +
                withCommas(active) + " active voxels in " + withCommas(leaves) + " leaves, " +
                bytesText(memory) + " in memory");
    JsonWriter& json = report.json();
    json.key("name").value(grid.getName()).key("valueType").value(grid.valueType());
    if (before)
        json.key("activeVoxelsBefore").value(static_cast<uint64_t>(*before));
    json.key("activeVoxels")
        .value(static_cast<uint64_t>(active))
        .key("leaves")
        .value(static_cast<uint64_t>(leaves))
        .key("memoryBytes")
        .value(static_cast<uint64_t>(memory));
}

// ---- Frame sequences

FrameNumber madeFrame(uint64_t number) {
    char digits[32];
    std::snprintf(digits, sizeof digits, "%04llu", static_cast<unsigned long long>(number));
    return {number, digits};
}

std::optional<std::pair<size_t, size_t>> frameHashRun(const std::string& path,
                                                      const std::string& what) {
    const std::string name = std::filesystem::path(path).filename().string();
    const size_t first = name.find('#');
    if (first == std::string::npos)
        return std::nullopt;
    const size_t end = name.find_first_not_of('#', first);
    const size_t length = (end == std::string::npos ? name.size() : end) - first;
    if (name.find('#', first + length) != std::string::npos)
        throw UsageError(what + ": only one run of # may stand for the frame number");
    return std::make_pair(first, length);
}

std::string framePath(const std::string& pattern, const FrameNumber& frame,
                      const std::string& option) {
    const std::filesystem::path folder = std::filesystem::path(pattern).parent_path();
    const std::string name = std::filesystem::path(pattern).filename().string();
    const auto run = frameHashRun(pattern, option + " " + pattern);
    if (!run)
        throw UsageError(option + " " + pattern +
                         ": a frame sequence needs # in the output file name for the frame "
                         "number");
    std::string digits = frame.digits;
    if (run->second > 1) {
        digits = std::to_string(frame.number);
        if (digits.size() < run->second)
            digits.insert(0, run->second - digits.size(), '0');
    }
    const std::string out =
        name.substr(0, run->first) + digits + name.substr(run->first + run->second);
    return folder.empty() ? out : (folder / out).string();
}

void appendQuoted(std::string& list, const std::string& name, const std::string& detail) {
    if (!list.empty())
        list += ", ";
    list += '"';
    list += name;
    list += '"';
    if (!detail.empty()) {
        list += " (";
        list += detail;
        list += ')';
    }
}

std::string numberText(double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", value);
    return buf;
}

std::string withCommas(uint64_t n) {
    std::string digits = std::to_string(n);
    std::string out;
    const size_t lead = digits.size() % 3;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i != 0 && (i + 3 - lead) % 3 == 0)
            out += ',';
        out += digits[i];
    }
    return out;
}

std::string bytesText(double bytes) {
    char buf[48];
    if (std::isnan(bytes) || std::isinf(bytes))
        return "infinitely many bytes";
    if (bytes < 1000)
        std::snprintf(buf, sizeof buf, "%.0f B", bytes);
    else if (bytes < 1e6)
        std::snprintf(buf, sizeof buf, "%.1f kB", bytes / 1e3);
    else if (bytes < 1e9)
        std::snprintf(buf, sizeof buf, "%.2f MB", bytes / 1e6);
    else if (bytes < 1e12)
        std::snprintf(buf, sizeof buf, "%.2f GB", bytes / 1e9);
    else if (bytes < 1e15)
        std::snprintf(buf, sizeof buf, "%.2f TB", bytes / 1e12);
    else
        std::snprintf(buf, sizeof buf, "%.2g B", bytes);
    return buf;
}

std::string secondsText(double seconds) {
    char buf[32];
    if (seconds < 60)
        std::snprintf(buf, sizeof buf, "%.2f s", seconds);
    else
        std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(seconds / 60),
                      static_cast<int>(std::fmod(seconds, 60.0)));
    return buf;
}

void requireMatchingTransforms(const GridBase& a, const std::string& pathA, const GridBase& b,
                               const std::string& pathB, const std::string& operation) {
    try {
        checkMatchingTransforms(a, b, operation);
    } catch (const ValueError& e) {
        throw UsageError(std::string(e.what()) + " (grid \"" + a.getName() + "\" of " + pathA +
                         ", grid \"" + b.getName() + "\" of " + pathB + ")");
    }
}

// ---- Report

Report::Report(const Context& ctx) : mCtx(ctx) {
    mJson.beginObject();
}

void Report::note(const std::string& text) const {
    if (mCtx.verbose())
        std::printf("%s\n", text.c_str());
}

void Report::recordStep(const std::string& label, double seconds) {
    mSteps.emplace_back(label, seconds);
    if (mCtx.verbose())
        std::printf("%-40s %10s\n", label.c_str(), secondsText(seconds).c_str());
    std::fflush(stdout);
}

void Report::finish() {
    if (!mCtx.json)
        return;
    mJson.key("steps").beginArray();
    for (const auto& [label, seconds] : mSteps)
        mJson.beginObject().key("step").value(label).key("seconds").value(seconds).endObject();
    mJson.endArray().endObject();
    std::fputs(mJson.str().c_str(), stdout);
}

// ---- Files

void warnAboutFileVersion(const io::File& file, const Context& ctx) {
    if (file.fileVersion() > io::NEWEST_FILE_VERSION && !ctx.quiet)
        std::fprintf(stderr,
                     "vdb: warning: %s has file format version %u, newer than the newest this "
                     "library knows (%u); it is read as version %u and may be misread\n",
                     file.filename().c_str(), file.fileVersion(), io::NEWEST_FILE_VERSION,
                     io::NEWEST_FILE_VERSION);
}

GridPtrVec readGrids(const std::string& path, const Context& ctx,
                     std::vector<io::UnsupportedGrid>* unsupported) {
    io::File file(path);
    file.open();
    warnAboutFileVersion(file, ctx);
    GridPtrVec grids = *file.getGrids();
    if (unsupported)
        *unsupported = file.unsupportedGrids();
    else if (!ctx.quiet)
        for (const auto& skipped : file.unsupportedGrids())
            std::fprintf(stderr, "vdb: warning: %s: skipping grid \"%s\" of unsupported type %s\n",
                         path.c_str(), skipped.name.c_str(), skipped.type.c_str());
    return grids;
}

GridPtrVec selectGrids(const GridPtrVec& grids, const std::string& name, const std::string& path) {
    GridPtrVec out;
    for (const auto& grid : grids)
        if (name.empty() || grid->getName() == name)
            out.push_back(grid);
    if (out.empty()) {
        if (name.empty())
            throw UsageError(path + " holds no grid this library can read");
        std::string names;
        for (const auto& grid : grids)
            appendQuoted(names, grid->getName());
        throw UsageError(path + " has no grid named \"" + name + "\"" +
                         (names.empty() ? "" : " (it has " + names + ")"));
    }
    return out;
}

void checkOutputPath(const std::string& path) {
    try {
        util::checkOutputFile(path);
    } catch (const IoError& e) {
        throw UsageError(e.what());
    }
}

uint32_t parseCompression(const std::string& name) {
    if (name == "raw")
        return io::COMPRESS_NONE;
    if (name == "none")
        return io::COMPRESS_ACTIVE_MASK;
    if (name == "zip")
        return io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK;
    if (name == "blosc")
        return io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK;
    throw UsageError("unknown compression \"" + name + "\" (use none, zip, blosc or raw)");
}

void writeGrids(const std::string& path, const GridPtrVec& grids, uint32_t compression) {
    io::File file(path);
    file.setCompression(compression);
    file.write(grids);
}

void addOutputOptions(CLI::App& cmd, OutputArgs& out) {
    cmd.add_option("-o,--output", out.path, "The .vdb file to write (replaced atomically)")
        ->required();
    cmd.add_option("--compression", out.compression,
                   "none, zip or blosc (each with active-mask compression), or raw")
        ->check(CLI::IsMember({"none", "zip", "blosc", "raw"}))
        ->capture_default_str();
    cmd.add_flag("--half", out.half, "Store float values as 16-bit halves");
}

void writeOutput(Report& report, const OutputArgs& out, const GridPtrVec& grids) {
    if (out.half)
        for (const auto& grid : grids)
            grid->setSaveFloatAsHalf(true);
    report.step("write " + out.path,
                [&] { writeGrids(out.path, grids, parseCompression(out.compression)); });
    std::error_code ec;
    const auto size = std::filesystem::file_size(out.path, ec);
    report.json()
        .key("output")
        .value(out.path)
        .key("outputBytes")
        .value(static_cast<uint64_t>(ec ? 0 : size));
}

void installInterruptHandler() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    std::thread([set] {
        int sig = 0;
        sigwait(&set, &sig);
        util::removeOutputTemporaries();
        static const char kMessage[] = "\nvdb: cancelled\n";
        [[maybe_unused]] auto n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
        ::_exit(128 + sig);
    }).detach();
}

}  // namespace vdb::app
