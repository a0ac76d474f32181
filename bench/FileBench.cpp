// SPDX-License-Identifier: Apache-2.0
// The file benchmarks of the paper's Tables IV, V and VI (Museth 2013, section 5.4 and
// appendix A): this library against OpenVDB 10 on the same level set, in one process.
//
// Input: the Enright sphere narrow band (half width 5 voxels, values in voxel units), inserted
// voxel by voxel in the same order into both libraries and sign-flood-filled by each. The grid
// class is left unknown so that every codec applies (both libraries drop ZIP for level sets).
//
// For each compression setting (Table V):
//   mask    COMPRESS_ACTIVE_MASK (inactive values coded per node)
//   zip     ACTIVE_MASK + ZIP (Deflate)
//   blosc   ACTIVE_MASK + BLOSC
//   half    ACTIVE_MASK with values saved as 16-bit floats
// it reports the file size, the write time, and the read time (Table VI) eager (open(false)
// then readGrid) and delayed (open(true), the default, then readGrid: topology only), and the
// memUsage() of the grid read each way (Table IV). Files go to --dir (default the system's
// temporary folder), so the operating system's page cache holds them: the times are those of
// the codecs and the parser, not of a disk. Every read grid is checked to have the input's
// active voxel count; medians of --reps runs; ratio = vdb / openvdb.
//
// The floors of the writes: the bytes of this library's file written by plain write() calls,
// once over the old file with no sync (as OpenVDB writes) and once durably (a new file in the
// same folder, fsync, rename over the old file, fsync of the folder: as this library writes).
//
// With --markdown FILE the program also writes its results as Markdown tables to FILE and one
// overview line to FILE.status, for docs/BENCHMARKS.md (scripts/bench).
//
// Usage: vdb_bench_io [--res 512,1024,2048] [--reps 5] [--settings mask,zip,blosc,half]
//                     [--dir /tmp] [--markdown FILE]

#include <vdb/tools/SignedFloodFill.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <fcntl.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using vdb::bench::BandVoxel;

constexpr float kBackground = 5.0f;  // the band's half width, in voxel units

struct Setting {
    std::string name;
    uint32_t flags;  // the same bits in both libraries
    bool half;
};

Setting settingNamed(const std::string& name) {
    const uint32_t mask = vdb::io::COMPRESS_ACTIVE_MASK;
    if (name == "mask")
        return {name, mask, false};
    if (name == "zip")
        return {name, mask | vdb::io::COMPRESS_ZIP, false};
    if (name == "blosc")
        return {name, mask | vdb::io::COMPRESS_BLOSC, false};
    if (name == "half")
        return {name, mask, true};
    std::fprintf(stderr, "unknown setting '%s'\n", name.c_str());
    std::exit(2);
}

static_assert(uint32_t(vdb::io::COMPRESS_ZIP) == uint32_t(openvdb::io::COMPRESS_ZIP) &&
              uint32_t(vdb::io::COMPRESS_ACTIVE_MASK) ==
                  uint32_t(openvdb::io::COMPRESS_ACTIVE_MASK) &&
              uint32_t(vdb::io::COMPRESS_BLOSC) == uint32_t(openvdb::io::COMPRESS_BLOSC));

/// What one library measured for one setting.
struct Result {
    uint64_t fileBytes = 0;
    double writeMs = 0, eagerMs = 0, delayedMs = 0;
    uint64_t eagerMem = 0, delayedMem = 0;
    bool ok = true;  // every read grid had the input's active voxel count
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

template <typename F>
double timeMs(F&& f) {
    const auto start = Clock::now();
    f();
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// ---- This library

vdb::FloatGrid::Ptr makeOurs(const std::vector<BandVoxel>& band) {
    auto grid = vdb::FloatGrid::create(kBackground);
    auto acc = grid->getAccessor();
    for (const BandVoxel& v : band)
        acc.setValueOn(vdb::Coord(v.x, v.y, v.z), v.value);
    vdb::tools::signedFloodFill(grid->tree());
    grid->setName("sphere");
    return grid;
}

Result measureOurs(const vdb::FloatGrid& input, const Setting& s, const std::string& path,
                   int reps) {
    Result r;
    auto typed = vdb::FloatGrid::create(kBackground);  // shares the input's tree
    typed->setTree(input.treePtr());
    typed->setName("sphere");
    typed->setSaveFloatAsHalf(s.half);
    const uint64_t active = input.activeVoxelCount();
    std::vector<double> write, eager, delayed;
    for (int i = 0; i < reps; ++i) {
        vdb::io::File out(path);
        out.setCompression(s.flags);
        write.push_back(timeMs([&] { out.write({typed}); }));
        for (bool delay : {false, true}) {
            vdb::GridBase::Ptr read;
            const double ms = timeMs([&] {
                vdb::io::File in(path);
                in.open(delay);
                read = in.readGrid("sphere");
            });
            (delay ? delayed : eager).push_back(ms);
            r.ok = r.ok && read->activeVoxelCount() == active;
            (delay ? r.delayedMem : r.eagerMem) = read->memUsage();
        }
    }
    r.fileBytes = std::filesystem::file_size(path);
    r.writeMs = median(write);
    r.eagerMs = median(eager);
    r.delayedMs = median(delayed);
    return r;
}

// ---- Floors of the writes

/// The medians of writing `bytes` bytes to `path` with plain write() calls: over the old file,
/// truncated, with no sync; and durably, into a new file beside it that is synced and renamed
/// over it, with the folder synced after.
struct WriteFloor {
    double plainMs = 0, durableMs = 0;
};

[[noreturn]] void failed(const char* what, const std::string& path) {
    std::fprintf(stderr, "write floor: %s %s: %s\n", what, path.c_str(), std::strerror(errno));
    std::exit(1);
}

WriteFloor measureWriteFloor(const std::string& path, uint64_t bytes, int reps) {
    std::vector<char> data(bytes);
    for (size_t i = 0; i < data.size(); ++i)  // every page touched before the clock runs
        data[i] = char(i * 131 + 7);
    const auto writeFile = [&](const std::string& file, bool sync) {
        const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd < 0)
            failed("open", file);
        for (size_t done = 0; done < data.size();) {
            const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
            if (n < 0 && errno != EINTR)
                failed("write", file);
            done += n > 0 ? size_t(n) : 0;
        }
        if ((sync && ::fsync(fd) != 0) || ::close(fd) != 0)
            failed("fsync or close", file);
    };
    const std::string temporary = path + ".floor";
    const std::string folder = std::filesystem::path(path).parent_path().string();
    std::vector<double> plain, durable;
    for (int i = 0; i < reps; ++i) {
        plain.push_back(timeMs([&] { writeFile(path, false); }));
        durable.push_back(timeMs([&] {
            writeFile(temporary, true);
            if (std::rename(temporary.c_str(), path.c_str()) != 0)
                failed("rename to", path);
            const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
            if (fd < 0 || ::fsync(fd) != 0 || ::close(fd) != 0)
                failed("fsync of the folder", folder);
        }));
    }
    std::filesystem::remove(path);
    return {median(plain), median(durable)};
}

// ---- OpenVDB

openvdb::FloatGrid::Ptr makeTheirs(const std::vector<BandVoxel>& band) {
    auto grid = openvdb::FloatGrid::create(kBackground);
    auto acc = grid->getAccessor();
    for (const BandVoxel& v : band)
        acc.setValueOn(openvdb::Coord(v.x, v.y, v.z), v.value);
    openvdb::tools::signedFloodFill(grid->tree());
    grid->setName("sphere");
    return grid;
}

Result measureTheirs(openvdb::FloatGrid& input, const Setting& s, const std::string& path,
                     int reps) {
    Result r;
    auto grid = input.copy();  // shares the input's tree
    grid->setSaveFloatAsHalf(s.half);
    const uint64_t active = input.activeVoxelCount();
    std::vector<double> write, eager, delayed;
    for (int i = 0; i < reps; ++i) {
        write.push_back(timeMs([&] {
            openvdb::io::File out(path);
            out.setCompression(s.flags);
            out.write({grid});
            out.close();
        }));
        for (bool delay : {false, true}) {
            openvdb::GridBase::Ptr read;
            const double ms = timeMs([&] {
                openvdb::io::File in(path);
                in.open(delay);
                read = in.readGrid("sphere");
            });
            (delay ? delayed : eager).push_back(ms);
            r.ok = r.ok && read->activeVoxelCount() == active;
            (delay ? r.delayedMem : r.eagerMem) = read->memUsage();
        }
    }
    r.fileBytes = std::filesystem::file_size(path);
    r.writeMs = median(write);
    r.eagerMs = median(eager);
    r.delayedMs = median(delayed);
    return r;
}

// ---- Command line

double mib(uint64_t bytes) {
    return double(bytes) / (1024.0 * 1024.0);
}

// ---- Markdown report

using vdb::bench::fmt;
using vdb::bench::ratioCell;

// The targets: files no larger than OpenVDB's, reading in 0.8 and writing in 0.7 of its time.
constexpr double kSizeTarget = 1.0, kReadTarget = 0.8, kWriteTarget = 0.7;

/// The paper's Table IV memory (in-core / out-of-core, MB) at `res`, or "" where it gives none.
std::string paperMemory(int res) {
    switch (res) {
        case 512:
            return "6.7 / 0.4";
        case 1024:
            return "26.5 / 1.9";
        case 2048:
            return "105.3 / 7.1";
        default:
            return "";
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> resolutions{512, 1024, 2048};
    int reps = 5;
    std::vector<std::string> settings{"mask", "zip", "blosc", "half"};
    std::string dir = std::filesystem::temp_directory_path().string();
    std::string markdownPath;
    vdb::bench::Options options(
        "vdb_bench_io [--res 512,1024,2048] [--reps 5] "
        "[--settings mask,zip,blosc,half] [--dir /tmp] [--markdown FILE]");
    options.numbers("--res", resolutions)
        .number("--reps", reps)
        .list("--settings", settings)
        .text("--dir", dir)
        .text("--markdown", markdownPath);
    options.parse(argc, argv);
    openvdb::initialize();
    const std::string ourPath = (std::filesystem::path(dir) / "vdb_bench_io_ours.vdb").string();
    const std::string theirPath =
        (std::filesystem::path(dir) / "vdb_bench_io_openvdb.vdb").string();
    const std::string floorPath = (std::filesystem::path(dir) / "vdb_bench_io_floor.vdb").string();

    std::printf(
        "# vdb_bench_io: medians of %d runs; times in ms, sizes in MiB; "
        "ratio = vdb / openvdb; %u hardware threads\n",
        reps, std::thread::hardware_concurrency());
    std::printf("%5s %-6s %-9s %10s %10s %6s\n", "res", "codec", "measure", "vdb", "openvdb",
                "ratio");
    bool ok = true;
    vdb::bench::MarkdownReport report;
    std::vector<vdb::bench::MarkdownReport::Row> rows, memoryRows, floorRows;
    std::vector<std::string> inputs, wrongCounts;
    std::string memorySetting;  // the setting whose reads the memory table shows
    vdb::bench::RatioRange readRatios, writeRatios, oursOverFloor, theirsOverFloor;
    bool sizesNoLarger = true;
    double maxSizeRatio = 0.0;
    for (const int res : resolutions) {
        const auto band = vdb::bench::makeEnrightBand(res);
        const auto ours = makeOurs(band);
        const auto theirs = makeTheirs(band);
        std::printf(
            "# %d^3: %llu active voxels, %u leaves; in memory vdb %.2f MiB, openvdb "
            "%.2f MiB\n",
            res, (unsigned long long)ours->activeVoxelCount(), ours->tree().leafCount(),
            mib(ours->memUsage()), mib(theirs->memUsage()));
        inputs.push_back(fmt(double(ours->activeVoxelCount()), 0) + " active voxels and " +
                         fmt(double(ours->tree().leafCount()), 0) + " leaves at " +
                         std::to_string(res) + "^3");
        bool firstOfRes = true;
        for (const std::string& name : settings) {
            const Setting s = settingNamed(name);
            const Result a = measureOurs(*ours, s, ourPath, reps);
            const Result b = measureTheirs(*theirs, s, theirPath, reps);
            const WriteFloor floor = measureWriteFloor(floorPath, a.fileBytes, reps);
            ok = ok && a.ok && b.ok;
            const auto row = [&](const char* what, double x, double y) {
                std::printf("%5d %-6s %-9s %10.2f %10.2f %6.2f\n", res, name.c_str(), what, x, y,
                            x / y);
            };
            row("size", mib(a.fileBytes), mib(b.fileBytes));
            row("write", a.writeMs, b.writeMs);
            std::printf("%5d %-6s %-9s %10.2f %10.2f %6s  (durable / plain)\n", res, name.c_str(),
                        "floor", floor.durableMs, floor.plainMs, "");
            row("read", a.eagerMs, b.eagerMs);
            row("delayed", a.delayedMs, b.delayedMs);
            row("mem", mib(a.eagerMem), mib(b.eagerMem));
            row("mem-dl", mib(a.delayedMem), mib(b.delayedMem));
            if (!a.ok || !b.ok)
                std::printf("# %s: a read grid had the wrong active voxel count\n",
                            !a.ok ? "vdb" : "openvdb");
            std::fflush(stdout);

            // One memory row per resolution, from the reads of its first setting.
            if (firstOfRes) {
                memorySetting = name;
                memoryRows.push_back({std::to_string(res), fmt(mib(a.eagerMem), 2),
                                      fmt(mib(a.delayedMem), 2), fmt(mib(b.eagerMem), 2),
                                      fmt(mib(b.delayedMem), 2), paperMemory(res)});
            }
            if (!a.ok || !b.ok)
                wrongCounts.push_back(std::string(!a.ok ? "vdb" : "OpenVDB") + " at " +
                                      std::to_string(res) + "^3, " + name);
            const double sizeRatio = double(a.fileBytes) / double(b.fileBytes);
            sizesNoLarger = sizesNoLarger && a.fileBytes <= b.fileBytes;
            maxSizeRatio = std::max(maxSizeRatio, sizeRatio);
            readRatios.add(a.eagerMs / b.eagerMs);
            readRatios.add(a.delayedMs / b.delayedMs);
            writeRatios.add(a.writeMs / b.writeMs);
            oursOverFloor.add(a.writeMs / floor.durableMs);
            theirsOverFloor.add(b.writeMs / floor.plainMs);
            floorRows.push_back(
                {firstOfRes ? std::to_string(res) : "", name, fmt(mib(a.fileBytes), 2),
                 fmt(a.writeMs, 1), fmt(floor.durableMs, 1), fmt(a.writeMs / floor.durableMs, 2),
                 fmt(b.writeMs, 1), fmt(floor.plainMs, 1), fmt(b.writeMs / floor.plainMs, 2)});
            // res and setting head only the first row of their group.
            bool firstOfSetting = true;
            const auto mdRow = [&](const char* what, const std::string& x, const std::string& y,
                                   double ratio, double target) {
                rows.push_back({firstOfSetting && firstOfRes ? std::to_string(res) : "",
                                firstOfSetting ? name : "", what, x, y, ratioCell(ratio, target)});
                firstOfSetting = false;
            };
            mdRow("size (MiB)", fmt(mib(a.fileBytes), 2), fmt(mib(b.fileBytes), 2), sizeRatio,
                  kSizeTarget);
            mdRow("write (ms)", fmt(a.writeMs, 1), fmt(b.writeMs, 1), a.writeMs / b.writeMs,
                  kWriteTarget);
            mdRow("read eager (ms)", fmt(a.eagerMs, 1), fmt(b.eagerMs, 1), a.eagerMs / b.eagerMs,
                  kReadTarget);
            mdRow("read delayed (ms)", fmt(a.delayedMs, 1), fmt(b.delayedMs, 1),
                  a.delayedMs / b.delayedMs, kReadTarget);
            firstOfRes = false;
        }
    }
    std::filesystem::remove(ourPath);
    std::filesystem::remove(theirPath);

    if (!markdownPath.empty()) {
        std::string input;
        for (const std::string& text : inputs)
            input += (input.empty() ? "" : "; ") + text;
        report.paragraph("Input: " + input + ".");
        report.paragraph("**Sizes and times** (Tables V, VI). Medians of " + std::to_string(reps) +
                         (reps == 1 ? " run" : " runs") +
                         "; ratio = vdb / OpenVDB, in bold where it meets the target (size 1.0, "
                         "write 0.7, read 0.8).");
        report.table({"res", "setting", "measure", "vdb", "OpenVDB", "ratio"}, rows);
        report.paragraph(
            "**Floors of the writes.** The bytes of this library's file written with plain "
            "`write()` calls, medians of " +
            std::to_string(reps) +
            ": durably, as this library writes (a new file in the same folder, `fsync`, "
            "`rename` over the old file, `fsync` of the folder), and over the old file with no "
            "sync, as OpenVDB writes. Times in ms; each library's write over the floor of its "
            "own way of writing:");
        report.table(
            {"res", "setting", "file (MiB)", "vdb write", "durable floor", "vdb / durable floor",
             "OpenVDB write", "plain floor", "OpenVDB / plain floor"},
            floorRows);
        report.paragraph(
            "**Memory (Table IV).** `memUsage()` of the grid read eager / delayed " +
            (memorySetting.empty() ? std::string() : "with setting `" + memorySetting + "`") +
            ", in MiB:");
        report.table({"res", "vdb eager", "vdb delayed", "OpenVDB eager", "OpenVDB delayed",
                      "paper (in-core / out-of-core, MB)"},
                     memoryRows);
        char sizes[96];
        std::snprintf(sizes, sizeof sizes, "sizes <= OpenVDB: %s (max size ratio %.3f)",
                      sizesNoLarger ? "yes" : "no", maxSizeRatio);
        report.status(sizes);
        report.status(readRatios.status("read", kReadTarget));
        report.status(writeRatios.status("write", kWriteTarget));
        report.status("write / its floor: vdb " + oursOverFloor.text() + ", OpenVDB " +
                      theirsOverFloor.text());
        if (!wrongCounts.empty()) {
            std::string where;
            for (const std::string& text : wrongCounts)
                where += (where.empty() ? "" : "; ") + text;
            report.paragraph("**A read grid had the wrong active voxel count:** " + where + ".");
            report.status("wrong active voxel count after reading");
        }
        if (!report.write(markdownPath))
            return 1;
    }
    return ok ? 0 : 1;
}
