// SPDX-License-Identifier: Apache-2.0
/// @file
/// Dense: a box of voxel values in one array, the bridge between a sparse grid and NumPy
/// arrays, image stacks and solvers; copyToDense() and copyFromDense() move values between the
/// two (OpenVDB's tools/Dense.h, with its names and meanings).
///
/// A Dense covers an index-space box and stores one value per voxel. Layout LayoutZYX (the
/// default) puts z fastest, as a C-ordered array indexed [x][y][z] and as the voxels of a leaf;
/// LayoutXYZ puts x fastest. A Dense may own its values or view memory it is given, with the
/// layout's strides or with any strides in elements (negative ones included), so that a NumPy
/// view is read and written in place.
///
/// - copyToDense(grid, dense): every voxel of the dense box gets the grid's value there (tiles
///   and background included). Threaded over leaf-sized blocks; exact.
/// - copyFromDense(dense, grid, tolerance): every voxel of the dense box becomes active with the
///   dense value, or inactive with the background where the value lies within `tolerance` of
///   the background; voxels outside the box keep their values and states. Leaf-sized blocks
///   are built in parallel from the grid's leaf or tile there and the dense values; a block
///   that comes out constant becomes a leaf-sized tile; then constant internal nodes are
///   pruned (pruneTiles). Where a block becomes all inactive background, whatever the grid
///   held there is replaced (OpenVDB keeps an existing leaf in that case).
///
/// Cost: one pass over the box; memory: the dense box's values when the Dense owns them.
/// Results do not depend on the thread count.
///
/// @code
/// vdb::tools::Dense<float> dense(vdb::CoordBBox(vdb::Coord(0), vdb::Coord(63)));
/// vdb::tools::copyToDense(*grid, dense);
/// dense.getValue(vdb::Coord(1, 2, 3)) += 1.0f;
/// vdb::tools::copyFromDense(dense, *grid, /*tolerance=*/0.0f);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/tools/Prune.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// Which axis varies fastest in a Dense's array: z (LayoutZYX, C order [x][y][z]) or x.
enum MemoryLayout { LayoutXYZ, LayoutZYX };

/// A dense box of `ValueT` values; see the file comment.
/// Threads: concurrent reads are safe; writes to different voxels are safe.
template <typename ValueT, MemoryLayout Layout = LayoutZYX>
class Dense {
public:
    using ValueType = ValueT;
    using Ptr = std::shared_ptr<Dense>;
    using ConstPtr = std::shared_ptr<const Dense>;

    /// Owns uninitialized values over `bbox`. @throw ValueError for an empty box or one of
    /// more values than memory can address.
    explicit Dense(const CoordBBox& bbox) : mBBox(bbox) {
        init();
        mOwned.reset(new ValueT[valueCount()]);
        mData = mOwned.get();
    }
    /// Owns values over `bbox`, all `value`.
    Dense(const CoordBBox& bbox, const ValueT& value) : Dense(bbox) { fill(value); }
    /// Views `data` (not owned; it must outlive the Dense) over `bbox` in the layout's order.
    Dense(const CoordBBox& bbox, ValueT* data) : mBBox(bbox), mData(data) { init(); }
    /// Views `data` over `bbox` with the strides, in elements, of a step in x, y and z: any
    /// layout, also a sliced or reversed NumPy view.
    Dense(const CoordBBox& bbox, ValueT* data, const std::array<std::ptrdiff_t, 3>& strides)
        : mBBox(bbox), mData(data) {
        init();
        mStrides = strides;
    }
    /// Owns values over the box of `dim` voxels per axis from `min`.
    explicit Dense(const Coord& dim, const Coord& min = Coord(0))
        : Dense(CoordBBox(min, min + dim.offsetBy(-1))) {}

    static MemoryLayout memoryLayout() { return Layout; }
    ValueT* data() { return mData; }
    const ValueT* data() const { return mData; }
    const CoordBBox& bbox() const { return mBBox; }
    const Coord& origin() const { return mBBox.min(); }
    Index64 valueCount() const { return mBBox.volume(); }

    /// Strides in elements of a step in x, y and z.
    std::ptrdiff_t xStride() const { return mStrides[0]; }
    std::ptrdiff_t yStride() const { return mStrides[1]; }
    std::ptrdiff_t zStride() const { return mStrides[2]; }

    /// The offset (in elements, from data()) of local voxel (i, j, k), 0 <= i < dim.x, ...
    std::ptrdiff_t coordToOffset(size_t i, size_t j, size_t k) const {
        return std::ptrdiff_t(i) * mStrides[0] + std::ptrdiff_t(j) * mStrides[1] +
               std::ptrdiff_t(k) * mStrides[2];
    }
    /// The offset of global voxel `ijk`. @pre bbox().isInside(ijk)
    std::ptrdiff_t coordToOffset(const Coord& ijk) const {
        return coordToOffset(size_t(Int64(ijk[0]) - mBBox.min()[0]),
                             size_t(Int64(ijk[1]) - mBBox.min()[1]),
                             size_t(Int64(ijk[2]) - mBBox.min()[2]));
    }

    const ValueT& getValue(const Coord& ijk) const { return mData[coordToOffset(ijk)]; }
    ValueT& getValue(const Coord& ijk) { return mData[coordToOffset(ijk)]; }
    void setValue(const Coord& ijk, const ValueT& value) { mData[coordToOffset(ijk)] = value; }
    const ValueT& getValue(size_t i, size_t j, size_t k) const {
        return mData[coordToOffset(i, j, k)];
    }
    ValueT& getValue(size_t i, size_t j, size_t k) { return mData[coordToOffset(i, j, k)]; }
    void setValue(size_t i, size_t j, size_t k, const ValueT& value) {
        mData[coordToOffset(i, j, k)] = value;
    }

    /// Sets every value of the box to `value`.
    void fill(const ValueT& value) {
        const auto e = mBBox.extents();
        for (Int64 i = 0; i < e[0]; ++i)
            for (Int64 j = 0; j < e[1]; ++j)
                for (Int64 k = 0; k < e[2]; ++k)
                    mData[coordToOffset(size_t(i), size_t(j), size_t(k))] = value;
    }

    /// Bytes of this object and, when it owns them, of its values.
    Index64 memUsage() const {
        return sizeof(*this) + (mOwned ? valueCount() * sizeof(ValueT) : 0);
    }

private:
    void init() {
        if (mBBox.empty())
            throw ValueError("Dense: the bounding box is empty");
        const auto e = mBBox.extents();
        if (double(e[0]) * double(e[1]) * double(e[2]) > double(PTRDIFF_MAX / sizeof(ValueT)))
            throw ValueError("Dense: the bounding box holds more values than memory can address");
        if constexpr (Layout == LayoutZYX) {
            mStrides = {std::ptrdiff_t(e[1] * e[2]), std::ptrdiff_t(e[2]), 1};
        } else {
            mStrides = {1, std::ptrdiff_t(e[0]), std::ptrdiff_t(e[0] * e[1])};
        }
    }

    CoordBBox mBBox;
    std::unique_ptr<ValueT[]> mOwned;
    ValueT* mData = nullptr;
    std::array<std::ptrdiff_t, 3> mStrides{};
};

/// Copies the values of `sparse` (a grid or a tree) over the box of `dense` into it.
template <typename DenseT, typename GridOrTreeT>
void copyToDense(const GridOrTreeT& sparse, DenseT& dense, bool serial = false);

/// Copies the values of `dense` into `sparse` (a grid or a tree): active where they differ
/// from the background by more than `tolerance`, else inactive background.
template <typename DenseT, typename GridOrTreeT>
void copyFromDense(const DenseT& dense, GridOrTreeT& sparse,
                   const typename GridOrTreeT::ValueType& tolerance, bool serial = false);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// The tree of a grid, or the tree itself.
template <typename T>
auto& treeOf(T& sparse) {
    if constexpr (requires { sparse.tree(); }) {
        return sparse.tree();
    } else {
        return sparse;
    }
}

/// One dense row of floating-point values into a leaf row: values within `tol` of `bg` become
/// `bg` with `on` 0, the others are kept with `on` 1 (for a NaN too: it is within no tolerance).
/// Separate pointers, so that the compiler vectorises the loop.
template <typename ValueT, typename SrcT>
void denseRowToLeaf(const SrcT* __restrict src, ValueT* __restrict out, uint8_t* __restrict on,
                    Index count, ValueT bg, ValueT tol) {
    for (Index k = 0; k < count; ++k) {
        const ValueT v = ValueT(src[k]);
        out[k] = math::isApproxEqual(bg, v, tol) ? bg : v;
    }
    // Active: what was not replaced by the background (a value within the tolerance was; a NaN
    // differs from everything).
    for (Index k = 0; k < count; ++k)
        on[k] = uint8_t(out[k] != bg);
}

/// The leaf-aligned blocks of `bbox`: each the part of `bbox` inside one leaf of edge `dim`.
inline std::vector<CoordBBox> leafBlocks(const CoordBBox& bbox, Int32 dim) {
    std::vector<CoordBBox> blocks;
    const auto lo = [dim](Int32 v) { return Int32(Int64(v) & ~Int64(dim - 1)); };
    for (Int64 x = lo(bbox.min()[0]); x <= bbox.max()[0]; x += dim)
        for (Int64 y = lo(bbox.min()[1]); y <= bbox.max()[1]; y += dim)
            for (Int64 z = lo(bbox.min()[2]); z <= bbox.max()[2]; z += dim) {
                CoordBBox b = CoordBBox::createCube(Coord(Int32(x), Int32(y), Int32(z)), dim);
                b.intersect(bbox);
                blocks.push_back(b);
            }
    return blocks;
}

}  // namespace detail

template <typename DenseT, typename GridOrTreeT>
void copyToDense(const GridOrTreeT& sparse, DenseT& dense, bool serial) {
    const auto& tree = detail::treeOf(sparse);
    using TreeT = std::remove_cvref_t<decltype(tree)>;
    using LeafT = typename TreeT::LeafNodeType;
    using DenseValueT = typename DenseT::ValueType;
    const std::vector<CoordBBox> blocks = detail::leafBlocks(dense.bbox(), Int32(LeafT::DIM));
    using ValueT = typename TreeT::ValueType;
    // Leaves with a plain value array are read row by row from it; bit leaves voxel by voxel.
    constexpr bool kArrayLeaf = requires(const LeafT& leaf) {
        { leaf.buffer(0).data() } -> std::same_as<const ValueT*>;
    };
    const std::ptrdiff_t step = dense.zStride();
    util::parallelForRange(
        blocks.size(),
        [&](size_t begin, size_t end) {
            tree::ValueAccessor<const TreeT> acc(tree);
            for (size_t b = begin; b < end; ++b) {
                const CoordBBox& box = blocks[b];
                const LeafT* leaf = acc.probeConstLeaf(box.min());
                const DenseValueT tile =
                    leaf ? DenseValueT{} : DenseValueT(acc.getValue(box.min()));
                const Int32 depth = box.max()[2] - box.min()[2] + 1;
                for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
                    for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j) {
                        DenseValueT* row = &dense.getValue(Coord(i, j, box.min()[2]));
                        if (!leaf) {
                            if (step == 1) {
                                std::fill_n(row, depth, tile);
                            } else {
                                for (Int32 k = 0; k < depth; ++k, row += step)
                                    *row = tile;
                            }
                            continue;
                        }
                        const Index n = LeafT::coordToOffset(Coord(i, j, box.min()[2]));
                        if constexpr (kArrayLeaf) {
                            const ValueT* in = leaf->buffer(0).data() + n;
                            if (step == 1 && std::is_same_v<DenseValueT, ValueT>) {
                                std::memcpy(row, in, size_t(depth) * sizeof(ValueT));
                            } else if (step == 1) {
                                for (Int32 k = 0; k < depth; ++k)
                                    row[k] = DenseValueT(in[k]);
                            } else {
                                for (Int32 k = 0; k < depth; ++k, row += step)
                                    *row = DenseValueT(in[k]);
                            }
                        } else {
                            for (Int32 k = 0; k < depth; ++k, row += step)
                                *row = DenseValueT(leaf->getValue(n + Index(k)));
                        }
                    }
            }
        },
        !serial, 8);
}

template <typename DenseT, typename GridOrTreeT>
void copyFromDense(const DenseT& dense, GridOrTreeT& sparse,
                   const typename GridOrTreeT::ValueType& tolerance, bool serial) {
    auto& tree = detail::treeOf(sparse);
    using TreeT = std::remove_cvref_t<decltype(tree)>;
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    using Word = typename LeafT::MaskType::Word;
    // Leaves with a plain value array are written in one pass; bit leaves voxel by voxel.
    constexpr bool kArrayLeaf = requires(LeafT & leaf) {
        { leaf.buffer(0).data() } -> std::same_as<ValueT*>;
        leaf.setBufferCount(1);
    };
    struct Block {
        CoordBBox box;
        std::unique_ptr<LeafT> leaf;  // the block as a leaf, or null for a tile
        ValueT tile{};
        bool tileOn = false;
        bool addTile = false;  // the tile differs from what the tree held
    };
    const std::vector<CoordBBox> boxes = detail::leafBlocks(dense.bbox(), Int32(LeafT::DIM));
    std::vector<Block> blocks(boxes.size());
    const ValueT background = tree.background();
    const ValueT bg = background, tol = tolerance;  // by value: no aliasing with the outputs
    const std::ptrdiff_t zStride = dense.zStride();
    util::parallelForRange(
        blocks.size(),
        [&](size_t begin, size_t end) {
            tree::ValueAccessor<const TreeT> acc(tree);
            // A block that comes out constant leaves its leaf here for the next block.
            std::unique_ptr<LeafT> scratch;
            for (size_t b = begin; b < end; ++b) {
                Block& block = blocks[b];
                block.box = boxes[b];
                const Coord origin = block.box.min().alignedDown(LeafT::LOG2DIM);
                const bool whole = block.box == CoordBBox::createCube(origin, LeafT::DIM);
                const LeafT* target = acc.probeConstLeaf(origin);
                ValueT before{};
                bool beforeOn = false;
                if (!target)
                    beforeOn = acc.probeValue(origin, before);
                if constexpr (kArrayLeaf) {
                    if (!scratch) {
                        scratch = std::make_unique<LeafT>(tree::PartialCreate{}, origin);
                        scratch->setBufferCount(1);
                    }
                } else if (!scratch) {
                    scratch = std::make_unique<LeafT>(origin, background, false);
                }
                LeafT& leaf = *scratch;
                leaf.setOrigin(origin);
                // A partial block starts from what the tree holds there: its leaf or its tile.
                if (!whole) {
                    if (target)
                        leaf = *target;
                    else
                        leaf.fill(before, beforeOn);
                }
                bool written = false;
                if constexpr (kArrayLeaf) {
                    if (whole) {
                        // Every voxel from the dense values: values and mask words at once.
                        ValueT* out = leaf.buffer(0).data();
                        Word* words = leaf.getValueMask().words();
                        if constexpr (std::is_floating_point_v<ValueT>) {
                            if (zStride == 1) {
                                // Contiguous rows: vectorised loops, then the mask from bytes.
                                uint8_t on[LeafT::NUM_VALUES];
                                constexpr Index DIM = LeafT::DIM;
                                for (Index i = 0; i < DIM; ++i)
                                    for (Index j = 0; j < DIM; ++j) {
                                        const Index n = (i * DIM + j) * DIM;
                                        detail::denseRowToLeaf(
                                            &dense.getValue(origin.offsetBy(Int32(i), Int32(j), 0)),
                                            out + n, on + n, DIM, bg, tol);
                                    }
                                leaf.getValueMask().setFromBytes(on);
                                written = true;
                            }
                        }
                        if (!written) {
                            std::fill_n(words, LeafT::MaskType::WORD_COUNT, Word(0));
                            Index n = 0;
                            for (Int32 i = 0; i < Int32(LeafT::DIM); ++i)
                                for (Int32 j = 0; j < Int32(LeafT::DIM); ++j) {
                                    const auto* src = &dense.getValue(origin.offsetBy(i, j, 0));
                                    for (Index k = 0; k < LeafT::DIM; ++k, ++n, src += zStride) {
                                        const ValueT v = ValueT(*src);
                                        const bool on = !math::isApproxEqual(bg, v, tol);
                                        out[n] = on ? v : bg;
                                        words[n >> 6] |= Word(on) << (n & 63);
                                    }
                                }
                            written = true;
                        }
                    }
                }
                if (!written) {
                    for (Int32 i = block.box.min()[0]; i <= block.box.max()[0]; ++i)
                        for (Int32 j = block.box.min()[1]; j <= block.box.max()[1]; ++j) {
                            const auto* src = &dense.getValue(Coord(i, j, block.box.min()[2]));
                            Index n = LeafT::coordToOffset(Coord(i, j, block.box.min()[2]));
                            for (Int32 k = block.box.min()[2]; k <= block.box.max()[2];
                                 ++k, src += zStride, ++n) {
                                const ValueT v = ValueT(*src);
                                if (math::isApproxEqual(background, v, tolerance))
                                    leaf.setValueOff(n, background);
                                else
                                    leaf.setValueOn(n, v);
                            }
                        }
                }
                if (leaf.isConstant(block.tile, block.tileOn, tolerance)) {
                    block.addTile = target || block.tileOn != beforeOn ||
                                    !math::isApproxEqual(block.tile, before, tolerance);
                } else {
                    block.leaf = std::move(scratch);
                }
            }
        },
        !serial, 8);
    // Link the blocks in order (the same tree for every thread count), then prune.
    for (Block& block : blocks) {
        if (block.leaf)
            tree.addLeaf(std::move(block.leaf));
        else if (block.addTile)
            tree.addTile(1, block.box.min(), block.tile, block.tileOn);
    }
    pruneTiles(tree, tolerance, !serial);
}

}  // namespace vdb::tools
