// SPDX-License-Identifier: Apache-2.0
/// @file
/// The blocks of a tree as the Python module lists them (tree::visitBlocks(): its leaves and its
/// tiles, in OpenVDB's iteration order), the level at which a coordinate's value is stored
/// (the ProbeNode descent), and the registry of trees whose leaf buffers NumPy arrays view.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vdb::python {

/// One block of a tree: a leaf (level 0, `leaf` set) or a tile of the node at `level`, which
/// covers the child region of that node at `origin`.
template <typename TreeT>
struct Block {
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    Coord origin;
    Index level = 0;
    LeafT* leaf = nullptr;
    ValueT value{};
    bool active = false;
};

/// Edge length in voxels of a block of `level` in TreeT (a leaf for level 0).
template <typename TreeT>
Int64 blockDim(Index level) {
    using LeafT = typename TreeT::LeafNodeType;
    if (level == 0)
        return LeafT::DIM;
    Int64 dim = 0;
    auto walk = [&]<typename NodeT>(auto& self, const NodeT*) -> void {
        if constexpr (NodeT::LEVEL > 0) {
            using ChildT = typename NodeT::ChildNodeType;
            if (NodeT::LEVEL == level)
                dim = Int64(1) << ChildT::TOTAL;
            else
                self(self, static_cast<const ChildT*>(nullptr));
        }
    };
    walk(walk, static_cast<const typename TreeT::TopNodeType*>(nullptr));
    return dim;
}

/// Calls `fn(Block)` for every leaf (when `withLeaves`) and every tile selected by `filter`,
/// depth first: root entries in (x, y, z) order of their keys (OpenVDB's order; the C++
/// iterators follow the hash table's), each node's table in offset order.
/// The blocks point at the leaves without const: callers that read a const tree only read them.
template <typename TreeT, typename FnT>
void visitBlocks(TreeT& tree, ValueFilter filter, bool withLeaves, const FnT& fn) {
    using T = std::remove_const_t<TreeT>;
    using ValueT = typename T::ValueType;
    const auto visit = [&]<ValueFilter F>() {
        const auto onTile = [&](const auto& tile) {
            fn(Block<T>{tile.origin, tile.level, nullptr, tile.value, tile.active});
        };
        const auto onLeaf = [&](typename T::LeafNodeType& leaf) {
            fn(Block<T>{leaf.origin(), 0, &leaf, ValueT{}, false});
        };
        T& top = const_cast<T&>(tree);
        if (withLeaves)
            tree::visitBlocks<F>(top.topNode(), onTile, onLeaf);
        else
            tree::visitBlocks<F>(top.topNode(), onTile, nullptr);
    };
    switch (filter) {
        case ValueFilter::On:
            return visit.template operator()<ValueFilter::On>();
        case ValueFilter::Off:
            return visit.template operator()<ValueFilter::Off>();
        case ValueFilter::All:
            return visit.template operator()<ValueFilter::All>();
    }
}

/// The blocks of `tree` as visitBlocks() finds them.
template <typename TreeT>
std::vector<Block<std::remove_const_t<TreeT>>> collectBlocks(TreeT& tree, ValueFilter filter,
                                                             bool withLeaves = true) {
    std::vector<Block<std::remove_const_t<TreeT>>> blocks;
    visitBlocks(tree, filter, withLeaves, [&](const auto& b) { blocks.push_back(b); });
    return blocks;
}

/// The level of the node that stores the value at `ijk` (0: a leaf voxel; the top level: a root
/// tile or a region without an entry): the lowest level with a node holding `ijk`.
template <typename TreeT>
Index valueLevel(const TreeT& tree, const Coord& ijk) {
    using TopT = typename TreeT::TopNodeType;
    Index level = TopT::LEVEL;
    [&]<Index... L>(std::integer_sequence<Index, L...>) {
        (void)((tree.template get<tree::ops::ProbeNode<tree::NodeAtLevelT<TopT, L>>>(ijk)
                    ? (level = L, true)
                    : false) ||
               ...);
    }
    (std::make_integer_sequence<Index, TopT::LEVEL>{});
    return level;
}

// ---- Leaf buffer views

/// Counts, per tree, the NumPy arrays that view its leaf buffers (leafBuffers()). While a tree
/// has any, operations that can free or move leaf buffers refuse to run (checkUnpinned), so no
/// array ever views freed memory. Guarded by the GIL.
class Pins {
public:
    static void add(const void* tree) { ++counts()[tree]; }
    static void remove(const void* tree) {
        auto it = counts().find(tree);
        if (it != counts().end() && --it->second == 0)
            counts().erase(it);
    }
    static size_t count(const void* tree) {
        auto it = counts().find(tree);
        return it == counts().end() ? 0 : it->second;
    }

private:
    static std::unordered_map<const void*, size_t>& counts() {
        static std::unordered_map<const void*, size_t> map;
        return map;
    }
};

/// Throws RuntimeError when NumPy arrays view the leaf buffers of `tree`; `operation` names the
/// refused call.
inline void checkUnpinned(const void* tree, const char* operation) {
    if (const size_t n = Pins::count(tree); n > 0)
        throw std::runtime_error(std::string(operation) + ": " + std::to_string(n) +
                                 " NumPy array(s) from leafBuffers() view this grid's leaves; "
                                 "delete them first (this operation can free leaves)");
}

}  // namespace vdb::python
