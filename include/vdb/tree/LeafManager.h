// SPDX-License-Identifier: Apache-2.0
/// @file
/// LeafManager: a flat array of a tree's leaves for parallel loops over leaves (paper App. B),
/// and the per-leaf temporal buffers that time integrators swap instead of copying grids
/// (paper 2.3, 4.2).
///
/// @code
/// vdb::tree::LeafManager<vdb::FloatTree> leaves(tree);
/// leaves.foreach([](auto& leaf, size_t) {
///     for (auto it = leaf.beginValueOn(); it; ++it) it.setValue(*it * 2.0f);
/// });
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <type_traits>
#include <vector>

namespace vdb::tree {

/// The leaves of one tree in an array, in the tree's iteration order.
///
/// The array is a snapshot: after a change of topology call rebuild(). Value-only changes
/// through the leaves need no rebuild. Temporal buffers exist only for leaves that store values
/// in buffers (not bool or mask leaves); asking such a manager for auxiliary buffers throws.
/// Threads: foreach() hands each leaf to exactly one task, so an operation that touches only
/// the leaf it is given needs no locking. `TreeT` may be const for read-only loops.
template <typename TreeT>
class LeafManager {
public:
    using TreeType = std::remove_const_t<TreeT>;
    using LeafNodeType =
        std::conditional_t<std::is_const_v<TreeT>, const typename TreeType::LeafNodeType,
                           typename TreeType::LeafNodeType>;
    /// True when the leaves hold their values in buffers that can be multiplied and swapped.
    static constexpr bool HAS_BUFFERS = requires(typename TreeType::LeafNodeType & leaf) {
        leaf.setBufferCount(Index(1));
    };

    /// Collects the leaves of `tree`. With `auxBuffers` > 0 every leaf gets that many
    /// temporal buffers beside buffer 0, each a copy of buffer 0.
    /// @throw ValueError when `auxBuffers` > 0 and the leaves have no buffers (bool, mask).
    explicit LeafManager(TreeT& tree, Index auxBuffers = 0) : mTree(&tree) { rebuild(auxBuffers); }

    /// Collects the leaves again (after the topology changed).
    void rebuild(Index auxBuffers = 0) {
        mLeaves.clear();
        mLeaves.reserve(mTree->leafCount());
        for (auto it = beginLeaf(); it; ++it)
            mLeaves.push_back(it.getLeaf());
        mAuxBuffers = 0;
        if (auxBuffers > 0)
            initAuxBuffers(auxBuffers);
    }

    TreeT& tree() const { return *mTree; }
    size_t leafCount() const { return mLeaves.size(); }
    LeafNodeType& leaf(size_t n) const { return *mLeaves[n]; }
    LeafNodeType* const* data() const { return mLeaves.data(); }
    Index64 activeLeafVoxelCount() const {
        return util::parallelReduce(
            mLeaves.size(), Index64(0),
            [&](size_t b, size_t e) {
                Index64 sum = 0;
                for (size_t i = b; i < e; ++i)
                    sum += mLeaves[i]->onVoxelCount();
                return sum;
            },
            [](Index64 a, Index64 b) { return a + b; });
    }

    /// Calls `op(leaf, index)` for every leaf, in parallel when `threaded`.
    template <typename OpT>
    void foreach (const OpT& op, bool threaded = true, size_t grain = 8) const {
        util::parallelFor(
            mLeaves.size(), [&](size_t i) { op(*mLeaves[i], i); }, threaded, grain);
    }

    // ---- Temporal buffers (not on a const tree)
    Index auxBufferCount() const { return mAuxBuffers; }
    /// Gives every leaf `count` buffers beside buffer 0 (0 to 2), each a copy of buffer 0.
    void setAuxBufferCount(Index count, bool threaded = true) {
        static_assert(!std::is_const_v<TreeT>, "temporal buffers need a non-const tree");
        static_assert(HAS_BUFFERS, "bool and mask leaves have no temporal buffers");
        // A leaf that gains buffers gets them as copies of buffer 0; one that had them already
        // has them refreshed. Either way each auxiliary buffer is written once.
        foreach (
            [count](auto& leaf, size_t) {
                if (leaf.bufferCount() != 1 + count) {
                    leaf.setBufferCount(1 + count);
                    return;
                }
                for (Index b = 1; b <= count; ++b) {
                    auto src = leaf.buffer(0);
                    std::copy(src.begin(), src.end(), leaf.buffer(b).begin());
                }
            },
            threaded)
            ;
        mAuxBuffers = count;
    }
    /// Copies buffer 0 into every auxiliary buffer of every leaf.
    void syncAuxBuffers(bool threaded = true) {
        static_assert(!std::is_const_v<TreeT>, "temporal buffers need a non-const tree");
        const Index aux = mAuxBuffers;
        foreach (
            [aux](auto& leaf, size_t) {
                for (Index b = 1; b <= aux; ++b) {
                    auto src = leaf.buffer(0);
                    std::copy(src.begin(), src.end(), leaf.buffer(b).begin());
                }
            },
            threaded)
            ;
    }
    /// Exchanges buffers `a` and `b` of every leaf, in O(1) per leaf.
    void swapLeafBuffers(Index a, Index b, bool threaded = true) {
        static_assert(!std::is_const_v<TreeT>, "temporal buffers need a non-const tree");
        foreach ([a, b](auto& leaf, size_t) { leaf.swapBuffers(a, b); }, threaded, 256)
            ;
    }

private:
    void initAuxBuffers(Index count) {
        if constexpr (!std::is_const_v<TreeT> && HAS_BUFFERS) {
            setAuxBufferCount(count);
        } else {
            throw ValueError(
                "LeafManager: temporal buffers need a non-const tree whose leaves "
                "store values in buffers (not bool or mask leaves)");
        }
    }
    auto beginLeaf() const {
        if constexpr (std::is_const_v<TreeT>) {
            return mTree->cbeginLeaf();
        } else {
            return mTree->beginLeaf();
        }
    }

    TreeT* mTree;
    std::vector<LeafNodeType*> mLeaves;
    Index mAuxBuffers = 0;
};

}  // namespace vdb::tree
