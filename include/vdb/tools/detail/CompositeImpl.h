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
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

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
/// Branches of b are stolen when `Steal` (b is then cleared by the caller) and copied
/// otherwise. Transferred branches get b's background replaced by a's in their inactive values
/// (within OpenVDB's tolerance), then are negated for a difference.
///
/// Without `Steal`, the merge can also build `a` itself from a third tree (startFrom(), for the
/// Copy forms): a copy of that tree's nodes except the branches b's tiles will decide, which
/// become the tile the merge leaves there, and, for an intersection, the root entries b lacks.
/// Nothing of either input is copied that the merge would then drop.
///
/// Threads: the walks over internal nodes are serial; leaf pairs, the leaves of transferred
/// branches and the leaves of copies are processed in parallel, each by one task, so the
/// result does not depend on the thread count.
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

    /// Makes `a`, which must be empty and have `start`'s background, the copy of `start` that
    /// merging b into it gives the same result as merging b into `start` itself.
    void startFrom(const TreeT& start, bool threaded) requires(!Steal) {
        if constexpr (TreeT::BOUNDED) {
            copyNodeInto(mA.topNode(), start.topNode(), &mB.topNode(), /*moved=*/false);
        } else {
            copyStartRoot(mA.root(), start.root(), mB.root());
        }
        linkLeafCopies(threaded);  // the merge walk looks at these leaves
        mStartCombined = true;
    }

    void run(bool threaded) {
        if constexpr (TreeT::BOUNDED) {
            mergeNode(mA.topNode(), static_cast<OtherTopT&>(mB.topNode()));
        } else if constexpr (DIFFERENCE) {
            mergeRootDifference(mA.root(), static_cast<OtherTopT&>(mB.root()));
        } else {
            mergeRoot(mA.root(), static_cast<OtherTopT&>(mB.root()));
        }
        // The voxel work: copies of b's leaves, overlapping leaves, then the leaves of
        // transferred branches.
        linkLeafCopies(threaded);
        util::parallelFor(
            mLeafPairs.size(),
            [this](size_t i) { combineLeaves(*mLeafPairs[i].first, *mLeafPairs[i].second); },
            threaded, 4);
        util::parallelFor(
            mMovedLeaves.size(), [this](size_t i) { fixMovedLeaf(*mMovedLeaves[i]); }, threaded,
            16);
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

    // ---- Branches moved from b to a

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

    void fixMovedLeaf(LeafT& leaf) const {
        auto values = leaf.buffer(0);
        const auto& mask = leaf.getValueMask();
        for (Index k = 0; k < LeafT::NUM_VALUES; ++k)
            values[k] = movedValue(values[k], mask.isOn(k));
    }

    /// Moves the child at `n` of b into entry `n` of a: stolen, or copied (a leaf is copied
    /// after the walk, by linkLeafCopies(); entry `n` keeps its tile until then and the walk
    /// does not look at it again).
    template <typename NodeT, typename BNodeT>
    void moveChild(NodeT& a, Index n, BNodeT& b) {
        if constexpr (Steal) {
            std::unique_ptr<typename NodeT::ChildNodeType> child(
                b.stealChild(n, mBackgroundB, false));
            prepareMoved(*child);
            a.setChild(n, child.release());
        } else if constexpr (NodeT::LEVEL == 1) {
            mLeafCopies.push_back({&a, n, b.getChild(n), /*moved=*/true});
        } else {
            a.setChild(n, copyBranch(*b.getChild(n), /*moved=*/true).release());
        }
    }

    static OtherTopChildT& otherChild(OtherTopT& bRoot, const Coord& key) {
        return *bRoot.findEntry(key)->child;
    }

    /// Moves b's root child at `key` into a (stolen or copied, as moveChild()).
    void moveRootChild(TopT& a, OtherTopT& bRoot, const Coord& key) {
        using ChildT = typename TopT::ChildNodeType;
        std::unique_ptr<ChildT> child;
        if constexpr (Steal) {
            child.reset(bRoot.stealChild(key));
            prepareMoved(*child);
        } else {
            child = copyBranch(otherChild(bRoot, key), /*moved=*/true);
        }
        a.setChild(child.get());
        child.release();
    }

    // ---- Copies (no Steal): internal nodes at once, leaves later in parallel

    /// A leaf to copy into entry `n` of `parent`; `moved` copies are prepared as moved values,
    /// others combined with b's leaf `other` where there is one.
    struct LeafCopy {
        tree::NodeAtLevelT<TopT, 1>* parent;
        Index n;
        const LeafT* source;
        bool moved;
        const LeafT* other = nullptr;
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

    /// A copy of the branch `src`, as moved values when `moved`; its leaves are copied by
    /// linkLeafCopies() (unless `src` is itself a leaf).
    template <typename NodeT>
    std::unique_ptr<NodeT> copyBranch(const NodeT& src, bool moved) {
        if constexpr (NodeT::LEVEL == 0) {
            auto leaf = std::make_unique<NodeT>(src);
            if (moved && mMovedNeedFix)
                fixMovedLeaf(*leaf);
            return leaf;
        } else {
            auto node = std::make_unique<NodeT>(src.origin());
            copyNodeInto(*node, src, static_cast<const NodeT*>(nullptr), moved);
            return node;
        }
    }

    /// Whether a tile of b of value `bTile` decides the whole region over a child of a, and
    /// the value the merge then leaves there (with b's tile's state).
    static bool decides(const ValueT& bTile) {
        if constexpr (DIFFERENCE) {
            return bTile < ValueT(0);
        } else {
            return UNION ? bTile < ValueT(0) : bTile > ValueT(0);
        }
    }
    ValueT decidedValue() const { return DIFFERENCE ? mBackgroundA : winningBackground(); }

    /// Copies internal node `src` into `dst` (a new node of the same origin), as moved values
    /// when `moved`, except the children that a tile of `b` (the node of b at the same place,
    /// or null) decides.
    template <typename NodeT>
    void copyNodeInto(NodeT& dst, const NodeT& src, const NodeT* b, bool moved) {
        using ChildT = typename NodeT::ChildNodeType;
        copyTiles(dst, src, moved);
        for (Index n : src.getChildMask().onBits()) {
            const ChildT* bChild = b ? b->getChild(n) : nullptr;
            if (b && !bChild && decides(b->getTileValue(n))) {
                dst.setTile(n, decidedValue(), b->isTileOn(n));
            } else if constexpr (NodeT::LEVEL == 1) {
                // A leaf of b here is combined with the copy at once (the merge walk would
                // pair the two); see mergeChildren().
                mLeafCopies.push_back({&dst, n, src.getChild(n), moved, bChild});
            } else {
                auto child = std::make_unique<ChildT>(src.getChild(n)->origin());
                copyNodeInto(*child, *src.getChild(n), bChild, moved);
                dst.setChild(n, child.release());
            }
        }
    }

    /// copyNodeInto() for the root of the start tree: an intersection also drops the entries b
    /// lacks.
    void copyStartRoot(TopT& dst, const TopT& start, const TopT& b) {
        using ChildT = typename TopT::ChildNodeType;
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
            if (be && !be->child && decides(be->tile)) {
                dst.setTile(key, decidedValue(), be->active);
                continue;
            }
            std::unique_ptr<ChildT> child;
            if constexpr (ChildT::LEVEL == 0) {
                child = std::make_unique<ChildT>(*e.child);
                if (be && be->child)
                    combineLeaves(*child, *be->child);
            } else {
                child = std::make_unique<ChildT>(e.child->origin());
                copyNodeInto(*child, *e.child, be ? be->child : nullptr, /*moved=*/false);
            }
            dst.setChild(child.get());
            child.release();
        }
    }

    /// Makes the leaf copies, in parallel, then links them in the order they were listed.
    void linkLeafCopies(bool threaded) {
        if constexpr (!Steal && !tree::IS_ROOT_NODE<tree::NodeAtLevelT<TopT, 1>>) {
            std::vector<std::unique_ptr<LeafT>> copies(mLeafCopies.size());
            util::parallelFor(
                mLeafCopies.size(),
                [&](size_t i) {
                    const LeafCopy& job = mLeafCopies[i];
                    auto leaf = std::make_unique<LeafT>(*job.source);
                    if (job.moved && mMovedNeedFix)
                        fixMovedLeaf(*leaf);
                    if (job.other)
                        combineLeaves(*leaf, *job.other);
                    copies[i] = std::move(leaf);
                },
                threaded, 16);
            for (size_t i = 0; i < copies.size(); ++i)
                mLeafCopies[i].parent->setChild(mLeafCopies[i].n, copies[i].release());
            mLeafCopies.clear();
        }
    }

    // ---- Leaves

    /// Each voxel takes the winning value and that input's active state; the states are
    /// merged a 64-bit mask word at a time.
    void combineLeaves(LeafT& a, const LeafT& b) const {
        auto av = a.buffer(0);
        const auto bv = b.buffer(0);
        auto& am = a.getValueMask();
        const auto& bm = b.getValueMask();
        for (Index w = 0; w < LeafT::MaskType::WORD_COUNT; ++w) {
            uint64_t take = 0;
            for (Index i = 0; i < 64; ++i) {
                const Index k = (w << 6) + i;
                const ValueT other = DIFFERENCE ? ValueT(-bv[k]) : bv[k];
                const bool fromB = UNION ? other < av[k] : av[k] < other;
                take |= uint64_t(fromB) << i;
                av[k] = fromB ? other : av[k];
            }
            am.getWord(w) = (am.getWord(w) & ~take) | (bm.getWord(w) & take);
        }
    }

    // ---- Internal nodes

    template <typename NodeT, typename BNodeT>
    void mergeChildren(NodeT& a, BNodeT& b) {
        if constexpr (NodeT::LEVEL == 0) {
            if (!mStartCombined)  // startFrom() combined every pair of leaves already
                mLeafPairs.emplace_back(&a, &b);
        } else {
            mergeNode(a, b);
        }
    }

    template <typename NodeT, typename BNodeT>
    void mergeNode(NodeT& a, BNodeT& b) {
        using MaskT = typename NodeT::MaskType;
        // No scratch masks (a bounded tree's top node has up to 2^30 entries): a's tiles are
        // classified from its current state, which changes at an entry only once that entry
        // has been settled, so this reads as masks taken before the loops.
        const auto bTiles = [&](Index w) { return ~b.getChildMask().getWord(w); };
        const auto bChildren = [&](Index w) { return b.getChildMask().getWord(w); };
        if constexpr (DIFFERENCE) {
            const auto inside = [&](Index n) {
                return !a.isChild(n) && a.getTileValue(n) < ValueT(0);
            };
            // b's inside tiles make a outside over a's inside tiles and children.
            tree::detail::forEachOnBit<MaskT>(bTiles, [&](Index n) {
                if (b.getTileValue(n) < ValueT(0) && (a.isChild(n) || inside(n)))
                    a.setTile(n, mBackgroundA, b.isTileOn(n));
            });
            // b's children: moved negated into a's inside tiles, merged with a's children.
            tree::detail::forEachOnBit<MaskT>(bChildren, [&](Index n) {
                if (inside(n)) {
                    moveChild(a, n, b);
                } else if (a.isChild(n)) {
                    mergeChildren(*a.getChild(n), *b.getChild(n));
                }
            });
        } else {
            // a's winning and losing tiles (zero tiles are neither).
            const auto winning = [&](Index n) {
                return !a.isChild(n) && isWinning(a.getTileValue(n));
            };
            const auto losing = [&](Index n) {
                return !a.isChild(n) && isLosing(a.getTileValue(n));
            };
            // b's winning tiles replace whatever a has that is not winning.
            tree::detail::forEachOnBit<MaskT>(bTiles, [&](Index n) {
                if (!winning(n) && isWinning(b.getTileValue(n)))
                    a.setTile(n, winningBackground(), b.isTileOn(n));
            });
            // b's children: dropped under a's winning tiles, moved into a's losing tiles,
            // merged with a's children.
            tree::detail::forEachOnBit<MaskT>(bChildren, [&](Index n) {
                if (winning(n))
                    return;
                if (losing(n)) {
                    moveChild(a, n, b);
                } else if (a.isChild(n)) {
                    mergeChildren(*a.getChild(n), *b.getChild(n));
                }
            });
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
    std::vector<std::pair<LeafT*, const LeafT*>> mLeafPairs;
    std::vector<LeafT*> mMovedLeaves;
    std::vector<LeafCopy> mLeafCopies;
    bool mStartCombined = false;
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
