// SPDX-License-Identifier: Apache-2.0
/// @file
/// forEachLeafPair: the leaves of one tree paired with the leaves of another tree of the same
/// layout at the same origins, processed in parallel. Not API.

#pragma once

#include <vdb/util/Parallel.h>

#include <cstddef>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

/// Calls op(srcLeaf, dstLeaf) for every leaf of `src` and the leaf of `dst` at the same origin
/// (created first, serially, where `dst` has none), in parallel when `threaded`.
template <typename SrcTreeT, typename DstTreeT, typename OpT>
void forEachLeafPair(const SrcTreeT& src, DstTreeT& dst, const OpT& op, bool threaded) {
    using SrcLeafT = typename SrcTreeT::LeafNodeType;
    using DstLeafT = typename DstTreeT::LeafNodeType;
    std::vector<std::pair<const SrcLeafT*, DstLeafT*>> pairs;
    for (auto leaf = src.cbeginLeaf(); leaf; ++leaf)
        pairs.emplace_back(leaf.getLeaf(), dst.touchLeaf(leaf->origin()));
    util::parallelFor(
        pairs.size(), [&](size_t i) { op(*pairs[i].first, *pairs[i].second); }, threaded, 16);
}

}  // namespace vdb::tools::detail
