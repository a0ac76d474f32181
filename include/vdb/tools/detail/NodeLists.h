// SPDX-License-Identifier: Apache-2.0
/// @file
/// NodeLists: the nodes of a tree below its top node, one flat array per level, so that a tool
/// can process every node of one level in parallel and then the level above (bottom-up), or
/// the other way round. NodeLists is not API; it also brings the tree concepts of
/// tree/NodeTraits.h into vdb::tools as tools::VdbTree and tools::SignedVdbTree.

#pragma once

#include <vdb/Types.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/NodeTraits.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

#include <cstddef>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools {

// The tree concepts of tree/NodeTraits.h, by the names the tools have always used.
using tree::SignedVdbTree;
using tree::VdbTree;

}  // namespace vdb::tools

namespace vdb::tools::detail {

/// The nodes of levels [minLevel, TOP) of one tree, in arrays per level (level 0 holds the
/// leaves). Within a level the order is the order of the parents' tables, so it depends only
/// on the tree, never on the thread count. `TreeT` may be const: the arrays then hold const
/// nodes.
///
/// The arrays are a snapshot: a node freed after construction leaves a dangling pointer in its
/// level's array, so a bottom-up pass must not revisit a level once the level above it has
/// replaced children with tiles.
/// Threads: construction fills each level below the top's children in parallel (each parent its
/// own stretch of the array) when `threaded`; the arrays may be read concurrently.
template <typename TreeT>
class NodeLists {
public:
    using TopT = typename std::remove_const_t<TreeT>::TopNodeType;
    static constexpr Index TOP = TopT::LEVEL;
    template <Index L>
    using NodeT = std::conditional_t<std::is_const_v<TreeT>, const tree::NodeAtLevelT<TopT, L>,
                                     tree::NodeAtLevelT<TopT, L>>;

    /// Collects every node of the levels minLevel to TOP - 1. O(number of those nodes), plus
    /// one scan of the top node's child mask.
    explicit NodeLists(TreeT& tree, Index minLevel = 0, bool threaded = true) {
        if (minLevel < TOP)
            collect<TOP - 1>(tree, minLevel, threaded);
    }

    template <Index L>
    const std::vector<NodeT<L>*>& nodes() const {
        return std::get<L>(mLists);
    }

    /// Calls `op(node)` for every collected node of level L, in parallel when `threaded`.
    template <Index L, typename OpT>
    void foreach (const OpT& op, bool threaded, size_t grain = 1) const {
        const auto& list = std::get<L>(mLists);
        util::parallelFor(
            list.size(), [&](size_t i) { op(*list[i]); }, threaded, grain);
    }

private:
    template <size_t... L>
    static auto makeLists(std::index_sequence<L...>) -> std::tuple<std::vector<NodeT<L>*>...>;
    using Lists = decltype(makeLists(std::make_index_sequence<TOP>{}));

    template <Index L>
    void collect(TreeT& tree, Index minLevel, bool threaded) {
        auto& list = std::get<L>(mLists);
        if constexpr (L + 1 == TOP) {
            auto& top = tree.topNode();
            list.reserve(tree::childCount(top));
            tree::forEachChild(top, [&list](auto& child) { list.push_back(&child); });
        } else {
            const auto& parents = std::get<L + 1>(mLists);
            std::vector<size_t> first(parents.size() + 1, 0);
            for (size_t p = 0; p < parents.size(); ++p)
                first[p + 1] = first[p] + parents[p]->getChildMask().countOn();
            list.resize(first.back());
            util::parallelFor(
                parents.size(),
                [&](size_t p) {
                    size_t k = first[p];
                    for (Index n : parents[p]->getChildMask().onBits())
                        list[k++] = parents[p]->getChild(n);
                },
                threaded, 8);
        }
        if constexpr (L > 0) {
            if (L > minLevel)
                collect<L - 1>(tree, minLevel, threaded);
        }
    }

    Lists mLists;
};

}  // namespace vdb::tools::detail
