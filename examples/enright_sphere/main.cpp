// SPDX-License-Identifier: Apache-2.0
// The Enright sphere of the VDB paper (Museth 2013, section 5) as a narrow band: a sphere of
// radius 0.15 centred at (0.35, 0.35, 0.35) in the unit box, voxel size 1/R, every voxel
// within 5 voxels of the surface active and holding its signed distance in voxel units.
//
//   enright_sphere [R]        R = resolution, default 1024
//
// The band is inserted in random order through an accessor, then read back at random (with
// the accessor and top-down from the root) and in sequence. The program prints the tree's
// statistics and timings, and exits with status 1 if any value read back differs from the
// value inserted.

#include <vdb/tree/ValueAccessor.h>
#include <vdb/vdb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

namespace {

struct BandVoxel {
    vdb::Coord ijk;
    float value;
};

constexpr double kCenter = 0.35;
constexpr double kRadius = 0.15;
constexpr double kHalfWidth = 5.0;  // voxels: the band is 10 voxels wide

// Active voxel counts the paper reports for this band, or 0 where it gives none.
uint64_t paperActiveVoxels(int resolution) {
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

// Voxel (i, j, k) sits at world position (i, j, k) / R; its value is the signed distance to
// the sphere in voxels, and it belongs to the band when that distance is below kHalfWidth
// in magnitude.
std::vector<BandVoxel> makeBand(int resolution) {
    const double center = kCenter * resolution;
    const double radius = kRadius * resolution;
    const double outer = radius + kHalfWidth;
    const int lo = int(std::floor(center - outer)) - 1;
    const int hi = int(std::ceil(center + outer)) + 1;
    std::vector<BandVoxel> band;
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
                if (std::abs(dist) < kHalfWidth)
                    band.push_back({vdb::Coord(i, j, k), float(dist)});
            }
        }
    }
    return band;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A 64-bit mix of one voxel's coordinate and value bits (SplitMix64's finaliser); the
// checksum adds these up, so it does not depend on the order of iteration.
uint64_t voxelHash(const vdb::Coord& ijk, float value) {
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    uint64_t h = (uint64_t(uint32_t(ijk.x())) << 42) ^ (uint64_t(uint32_t(ijk.y())) << 21) ^
                 uint64_t(uint32_t(ijk.z())) ^ (uint64_t(bits) * 0x9E3779B97F4A7C15ull);
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    return h ^ (h >> 31);
}

}  // namespace

int main(int argc, char** argv) {
    const int resolution = argc > 1 ? std::atoi(argv[1]) : 1024;
    if (resolution < 16 || resolution > 8192) {
        std::fprintf(stderr, "usage: %s [resolution in 16..8192, default 1024]\n", argv[0]);
        return 2;
    }

    // The band, in random order (a fixed seed, so every run inserts in the same order).
    std::vector<BandVoxel> band = makeBand(resolution);
    std::shuffle(band.begin(), band.end(), std::mt19937_64(20130601));

    // Build by random insertion through an accessor.
    const float background = float(kHalfWidth);
    vdb::FloatTree tree(background);
    auto start = std::chrono::steady_clock::now();
    {
        vdb::tree::ValueAccessor<vdb::FloatTree> acc(tree);
        for (const BandVoxel& v : band)
            acc.setValue(v.ijk, v.value);
    }
    const double buildSeconds = secondsSince(start);

    const uint64_t active = tree.activeVoxelCount();
    const uint64_t paper = paperActiveVoxels(resolution);
    std::printf("Enright sphere, R = %d, band half width %.0f voxels\n", resolution, kHalfWidth);
    std::printf("  active voxels       %llu", (unsigned long long)active);
    if (paper) {
        std::printf("   (paper: %llu)", (unsigned long long)paper);
    }
    std::printf("\n  leaf nodes          %llu\n  internal nodes      %llu\n",
                (unsigned long long)tree.leafCount(), (unsigned long long)tree.nonLeafCount());
    const double bytes = double(tree.memUsage());
    std::printf("  memUsage            %.2f MB   %.2f bytes per active voxel\n",
                bytes / (1024.0 * 1024.0), bytes / double(active));
    std::printf("  build (random)      %.3f s   %.1f ns per voxel\n", buildSeconds,
                buildSeconds * 1e9 / double(band.size()));

    // Check every inserted voxel: active, and holding exactly the value inserted.
    uint64_t wrong = active == band.size() ? 0 : 1;
    {
        vdb::tree::ValueAccessor<const vdb::FloatTree> acc(tree);
        for (const BandVoxel& v : band) {
            if (!acc.isValueOn(v.ijk) || acc.getValue(v.ijk) != v.value) {
                if (wrong++ < 10) {
                    std::fprintf(stderr, "mismatch at (%d, %d, %d): inserted %g, read %g\n",
                                 v.ijk.x(), v.ijk.y(), v.ijk.z(), double(v.value),
                                 double(acc.getValue(v.ijk)));
                }
            }
        }
    }

    // Random lookups, in the insertion order: accessor, then top-down from the root.
    double sumCached = 0, sumTopDown = 0;
    start = std::chrono::steady_clock::now();
    {
        vdb::tree::ValueAccessor<const vdb::FloatTree> acc(tree);
        for (const BandVoxel& v : band)
            sumCached += acc.getValue(v.ijk);
    }
    const double cachedSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    for (const BandVoxel& v : band)
        sumTopDown += tree.getValue(v.ijk);
    const double topDownSeconds = secondsSince(start);
    std::printf("  random lookup       %.1f ns (accessor)   %.1f ns (top-down)\n",
                cachedSeconds * 1e9 / double(band.size()),
                topDownSeconds * 1e9 / double(band.size()));

    // Sequential iteration over the active voxels.
    double sumSequential = 0;
    uint64_t visited = 0, checksum = 0;
    start = std::chrono::steady_clock::now();
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        sumSequential += *it;
        ++visited;
    }
    const double sequentialSeconds = secondsSince(start);
    std::printf("  sequential          %.2f ns per active voxel\n",
                sequentialSeconds * 1e9 / double(visited));
    for (auto it = tree.cbeginValueOn(); it; ++it)
        checksum += voxelHash(it.getCoord(), *it);
    std::printf("  checksum            %016llx   sum of values %.3f\n",
                (unsigned long long)checksum, sumSequential);

    // Every pass must see the same values.
    uint64_t expectedChecksum = 0;
    for (const BandVoxel& v : band)
        expectedChecksum += voxelHash(v.ijk, v.value);
    if (visited != band.size() || checksum != expectedChecksum || sumCached != sumTopDown) {
        ++wrong;
    }
    if (wrong != 0) {
        std::fprintf(stderr, "FAILED: the tree does not hold the values inserted\n");
        return 1;
    }
    std::printf("  all %llu values read back as inserted\n", (unsigned long long)band.size());
    return 0;
}
