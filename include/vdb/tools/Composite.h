// SPDX-License-Identifier: Apache-2.0
/// @file
/// CSG union, intersection and difference of narrow-band level sets (paper section 4.3).
///
/// Both inputs must be level sets of the same tree type: signed distances, negative inside, with
/// a positive background (the outside value). The operations work on whole branches: where one
/// tree has a tile and the other a child, the tile decides the whole region (an inside tile of
/// a union keeps its tile and drops the other branch; an outside tile gives way, and the other
/// tree's branch is moved over without touching its voxels). Only leaves present in both trees
/// are combined voxel by voxel: min(a, b) for a union, max(a, b) for an intersection and
/// max(a, -b) for a difference a - b, each voxel taking the active state of the input its value
/// came from (a on ties). The results equal OpenVDB 10's csgUnion / csgIntersection /
/// csgDifference value for value, tile for tile.
///
/// The in-place forms leave the result in `a` and `b` empty: b's branches are stolen, never
/// copied. The Copy forms leave both inputs intact and return a new grid or tree equal to what
/// the in-place form (with pruning) would leave in `a`. They write only what the result keeps,
/// once: a's branches that a tile of b decides (and, for an intersection, a's root entries
/// where b has none) are never copied, nor b's branches that the merge drops; a leaf present
/// in both is written in one pass from the two, a leaf moved from b in one pass from b's
/// (with its background replaced or its values negated). (OpenVDB's csg*Copy builds its result
/// another way, from the leaves and a signed flood fill, so its tiles and inactive values can
/// differ from its in-place result; ours do not.) OpenVDB's optional pruneCancelledTiles argument
/// is not offered; `threaded` is ours.
///
/// Backgrounds: each input's background must be positive, else ValueError is thrown. When they
/// differ, the result keeps a's background, and a branch moved over from b has its inactive
/// values equal to +-b's background (within 1e-8 for float) replaced by +-a's, as OpenVDB does.
///
/// Cost: one serial walk over the internal nodes where the trees overlap, then the overlapping
/// leaves (and, for a difference, the negated moved leaves) in parallel, then
/// pruneLevelSet(). The Copy forms walk the root and the internal nodes above level 1
/// serially, then build the level-1 nodes of the result in parallel, each with its leaves
/// (in parallel again), then pruneLevelSet(). Results do not depend on the thread count.
///
/// @code
/// vdb::tools::csgUnion(*sphereA, *sphereB);                        // A = A u B, B emptied
/// auto cut = vdb::tools::csgDifferenceCopy(*sphereA, *sphereB);     // new grid A - B
/// vdb::tools::csgIntersection(treeA, treeB, /*prune=*/false);       // trees work too
/// @endcode
///
/// The compositing operations compMax, compMin, compSum, compMul and compDiv work on any two
/// trees of one type (OpenVDB 10's names and rules, through Tree::combineExtended): every
/// value of A, voxel or tile, active or not, becomes max(a, b), min(a, b), a + b, a * b or
/// a / b of the values A and B hold at that place, and is active where either was active.
/// Where one tree has a tile and the other a branch, the tile's value is combined with every
/// value of the branch (B's branches are moved into A, never copied); regions where a tree has
/// no node count as its background, inactive; A's background becomes op(background of A,
/// background of B). B is left empty. Vectors compare by length in compMax / compMin (ties
/// go to the lexicographically larger / smaller vector); integer division by zero gives 0 for
/// 0 / 0 and otherwise the largest value of the type with a's sign; bools divide as `a`.
/// compReplace(A, B) copies B's active values into A (A's active topology becomes the union of
/// both) and leaves B untouched. Nothing is pruned.
///
/// @code
/// vdb::tools::compMax(*densityA, *densityB);      // A = max(A, B), B emptied
/// vdb::tools::compReplace(*grid, *patch);         // B's active values pasted into A
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/detail/CompositeImpl.h>
#include <vdb/tools/detail/LeafPairs.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <type_traits>

namespace vdb::tools {

/// True for trees that can hold a level set: a tree type with floating-point values.
template <typename TreeT>
concept LevelSetTreeType = tree::TopNodeType<typename TreeT::TopNodeType> &&
    std::is_floating_point_v<typename TreeT::ValueType>;

// ---- In place: the result goes to `a`, `b` is left empty

/// Replaces level set `a` with the union of `a` and `b` and empties `b`. With `prune`, the
/// result is pruned with pruneLevelSet(). @throw ValueError when a background is not positive
/// or `a` and `b` are the same tree.
template <LevelSetTreeType TreeT>
void csgUnion(TreeT& a, TreeT& b, bool prune = true, bool threaded = true);
/// Replaces level set `a` with the intersection of `a` and `b` and empties `b`.
template <LevelSetTreeType TreeT>
void csgIntersection(TreeT& a, TreeT& b, bool prune = true, bool threaded = true);
/// Replaces level set `a` with the difference `a` - `b` and empties `b`.
template <LevelSetTreeType TreeT>
void csgDifference(TreeT& a, TreeT& b, bool prune = true, bool threaded = true);

/// The grid forms operate on the grids' trees; transforms and metadata are not changed.
/// @throw ValueError also when the grids' transforms differ by more than a relative 1e-6
/// (checkMatchingTransforms()).
template <LevelSetTreeType TreeT>
void csgUnion(Grid<TreeT>& a, Grid<TreeT>& b, bool prune = true, bool threaded = true);
template <LevelSetTreeType TreeT>
void csgIntersection(Grid<TreeT>& a, Grid<TreeT>& b, bool prune = true, bool threaded = true);
template <LevelSetTreeType TreeT>
void csgDifference(Grid<TreeT>& a, Grid<TreeT>& b, bool prune = true, bool threaded = true);

// ---- Copies: both inputs are left intact

/// Returns a new tree holding the union of level sets `a` and `b` (pruned), with a's
/// background.
template <LevelSetTreeType TreeT>
std::unique_ptr<TreeT> csgUnionCopy(const TreeT& a, const TreeT& b, bool threaded = true);
template <LevelSetTreeType TreeT>
std::unique_ptr<TreeT> csgIntersectionCopy(const TreeT& a, const TreeT& b, bool threaded = true);
template <LevelSetTreeType TreeT>
std::unique_ptr<TreeT> csgDifferenceCopy(const TreeT& a, const TreeT& b, bool threaded = true);

/// Returns a new grid holding the result, with copies of a's transform and metadata.
template <LevelSetTreeType TreeT>
typename Grid<TreeT>::Ptr csgUnionCopy(const Grid<TreeT>& a, const Grid<TreeT>& b,
                                       bool threaded = true);
template <LevelSetTreeType TreeT>
typename Grid<TreeT>::Ptr csgIntersectionCopy(const Grid<TreeT>& a, const Grid<TreeT>& b,
                                              bool threaded = true);
template <LevelSetTreeType TreeT>
typename Grid<TreeT>::Ptr csgDifferenceCopy(const Grid<TreeT>& a, const Grid<TreeT>& b,
                                            bool threaded = true);

// ---- Compositing of any two trees of one type: the result goes to `a`, `b` is left empty

/// a = max(a, b) value by value (vectors: the longer); see the file comment.
template <VdbTree TreeT>
void compMax(TreeT& a, TreeT& b, bool threaded = true);
/// a = min(a, b) value by value (vectors: the shorter).
template <VdbTree TreeT>
void compMin(TreeT& a, TreeT& b, bool threaded = true);
/// a = a + b value by value.
template <VdbTree TreeT>
void compSum(TreeT& a, TreeT& b, bool threaded = true);
/// a = a * b value by value.
template <VdbTree TreeT>
void compMul(TreeT& a, TreeT& b, bool threaded = true);
/// a = a / b value by value (integers: see the file comment for division by zero).
template <VdbTree TreeT>
void compDiv(TreeT& a, TreeT& b, bool threaded = true);
/// Copies the active values of `b` into `a`, activating them; `b` is not changed.
template <VdbTree TreeT>
void compReplace(TreeT& a, const TreeT& b, bool threaded = true);

/// OpenVDB's Tree::combine(): every value of `a`, voxel or tile, active or not, becomes the
/// result of `op(aValue, bValue, result)` (ValueType arguments, the result by reference) of the
/// values `a` and `b` hold there, active where either was active; `a`'s background becomes op
/// of the two backgrounds. The rules of compMax() apply (b's branches are moved into `a`; `b`
/// is left empty). With `prune`, the children of a's top node are then pruned (exactly equal
/// values), as OpenVDB prunes them. `op` runs on several threads when `threaded`.
/// @throw ValueError when `a` and `b` are the same tree.
///
/// @code
/// vdb::tools::combine(treeA, treeB, [](float a, float b, float& r) { r = 0.25f * a + b; });
/// @endcode
template <VdbTree TreeT, typename OpT>
void combine(TreeT& a, TreeT& b, const OpT& op, bool prune = false, bool threaded = true);
/// OpenVDB's Tree::combineExtended(): as combine(), with `op(CombineArgs<ValueType>&)` (Types.h),
/// which sees the active states of both values and may set the result's.
template <VdbTree TreeT, typename OpT>
void combineExtended(TreeT& a, TreeT& b, const OpT& op, bool prune = false, bool threaded = true);

/// The grid forms work on the grids' trees; transforms and metadata are not changed.
/// @throw ValueError when the grids' transforms differ by more than a relative 1e-6.
template <VdbTree TreeT>
void compMax(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded = true);
template <VdbTree TreeT>
void compMin(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded = true);
template <VdbTree TreeT>
void compSum(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded = true);
template <VdbTree TreeT>
void compMul(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded = true);
template <VdbTree TreeT>
void compDiv(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded = true);
template <VdbTree TreeT>
void compReplace(Grid<TreeT>& a, const Grid<TreeT>& b, bool threaded = true);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// The CSG entry points for one tree type, as one class so that the standard trees are
/// instantiated once (src/instantiate/Composite.cpp) rather than in every user's translation
/// unit. The kind of operation is a run-time argument.
template <typename TreeT>
struct CsgRunner {
    /// Merges `b` into `a`, clears `b`, then prunes `a` if asked.
    static void inPlace(CsgKind kind, TreeT& a, TreeT& b, bool prune, bool threaded);
    /// The result of merging `b` into `a`, built from the nodes of both (only what the result
    /// keeps is copied), then pruned; `a` and `b` are left as they are.
    static std::unique_ptr<TreeT> copy(CsgKind kind, const TreeT& a, const TreeT& b, bool threaded);

private:
    template <CsgKind Kind>
    static std::unique_ptr<TreeT> copyAs(const TreeT& a, const TreeT& b, bool threaded);
};

constexpr const char* csgName(CsgKind kind) {
    return kind == CsgKind::Union          ? "csgUnion"
           : kind == CsgKind::Intersection ? "csgIntersection"
                                           : "csgDifference";
}

template <typename TreeT>
void CsgRunner<TreeT>::inPlace(CsgKind kind, TreeT& a, TreeT& b, bool prune, bool threaded) {
    validateLevelSetBackground(a.background(), csgName(kind), "A");
    validateLevelSetBackground(b.background(), csgName(kind), "B");
    if (&a == &b)
        throw ValueError(std::string(csgName(kind)) + ": A and B must be different trees");
    switch (kind) {
        case CsgKind::Union:
            CsgMerge<TreeT, CsgKind::Union, /*Steal=*/true>(a, b).run(threaded);
            break;
        case CsgKind::Intersection:
            CsgMerge<TreeT, CsgKind::Intersection, true>(a, b).run(threaded);
            break;
        case CsgKind::Difference:
            CsgMerge<TreeT, CsgKind::Difference, true>(a, b).run(threaded);
            break;
    }
    b.clear();
    if (prune)
        tools::pruneLevelSet(a, threaded);
}

template <typename TreeT>
template <CsgKind Kind>
std::unique_ptr<TreeT> CsgRunner<TreeT>::copyAs(const TreeT& a, const TreeT& b, bool threaded) {
    auto result = std::make_unique<TreeT>(a.background());
    CsgMerge<TreeT, Kind, /*Steal=*/false>(*result, b).buildFrom(a, threaded);
    tools::pruneLevelSet(*result, threaded);
    return result;
}

template <typename TreeT>
std::unique_ptr<TreeT> CsgRunner<TreeT>::copy(CsgKind kind, const TreeT& a, const TreeT& b,
                                              bool threaded) {
    validateLevelSetBackground(a.background(), csgName(kind), "A");
    validateLevelSetBackground(b.background(), csgName(kind), "B");
    switch (kind) {
        case CsgKind::Union:
            return copyAs<CsgKind::Union>(a, b, threaded);
        case CsgKind::Intersection:
            return copyAs<CsgKind::Intersection>(a, b, threaded);
        case CsgKind::Difference:
            break;
    }
    return copyAs<CsgKind::Difference>(a, b, threaded);
}

template <typename TreeT>
std::unique_ptr<TreeT> csgTreeCopy(CsgKind kind, const TreeT& a, const TreeT& b, bool threaded) {
    return CsgRunner<TreeT>::copy(kind, a, b, threaded);
}

template <typename TreeT>
typename Grid<TreeT>::Ptr csgGridCopy(CsgKind kind, const Grid<TreeT>& a, const Grid<TreeT>& b,
                                      bool threaded) {
    checkMatchingTransforms(a, b, csgName(kind));
    typename Grid<TreeT>::Ptr result = a.copy();  // a's transform and metadata
    result->setTree(CsgRunner<TreeT>::copy(kind, a.tree(), b.tree(), threaded));
    return result;
}

}  // namespace detail

template <LevelSetTreeType TreeT>
void csgUnion(TreeT& a, TreeT& b, bool prune, bool threaded) {
    detail::CsgRunner<TreeT>::inPlace(detail::CsgKind::Union, a, b, prune, threaded);
}
template <LevelSetTreeType TreeT>
void csgIntersection(TreeT& a, TreeT& b, bool prune, bool threaded) {
    detail::CsgRunner<TreeT>::inPlace(detail::CsgKind::Intersection, a, b, prune, threaded);
}
template <LevelSetTreeType TreeT>
void csgDifference(TreeT& a, TreeT& b, bool prune, bool threaded) {
    detail::CsgRunner<TreeT>::inPlace(detail::CsgKind::Difference, a, b, prune, threaded);
}

template <LevelSetTreeType TreeT>
void csgUnion(Grid<TreeT>& a, Grid<TreeT>& b, bool prune, bool threaded) {
    checkMatchingTransforms(a, b, "csgUnion");
    detail::CsgRunner<TreeT>::inPlace(detail::CsgKind::Union, a.tree(), b.tree(), prune, threaded);
}
template <LevelSetTreeType TreeT>
void csgIntersection(Grid<TreeT>& a, Grid<TreeT>& b, bool prune, bool threaded) {
    checkMatchingTransforms(a, b, "csgIntersection");
    detail::CsgRunner<TreeT>::inPlace(detail::CsgKind::Intersection, a.tree(), b.tree(), prune,
                                      threaded);
}
template <LevelSetTreeType TreeT>
void csgDifference(Grid<TreeT>& a, Grid<TreeT>& b, bool prune, bool threaded) {
    checkMatchingTransforms(a, b, "csgDifference");
    detail::CsgRunner<TreeT>::inPlace(detail::CsgKind::Difference, a.tree(), b.tree(), prune,
                                      threaded);
}

template <LevelSetTreeType TreeT>
std::unique_ptr<TreeT> csgUnionCopy(const TreeT& a, const TreeT& b, bool threaded) {
    return detail::csgTreeCopy(detail::CsgKind::Union, a, b, threaded);
}
template <LevelSetTreeType TreeT>
std::unique_ptr<TreeT> csgIntersectionCopy(const TreeT& a, const TreeT& b, bool threaded) {
    return detail::csgTreeCopy(detail::CsgKind::Intersection, a, b, threaded);
}
template <LevelSetTreeType TreeT>
std::unique_ptr<TreeT> csgDifferenceCopy(const TreeT& a, const TreeT& b, bool threaded) {
    return detail::csgTreeCopy(detail::CsgKind::Difference, a, b, threaded);
}

template <LevelSetTreeType TreeT>
typename Grid<TreeT>::Ptr csgUnionCopy(const Grid<TreeT>& a, const Grid<TreeT>& b, bool threaded) {
    return detail::csgGridCopy(detail::CsgKind::Union, a, b, threaded);
}
template <LevelSetTreeType TreeT>
typename Grid<TreeT>::Ptr csgIntersectionCopy(const Grid<TreeT>& a, const Grid<TreeT>& b,
                                              bool threaded) {
    return detail::csgGridCopy(detail::CsgKind::Intersection, a, b, threaded);
}
template <LevelSetTreeType TreeT>
typename Grid<TreeT>::Ptr csgDifferenceCopy(const Grid<TreeT>& a, const Grid<TreeT>& b,
                                            bool threaded) {
    return detail::csgGridCopy(detail::CsgKind::Difference, a, b, threaded);
}

// ---- Compositing

namespace detail {

template <typename T>
concept VectorValue = requires(const T& v) {
    v.lengthSqr();
};

/// True when `a` precedes `b`: by length for vectors (lexicographically on equal lengths), by
/// value otherwise.
template <typename T>
bool compositeLess(const T& a, const T& b) {
    if constexpr (VectorValue<T>) {
        const auto la = a.lengthSqr(), lb = b.lengthSqr();
        if (la != lb)
            return la < lb;
        for (int i = 0; i < 3; ++i) {
            if (a[i] != b[i])
                return a[i] < b[i];
        }
        return false;
    } else {
        return a < b;
    }
}

struct CompMaxOp {
    template <typename T>
    T operator()(const T& a, const T& b) const {
        return compositeLess(a, b) ? b : a;
    }
};
struct CompMinOp {
    template <typename T>
    T operator()(const T& a, const T& b) const {
        return compositeLess(b, a) ? b : a;
    }
};
struct CompSumOp {
    template <typename T>
    T operator()(const T& a, const T& b) const {
        return T(a + b);
    }
};
struct CompMulOp {
    template <typename T>
    T operator()(const T& a, const T& b) const {
        return T(a * b);
    }
};
struct CompDivOp {
    template <typename T>
    T operator()(const T& a, const T& b) const {
        if constexpr (std::is_same_v<T, bool>) {
            return a;
        } else if constexpr (std::is_integral_v<T>) {
            if (b != T(0))
                return T(a / b);
            if (a == T(0))
                return T(0);
            return a > T(0) ? std::numeric_limits<T>::max() : T(-std::numeric_limits<T>::max());
        } else {
            return T(a / b);
        }
    }
};

template <typename TreeT, typename OpT>
void combineTrees(TreeT& a, TreeT& b, const OpT& op, bool threaded, const char* name) {
    if (&a == &b)
        throw ValueError(std::string(name) + ": A and B must be different trees");
    CombineTrees<TreeT, OpT>(a, b, op).run(threaded);
}

/// Prunes the children of the top node of `tree` (exactly equal values), not the top node's
/// own entries: what OpenVDB's combine does with `prune`.
template <typename TreeT>
void pruneBelowTop(TreeT& tree) {
    tree::forEachChild(tree.topNode(), [](auto& child) {
        using ChildT = std::remove_cvref_t<decltype(child)>;
        if constexpr (ChildT::LEVEL > 0)
            child.prune(typename ChildT::ValueType{});
    });
    tree.clearAllAccessors();
}

template <typename TreeT, typename OpT>
void combineGrids(Grid<TreeT>& a, Grid<TreeT>& b, const OpT& op, bool threaded, const char* name) {
    checkMatchingTransforms(a, b, name);
    combineTrees(a.tree(), b.tree(), op, threaded, name);
}

}  // namespace detail

template <VdbTree TreeT, typename OpT>
void combineExtended(TreeT& a, TreeT& b, const OpT& op, bool prune, bool threaded) {
    static_assert(std::is_invocable_v<const OpT&, CombineArgs<typename TreeT::ValueType>&>,
                  "combineExtended: op must take a CombineArgs<ValueType>&");
    detail::combineTrees(a, b, op, threaded, "combineExtended");
    if (prune)
        detail::pruneBelowTop(a);
}

template <VdbTree TreeT, typename OpT>
void combine(TreeT& a, TreeT& b, const OpT& op, bool prune, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    static_assert(std::is_invocable_v<const OpT&, const ValueT&, const ValueT&, ValueT&>,
                  "combine: op must be op(const ValueType& a, const ValueType& b, ValueType& r)");
    // A plain op: the leaves' active masks are or-ed a word at a time.
    const auto plain = [&op](const ValueT& x, const ValueT& y) {
        ValueT result = x;
        op(x, y, result);
        return result;
    };
    detail::combineTrees(a, b, plain, threaded, "combine");
    if (prune)
        detail::pruneBelowTop(a);
}

template <VdbTree TreeT>
void compMax(TreeT& a, TreeT& b, bool threaded) {
    detail::combineTrees(a, b, detail::CompMaxOp{}, threaded, "compMax");
}
template <VdbTree TreeT>
void compMin(TreeT& a, TreeT& b, bool threaded) {
    detail::combineTrees(a, b, detail::CompMinOp{}, threaded, "compMin");
}
template <VdbTree TreeT>
void compSum(TreeT& a, TreeT& b, bool threaded) {
    detail::combineTrees(a, b, detail::CompSumOp{}, threaded, "compSum");
}
template <VdbTree TreeT>
void compMul(TreeT& a, TreeT& b, bool threaded) {
    detail::combineTrees(a, b, detail::CompMulOp{}, threaded, "compMul");
}
template <VdbTree TreeT>
void compDiv(TreeT& a, TreeT& b, bool threaded) {
    detail::combineTrees(a, b, detail::CompDivOp{}, threaded, "compDiv");
}

template <VdbTree TreeT>
void compReplace(TreeT& a, const TreeT& b, bool threaded) {
    if (&a == &b)
        return;
    // B's active states, then B's active tile values, then B's active voxel values.
    a.topologyUnion(b);
    for (auto it = b.cbeginValueOn(); it; ++it) {
        if (it.isTileValue()) {
            CoordBBox bbox;
            it.getBoundingBox(bbox);
            a.fill(bbox, it.getValue(), true);
        }
    }
    detail::forEachLeafPair(
        b, a,
        [](const auto& from, auto& to) {
            for (Index n : from.getValueMask().onBits())
                to.setValueOn(n, from.getValue(n));
        },
        threaded);
}

template <VdbTree TreeT>
void compMax(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded) {
    detail::combineGrids(a, b, detail::CompMaxOp{}, threaded, "compMax");
}
template <VdbTree TreeT>
void compMin(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded) {
    detail::combineGrids(a, b, detail::CompMinOp{}, threaded, "compMin");
}
template <VdbTree TreeT>
void compSum(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded) {
    detail::combineGrids(a, b, detail::CompSumOp{}, threaded, "compSum");
}
template <VdbTree TreeT>
void compMul(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded) {
    detail::combineGrids(a, b, detail::CompMulOp{}, threaded, "compMul");
}
template <VdbTree TreeT>
void compDiv(Grid<TreeT>& a, Grid<TreeT>& b, bool threaded) {
    detail::combineGrids(a, b, detail::CompDivOp{}, threaded, "compDiv");
}
template <VdbTree TreeT>
void compReplace(Grid<TreeT>& a, const Grid<TreeT>& b, bool threaded) {
    checkMatchingTransforms(a, b, "compReplace");
    compReplace(a.tree(), b.tree(), threaded);
}

// ---- Instantiated once in src/instantiate/Composite.cpp

extern template struct detail::CsgRunner<FloatTree>;
extern template struct detail::CsgRunner<DoubleTree>;

}  // namespace vdb::tools
