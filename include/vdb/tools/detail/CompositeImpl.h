// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery of the CSG operations of tools/Composite.h: one top-down walk over two level
/// set trees that settles whole branches by their tiles and collects the pairs of overlapping
/// leaves, which are then combined voxel by voxel in parallel. Not API.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/tree/LeafNode.h>
#include <vdb/tree/NodeTraits.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Assert.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

enum class CsgKind { Union, Intersection, Difference };

/// Throws ValueError unless `background` is positive (and its negation negative), the sign
/// convention every level set input of a CSG operation must follow.
template <typename ValueT>
void validateLevelSetBackground(const ValueT& background, const char* operation, const char* name) {
    if (!(background > ValueT(0)) || !(-background < ValueT(0))) {
        std::ostringstream msg;
        msg << operation << ": expected the background of level set " << name
            << " to be positive (the outside value), got " << background;
        throw ValueError(msg.str());
    }
}

/// Merges level set `b` into level set `a` (paper 4.3), with OpenVDB 10's rules:
///
/// - Where one tree has a tile and the other a child, the tile decides for the whole branch.
///   For a union an inside tile (negative) wins over anything and is stored as -background; an
///   outside tile (positive) loses, so the other tree's branch is kept or transferred. For an
///   intersection the roles of inside and outside swap. For a difference a - b, an inside tile
///   of b over anything of a makes an outside tile (+background), and b's branches that fall
///   in an inside tile of a are transferred negated.
/// - Where both trees have a leaf, each voxel takes min(a, b) (union), max(a, b) (intersection)
///   or max(a, -b) (difference), with the active state of the input it came from; ties keep a.
/// - At the root, tiles are normalised to +-background of `a` and background tiles dropped.
///
/// Transferred branches get b's background replaced by a's in their inactive values (within
/// OpenVDB's tolerance), then are negated for a difference.
///
/// With `Steal` (the in-place forms), run() merges b into a: b's branches are stolen (b is then
/// cleared by the caller), the overlapping leaves are combined in a's leaves and the stolen
/// leaves fixed up in place. Without `Steal` (the Copy forms), buildFrom() makes `a`, an empty
/// tree, the result of merging b into a third tree, reading both inputs and writing each node
/// of the result once: a's nodes that b's tiles decide, b's branches the merge drops and, for an
/// intersection, a's root entries b lacks are never copied; a leaf present in both is written
/// in one pass from the two, a transferred leaf in one pass from b's.
///
/// Threads: the walks over the root and the internal nodes above level 1 are serial. The
/// voxel work runs in parallel: with Steal over the leaf pairs and the transferred leaves;
/// without, over the level-1 nodes of the result, each built by one task that builds its
/// leaves in parallel again. Each node and leaf is written by one task, so the result does not
/// depend on the thread count.
template <typename TreeT, CsgKind Kind, bool Steal>
class CsgMerge {
public:
    using ValueT = typename TreeT::ValueType;
    using TopT = typename TreeT::TopNodeType;
    using LeafT = typename TreeT::LeafNodeType;
    using OtherTreeT = std::conditional_t<Steal, TreeT, const TreeT>;
    using OtherTopT = std::conditional_t<Steal, TopT, const TopT>;
    using OtherTopChildT =
        std::conditional_t<Steal, typename TopT::ChildNodeType, const typename TopT::ChildNodeType>;

    static constexpr bool UNION = Kind == CsgKind::Union;
    static constexpr bool DIFFERENCE = Kind == CsgKind::Difference;

    CsgMerge(TreeT& a, OtherTreeT& b)
        : mA(a),
          mB(b),
          mBackgroundA(a.background()),
          mBackgroundB(b.background()),
          mMovedNeedFix(DIFFERENCE || !(a.background() == b.background())) {}

    /// Merges b into a.
    void run(bool threaded) requires(Steal) {
        if constexpr (TreeT::BOUNDED) {
            mergeNode(mA.topNode(), mB.topNode());
        } else if constexpr (DIFFERENCE) {
            mergeRootDifference(mA.root(), mB.root());
        } else {
            mergeRoot(mA.root(), mB.root());
        }
        // The voxel work: overlapping leaves, then the leaves of transferred branches.
        util::parallelFor(
            mLeafPairs.size(),
            [this](size_t i) {
                LeafT& leaf = *mLeafPairs[i].first;
                const auto values = leaf.buffer(0);
                combineValues(values.data(), leaf.getValueMask(), *mLeafPairs[i].second,
                              values.data(), leaf.getValueMask());
            },
            threaded, 4);
        util::parallelFor(
            mMovedLeaves.size(),
            [this](size_t i) {
                LeafT& leaf = *mMovedLeaves[i];
                const auto values = leaf.buffer(0);
                moveValues(values.data(), leaf.getValueMask(), values.data());
            },
            threaded, 16);
        mA.clearAllAccessors();
    }

    /// Makes `a`, which must be empty and have `start`'s background, what merging b into
    /// `start` gives, without changing `start` or b.
    void buildFrom(const TreeT& start, bool threaded) requires(!Steal) {
        mThreaded = threaded;
        if constexpr (TreeT::BOUNDED) {
            buildNode(mA.topNode(), start.topNode(), &mB.topNode(), /*moved=*/false);
        } else {
            // The children of the root are merged in full as they are built; the root's own
            // entries follow the merge's root rules.
            buildStartRoot(mA.root(), start.root(), mB.root());
            if constexpr (DIFFERENCE) {
                mergeRootDifference(mA.root(), mB.root());
            } else {
                mergeRoot(mA.root(), mB.root());
            }
        }
        buildLevelOneNodes();
        mA.clearAllAccessors();
    }

private:
    // ---- Values

    bool isWinning(const ValueT& v) const { return UNION ? v < ValueT(0) : v > ValueT(0); }
    bool isLosing(const ValueT& v) const { return UNION ? v > ValueT(0) : v < ValueT(0); }
    /// The tile value of a winning tile: inside for a union, outside for an intersection.
    ValueT winningBackground() const { return UNION ? ValueT(-mBackgroundA) : mBackgroundA; }

    /// A value of a branch moved from b to a: b's background becomes a's (inactive values
    /// only), then the value is negated for a difference.
    ValueT movedValue(ValueT v, bool active) const {
        if (!active && !(mBackgroundA == mBackgroundB)) {
            if (math::isApproxEqual(v, mBackgroundB)) {
                v = mBackgroundA;
            } else if (math::isApproxEqual(v, ValueT(-mBackgroundB))) {
                v = -mBackgroundA;
            }
        }
        if constexpr (DIFFERENCE)
            v = -v;
        return v;
    }

    // ---- Entries of internal nodes

    /// What the merge makes of one entry of two internal nodes at the same place.
    enum class EntryRule {
        KeepA,  ///< a's tile or child stays
        Tile,   ///< a tile of b decides: decidedValue(), with the state of b's tile
        MoveB,  ///< b's child moves into a's tile
        Merge,  ///< both children are merged
    };

    /// The rule for an entry where a holds a child (`aChild`) or the tile `aTile`, and b a
    /// child or the tile `bTile` (a tile value is ignored where there is a child).
    EntryRule entryRule(bool aChild, const ValueT& aTile, bool bChild, const ValueT& bTile) const {
        if constexpr (DIFFERENCE) {
            // b's inside tiles make a outside over a's inside tiles and children; b's children
            // move negated into a's inside tiles.
            const bool aInside = !aChild && aTile < ValueT(0);
            if (!bChild)
                return bTile < ValueT(0) && (aChild || aInside) ? EntryRule::Tile
                                                                : EntryRule::KeepA;
            return aInside ? EntryRule::MoveB : aChild ? EntryRule::Merge : EntryRule::KeepA;
        } else {
            // A winning tile of a keeps its place; b's winning tiles replace anything else of
            // a; b's children move into a's losing tiles (zero tiles are neither).
            if (!aChild && isWinning(aTile))
                return EntryRule::KeepA;
            if (!bChild)
                return isWinning(bTile) ? EntryRule::Tile : EntryRule::KeepA;
            return aChild            ? EntryRule::Merge
                   : isLosing(aTile) ? EntryRule::MoveB
                                     : EntryRule::KeepA;
        }
    }
    template <typename ANodeT, typename BNodeT>
    EntryRule entryRule(const ANodeT& a, const BNodeT& b, Index n) const {
        const bool aChild = a.isChild(n), bChild = b.isChild(n);
        return entryRule(aChild, aChild ? ValueT{} : a.getTileValue(n), bChild,
                         bChild ? ValueT{} : b.getTileValue(n));
    }
    /// The value of an EntryRule::Tile.
    ValueT decidedValue() const { return DIFFERENCE ? mBackgroundA : winningBackground(); }

    // ---- Leaves

    /// Combines the values `av` and states `am` of a's leaf with b's leaf `b` into `out` and
    /// `outMask` (which may be `av` and `am`): each voxel takes the winning value and that
    /// input's active state; the states are merged a 64-bit mask word at a time.
    template <typename MaskT>
    static void combineValues(const ValueT* av, const MaskT& am, const LeafT& b, ValueT* out,
                              MaskT& outMask) {
        const auto bv = b.buffer(0);
        const auto& bm = b.getValueMask();
        for (Index w = 0; w < MaskT::WORD_COUNT; ++w) {
            uint64_t take = 0;
            for (Index i = 0; i < 64; ++i) {
                const Index k = (w << 6) + i;
                const ValueT other = DIFFERENCE ? ValueT(-bv[k]) : bv[k];
                const bool fromB = UNION ? other < av[k] : av[k] < other;
                take |= uint64_t(fromB) << i;
                out[k] = fromB ? other : av[k];
            }
            outMask.getWord(w) = (am.getWord(w) & ~take) | (bm.getWord(w) & take);
        }
    }

    /// Writes movedValue() of the values `in` with states `mask` to `out` (which may be `in`).
    template <typename MaskT>
    void moveValues(const ValueT* in, const MaskT& mask, ValueT* out) const {
        if (mBackgroundA == mBackgroundB) {
            // The values of a difference, negated; states do not matter.
            for (Index k = 0; k < LeafT::NUM_VALUES; ++k)
                out[k] = DIFFERENCE ? ValueT(-in[k]) : in[k];
            return;
        }
        for (Index w = 0; w < MaskT::WORD_COUNT; ++w) {
            const uint64_t on = mask.getWord(w);
            for (Index i = 0; i < 64; ++i) {
                const Index k = (w << 6) + i;
                out[k] = movedValue(in[k], (on >> i) & 1u);
            }
        }
    }

    // ---- Branches moved from b to a (Steal)

    template <typename NodeT>
    void prepareMoved(NodeT& node) {
        if (!mMovedNeedFix)
            return;
        if constexpr (NodeT::LEVEL == 0) {
            mMovedLeaves.push_back(&node);
        } else {
            for (Index n : node.getChildMask().offBits())
                node.setTileValueOnly(n, movedValue(node.getTileValue(n), node.isTileOn(n)));
            for (Index n : node.getChildMask().onBits())
                prepareMoved(*node.getChild(n));
        }
    }

    /// Steals the child at `n` of b into entry `n` of a.
    template <typename NodeT>
    void moveChild(NodeT& a, Index n, NodeT& b) {
        std::unique_ptr<typename NodeT::ChildNodeType> child(b.stealChild(n, mBackgroundB, false));
        prepareMoved(*child);
        a.setChild(n, child.release());
    }

    static OtherTopChildT& otherChild(OtherTopT& bRoot, const Coord& key) {
        return *bRoot.findEntry(key)->child;
    }

    /// Moves b's root child at `key` into a: stolen, or built as a moved branch.
    void moveRootChild(TopT& a, OtherTopT& bRoot, const Coord& key) {
        using ChildT = typename TopT::ChildNodeType;
        std::unique_ptr<ChildT> child;
        if constexpr (Steal) {
            child.reset(bRoot.stealChild(key));
            prepareMoved(*child);
        } else {
            child = buildBranch(otherChild(bRoot, key), static_cast<const ChildT*>(nullptr),
                                /*moved=*/true);
        }
        a.setChild(child.get());
        child.release();
    }

    // ---- Building the result (no Steal)

    /// The level-1 nodes of the result are built by tasks, where their parents are internal
    /// nodes: each task builds one with its leaves, and the parents take them afterwards.
    using LevelOneT = tree::NodeAtLevelT<TopT, 1>;
    using LevelTwoT = tree::NodeAtLevelT<TopT, (TopT::LEVEL >= 2 ? 2 : 1)>;
    static constexpr bool LEVEL_ONE_JOBS = TopT::LEVEL >= 2 && !tree::IS_ROOT_NODE<LevelTwoT>;
    struct LevelOneJob {
        LevelTwoT* parent;
        Index n;
        const LevelOneT* source;
        const LevelOneT* other;  // b's node at the same place, merged with `source`, or null
        bool moved;
    };

    /// Copies the tiles of internal node `src` into `dst` (a new node of the same origin),
    /// as moved values when `moved`. The entries of src's children are left to the caller.
    template <typename NodeT>
    void copyTiles(NodeT& dst, const NodeT& src, bool moved) const {
        const bool fix = moved && mMovedNeedFix;
        const auto copy = [&](Index n) {
            const ValueT& v = src.getTileValue(n);
            dst.setTileValueOnly(n, fix ? movedValue(v, src.isTileOn(n)) : v);
        };
        const auto& children = src.getChildMask();
        if constexpr (NodeT::NUM_VALUES % 64 == 0) {
            // A mask word at a time: most words of a node hold tiles only.
            for (Index w = 0; w < NodeT::NUM_VALUES / 64; ++w) {
                const Index base = w << 6;
                uint64_t tiles = ~children.getWord(w);
                if (tiles == ~uint64_t(0) && !fix) {
                    for (Index i = 0; i < 64; ++i)
                        dst.setTileValueOnly(base + i, src.getTileValue(base + i));
                    continue;
                }
                for (; tiles; tiles &= tiles - 1)
                    copy(base + Index(std::countr_zero(tiles)));
            }
        } else {
            for (Index n : children.offBits())
                copy(n);
        }
        dst.updateTileStates([&](Index w, uint64_t) { return src.getValueMask().getWord(w); });
    }

    /// The leaf of the result built from `src`: its copy, its moved values when `moved`, or
    /// its values combined with those of b's leaf `other`, written in one pass.
    std::unique_ptr<LeafT> buildLeaf(const LeafT& src, const LeafT* other, bool moved) const {
        const bool fix = moved && mMovedNeedFix;
        if ((!other && !fix) || !src.isAllocated())
            return std::make_unique<LeafT>(src);
        auto leaf = std::make_unique<LeafT>(tree::PartialCreate{}, src.origin());
        leaf->setBufferCount(src.bufferCount());  // values not yet set
        for (Index i = 1; i < src.bufferCount(); ++i)
            std::copy_n(src.buffer(i).data(), LeafT::NUM_VALUES, leaf->buffer(i).data());
        const ValueT* in = src.buffer(0).data();
        ValueT* out = leaf->buffer(0).data();
        if (other) {
            combineValues(in, src.getValueMask(), *other, out, leaf->getValueMask());
        } else {
            moveValues(in, src.getValueMask(), out);
            leaf->setValueMask(src.getValueMask());
        }
        return leaf;
    }

    /// The branch of the result built from `src` (a's, or b's when `moved`), merged with b's
    /// node `other` at the same place where there is one.
    template <typename NodeT>
    std::unique_ptr<NodeT> buildBranch(const NodeT& src, const NodeT* other, bool moved) {
        if constexpr (NodeT::LEVEL == 0) {
            return buildLeaf(src, other, moved);
        } else {
            auto node = std::make_unique<NodeT>(src.origin());
            buildNode(*node, src, other, moved);
            return node;
        }
    }

    /// Makes `dst`, a new node of src's origin, the merge of internal node `src` (a's, or b's
    /// when `moved`) with b's node `other` at the same place, or a copy of `src` when `other`
    /// is null. Level-1 children are left to buildLevelOneNodes(); leaves are built in
    /// parallel (also inside the tasks of buildLevelOneNodes()).
    template <typename NodeT>
    void buildNode(NodeT& dst, const NodeT& src, const NodeT* other, bool moved) {
        using ChildT = typename NodeT::ChildNodeType;
        VDB_ASSERT(!(other && moved));
        copyTiles(dst, src, moved);
        // The children of the result: (entry, source, b's child to merge with, moved).
        struct Child {
            Index n;
            const ChildT* source;
            const ChildT* other;
            bool moved;
        };
        std::vector<Child> children;
        if (!other) {
            for (Index n : src.getChildMask().onBits())
                children.push_back({n, src.getChild(n), nullptr, moved});
        } else {
            for (Index n = 0; n < NodeT::NUM_VALUES; ++n) {
                switch (entryRule(src, *other, n)) {
                    case EntryRule::KeepA:
                        if (src.isChild(n))
                            children.push_back({n, src.getChild(n), nullptr, false});
                        break;
                    case EntryRule::Tile:
                        dst.setTile(n, decidedValue(), other->isTileOn(n));
                        break;
                    case EntryRule::MoveB:
                        children.push_back({n, other->getChild(n), nullptr, true});
                        break;
                    case EntryRule::Merge:
                        children.push_back({n, src.getChild(n), other->getChild(n), false});
                        break;
                }
            }
        }
        if constexpr (ChildT::LEVEL == 1 && LEVEL_ONE_JOBS) {
            for (const Child& c : children)
                mLevelOneJobs.push_back({&dst, c.n, c.source, c.other, c.moved});
        } else {
            std::vector<std::unique_ptr<ChildT>> built(children.size());
            util::parallelForRange(
                children.size(),
                [&](size_t begin, size_t end) {
                    for (size_t i = begin; i < end; ++i) {
                        if constexpr (ChildT::LEVEL == 0) {
                            // The next leaf's values load while this one is written.
                            if (i + 1 < end) {
                                children[i + 1].source->prefetchValues();
                                if (children[i + 1].other)
                                    children[i + 1].other->prefetchValues();
                            }
                        }
                        const Child& c = children[i];
                        built[i] = buildBranch(*c.source, c.other, c.moved);
                    }
                },
                ChildT::LEVEL == 0 && mThreaded, 16);
            for (size_t i = 0; i < children.size(); ++i)
                dst.setChild(children[i].n, built[i].release());
        }
    }

    /// buildNode() for the root of the start tree, whose children are merged with b's root
    /// children at their keys in full; an intersection drops the entries b lacks. The root
    /// entries themselves are left to mergeRoot() / mergeRootDifference().
    void buildStartRoot(TopT& dst, const TopT& start, const TopT& b) {
        for (auto c = start.cbegin(); start.valid(c); start.next(c)) {
            const Coord key = start.key(c);
            const auto& e = start.entry(c);
            if (!e.child) {
                dst.setTile(key, e.tile, e.active);
                continue;
            }
            const auto* be = b.findEntry(key);
            if (!UNION && !DIFFERENCE && !be)
                continue;
            if (be && !be->child && entryRule(true, ValueT{}, false, be->tile) == EntryRule::Tile) {
                dst.setTile(key, decidedValue(), be->active);
                continue;
            }
            dst.setChild(buildBranch(*e.child, be ? be->child : nullptr, false).release());
        }
    }

    /// Builds the level-1 nodes listed by buildNode(), in parallel, and hands them to their
    /// parents in the order they were listed.
    void buildLevelOneNodes() {
        if constexpr (LEVEL_ONE_JOBS) {
            std::vector<std::unique_ptr<LevelOneT>> built(mLevelOneJobs.size());
            util::parallelFor(
                mLevelOneJobs.size(),
                [&](size_t i) {
                    const LevelOneJob& job = mLevelOneJobs[i];
                    built[i] = buildBranch(*job.source, job.other, job.moved);
                },
                mThreaded, 1);
            for (size_t i = 0; i < built.size(); ++i)
                mLevelOneJobs[i].parent->setChild(mLevelOneJobs[i].n, built[i].release());
            mLevelOneJobs.clear();
        }
    }

    // ---- Internal nodes (Steal)

    template <typename NodeT, typename BNodeT>
    void mergeChildren(NodeT& a, BNodeT& b) {
        if constexpr (!Steal) {
            return;  // buildStartRoot() merged the whole branch as it built it
        } else if constexpr (NodeT::LEVEL == 0) {
            mLeafPairs.emplace_back(&a, &b);
        } else {
            mergeNode(a, b);
        }
    }

    template <typename NodeT>
    void mergeNode(NodeT& a, NodeT& b) requires(Steal) {
        // Each entry is settled by its own state alone, so a's entries change as they go.
        for (Index n = 0; n < NodeT::NUM_VALUES; ++n) {
            switch (entryRule(a, b, n)) {
                case EntryRule::KeepA:
                    break;
                case EntryRule::Tile:
                    a.setTile(n, decidedValue(), b.isTileOn(n));
                    break;
                case EntryRule::MoveB:
                    moveChild(a, n, b);
                    break;
                case EntryRule::Merge:
                    mergeChildren(*a.getChild(n), *b.getChild(n));
                    break;
            }
        }
    }

    // ---- Root nodes

    static constexpr uint8_t ACTIVE_TILE = 0x1;
    static constexpr uint8_t INSIDE_TILE = 0x2;
    static constexpr uint8_t OUTSIDE_TILE = 0x4;
    static constexpr uint8_t CHILD = 0x8;

    static uint8_t tileFlags(const ValueT& value, bool active) {
        uint8_t flags = active ? ACTIVE_TILE : 0;
        if (value < ValueT(0)) {
            flags |= INSIDE_TILE;
        } else if (value > ValueT(0)) {
            flags |= OUTSIDE_TILE;
        }
        return flags;
    }

    /// Removes the inactive root tiles equal to a's background (within OpenVDB's tolerance).
    void eraseBackgroundTiles(TopT& root) const {
        std::vector<Coord> keys;
        for (auto c = root.cbegin(); root.valid(c); root.next(c)) {
            const auto& e = root.entry(c);
            if (!e.child && !e.active && math::isApproxEqual(e.tile, mBackgroundA))
                keys.push_back(root.key(c));
        }
        for (const Coord& key : keys)
            root.eraseEntry(key);
    }

    void mergeRoot(TopT& a, OtherTopT& b) {
        constexpr uint8_t WIN = UNION ? INSIDE_TILE : OUTSIDE_TILE;
        constexpr uint8_t LOSE = UNION ? OUTSIDE_TILE : INSIDE_TILE;
        eraseBackgroundTiles(a);
        // An intersection is empty (outside) wherever b has no entry.
        if constexpr (!UNION) {
            std::vector<Coord> keys;
            for (auto c = a.cbegin(); a.valid(c); a.next(c)) {
                if (!b.findEntry(a.key(c)))
                    keys.push_back(a.key(c));
            }
            for (const Coord& key : keys)
                a.eraseEntry(key);
        }
        // The tiles of both roots; a winning tile of b replaces a losing tile of a.
        std::map<Coord, uint8_t> tiles;
        for (auto c = a.cbegin(); a.valid(c); a.next(c)) {
            const auto& e = a.entry(c);
            if (!e.child)
                tiles.emplace(a.key(c), tileFlags(e.tile, e.active));
        }
        std::vector<Coord> bChildren;
        for (auto c = b.cbegin(); b.valid(c); b.next(c)) {
            const auto& e = b.entry(c);
            if (e.child) {
                bChildren.push_back(b.key(c));
                continue;
            }
            const uint8_t flags = tileFlags(e.tile, e.active);
            auto [it, inserted] = tiles.emplace(b.key(c), flags);
            if (!inserted && (it->second & LOSE) && (flags & WIN))
                it->second = flags;
        }
        // Winning tiles, as +-background, over anything.
        for (const auto& [key, flags] : tiles) {
            if ((flags & WIN) && (UNION || a.findEntry(key)))
                a.setTile(key, winningBackground(), (flags & ACTIVE_TILE) != 0);
        }
        // b's children: merged with a's children, dropped under an inactive winning tile,
        // moved anywhere else.
        std::set<Coord> children;
        for (auto c = a.cbegin(); a.valid(c); a.next(c)) {
            if (a.entry(c).child)
                children.insert(a.key(c));
        }
        std::vector<Coord> pairs;
        for (const Coord& key : bChildren) {
            if (!UNION && !a.findEntry(key))
                continue;
            if (children.count(key)) {
                pairs.push_back(key);
                continue;
            }
            const auto it = tiles.find(key);
            if (it != tiles.end() && it->second == WIN)
                continue;
            moveRootChild(a, b, key);
            children.insert(key);
        }
        // Losing tiles, as -+background, where no child took their place.
        for (const auto& [key, flags] : tiles) {
            if ((flags & LOSE) && !children.count(key) && (UNION || a.findEntry(key)))
                a.setTile(key, ValueT(-winningBackground()), (flags & ACTIVE_TILE) != 0);
        }
        eraseBackgroundTiles(a);
        for (const Coord& key : pairs)
            mergeChildren(*a.findEntry(key)->child, otherChild(b, key));
    }

    void mergeRootDifference(TopT& a, OtherTopT& b) {
        eraseBackgroundTiles(a);
        // a's children and inside tiles.
        std::map<Coord, uint8_t> flags;
        for (auto c = a.cbegin(); a.valid(c); a.next(c)) {
            const auto& e = a.entry(c);
            if (e.child) {
                flags.emplace(a.key(c), CHILD);
            } else if (e.tile < ValueT(0)) {
                flags.emplace(a.key(c), tileFlags(e.tile, e.active));
            }
        }
        // b's inside tiles make a outside over a's inside tiles and children.
        std::vector<Coord> bChildren;
        for (auto c = b.cbegin(); b.valid(c); b.next(c)) {
            const auto& e = b.entry(c);
            if (e.child) {
                bChildren.push_back(b.key(c));
            } else if (e.tile < ValueT(0) && flags.count(b.key(c))) {
                a.setTile(b.key(c), mBackgroundA, e.active);
            }
        }
        // b's children: merged with a's children, moved negated into a's inside tiles.
        std::vector<Coord> pairs;
        for (const Coord& key : bChildren) {
            const auto it = flags.find(key);
            if (it == flags.end())
                continue;
            if (it->second & CHILD) {
                pairs.push_back(key);
            } else if (it->second & INSIDE_TILE) {
                moveRootChild(a, b, key);
            }
        }
        eraseBackgroundTiles(a);
        for (const Coord& key : pairs)
            mergeChildren(*a.findEntry(key)->child, otherChild(b, key));
    }

    TreeT& mA;
    OtherTreeT& mB;
    const ValueT mBackgroundA;
    const ValueT mBackgroundB;
    const bool mMovedNeedFix;  // moved branches need background replacement or negation
    bool mThreaded = true;     // buildFrom()'s `threaded`
    // With Steal: the leaf pairs to combine and the moved leaves to fix.
    std::vector<std::pair<LeafT*, const LeafT*>> mLeafPairs;
    std::vector<LeafT*> mMovedLeaves;
    // Without: the level-1 nodes buildNode() left to buildLevelOneNodes().
    std::vector<LevelOneJob> mLevelOneJobs;
};

/// Combines tree `b` into tree `a` value by value, with the rules of OpenVDB 10's
/// Tree::combineExtended: every value of `a` becomes op(a, b) of the values both trees hold
/// there, active when either was active, and `b` is left empty. An op that takes a
/// CombineArgs (an extended op) sets the result and its active state itself.
///
/// - Two tiles (a missing root entry counts as an inactive tile of its tree's background) give
///   one tile. A tile over a child of the other tree is combined with every value of that
///   branch: a's child keeps its place; b's child is moved into `a` (op still takes a's tile as
///   its first argument).
/// - Two leaves combine voxel by voxel; for a plain op their active masks are or-ed a word at
///   a time.
/// - The result's background is op(background of a, background of b), both inactive.
///
/// Threads: the walk over the internal nodes is serial; the leaves are combined in parallel,
/// each by one task, so results do not depend on the thread count. A bounded tree's top node
/// is walked entry by entry.
template <typename TreeT, typename OpT>
class CombineTrees {
public:
    using ValueT = typename TreeT::ValueType;
    using TopT = typename TreeT::TopNodeType;
    using LeafT = typename TreeT::LeafNodeType;
    static constexpr bool EXTENDED = std::is_invocable_v<const OpT&, CombineArgs<ValueT>&>;

    CombineTrees(TreeT& a, TreeT& b, const OpT& op) : mA(a), mB(b), mOp(op) {}

    void run(bool threaded) {
        if constexpr (TreeT::BOUNDED) {
            combineNodes(mA.topNode(), mB.topNode());
        } else {
            combineRoots(mA.root(), mB.root());
        }
        util::parallelFor(
            mLeafPairs.size(),
            [this](size_t i) { combineLeaves(*mLeafPairs[i].first, *mLeafPairs[i].second); },
            threaded, 4);
        util::parallelFor(
            mLeafTiles.size(), [this](size_t i) { combineLeafWithTile(mLeafTiles[i]); }, threaded,
            4);
        mA.setBackground(combined(mA.background(), false, mB.background(), false).first);
        mB.clear();
        mA.clearAllAccessors();
    }

private:
    /// A leaf to combine with a tile value: op(leaf, tile), or op(tile, leaf) when `swapped`.
    struct LeafTile {
        LeafT* leaf;
        ValueT tile;
        bool active;
        bool swapped;
    };

    /// op of a value of `a` and a value of `b` and their states: the result and its state.
    std::pair<ValueT, bool> combined(const ValueT& a, bool aOn, const ValueT& b, bool bOn) const {
        if constexpr (EXTENDED) {
            CombineArgs<ValueT> args(a, b, aOn, bOn);
            mOp(args);
            return {args.result(), args.resultIsActive()};
        } else {
            return {mOp(a, b), aOn || bOn};
        }
    }
    /// combined() of a value `x` of the branch and a tile of the other tree.
    std::pair<ValueT, bool> withTile(const ValueT& x, bool xOn, const ValueT& tile, bool tileOn,
                                     bool swapped) const {
        return swapped ? combined(tile, tileOn, x, xOn) : combined(x, xOn, tile, tileOn);
    }

    void combineLeaves(LeafT& a, const LeafT& b) const {
        if constexpr (EXTENDED) {
            for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                const auto [value, on] =
                    combined(a.getValue(n), a.isValueOn(n), b.getValue(n), b.isValueOn(n));
                a.setValueOnly(n, value);
                a.setActiveState(n, on);
            }
        } else {
            for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                a.setValueOnly(n, mOp(a.getValue(n), b.getValue(n)));
            auto& mask = a.getValueMask();
            for (Index w = 0; w < LeafT::MaskType::WORD_COUNT; ++w)
                mask.getWord(w) |= b.getValueMask().getWord(w);
        }
    }

    void combineLeafWithTile(const LeafTile& t) const {
        if constexpr (EXTENDED) {
            for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                const auto [value, on] = withTile(t.leaf->getValue(n), t.leaf->isValueOn(n), t.tile,
                                                  t.active, t.swapped);
                t.leaf->setValueOnly(n, value);
                t.leaf->setActiveState(n, on);
            }
        } else {
            for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                const ValueT x = t.leaf->getValue(n);
                t.leaf->setValueOnly(n, t.swapped ? mOp(t.tile, x) : mOp(x, t.tile));
            }
            if (t.active) {
                auto& mask = t.leaf->getValueMask();
                for (Index w = 0; w < LeafT::MaskType::WORD_COUNT; ++w)
                    mask.getWord(w) = ~uint64_t(0);
            }
        }
    }

    /// Combines every value of the branch under `node` with a tile value.
    template <typename NodeT>
    void combineBranchWithTile(NodeT& node, const ValueT& tile, bool active, bool swapped) {
        if constexpr (NodeT::LEVEL == 0) {
            mLeafTiles.push_back({&node, tile, active, swapped});
        } else {
            for (Index n = 0; n < NodeT::NUM_VALUES; ++n) {
                if (auto* child = node.getChild(n)) {
                    combineBranchWithTile(*child, tile, active, swapped);
                } else {
                    const auto [value, on] =
                        withTile(node.getTileValue(n), node.isTileOn(n), tile, active, swapped);
                    node.setTile(n, value, on);
                }
            }
        }
    }

    template <typename NodeT>
    void combineNodes(NodeT& a, NodeT& b) {
        if constexpr (NodeT::LEVEL == 0) {
            mLeafPairs.emplace_back(&a, &b);
        } else {
            for (Index n = 0; n < NodeT::NUM_VALUES; ++n) {
                auto* childA = a.getChild(n);
                auto* childB = b.getChild(n);
                if (childA && childB) {
                    combineNodes(*childA, *childB);
                } else if (childA) {
                    combineBranchWithTile(*childA, b.getTileValue(n), b.isTileOn(n), false);
                } else if (childB) {
                    const ValueT tile = a.getTileValue(n);
                    const bool active = a.isTileOn(n);
                    a.setChild(n, b.stealChild(n, mB.background(), false));
                    combineBranchWithTile(*childB, tile, active, true);
                } else {
                    const auto [value, on] = combined(a.getTileValue(n), a.isTileOn(n),
                                                      b.getTileValue(n), b.isTileOn(n));
                    a.setTile(n, value, on);
                }
            }
        }
    }

    void combineRoots(TopT& a, TopT& b) {
        std::set<Coord> keys;
        for (auto c = a.cbegin(); a.valid(c); a.next(c))
            keys.insert(a.key(c));
        for (auto c = b.cbegin(); b.valid(c); b.next(c))
            keys.insert(b.key(c));
        for (const Coord& key : keys) {
            auto* ea = a.findEntry(key);
            auto* eb = b.findEntry(key);
            const ValueT tileA = ea ? ea->tile : mA.background();
            const ValueT tileB = eb ? eb->tile : mB.background();
            const bool onA = ea && !ea->child && ea->active;
            const bool onB = eb && !eb->child && eb->active;
            auto* childA = ea ? ea->child : nullptr;
            auto* childB = eb ? eb->child : nullptr;
            if (childA && childB) {
                combineNodes(*childA, *childB);
            } else if (childA) {
                combineBranchWithTile(*childA, tileB, onB, false);
            } else if (childB) {
                auto* moved = b.stealChild(key);
                a.setChild(moved);
                combineBranchWithTile(*moved, tileA, onA, true);
            } else {
                const auto [value, on] = combined(tileA, onA, tileB, onB);
                a.setTile(key, value, on);
            }
        }
    }

    TreeT& mA;
    TreeT& mB;
    const OpT& mOp;
    std::vector<std::pair<LeafT*, const LeafT*>> mLeafPairs;
    std::vector<LeafTile> mLeafTiles;
};

}  // namespace vdb::tools::detail
