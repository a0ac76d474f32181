// SPDX-License-Identifier: Apache-2.0
/// @file
/// Library-neutral inputs for the benchmarks: the Enright sphere narrow band of the paper's
/// section 5, a portable seeded shuffle, the process memory readings of Table II, and the
/// command-line helpers the benchmark programs share, and the Markdown report each program
/// writes for docs/BENCHMARKS.md (scripts/bench).
///
/// Nothing here includes either tree library, so every benchmark feeds this library and
/// OpenVDB the same coordinates and values in the same order.

#pragma once

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace vdb::bench {

/// One active voxel of a test band: index-space coordinate and value.
struct BandVoxel {
    int32_t x, y, z;
    float value;
};

/// The Enright sphere of the paper's section 5: radius 0.15 centred at (0.35, 0.35, 0.35) in
/// the unit box, sampled at voxel size 1/resolution.
struct EnrightSphere {
    static constexpr double kCenter = 0.35;
    static constexpr double kRadius = 0.15;
    /// Half width of the narrow band in voxels: the band is 10 voxels wide.
    static constexpr double kHalfWidth = 5.0;

    /// Active voxel counts the paper reports for this band (section 5), or 0 when it gives none.
    static constexpr uint64_t paperActiveVoxels(int resolution) {
        switch (resolution) {
            case 512:
                return 794'720;
            case 1024:
                return 3'189'240;
            case 2048:
                return 12'784'621;
            case 4096:
                return 51'033'829;
            default:
                return 0;
        }
    }
};

/// Returns the voxels of the Enright sphere's narrow band at `resolution`, in x-major scanline
/// order.
///
/// Voxel (i, j, k) sits at world position (i, j, k) / resolution. Its value is the signed
/// distance to the sphere in voxel units (negative inside), and it belongs to the band when
/// that distance is less than kHalfWidth in magnitude. Cost: one square root per voxel of the
/// sphere's bounding box, less the rows that miss the band.
inline std::vector<BandVoxel> makeEnrightBand(int resolution) {
    const double center = EnrightSphere::kCenter * resolution;
    const double radius = EnrightSphere::kRadius * resolution;
    const double outer = radius + EnrightSphere::kHalfWidth;
    const int lo = int(std::floor(center - outer)) - 1;
    const int hi = int(std::ceil(center + outer)) + 1;

    std::vector<BandVoxel> band;
    band.reserve(size_t(4.0 * 3.15 * radius * radius * 2.0 * EnrightSphere::kHalfWidth * 1.1));
    for (int i = lo; i <= hi; ++i) {
        const double dx = i - center;
        for (int j = lo; j <= hi; ++j) {
            const double dy = j - center;
            // Only the k within the outer radius can hold band voxels.
            const double rest = outer * outer - dx * dx - dy * dy;
            if (rest < 0.0)
                continue;
            const double reach = std::sqrt(rest);
            const int kLo = std::max(lo, int(std::floor(center - reach)));
            const int kHi = std::min(hi, int(std::ceil(center + reach)));
            for (int k = kLo; k <= kHi; ++k) {
                const double dz = k - center;
                const double dist = std::sqrt(dx * dx + dy * dy + dz * dz) - radius;
                if (std::abs(dist) < EnrightSphere::kHalfWidth) {
                    band.push_back({i, j, k, float(dist)});
                }
            }
        }
    }
    return band;
}

/// SplitMix64: a small seeded generator whose output is the same on every platform, unlike the
/// distributions of <random>.
class SplitMix64 {
public:
    explicit SplitMix64(uint64_t seed) : mState(seed) {}
    uint64_t operator()() {
        uint64_t z = (mState += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Returns a number in [0, n); the modulo bias is below n / 2^64.
    uint64_t below(uint64_t n) { return (*this)() % n; }

private:
    uint64_t mState;
};

/// Fisher-Yates shuffle driven by SplitMix64(seed): the same permutation on every platform.
template <typename T>
void shuffle(std::vector<T>& items, uint64_t seed) {
    SplitMix64 rng(seed);
    for (size_t n = items.size(); n > 1; --n) {
        std::swap(items[n - 1], items[rng.below(n)]);
    }
}

/// Returns `count` items drawn uniformly, with replacement, from `items`.
template <typename T>
std::vector<T> sample(const std::vector<T>& items, size_t count, uint64_t seed) {
    SplitMix64 rng(seed);
    std::vector<T> out(count);
    for (T& item : out)
        item = items[rng.below(items.size())];
    return out;
}

/// The non-empty items of a `sep`-separated list, as the benchmarks' command lines take them.
inline std::vector<std::string> splitList(const std::string& s, char sep = ',') {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, sep))
        if (!item.empty())
            out.push_back(item);
    return out;
}

/// Resident set size of this process in bytes, from /proc/self/statm (the paper's Table II
/// reads memory from the OS); 0 where that file cannot be read.
inline uint64_t residentBytes() {
    unsigned long pages = 0, resident = 0;
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f)
        return 0;
    const int n = std::fscanf(f, "%lu %lu", &pages, &resident);
    std::fclose(f);
    return n == 2 ? uint64_t(resident) * uint64_t(sysconf(_SC_PAGESIZE)) : 0;
}

/// Hands freed heap pages back to the OS, so that a following RSS delta counts only new
/// allocations.
inline void releaseFreeMemory() {
    malloc_trim(0);
}

/// Stops glibc from shrinking the heap inside free(): by default, whenever the free block at
/// the top of the heap grows past a threshold (which glibc also moves as the program frees
/// large blocks), free() returns it to the OS with brk(), and the next allocations fault the
/// pages back in. How often that happens during an operation depends on the heap left by
/// earlier ones, not on the operation. releaseFreeMemory() still returns memory explicitly.
inline void keepHeapOnFree() {
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    // Setting the trim threshold also stops glibc from raising the size above which blocks
    // are mapped one by one (and faulted in on every use); set it where glibc would have.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
}

/// The command line of a benchmark program: `--name value` pairs, each declared with where
/// its value goes. An unknown name, a missing value or a value out of range prints the
/// problem and the usage line on stderr and exits with status 2.
///
/// @code
/// vdb::bench::Options options("vdb_bench_x [--res 512,1024] [--reps 5] [--markdown FILE]");
/// options.numbers("--res", resolutions).number("--reps", reps).text("--markdown", path);
/// options.parse(argc, argv);
/// @endcode
class Options {
public:
    using Handler = std::function<void(const std::string&)>;

    explicit Options(std::string usageLine) : mUsage(std::move(usageLine)) {}

    /// `name VALUE`, handed to `f`.
    Options& on(const std::string& name, Handler f) {
        mHandlers[name] = std::move(f);
        return *this;
    }
    /// `name TEXT`.
    Options& text(const std::string& name, std::string& out) {
        return on(name, [&out](const std::string& v) { out = v; });
    }
    /// `name A,B,...`; "none" for no items.
    Options& list(const std::string& name, std::vector<std::string>& out) {
        return on(name, [&out](const std::string& v) {
            out = v == "none" ? std::vector<std::string>{} : splitList(v);
        });
    }
    /// `name N`, a whole number in [lo, hi].
    Options& number(const std::string& name, int& out, long lo = 1, long hi = 1 << 16) {
        return on(name, [this, &out, name, lo, hi](const std::string& v) {
            out = int(toNumber(v, name.c_str(), lo, hi));
        });
    }
    /// `name N,M,...`, at least one whole number in [1, 65536].
    Options& numbers(const std::string& name, std::vector<int>& out) {
        return on(name, [this, &out, name](const std::string& v) {
            out.clear();
            for (const std::string& item : splitList(v))
                out.push_back(int(toNumber(item, name.c_str())));
            if (out.empty())
                fail(name + " needs at least one number");
        });
    }
    /// `name WxH`.
    Options& size(const std::string& name, size_t& width, size_t& height) {
        return on(name, [this, &width, &height, name](const std::string& v) {
            const auto wh = splitList(v, 'x');
            if (wh.size() != 2)
                fail(name + " takes WxH, not '" + v + "'");
            width = size_t(toNumber(wh[0], "width"));
            height = size_t(toNumber(wh[1], "height"));
        });
    }

    /// Reads `argv`. Arguments that are not declared options go to `rest`, in order, when it
    /// is given (for a library that reads its own flags); otherwise they are an error.
    void parse(int argc, char** argv, std::vector<char*>* rest = nullptr) const {
        for (int i = 1; i < argc; ++i) {
            const std::string arg = argv[i];
            const size_t eq = arg.find('=');
            const auto handler = mHandlers.find(arg.substr(0, eq));
            if (handler == mHandlers.end()) {
                if (!rest)
                    fail("unknown argument " + arg);
                rest->push_back(argv[i]);
            } else if (eq != std::string::npos) {
                handler->second(arg.substr(eq + 1));
            } else if (i + 1 < argc) {
                handler->second(argv[++i]);
            } else {
                fail("missing value after " + arg);
            }
        }
    }

    /// `s` as a whole number in [lo, hi], or fail() naming `what`.
    long toNumber(const std::string& s, const char* what, long lo = 1, long hi = 1 << 16) const {
        char* end = nullptr;
        errno = 0;
        const long v = std::strtol(s.c_str(), &end, 10);
        if (s.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi)
            fail(std::string("bad ") + what + " '" + s + "': a whole number from " +
                 std::to_string(lo) + " to " + std::to_string(hi));
        return v;
    }

    /// An item of a `--threads` list: a thread count, or "all" for every hardware thread.
    int threadCount(const std::string& s) const {
        if (s == "all")
            return int(std::max(1u, std::thread::hardware_concurrency()));
        return int(toNumber(s, "thread count"));
    }

    /// Prints `message` and the usage line on stderr and exits with status 2.
    [[noreturn]] void fail(const std::string& message) const {
        std::fprintf(stderr, "%s\nusage: %s\n", message.c_str(), mUsage.c_str());
        std::exit(2);
    }

private:
    std::string mUsage;
    std::map<std::string, Handler> mHandlers;
};

/// The median of `values` (the mean of the two middle ones for an even count); 0 when empty.
inline double median(std::vector<double> values) {
    if (values.empty())
        return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// The sentence that opens a report of medians: how many runs, what the ratio is, the target
/// and the machine's hardware threads.
inline std::string mediansNote(int reps, double target, int cores) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "Medians of %d runs in milliseconds; ratio = vdb / OpenVDB, in bold where it "
                  "meets the target (at most %.2f). The machine has %d hardware threads.",
                  reps, target, cores);
    return line;
}

/// The smallest and largest of a set of ratios (this library / OpenVDB), for the overview line
/// of a report.
class RatioRange {
public:
    void add(double ratio) {
        if (!std::isfinite(ratio))
            return;
        mMin = std::min(mMin, ratio);
        mMax = std::max(mMax, ratio);
    }
    bool empty() const { return mMin > mMax; }
    double min() const { return mMin; }
    double max() const { return mMax; }
    /// "0.42" or "0.13-0.71"; "n/a" when nothing was added.
    std::string text() const {
        if (empty())
            return "n/a";
        char buf[64];
        if (std::abs(mMax - mMin) < 0.005)
            std::snprintf(buf, sizeof buf, "%.2f", mMin);
        else
            std::snprintf(buf, sizeof buf, "%.2f-%.2f", mMin, mMax);
        return buf;
    }
    /// `name range`, with " (target <= t: met|not met)" when the target is positive. Smaller is
    /// better unless `higherIsBetter` (rays per second).
    std::string status(const std::string& name, double target = 0.0,
                       bool higherIsBetter = false) const {
        std::string out = name + " " + text();
        if (target > 0.0 && !empty()) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.2f", target);
            const bool met = higherIsBetter ? mMin >= target : mMax <= target;
            out += std::string(" (target ") + (higherIsBetter ? ">= " : "<= ") + buf +
                   (met ? ": met)" : ": not met)");
        }
        return out;
    }

private:
    double mMin = std::numeric_limits<double>::infinity();
    double mMax = -std::numeric_limits<double>::infinity();
};

/// Formats a number for a report table: `decimals` digits after the point, thousands separated
/// by commas ("1,234.5").
inline std::string fmt(double value, int decimals = 2) {
    if (!std::isfinite(value))
        return "n/a";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
    std::string text(buf);
    const size_t begin = text[0] == '-' ? 1 : 0;
    const size_t point = std::min(text.find('.'), text.size());
    for (size_t i = point; i > begin + 3; i -= 3)
        text.insert(i - 3, ",");
    return text;
}

/// A ratio cell: two decimals, in bold when it meets `target` (smaller is better unless
/// `higherIsBetter`); plain when the target is 0.
inline std::string ratioCell(double ratio, double target = 0.0, bool higherIsBetter = false) {
    const std::string text = fmt(ratio, 2);
    const bool met = target > 0.0 && std::isfinite(ratio) &&
                     (higherIsBetter ? ratio >= target : ratio <= target);
    return met ? "**" + text + "**" : text;
}

/// The Markdown a benchmark program writes with `--markdown FILE`: its result tables and
/// notes, which scripts/bench places into its section of docs/BENCHMARKS.md, and one status line
/// (FILE.status) for the overview table at the top of that document.
class MarkdownReport {
public:
    using Row = std::vector<std::string>;

    void paragraph(const std::string& text) { mText += text + "\n\n"; }

    void table(const Row& header, const std::vector<Row>& rows) {
        const auto line = [this](const Row& cells) {
            mText += "|";
            for (const std::string& cell : cells)
                mText += " " + cell + " |";
            mText += "\n";
        };
        line(header);
        mText += "|";
        for (size_t i = 0; i < header.size(); ++i)
            mText += "---|";
        mText += "\n";
        for (const Row& row : rows)
            line(row);
        mText += "\n";
    }

    /// Appends `text` to the overview status, separated by "; ".
    void status(const std::string& text) { mStatus += (mStatus.empty() ? "" : "; ") + text; }

    const std::string& text() const { return mText; }

    /// Writes FILE and FILE.status; false (with a message on stderr) when either fails.
    bool write(const std::string& path) const {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out << mText;
        std::ofstream status(path + ".status", std::ios::binary | std::ios::trunc);
        status << mStatus << "\n";
        out.close();
        status.close();
        if (!out || !status) {
            std::fprintf(stderr, "cannot write the report %s\n", path.c_str());
            return false;
        }
        return true;
    }

private:
    std::string mText;
    std::string mStatus;
};

}  // namespace vdb::bench
