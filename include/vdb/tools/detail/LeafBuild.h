// SPDX-License-Identifier: Apache-2.0
/// @file
/// Building a tree from leaves made in parallel (not API): tools that compute one output leaf
/// per input leaf (the grid operators, the filters' masks, the level set utilities) make the
/// leaves in parallel tasks, then link them into the tree here. Leaves under different
/// children of the top node are linked in parallel; the children themselves are created
/// serially, in the order of their keys, so the tree does not depend on the thread count.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <vector>

namespace vdb::tools::detail {

/// Takes ownership of the non-null leaves of `leaves` and links each into `tree`, creating the
/// internal nodes above it from the tiles (or background) they replace.
/// @pre no two leaves share an origin, and the tree has no leaf at any of their origins
template <typename TreeT>
void linkLeaves(TreeT& tree, std::vector<std::unique_ptr<typename TreeT::LeafNodeType>>& leaves,
                bool threaded) {
    using TopT = typename TreeT::TopNodeType;
    if constexpr (!tree::IS_ROOT_NODE<TopT>) {
        for (auto& leaf : leaves) {
            if (leaf)
                tree.addLeaf(std::move(leaf));
        }
    } else {
        using ChildT = typename TopT::ChildNodeType;
        // Group the leaves by the child of the root they fall in, in key order.
        std::vector<size_t> order;
        order.reserve(leaves.size());
        for (size_t i = 0; i < leaves.size(); ++i) {
            if (leaves[i])
                order.push_back(i);
        }
        const auto key = [&](size_t i) { return TopT::coordToKey(leaves[i]->origin()); };
        std::stable_sort(order.begin(), order.end(),
                         [&](size_t a, size_t b) { return key(a) < key(b); });
        std::vector<size_t> groupStart;
        std::vector<ChildT*> children;
        TopT& top = tree.topNode();
        for (size_t n = 0; n < order.size(); ++n) {
            const Coord k = key(order[n]);
            if (n > 0 && k == key(order[n - 1]))
                continue;
            TreeT::checkDomain(k);
            groupStart.push_back(n);
            children.push_back(&tree::touchChild(top, k));
        }
        groupStart.push_back(order.size());
        // Each group fills its own branch.
        util::parallelFor(
            children.size(),
            [&](size_t g) {
                for (size_t n = groupStart[g]; n < groupStart[g + 1]; ++n)
                    tree::addLeaf(*children[g], std::move(leaves[order[n]]));
            },
            threaded, 1);
    }
    tree.clearAllAccessors();
}

}  // namespace vdb::tools::detail
