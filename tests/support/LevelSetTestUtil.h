// SPDX-License-Identifier: Apache-2.0
// Helpers shared by the level-set tool tests: whole-tree listings compared bit for bit, a walk
// over the internal nodes of one level, and analytic signed distance functions.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/Tree.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

namespace vdb::test {

/// One stored value of a tree: a voxel (level 0, dim 1) or a tile (its level and edge).
template <typename ValueT>
struct StoredValue {
    Coord min;
    Int32 dim;
    Index level;
    ValueT value;
    bool on;
};

/// Every voxel and tile of `tree` (or only the tiles), in the order of its ValueAll iterator.
template <typename TreeT>
std::vector<StoredValue<typename TreeT::ValueType>> listStoredValues(const TreeT& tree,
                                                                     bool tilesOnly = false) {
    std::vector<StoredValue<typename TreeT::ValueType>> items;
    for (auto it = tree.cbeginValueAll(); it; ++it) {
        if (tilesOnly && it.getLevel() == 0)
            continue;
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        items.push_back(
            {bbox.min(), bbox.dim()[0], Index(it.getLevel()), it.getValue(), it.isValueOn()});
    }
    return items;
}

/// Success when the two trees have the same leaves (same masks, bit-identical values) and the
/// same tiles (regions, bit-identical values, states), and the same background.
template <typename TreeT>
::testing::AssertionResult identicalTrees(const TreeT& a, const TreeT& b) {
    if (!sameBits(a.background(), b.background()))
        return ::testing::AssertionFailure() << "the backgrounds differ";
    if (a.leafCount() != b.leafCount()) {
        return ::testing::AssertionFailure()
               << "leaf counts differ: " << a.leafCount() << " vs " << b.leafCount();
    }
    for (const auto& leaf : a.leaves()) {
        const auto* other = b.probeConstLeaf(leaf.origin());
        if (!other || other->origin() != leaf.origin())
            return ::testing::AssertionFailure() << "no leaf at " << leaf.origin();
        if (!(leaf.getValueMask() == other->getValueMask()))
            return ::testing::AssertionFailure() << "leaf masks differ at " << leaf.origin();
        for (Index n = 0; n < leaf.NUM_VALUES; ++n) {
            if (!sameBits(leaf.getValue(n), other->getValue(n))) {
                return ::testing::AssertionFailure()
                       << "voxel " << leaf.offsetToGlobalCoord(n) << ": " << leaf.getValue(n)
                       << " vs " << other->getValue(n);
            }
        }
    }
    auto x = listStoredValues(a, true), y = listStoredValues(b, true);
    const auto same = [](const auto& p, const auto& q) {
        return p.min == q.min && p.dim == q.dim && p.on == q.on && sameBits(p.value, q.value);
    };
    if (x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(), same))
        return ::testing::AssertionSuccess();
    // Root tables of different histories may list their tiles in different orders.
    const auto order = [](const auto& p, const auto& q) {
        return std::tie(p.min, p.dim) < std::tie(q.min, q.dim);
    };
    std::sort(x.begin(), x.end(), order);
    std::sort(y.begin(), y.end(), order);
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
        if (x[i].min != y[i].min || x[i].dim != y[i].dim || x[i].on != y[i].on ||
            !sameBits(x[i].value, y[i].value)) {
            return ::testing::AssertionFailure()
                   << "tile " << i << " differs: " << x[i].min << " dim " << x[i].dim << " = "
                   << x[i].value << (x[i].on ? " on" : " off") << " vs " << y[i].min << " dim "
                   << y[i].dim << " = " << y[i].value << (y[i].on ? " on" : " off");
        }
    }
    if (x.size() != y.size())
        return ::testing::AssertionFailure() << x.size() << " vs " << y.size() << " tiles";
    return ::testing::AssertionSuccess();
}

/// Calls `fn(node)` for every node of level L (0 < L < top level) of `tree`.
template <Index L, typename TreeT, typename FnT>
void forEachNodeAtLevel(const TreeT& tree, const FnT& fn) {
    using NodeT = tree::NodeAtLevelT<typename TreeT::TopNodeType, L>;
    for (auto it = tree.cbeginNode(); it; ++it) {
        if (const NodeT* node = it.template getNode<const NodeT>())
            fn(*node);
    }
}

/// Calls `fn(std::integral_constant<Index, L>)` for L = First .. Last - 1.
template <Index First, Index Last, typename FnT>
void forEachLevel(const FnT& fn) {
    if constexpr (First < Last) {
        fn(std::integral_constant<Index, First>{});
        forEachLevel<First + 1, Last>(fn);
    }
}

// ---- Analytic signed distances in voxel units (negative inside) --------------------------------

using Sdf = std::function<double(double, double, double)>;

inline Sdf sphereSdf(double cx, double cy, double cz, double r) {
    return [=](double x, double y, double z) {
        return std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz)) - r;
    };
}

inline Sdf torusSdf(double cx, double cy, double cz, double major, double minor) {
    return [=](double x, double y, double z) {
        const double q = std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy)) - major;
        return std::sqrt(q * q + (z - cz) * (z - cz)) - minor;
    };
}

inline Sdf boxSdf(double cx, double cy, double cz, double hx, double hy, double hz) {
    return [=](double x, double y, double z) {
        const double dx = std::abs(x - cx) - hx, dy = std::abs(y - cy) - hy,
                     dz = std::abs(z - cz) - hz;
        const double ox = std::max(dx, 0.0), oy = std::max(dy, 0.0), oz = std::max(dz, 0.0);
        return std::sqrt(ox * ox + oy * oy + oz * oz) +
               std::min(std::max(dx, std::max(dy, dz)), 0.0);
    };
}

inline double sdfAt(const Sdf& sdf, const Coord& ijk) {
    return sdf(double(ijk[0]), double(ijk[1]), double(ijk[2]));
}

}  // namespace vdb::test
