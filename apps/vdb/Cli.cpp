// SPDX-License-Identifier: Apache-2.0

#include "Cli.h"

#include <vdb/Exceptions.h>

#include <dirent.h>
#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

namespace vdb::app {

void Context::applyThreads() {
    if (threads > 0)
        threadLimit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
}

CLI::App* addCommand(CLI::App& app, Context& ctx, std::string name, std::string description,
                     bool reportsFigures, std::function<void()> run) {
    CLI::App* cmd = app.add_subcommand(std::move(name), std::move(description));
    cmd->add_option("--threads", ctx.threads, "Worker threads (default: every core)")
        ->check(CLI::Range(1, 4096));
    cmd->add_flag("-q,--quiet", ctx.quiet, "No progress display and no report lines");
    if (reportsFigures)
        cmd->add_flag("--json", ctx.json, "Print the figures as one JSON document");
    ctx.commands.push_back({cmd, std::move(run)});
    return cmd;
}

const CLI::Validator& positive() {
    static const CLI::Validator check(
        [](const std::string& text) -> std::string {
            double value = 0;
            if (!CLI::detail::lexical_cast(text, value))
                return "\"" + text + "\" is not a number";
            return value > 0 && std::isfinite(value) ? ""
                                                     : "must be a positive number, not " + text;
        },
        "POSITIVE");
    return check;
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

std::string bytesText(uint64_t bytes) {
    char buf[32];
    if (bytes < 1000)
        std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(bytes));
    else if (bytes < 1000ull * 1000)
        std::snprintf(buf, sizeof buf, "%.1f kB", bytes / 1e3);
    else if (bytes < 1000ull * 1000 * 1000)
        std::snprintf(buf, sizeof buf, "%.2f MB", bytes / 1e6);
    else
        std::snprintf(buf, sizeof buf, "%.2f GB", bytes / 1e9);
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

namespace {

/// The memory this process may use, and what sets that limit: the smallest of the memory
/// available on the machine (MemAvailable, else the physical memory), the address-space and
/// data-segment limits (ulimit -v, -d), and the memory limit of its cgroup (v2 or v1).
std::pair<double, std::string> memoryLimit() {
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

void checkMemoryEstimate(double bytes, const std::string& what) {
    const auto [limit, why] = memoryLimit();
    if (limit > 0 && bytes > limit)
        throw UsageError(what + " would need about " + bytesText(static_cast<uint64_t>(bytes)) +
                         " (" + withCommas(static_cast<uint64_t>(bytes)) +
                         " bytes) of memory; the limit is " +
                         bytesText(static_cast<uint64_t>(limit)) + " (" +
                         withCommas(static_cast<uint64_t>(limit)) + " bytes, " + why + ")");
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

GridPtrVec readGrids(const std::string& path, const Context& ctx) {
    io::File file(path);
    file.open();
    GridPtrVec grids = *file.getGrids();
    if (!ctx.quiet)
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
            names += (names.empty() ? "" : ", ") + ("\"" + grid->getName() + "\"");
        throw UsageError(path + " has no grid named \"" + name + "\"" +
                         (names.empty() ? "" : " (it has " + names + ")"));
    }
    return out;
}

void checkOutputPath(const std::string& path) {
    namespace fs = std::filesystem;
    if (path.empty())
        throw UsageError("the output path is empty");
    const fs::path p(path);
    std::error_code ec;
    if (fs::is_directory(p, ec))
        throw UsageError("output " + path + " is a folder");
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec))
        throw UsageError("cannot write " + path + ": folder " + dir.string() + " does not exist");
    if (::access(dir.c_str(), W_OK) != 0)
        throw UsageError("cannot write " + path + ": folder " + dir.string() + " is not writable");
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

namespace {

// Outputs being written, for the interrupt thread to clean up after.
std::mutex sOutputsMutex;
std::set<std::string> sOutputs;

struct WatchedOutput {
    explicit WatchedOutput(const std::string& path) : mPath(path) {
        std::lock_guard lock(sOutputsMutex);
        sOutputs.insert(mPath);
    }
    ~WatchedOutput() {
        std::lock_guard lock(sOutputsMutex);
        sOutputs.erase(mPath);
    }
    std::string mPath;
};

// Removes "<path>.tmp-*", the temporary files io::File writes before renaming into place.
void removeTemporaries(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    const std::string prefix = p.filename().string() + ".tmp-";
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.compare(0, prefix.size(), prefix) == 0)
            fs::remove(entry.path(), ec);
    }
}

}  // namespace

void writeWatched(const std::string& path, const std::function<void()>& write) {
    WatchedOutput watch(path);
    write();
}

void writeGrids(const std::string& path, const GridPtrVec& grids, uint32_t compression) {
    WatchedOutput watch(path);
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
        {
            std::lock_guard lock(sOutputsMutex);
            for (const auto& path : sOutputs)
                removeTemporaries(path);
        }
        static const char kMessage[] = "\nvdb: cancelled\n";
        [[maybe_unused]] auto n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
        ::_exit(128 + sig);
    }).detach();
}

}  // namespace vdb::app
