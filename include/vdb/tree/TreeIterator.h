// SPDX-License-Identifier: Apache-2.0
/// @file
/// Tree-level iterators: every value (voxel or tile) selected by a filter, and every leaf.
/// They walk the node masks with word-wide bit searches (paper 3.3), so the cost is one
/// count-trailing-zeros per visited item plus one per empty 64-bit mask word.
/// Included by Tree.h; include that header instead.

#pragma once

#include <vdb/tree/Tree.h>

#include <bit>
#include <iterator>
#include <tuple>
#include <utility>

namespace vdb::tree {

namespace detail {

/// Returns the first position at or after `start` whose bit is set in the words produced by
/// `word(w)`, or `Size` when there is none.
template <Index Size, typename WordFn>
inline Index scanWords(Index start, const WordFn& word) {
    if (start >= Size)
        return Size;
    Index w = start >> 6;
    uint64_t bits = word(w) & (~uint64_t(0) << (start & 63));
    while (bits == 0) {
        if (++w == Size / 64)
            return Size;
        bits = word(w);
    }
    return (w << 6) + Index(std::countr_zero(bits));
}

/// A tuple of pointers to the node types of levels 0 .. Top of `TopT`.
template <typename TopT, typename Seq>
struct NodePtrTupleImpl;
template <typename TopT, size_t... L>
struct NodePtrTupleImpl<TopT, std::index_sequence<L...>> {
    using Type = std::tuple<NodeAtLevelT<TopT, Index(L)>*...>;
};
template <typename TopT>
using NodePtrTuple =
    typename NodePtrTupleImpl<TopT, std::make_index_sequence<TopT::LEVEL + 1>>::Type;

enum class WalkMode { ValueOn, ValueOff, ValueAll, Leaf, Node };

/// The depth-first walk shared by the value and leaf iterators. It keeps one node and one table
/// position per level; `mLevel` is the level of the current item.
template <typename TreeT, WalkMode Mode>
class TreeWalk {
public:
    using Tree = std::remove_const_t<TreeT>;
    using TopT = typename Tree::TopNodeType;
    using ValueType = typename Tree::ValueType;
    static constexpr Index TOP = TopT::LEVEL;
    static constexpr bool ROOT_TOP = IS_ROOT_NODE<TopT>;
    // Walks over active or inactive voxels read a leaf's mask a word at a time and keep the
    // rest of the current word, as BitMask's iterators do.
    static constexpr bool VOXEL_BITS = Mode == WalkMode::ValueOn || Mode == WalkMode::ValueOff;
    template <Index L>
    using NodeT = NodeAtLevelT<TopT, L>;
    template <typename N, bool IsRoot = IS_ROOT_NODE<N>>
    struct TopPosOf {
        using Type = Index;
    };
    template <typename N>
    struct TopPosOf<N, true> {
        using Type = typename N::Cursor;
    };
    using TopPos = typename TopPosOf<TopT>::Type;

    TreeWalk() = default;
    explicit TreeWalk(TreeT& tree) {
        std::get<TOP>(mNodes) = const_cast<TopT*>(&tree.topNode());
        if constexpr (ROOT_TOP) {
            mTopPos = top()->cbegin();
        } else {
            mTopPos = 0;
        }
        mDone = false;
        if constexpr (Mode == WalkMode::Node) {
            mLevel = TOP;  // the top node is the first item
        } else {
            climb<TOP>();
        }
    }

    bool done() const { return mDone; }
    Index level() const { return mLevel; }
    void increment() {
        if constexpr (VOXEL_BITS) {
            // The next voxel in the current mask word of the leaf: no load. (mBits is zero
            // unless the walk is at a voxel.)
            if (mBits != 0) {
                mPos[0] = (mPos[0] & ~Index(63)) + Index(std::countr_zero(mBits));
                mBits &= mBits - 1;
                return;
            }
        }
        if constexpr (Mode == WalkMode::Node) {
            incrementNode<0>();
        } else {
            incrementAt<Mode == WalkMode::Leaf ? 1 : 0>();
        }
    }

    template <Index L>
    NodeT<L>* node() const {
        return std::get<L>(mNodes);
    }
    TopT* top() const { return std::get<TOP>(mNodes); }

    /// Calls `fn(std::integral_constant<Index, L>)` for the current level L.
    template <typename Fn, Index L = 0>
    decltype(auto) dispatch(const Fn& fn) const {
        if constexpr (L == TOP) {
            return fn(std::integral_constant<Index, L>{});
        } else {
            if (mLevel == L)
                return fn(std::integral_constant<Index, L>{});
            return dispatch<Fn, L + 1>(fn);
        }
    }

    /// Position of the current item in its node's table (L < TOP or a bounded top).
    template <Index L>
    Index pos() const {
        if constexpr (L == TOP) {
            return mTopPos;
        } else {
            return mPos[L];
        }
    }
    const TopPos& topPos() const { return mTopPos; }
    /// The root entry at the current top position; a template so that it is only
    /// instantiated for trees whose top is a root.
    template <Index L>
    auto& topEntry() const {
        return top()->entry(mTopPos);
    }
    template <Index L>
    Coord topKey() const {
        return top()->key(mTopPos);
    }

private:
    static constexpr bool tileMatches(bool active) {
        if constexpr (Mode == WalkMode::ValueOn) {
            return active;
        } else if constexpr (Mode == WalkMode::ValueOff) {
            return !active;
        } else {
            return Mode == WalkMode::ValueAll;
        }
    }

    template <Index L>
    Index& posAt() {
        if constexpr (L == TOP) {
            return mTopPos;
        } else {
            return mPos[L];
        }
    }

    // Enters the child `child` of the node at level L and searches it from its start.
    template <Index L>
    bool descend(NodeT<L - 1>* child) {
        std::get<L - 1>(mNodes) = child;
        if constexpr (Mode == WalkMode::Node) {
            mLevel = L - 1;  // a node is visited when it is entered
            return true;
        } else if constexpr (Mode == WalkMode::Leaf && L == 1) {
            mLevel = 1;
            return true;
        } else {
            mPos[L - 1] = 0;
            return seek<L - 1>();
        }
    }

    // Finds the next item at or after the current position of level L, descending into
    // children; false when the node at level L is exhausted.
    template <Index L>
    bool seek() {
        if constexpr (L == 0) {
            const auto* leaf = node<0>();
            Index p = mPos[0];
            if constexpr (Mode == WalkMode::ValueOn) {
                p = leaf->getValueMask().findNextOn(p);
            } else if constexpr (Mode == WalkMode::ValueOff) {
                p = leaf->getValueMask().findNextOff(p);
            }
            mPos[0] = p;
            if (p >= NodeT<0>::NUM_VALUES)
                return false;
            if constexpr (VOXEL_BITS) {
                const uint64_t word = leaf->getValueMask().getWord(p >> 6);
                mBits = (Mode == WalkMode::ValueOn ? word : ~word) & (~uint64_t(1) << (p & 63));
            }
            mLevel = 0;
            return true;
        } else if constexpr (L == TOP && ROOT_TOP) {
            TopT* root = top();
            for (; root->valid(mTopPos); root->next(mTopPos)) {
                auto& e = root->entry(mTopPos);
                if (e.child) {
                    if (descend<L>(e.child))
                        return true;
                } else if (tileMatches(e.active)) {
                    mLevel = L;
                    return true;
                }
            }
            return false;
        } else {
            using N = NodeT<L>;
            N* n = node<L>();
            const auto& child = n->getChildMask();
            const auto& value = n->getValueMask();
            Index& p = posAt<L>();
            for (;;) {
                if constexpr (Mode == WalkMode::ValueOn) {
                    p = scanWords<N::NUM_VALUES>(
                        p, [&](Index w) { return child.getWord(w) | value.getWord(w); });
                } else if constexpr (Mode == WalkMode::ValueOff) {
                    p = scanWords<N::NUM_VALUES>(p, [&](Index w) { return ~value.getWord(w); });
                } else if constexpr (Mode == WalkMode::Leaf || Mode == WalkMode::Node) {
                    p = child.findNextOn(p);
                }
                if (p >= N::NUM_VALUES)
                    return false;
                if (child.isOn(p)) {
                    if constexpr (L == 1 && Mode != WalkMode::Node)
                        prefetchLeafAfter(*n, p);
                    if (descend<L>(n->getChild(p)))
                        return true;
                    ++p;
                    continue;
                }
                mLevel = L;
                return true;
            }
        }
    }

    // Entering the leaf at `p` of `node`: hints the values of the next leaf, so that its cache
    // misses overlap the walk over this one (leaves and their buffers lie anywhere in memory).
    template <typename N>
    static void prefetchLeafAfter(const N& node, Index p) {
        if constexpr (requires(const NodeT<0>& leaf) { leaf.prefetchValues(); }) {
            const Index next = node.getChildMask().findNextOn(p + 1);
            if (next < N::NUM_VALUES)
                node.getChild(next)->prefetchValues();
        }
    }

    // Steps past the current position at level L, then continues the search upwards.
    template <Index L>
    void advance() {
        if constexpr (L == TOP && ROOT_TOP) {
            top()->next(mTopPos);
        } else {
            ++posAt<L>();
        }
        climb<L>();
    }
    template <Index L>
    void climb() {
        if (seek<L>())
            return;
        if constexpr (L == TOP) {
            mDone = true;
        } else {
            advance<L + 1>();
        }
    }
    // Node mode: after a leaf, move on in its parent; after any other node, enter its table.
    template <Index L>
    void incrementNode() {
        if constexpr (L < TOP) {
            if (mLevel != L) {
                incrementNode<L + 1>();
                return;
            }
        }
        if constexpr (L == 0) {
            advance<1>();
        } else {
            if constexpr (L == TOP && ROOT_TOP) {
                mTopPos = top()->cbegin();
            } else {
                posAt<L>() = 0;
            }
            climb<L>();
        }
    }
    template <Index L>
    void incrementAt() {
        if constexpr (L < TOP) {
            if (mLevel != L) {
                incrementAt<L + 1>();
                return;
            }
        }
        advance<L>();
    }

    NodePtrTuple<TopT> mNodes{};
    std::array<Index, TOP> mPos{};  // table position per level below the top
    TopPos mTopPos{};
    Index mLevel = 0;
    bool mDone = true;
    uint64_t mBits = 0;  // VOXEL_BITS: the voxels after mPos[0] in its mask word, at a voxel
};

}  // namespace detail

/// Visits every value of a tree selected by `Filter`: voxels in leaves and tiles at every level
/// (an On iterator visits active voxels and active tiles; Off and All also visit inactive
/// tiles of internal nodes, but never the implicit background outside the root's entries).
///
/// Use: `for (auto it = tree.cbeginValueOn(); it; ++it) f(it.getCoord(), *it);`
/// The order is depth-first by table position. Changing values with setValue() is allowed
/// during iteration; changing the topology is not. Active states: the current item's may
/// change (see setActiveState()); a leaf's mask is read 64 voxels (one word) at a time, so a
/// change to another voxel of the current word is not seen by an On or Off iterator.
template <typename TreeT, ValueFilter Filter>
class TreeValueIterator {
    static constexpr detail::WalkMode MODE = Filter == ValueFilter::On ? detail::WalkMode::ValueOn
                                             : Filter == ValueFilter::Off
                                                 ? detail::WalkMode::ValueOff
                                                 : detail::WalkMode::ValueAll;
    using Walk = detail::TreeWalk<TreeT, MODE>;
    static constexpr Index TOP = Walk::TOP;
    static constexpr bool IS_CONST = std::is_const_v<TreeT>;

public:
    using ValueType = typename Walk::ValueType;

    TreeValueIterator() = default;
    explicit TreeValueIterator(TreeT& tree) : mWalk(tree), mTree(&tree) {}

    /// The tree the iterator walks. @pre the iterator was made from a tree
    TreeT& getTree() const { return *mTree; }

    explicit operator bool() const { return !mWalk.done(); }
    bool test() const { return !mWalk.done(); }
    bool operator==(std::default_sentinel_t) const { return mWalk.done(); }
    TreeValueIterator& operator++() {
        mWalk.increment();
        return *this;
    }

    /// 0 for a voxel, the level of the node holding the tile otherwise.
    Index getLevel() const { return mWalk.level(); }
    bool isVoxelValue() const { return mWalk.level() == 0; }
    bool isTileValue() const { return mWalk.level() != 0; }

    ValueType getValue() const {
        return mWalk.dispatch([&](auto level) -> ValueType {
            constexpr Index L = decltype(level)::value;
            if constexpr (L == 0) {
                return mWalk.template node<0>()->getValue(mWalk.template pos<0>());
            } else if constexpr (L == TOP && Walk::ROOT_TOP) {
                return mWalk.template topEntry<L>().tile;
            } else {
                return mWalk.template node<L>()->getTileValue(mWalk.template pos<L>());
            }
        });
    }
    ValueType operator*() const { return getValue(); }

    bool isValueOn() const {
        if constexpr (Filter == ValueFilter::On) {
            return true;
        } else if constexpr (Filter == ValueFilter::Off) {
            return false;
        } else {
            return mWalk.dispatch([&](auto level) -> bool {
                constexpr Index L = decltype(level)::value;
                if constexpr (L == 0) {
                    return mWalk.template node<0>()->isValueOn(mWalk.template pos<0>());
                } else if constexpr (L == TOP && Walk::ROOT_TOP) {
                    return mWalk.template topEntry<L>().active;
                } else {
                    return mWalk.template node<L>()->isTileOn(mWalk.template pos<L>());
                }
            });
        }
    }

    /// The voxel, or the first voxel of the tile.
    Coord getCoord() const {
        return mWalk.dispatch([&](auto level) -> Coord {
            constexpr Index L = decltype(level)::value;
            if constexpr (L == TOP && Walk::ROOT_TOP) {
                return mWalk.template topKey<L>();
            } else {
                return mWalk.template node<L>()->offsetToGlobalCoord(mWalk.template pos<L>());
            }
        });
    }
    /// Sets `bbox` to the voxel or to the whole region of the tile; returns true.
    bool getBoundingBox(CoordBBox& bbox) const {
        const Coord ijk = getCoord();
        const Int32 dim = mWalk.dispatch([](auto level) -> Int32 {
            constexpr Index L = decltype(level)::value;
            if constexpr (L == 0) {
                return 1;
            } else {
                return Int32(Walk::template NodeT<L - 1>::DIM);
            }
        });
        bbox = CoordBBox::createCube(ijk, dim);
        return true;
    }

    /// Changes the current voxel's or tile's value, keeping its state.
    void setValue(const ValueType& value) const requires(!IS_CONST) {
        mWalk.dispatch([&](auto level) {
            constexpr Index L = decltype(level)::value;
            if constexpr (L == 0) {
                mWalk.template node<0>()->setValueOnly(mWalk.template pos<0>(), value);
            } else if constexpr (L == TOP && Walk::ROOT_TOP) {
                mWalk.template topEntry<L>().tile = value;
            } else {
                mWalk.template node<L>()->setTileValueOnly(mWalk.template pos<L>(), value);
            }
        });
    }

    /// Changes the current voxel's or tile's active state, keeping its value (in a mask tree a
    /// tile's value follows its state). A value-on iterator may turn off its current item and
    /// go on; the walk continues after it.
    void setActiveState(bool on) const requires(!IS_CONST) {
        mWalk.dispatch([&](auto level) {
            constexpr Index L = decltype(level)::value;
            if constexpr (L == 0) {
                mWalk.template node<0>()->setActiveState(mWalk.template pos<0>(), on);
            } else if constexpr (L == TOP && Walk::ROOT_TOP) {
                auto& entry = mWalk.template topEntry<L>();
                entry.tile = detail::tileValue<typename Walk::template NodeT<L>>(entry.tile, on);
                entry.active = on;
            } else {
                auto* node = mWalk.template node<L>();
                const Index n = mWalk.template pos<L>();
                node->setTile(
                    n,
                    detail::tileValue<typename Walk::template NodeT<L>>(node->getTileValue(n), on),
                    on);
            }
        });
    }
    /// OpenVDB's names for setActiveState(on) and setActiveState(false).
    void setValueOn(bool on = true) const requires(!IS_CONST) { setActiveState(on); }
    void setValueOff() const requires(!IS_CONST) { setActiveState(false); }

private:
    Walk mWalk;
    TreeT* mTree = nullptr;
};

/// Visits every leaf of a tree once: `for (auto it = tree.cbeginLeaf(); it; ++it) it->origin();`
/// or `for (auto& leaf : tree.leaves())`.
template <typename TreeT>
class TreeLeafIterator {
    using Walk = detail::TreeWalk<TreeT, detail::WalkMode::Leaf>;

public:
    using LeafT = std::conditional_t<std::is_const_v<TreeT>,
                                     const typename std::remove_const_t<TreeT>::LeafNodeType,
                                     typename std::remove_const_t<TreeT>::LeafNodeType>;

    TreeLeafIterator() = default;
    explicit TreeLeafIterator(TreeT& tree) : mWalk(tree) {}

    explicit operator bool() const { return !mWalk.done(); }
    bool test() const { return !mWalk.done(); }
    bool operator==(std::default_sentinel_t) const { return mWalk.done(); }
    TreeLeafIterator& operator++() {
        mWalk.increment();
        return *this;
    }
    LeafT& operator*() const { return *mWalk.template node<0>(); }
    LeafT* operator->() const { return mWalk.template node<0>(); }
    LeafT* getLeaf() const { return mWalk.template node<0>(); }

private:
    Walk mWalk;
};

/// Visits every node of a tree once, depth-first, each before its children, the top node
/// first: `for (auto it = tree.cbeginNode(); it; ++it) if (auto* leaf =
/// it.getNode<LeafT>()) ...`.
template <typename TreeT>
class TreeNodeIterator {
    using Walk = detail::TreeWalk<TreeT, detail::WalkMode::Node>;
    static constexpr Index TOP = Walk::TOP;

public:
    TreeNodeIterator() = default;
    explicit TreeNodeIterator(TreeT& tree) : mWalk(tree) {}

    explicit operator bool() const { return !mWalk.done(); }
    bool test() const { return !mWalk.done(); }
    bool operator==(std::default_sentinel_t) const { return mWalk.done(); }
    TreeNodeIterator& operator++() {
        mWalk.increment();
        return *this;
    }

    /// The current node's level: 0 for a leaf, DEPTH-1 for the top.
    Index getLevel() const { return mWalk.level(); }
    /// The current node if its type is NodeT, else null.
    template <typename NodeT>
    NodeT* getNode() const {
        return mWalk.dispatch([&](auto level) -> NodeT* {
            constexpr Index L = decltype(level)::value;
            using Found = typename Walk::template NodeT<L>;
            if constexpr (std::is_same_v<std::remove_const_t<NodeT>, Found> &&
                          (std::is_const_v<NodeT> || !std::is_const_v<TreeT>)) {
                return mWalk.template node<L>();
            } else {
                return nullptr;
            }
        });
    }
    /// The origin of the current node (the origin of index space for a root).
    Coord getCoord() const {
        return mWalk.dispatch([&](auto level) -> Coord {
            constexpr Index L = decltype(level)::value;
            if constexpr (L == TOP && Walk::ROOT_TOP) {
                return Coord(0);
            } else {
                return mWalk.template node<L>()->origin();
            }
        });
    }
    /// Sets `bbox` to the region the current node covers.
    bool getBoundingBox(CoordBBox& bbox) const {
        bbox = mWalk.dispatch([&](auto level) -> CoordBBox {
            constexpr Index L = decltype(level)::value;
            if constexpr (L == TOP && Walk::ROOT_TOP) {
                return CoordBBox::inf();
            } else {
                return mWalk.template node<L>()->getNodeBoundingBox();
            }
        });
        return true;
    }

private:
    Walk mWalk;
};

// ---- Tree's iterator factories

template <TopNodeType TopT>
auto Tree<TopT>::beginNode() -> NodeIter {
    return NodeIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::cbeginNode() const -> NodeCIter {
    return NodeCIter(*this);
}

template <TopNodeType TopT>
auto Tree<TopT>::beginValueOn() -> ValueOnIter {
    return ValueOnIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::beginValueOn() const -> ValueOnCIter {
    return ValueOnCIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::cbeginValueOn() const -> ValueOnCIter {
    return ValueOnCIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::beginValueOff() -> ValueOffIter {
    return ValueOffIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::beginValueOff() const -> ValueOffCIter {
    return ValueOffCIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::cbeginValueOff() const -> ValueOffCIter {
    return ValueOffCIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::beginValueAll() -> ValueAllIter {
    return ValueAllIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::beginValueAll() const -> ValueAllCIter {
    return ValueAllCIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::cbeginValueAll() const -> ValueAllCIter {
    return ValueAllCIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::beginLeaf() -> LeafIter {
    return LeafIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::beginLeaf() const -> LeafCIter {
    return LeafCIter(*this);
}
template <TopNodeType TopT>
auto Tree<TopT>::cbeginLeaf() const -> LeafCIter {
    return LeafCIter(*this);
}

}  // namespace vdb::tree
