// SPDX-License-Identifier: Apache-2.0
/// @file
/// The tree walks of the Python module, written once: the blocks of a tree (its leaves and its
/// tiles, in OpenVDB's iteration order), the level at which a coordinate's value
/// is stored, and the registry of trees whose leaf buffers NumPy arrays view.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/Tree.h>

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <unordered_map>
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

namespace detail {

template <typename TreeT, typename NodeT, typename FnT>
void visitNode(NodeT& node, ValueFilter filter, bool withLeaves, const FnT& fn) {
    using ValueT = typename TreeT::ValueType;
    const auto tileSelected = [filter](bool active) {
        return filter == ValueFilter::All || (filter == ValueFilter::On) == active;
    };
    if constexpr (NodeT::LEVEL == 0) {
        if (withLeaves)
            fn(Block<TreeT>{node.origin(), 0, &node, ValueT{}, false});
    } else if constexpr (tree::IS_ROOT_NODE<NodeT>) {
        // Root entries in (x, y, z) order, as OpenVDB's root map keeps them.
        for (const Coord& key : node.sortedKeys()) {
            auto& entry = *node.findEntry(key);
            if (entry.child)
                visitNode<TreeT>(*entry.child, filter, withLeaves, fn);
            else if (tileSelected(entry.active))
                fn(Block<TreeT>{key, NodeT::LEVEL, nullptr, entry.tile, entry.active});
        }
    } else {
        const uint64_t* children = node.getChildMask().words();
        const uint64_t* values = node.getValueMask().words();
        for (Index w = 0; w < NodeT::NUM_VALUES / 64; ++w) {
            uint64_t tiles = ~children[w];
            if (filter == ValueFilter::On)
                tiles &= values[w];
            else if (filter == ValueFilter::Off)
                tiles &= ~values[w];
            uint64_t bits = children[w] | tiles;
            while (bits) {
                const Index n = w * 64 + Index(std::countr_zero(bits));
                bits &= bits - 1;
                if (auto* child = node.getChild(n))
                    visitNode<TreeT>(*child, filter, withLeaves, fn);
                else
                    fn(Block<TreeT>{node.offsetToGlobalCoord(n), NodeT::LEVEL, nullptr,
                                    node.getTileValue(n), ((values[w] >> (n & 63)) & 1) != 0});
            }
        }
    }
}

}  // namespace detail

/// Calls `fn(Block)` for every leaf (when `withLeaves`) and every tile selected by `filter`,
/// depth first: root entries in (x, y, z) order of their keys (OpenVDB's order; the C++
/// iterators follow the hash table's), each node's table in offset order.
/// The blocks point at the leaves without const: callers that read a const tree only read them.
template <typename TreeT, typename FnT>
void visitBlocks(TreeT& tree, ValueFilter filter, bool withLeaves, const FnT& fn) {
    using T = std::remove_const_t<TreeT>;
    detail::visitNode<T>(const_cast<T&>(tree).topNode(), filter, withLeaves, fn);
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
/// tile or a region without an entry).
template <typename TreeT>
Index valueLevel(const TreeT& tree, const Coord& ijk) {
    auto walk = [&]<typename NodeT>(auto& self, const NodeT& node) -> Index {
        if constexpr (NodeT::LEVEL == 0) {
            return 0;
        } else if constexpr (tree::IS_ROOT_NODE<NodeT>) {
            const auto* e = node.findEntry(NodeT::coordToKey(ijk));
            return e && e->child ? self(self, *e->child) : NodeT::LEVEL;
        } else {
            const auto* child = node.getChild(NodeT::coordToOffset(ijk));
            return child ? self(self, *child) : NodeT::LEVEL;
        }
    };
    return walk(walk, tree.topNode());
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
