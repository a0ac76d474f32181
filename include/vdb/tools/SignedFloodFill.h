// SPDX-License-Identifier: Apache-2.0
/// @file
/// Hierarchical signed flood fill (paper section 4.6): after a narrow band of signed distances
/// has been written, every inactive value outside the band (voxels and tiles at every level)
/// gets -|inside| or +|outside| by the side of the surface it lies on.
///
/// The fill runs bottom-up and makes the same choices as OpenVDB 10's tools/SignedFloodFill.h:
/// - Leaves, in parallel: along each z-scanline an inactive voxel takes the sign of the last
///   active voxel before it on that line. A line starts with the sign of its (x, y, 0) voxel if
///   that is active, else with the sign its (x, y-1) line started with; the first line of an
///   x-slice starts from its (x, 0, 0) voxel if active, else from the previous slice's first
///   line, and the leaf's first active voxel seeds it all. A leaf without active voxels takes
///   the sign of its first value. Lines are read from the value mask word by word.
/// - Internal nodes, level by level, in parallel: the same scan over the node's table, where
///   children play the active voxels: a child's sign is that of its last value (its corner of
///   largest coordinates), and the first child's first value seeds the scan. A node without
///   children takes the sign of its first tile.
/// - The root: between two children on one z-line with only tiles or nothing between them, the
///   gap becomes inactive tiles of the inside value when the lower child's last value and the
///   upper child's first value are both negative. Then the background becomes the outside
///   value. A bounded tree's top node is scanned like an internal node, in spatial order.
/// Active voxels and active tiles keep their values and never influence the scan of a tile
/// level (OpenVDB overwrites the value of active tiles; here they are left alone).
///
/// Cost: one pass over every leaf's value mask, a fill per run of inactive voxels (an active
/// voxel is read only where such a run follows it), one pass over the tables of the internal
/// nodes, plus a sort of the root's children. Results do not depend on the thread count.
///
/// @code
/// // Write the band's active voxels, then:
/// vdb::tools::signedFloodFill(grid->tree());  // inside -background, outside +background
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools {

/// Sets every inactive value of a closed narrow-band level set to -|background| inside and
/// +|background| outside, from the signs of the active voxels; the background becomes
/// +|background|. Leaves are filled in parallel when `threaded`, then each level above.
/// @throw ValueError for an integer background whose magnitude the type cannot hold (its
///        minimum, e.g. -2^31 for int32).
template <SignedVdbTree TreeT>
void signedFloodFill(TreeT& tree, bool threaded = true);

/// As signedFloodFill(), with inactive values -|insideValue| inside and +|outsideValue| outside;
/// the tree's background becomes +|outsideValue|.
/// @throw ValueError for an integer value whose magnitude the type cannot hold.
template <SignedVdbTree TreeT>
void signedFloodFillWithValues(TreeT& tree, const typename TreeT::ValueType& outsideValue,
                               const typename TreeT::ValueType& insideValue, bool threaded = true);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

template <typename ValueT>
ValueT floodAbs(const ValueT& v) {
    if constexpr (std::is_floating_point_v<ValueT>) {
        return std::abs(v);
    } else {
        if (v == std::numeric_limits<ValueT>::min())
            throw ValueError("signedFloodFill: the value " + std::to_string(v) +
                             " has no positive counterpart in its integer type; use a "
                             "magnitude of at most " +
                             std::to_string(std::numeric_limits<ValueT>::max()));
        return v < ValueT(0) ? ValueT(-v) : v;
    }
}

/// The value at the smallest (`last` false) or largest (`last` true) corner of `node`'s region.
template <typename NodeT>
typename NodeT::ValueType floodCornerValue(const NodeT& node, bool last) {
    using ValueT = typename NodeT::ValueType;
    const Index n = last ? NodeT::NUM_VALUES - 1 : 0;
    if constexpr (NodeT::LEVEL == 0) {
        return node.isAllocated() ? node.getValue(n) : ValueT(0);
    } else {
        if (const auto* child = node.getChild(n))
            return floodCornerValue(*child, last);
        return node.getTileValue(n);
    }
}

/// Bitwise equality, so that 0 and -0 count as different values.
template <typename ValueT>
bool floodSameBits(const ValueT& a, const ValueT& b) {
    return std::memcmp(&a, &b, sizeof(ValueT)) == 0;
}

/// Flood-fills one leaf (see the file comment).
template <typename LeafT, typename ValueT>
void floodFillLeaf(LeafT& leaf, const ValueT& outside, const ValueT& inside) {
    constexpr Index LOG2 = LeafT::LOG2DIM;
    constexpr Index DIM = LeafT::DIM;
    constexpr Index N = LeafT::NUM_VALUES;
    if (!leaf.isAllocated())
        return;
    ValueT* data = leaf.buffer(0).data();
    const auto& mask = leaf.getValueMask();
    const Index first = mask.findFirstOn();
    if (first == N) {
        std::fill_n(data, N, data[0] < ValueT(0) ? inside : outside);
        return;
    }
    const uint64_t* words = mask.words();
    // The mask bits of the z-line starting at offset `row`, one 64-bit chunk at a time.
    constexpr Index CHUNK = DIM < 64 ? DIM : 64;
    constexpr uint64_t CHUNK_MASK = CHUNK == 64 ? ~uint64_t(0) : (uint64_t(1) << CHUNK) - 1;

    bool xInside = data[first] < ValueT(0);
    for (Index x = 0; x < DIM; ++x) {
        const Index x00 = x << (2 * LOG2);
        if (mask.isOn(x00))
            xInside = data[x00] < ValueT(0);
        bool yInside = xInside;
        for (Index y = 0; y < DIM; ++y) {
            const Index row = x00 + (y << LOG2);
            if (mask.isOn(row))
                yInside = data[row] < ValueT(0);
            // Fill each run of inactive voxels with the sign of the active voxel just before it
            // (or the line's starting sign); active runs are skipped without reading them.
            bool zInside = yInside;
            for (Index c = 0; c < DIM; c += CHUNK) {
                const Index base = row + c;
                uint64_t holes = ~(words[base >> 6] >> (base & 63)) & CHUNK_MASK;
                while (holes) {
                    const Index p = Index(std::countr_zero(holes));
                    const Index q = p + Index(std::countr_one(holes >> p));
                    if (p > 0 || (c > 0 && mask.isOn(base - 1)))
                        zInside = data[base + p - 1] < ValueT(0);
                    std::fill(data + base + p, data + base + q, zInside ? inside : outside);
                    holes &= q >= 64 ? 0 : ~uint64_t(0) << q;
                }
            }
        }
    }
}

/// Flood-fills the tiles of one internal node, whose children are already filled. The scan
/// runs in spatial order, which differs from table order only for the centered top node of a
/// bounded tree.
template <typename NodeT, typename ValueT>
void floodFillInternal(NodeT& node, const ValueT& outside, const ValueT& inside) {
    constexpr Index LOG2 = NodeT::LOG2DIM;
    constexpr Index DIM = Index(1) << LOG2;
    constexpr Index LOW = DIM - 1;
    const auto& childMask = node.getChildMask();
    const auto& valueMask = node.getValueMask();

    // Table offset of each spatial index, per axis: the table index is the spatial index plus
    // `rot`, modulo DIM (rot is 0 except on the centered top node).
    std::array<Index, 3> rot;
    std::array<std::array<Index, DIM>, 3> off;
    for (int a = 0; a < 3; ++a) {
        rot[a] = (uint32_t(node.origin()[a]) >> NodeT::ChildNodeType::TOTAL) & LOW;
        const Index shift = (2 - Index(a)) * LOG2;
        for (Index s = 0; s < DIM; ++s)
            off[a][s] = ((s + rot[a]) & LOW) << shift;
    }
    const bool rotated = rot[0] != 0 || rot[1] != 0 || rot[2] != 0;

    const auto setTile = [&](Index n, const ValueT& v) {
        if (!valueMask.isOn(n) && !floodSameBits(node.getTileValue(n), v))
            node.setTileValueOnly(n, v);
    };

    // The first child in spatial order seeds the scan.
    Index first = NodeT::NUM_VALUES;
    if (!rotated) {
        first = childMask.findFirstOn();
    } else {
        Index best = ~Index(0);
        for (Index n : childMask.onBits()) {
            const Index x = ((n >> (2 * LOG2)) - rot[0]) & LOW;
            const Index y = ((n >> LOG2) - rot[1]) & LOW;
            const Index z = (n - rot[2]) & LOW;
            const Index s = (x << (2 * LOG2)) | (y << LOG2) | z;
            if (s < best) {
                best = s;
                first = n;
            }
        }
    }
    if (first == NodeT::NUM_VALUES) {
        const Index corner = off[0][0] | off[1][0] | off[2][0];
        const ValueT v = node.getTileValue(corner) < ValueT(0) ? inside : outside;
        for (Index n = 0; n < NodeT::NUM_VALUES; ++n)
            setTile(n, v);
        return;
    }

    bool xInside = floodCornerValue(*node.getChild(first), false) < ValueT(0);
    for (Index x = 0; x < DIM; ++x) {
        const Index x00 = off[0][x] | off[1][0] | off[2][0];
        if (childMask.isOn(x00))
            xInside = floodCornerValue(*node.getChild(x00), true) < ValueT(0);
        bool yInside = xInside;
        for (Index y = 0; y < DIM; ++y) {
            const Index xy = off[0][x] | off[1][y];
            if (childMask.isOn(xy | off[2][0]))
                yInside = floodCornerValue(*node.getChild(xy | off[2][0]), true) < ValueT(0);
            bool zInside = yInside;
            for (Index z = 0; z < DIM; ++z) {
                const Index n = xy | off[2][z];
                if (childMask.isOn(n)) {
                    zInside = floodCornerValue(*node.getChild(n), true) < ValueT(0);
                } else {
                    setTile(n, zInside ? inside : outside);
                }
            }
        }
    }
}

/// Fills the gaps between a root's children along z-lines where both facing children say
/// inside (see the file comment).
template <typename RootT, typename ValueT>
void floodFillRoot(RootT& root, const ValueT& inside) {
    using ChildT = typename RootT::ChildNodeType;
    std::vector<std::pair<Coord, const ChildT*>> children;
    for (auto c = root.cbegin(); root.valid(c); root.next(c)) {
        if (const ChildT* child = root.entry(c).child)
            children.emplace_back(root.key(c), child);
    }
    std::sort(children.begin(), children.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    constexpr Int64 DIM = Int64(ChildT::DIM);
    for (size_t i = 1; i < children.size(); ++i) {
        const Coord& a = children[i - 1].first;
        const Coord& b = children[i].first;
        if (a[0] != b[0] || a[1] != b[1] || Int64(b[2]) - Int64(a[2]) == DIM)
            continue;
        if (!(floodCornerValue(*children[i - 1].second, true) < ValueT(0)) ||
            !(floodCornerValue(*children[i].second, false) < ValueT(0))) {
            continue;
        }
        for (Int64 z = Int64(a[2]) + DIM; z < Int64(b[2]); z += DIM) {
            const Coord key(a[0], a[1], Int32(z));
            const auto* e = root.findEntry(key);
            if (e && e->active)
                continue;
            root.setTile(key, inside, false);
        }
    }
}

template <Index L, Index Top, typename ListsT, typename OpT>
void floodFillLevels(const ListsT& lists, const OpT& op, bool threaded) {
    if constexpr (L < Top) {
        lists.template foreach<L>(op, threaded, L == 0 ? 16 : 1);
        floodFillLevels<L + 1, Top>(lists, op, threaded);
    }
}

/// The fill of the levels FIRST and up: FIRST = 1 leaves the leaves as they are (a tool that
/// signs every voxel of its leaves itself fills only the tiles).
template <Index FIRST = 0, typename TreeT>
void signedFloodFillImpl(TreeT& tree, const typename TreeT::ValueType& outside,
                         const typename TreeT::ValueType& inside, bool threaded) {
    using TopT = typename TreeT::TopNodeType;
    const auto fillNode = [&](auto& node) {
        if constexpr (std::remove_cvref_t<decltype(node)>::LEVEL == 0) {
            floodFillLeaf(node, outside, inside);
        } else {
            floodFillInternal(node, outside, inside);
        }
    };
    {
        const NodeLists<TreeT> lists(tree, FIRST);
        floodFillLevels<FIRST, TopT::LEVEL>(lists, fillNode, threaded);
    }
    if constexpr (tree::IS_ROOT_NODE<TopT>) {
        floodFillRoot(tree.topNode(), inside);
    } else {
        floodFillInternal(tree.topNode(), outside, inside);
    }
    tree.setBackground(outside);
}

}  // namespace detail

template <SignedVdbTree TreeT>
void signedFloodFill(TreeT& tree, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    const ValueT outside = detail::floodAbs(tree.background());
    detail::signedFloodFillImpl(tree, outside, ValueT(-outside), threaded);
}

template <SignedVdbTree TreeT>
void signedFloodFillWithValues(TreeT& tree, const typename TreeT::ValueType& outsideValue,
                               const typename TreeT::ValueType& insideValue, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    const ValueT outside = detail::floodAbs(outsideValue);
    const ValueT inside = ValueT(-detail::floodAbs(insideValue));
    detail::signedFloodFillImpl(tree, outside, inside, threaded);
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/SignedFloodFill.cpp

namespace vdb::tools {

extern template void signedFloodFill(FloatTree&, bool);
extern template void signedFloodFill(DoubleTree&, bool);
extern template void signedFloodFillWithValues(FloatTree&, const float&, const float&, bool);
extern template void signedFloodFillWithValues(DoubleTree&, const double&, const double&, bool);

}  // namespace vdb::tools
