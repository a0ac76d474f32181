// SPDX-License-Identifier: Apache-2.0
/// @file
/// Test support for file tests: a grid filled with a random mix of active and inactive voxels
/// and tiles at every level; a flat listing of a tree's contents (every voxel and tile with
/// its box, state and value) that two trees, or a tree and an OpenVDB tree, can be compared by,
/// and such a comparison of two trees; and temporary files.

#pragma once

#include <vdb/Grid.h>
#include <vdb/math/Half.h>

#include "Oracles.h"
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

namespace vdb::test {

/// A path named `name` in a folder of the system's temporary directory private to this
/// process (`prefix` + process id).
inline std::string tempPath(const std::string& prefix, const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

/// The names of the entries of folder `dir`, sorted.
inline std::vector<std::string> folderNames(const std::filesystem::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

inline std::vector<uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

/// One value of a tree: a voxel (level 0) or a tile, as the all-values iterator yields it.
template <typename ValueT>
struct ContentItem {
    Coord min, max;
    int level = 0;
    bool active = false;
    ValueT value{};
    bool operator==(const ContentItem&) const = default;
};

/// Every value the tree stores (voxels and tiles, active or not), sorted by box (its minimum
/// corner, then its level).
template <typename TreeT>
auto treeContents(const TreeT& tree) {
    using ValueT = typename TreeT::ValueType;
    std::vector<ContentItem<ValueT>> items;
    // The sort key of each item: its corner's coordinates as unsigned numbers in the order of
    // the signed ones, then its level, in two 64-bit words; sorted with its item's index.
    struct Key {
        uint64_t high, low;
        uint32_t item;
    };
    std::vector<Key> keys;
    const auto ordered = [](Int32 v) { return uint64_t(uint32_t(v) ^ 0x80000000u); };
    for (auto it = tree.cbeginValueAll(); it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        const Coord& min = box.min();
        keys.push_back({(ordered(min[0]) << 32) | ordered(min[1]),
                        (ordered(min[2]) << 32) | uint64_t(it.getLevel()), uint32_t(items.size())});
        items.push_back({min, box.max(), int(it.getLevel()), it.isValueOn(), it.getValue()});
    }
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
        return a.high != b.high ? a.high < b.high : a.low < b.low;
    });
    std::vector<ContentItem<ValueT>> sorted;
    sorted.reserve(items.size());
    for (const Key& key : keys)
        sorted.push_back(items[key.item]);
    return sorted;
}

/// Success when both trees hold the same voxels and tiles, in the same states, with bitwise
/// equal values; else a failure naming the first item that differs.
template <typename TreeT>
::testing::AssertionResult sameContents(const TreeT& a, const TreeT& b) {
    const auto ca = treeContents(a), cb = treeContents(b);
    if (ca.size() != cb.size())
        return ::testing::AssertionFailure() << ca.size() << " vs " << cb.size() << " items";
    for (size_t n = 0; n < ca.size(); ++n) {
        if (!(ca[n].min == cb[n].min) || !(ca[n].max == cb[n].max) ||
            ca[n].active != cb[n].active || !sameBits(ca[n].value, cb[n].value)) {
            return ::testing::AssertionFailure()
                   << "item " << n << " at " << ca[n].min << " differs";
        }
    }
    return ::testing::AssertionSuccess();
}

/// A random value of T drawn from `rng`.
template <typename T>
T randomValue(std::mt19937& rng) {
    std::uniform_real_distribution<double> real(-100.0, 100.0);
    std::uniform_int_distribution<int> integer(-1000000, 1000000);
    if constexpr (std::is_same_v<T, bool>) {
        return (rng() & 1) != 0;
    } else if constexpr (std::is_floating_point_v<T>) {
        return T(real(rng));
    } else if constexpr (std::is_integral_v<T>) {
        return T(integer(rng)) * (sizeof(T) == 8 ? T(1000003) : T(1));
    } else if constexpr (std::is_same_v<T, Vec3i>) {
        return Vec3i(integer(rng), integer(rng), integer(rng));
    } else {
        using S = typename T::ValueType;
        return T(S(real(rng)), S(real(rng)), S(real(rng)));
    }
}

/// The first random value of T of a generator seeded with `seed`.
template <typename T>
T randomValue(unsigned seed) {
    std::mt19937 rng(seed);
    return randomValue<T>(rng);
}

/// Fills `grid` with: random active and inactive voxels spread over leaves and the two upper
/// nodes on either side of x = 0; a few inactive runs of one other value (so leaves need
/// each mask-compression case); an active and an inactive tile at each internal level; an
/// active and an inactive root tile.
template <typename GridT>
void fillTestGrid(GridT& grid, unsigned seed) {
    using ValueT = typename GridT::ValueType;
    std::mt19937 rng(seed);
    auto& tree = grid.tree();
    auto acc = grid.getAccessor();
    std::uniform_int_distribution<int> coord(-60, 60), positive(0, 120);
    const ValueT other = randomValue<ValueT>(rng);
    for (int i = 0; i < 300; ++i) {
        const Coord ijk(coord(rng), positive(rng), positive(rng));
        const int kind = int(rng() % 4);
        if (kind == 0)
            acc.setValueOff(ijk, randomValue<ValueT>(rng));
        else if (kind == 1)
            acc.setValueOff(ijk, other);
        else
            acc.setValueOn(ijk, randomValue<ValueT>(rng));
    }
    // A dense leaf and a leaf whose inactive voxels hold -background and background.
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 8; ++k)
                acc.setValueOn(Coord(400 + i, 400 + j, 400 + k), randomValue<ValueT>(rng));
    // Tiles: one leaf-sized and one lower-node-sized region, active and inactive.
    tree.fill(CoordBBox::createCube(Coord(512, 0, 0), 8), randomValue<ValueT>(rng), true);
    tree.fill(CoordBBox::createCube(Coord(520, 0, 0), 8), randomValue<ValueT>(rng), false);
    tree.fill(CoordBBox::createCube(Coord(640, 0, 0), 128), randomValue<ValueT>(rng), true);
    tree.fill(CoordBBox::createCube(Coord(768, 0, 0), 128), randomValue<ValueT>(rng), false);
    // Root tiles (whole 4096^3 regions).
    tree.topNode().setTile(Coord(8192, 0, 0), randomValue<ValueT>(rng), true);
    tree.topNode().setTile(Coord(-8192, 4096, 0), randomValue<ValueT>(rng), false);
}

}  // namespace vdb::test
