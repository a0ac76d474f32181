// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery of tools/VolumeToMesh.h: the tables of the cell cube (which crossing edges of
/// a cell form one sheet), the walk over the tiles of a tree, and the block-by-block mesher.
/// Included by VolumeToMesh.h after its declarations. Not API.
///
/// The mesher works on blocks: the leaf-sized cubes of cells whose lowest corner lies in one
/// leaf's region. Every leaf is a block; so is every leaf-sized region of tiles next to a leaf
/// or to a tile of the other side of the isovalue. A block's cells read a dense lattice of
/// (DIM + 1)^3 values (its own and one layer of its upper neighbours), gathered once. A cell
/// owns the three edges that leave its lowest corner, so every edge, cell and vertex belongs to
/// exactly one block, and a block's quads reach only into its lower neighbours.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/RootTable.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Assert.h>
#include <vdb/util/BitMask.h>
#include <vdb/util/Parallel.h>

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

// ---- The cell cube ----
//
// Corner n of a cell sits at (n & 1, n >> 1 & 1, n >> 2 & 1); bit n of a cell's sign byte is set
// when corner n lies below the isovalue. Edge e runs along axis e >> 2, at offsets e & 1 and
// e >> 1 & 1 along the two other axes (in increasing order). Face f is normal to axis f >> 1,
// on side f & 1. A face is ambiguous when its diagonal corners agree and its neighbours do not:
// it then holds two segments of surface, which either cut off the two corners below the
// isovalue ("separated") or the two above ("joined" below). Bit f of a cell's face byte says
// that face f is resolved as joined.

/// The least distance, in voxels, between an edge's crossing point and the edge's ends.
inline constexpr double kCrossingMargin = 1e-3;

/// The two axes other than `axis`, in increasing order.
inline constexpr int kOtherAxes[3][2] = {{1, 2}, {0, 2}, {0, 1}};

/// The sheets of one cell configuration: the sheet (0-3) of each crossing edge, two bits per
/// edge, the number of sheets, and the ambiguous faces whose two segments lie on one sheet.
struct CellSheets {
    uint32_t edgeSheet = 0;
    uint8_t count = 0;
    uint8_t joined = 0;

    unsigned sheetOf(int edge) const { return (edgeSheet >> (2 * edge)) & 3u; }
};

/// Lookup tables of the cell cube, built once.
struct CubeTables {
    std::array<uint8_t, 12> edgeLow{}, edgeHigh{};       // corner indices of each edge
    std::array<std::array<uint8_t, 4>, 6> faceCorner{};  // corners of each face, in cycle order
    std::array<std::array<uint8_t, 4>, 6> faceEdge{};    // edge from faceCorner[i] to [i + 1]
    std::array<uint8_t, 256> ambiguous{};                // ambiguous faces of each sign byte
    std::vector<CellSheets> sheets;  // [signs * 64 + (faces & ambiguous[signs])]

    const CellSheets& of(unsigned signs, unsigned faces) const {
        return sheets[signs * 64u + (faces & ambiguous[signs])];
    }
    /// True when the configuration holds one sheet and no ambiguous face.
    bool isSimple(unsigned signs) const { return ambiguous[signs] == 0 && of(signs, 0).count == 1; }

    CubeTables() {
        const auto bit = [](int n, int axis) { return (n >> axis) & 1; };
        const auto edgeAt = [&](int axis, int corner) {
            return 4 * axis + bit(corner, kOtherAxes[axis][0]) +
                   2 * bit(corner, kOtherAxes[axis][1]);
        };
        for (int e = 0; e < 12; ++e) {
            const int axis = e >> 2;
            const int base = (e & 1) << kOtherAxes[axis][0] | ((e >> 1) & 1) << kOtherAxes[axis][1];
            edgeLow[e] = uint8_t(base);
            edgeHigh[e] = uint8_t(base | 1 << axis);
        }
        for (int f = 0; f < 6; ++f) {
            const int axis = f >> 1, p = kOtherAxes[axis][0], q = kOtherAxes[axis][1];
            const int side = (f & 1) << axis;
            const int cycle[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int i = 0; i < 4; ++i)
                faceCorner[f][i] = uint8_t(side | cycle[i][0] << p | cycle[i][1] << q);
            for (int i = 0; i < 4; ++i) {
                const int a = faceCorner[f][i], b = faceCorner[f][(i + 1) & 3];
                faceEdge[f][i] = uint8_t(edgeAt(std::countr_zero(unsigned(a ^ b)), a & b));
            }
        }
        for (int s = 0; s < 256; ++s) {
            for (int f = 0; f < 6; ++f) {
                const auto& c = faceCorner[f];
                const int b0 = bit(s, c[0]), b1 = bit(s, c[1]), b2 = bit(s, c[2]),
                          b3 = bit(s, c[3]);
                if (b0 == b2 && b1 == b3 && b0 != b1)
                    ambiguous[s] |= uint8_t(1 << f);
            }
        }
        sheets.resize(256 * 64);
        for (int s = 0; s < 256; ++s) {
            for (int faces = 0; faces < 64; ++faces) {
                if ((faces & ~ambiguous[s]) == 0)
                    sheets[s * 64 + faces] = build(s, faces);
            }
        }
    }

private:
    // Joins the crossing edges of each face into segments and numbers the cycles they form.
    CellSheets build(int signs, int faces) const {
        std::array<int, 12> parent{};
        for (int e = 0; e < 12; ++e)
            parent[e] = e;
        const auto find = [&](int e) {
            while (parent[e] != e)
                e = parent[e] = parent[parent[e]];
            return e;
        };
        const auto unite = [&](int a, int b) { parent[find(a)] = find(b); };
        const auto crosses = [&](int e) {
            return ((signs >> edgeLow[e]) & 1) != ((signs >> edgeHigh[e]) & 1);
        };
        CellSheets out;
        for (int f = 0; f < 6; ++f) {
            const auto& ed = faceEdge[f];
            int crossing[4], n = 0;
            for (int i = 0; i < 4; ++i)
                if (crosses(ed[i]))
                    crossing[n++] = ed[i];
            if (n == 2) {
                unite(crossing[0], crossing[1]);
            } else if (n == 4) {
                // Cut off corners 0 and 2 of the cycle, or corners 1 and 3: the pair below the
                // isovalue when separated, the pair above when joined.
                const bool below0 = (signs >> faceCorner[f][0]) & 1;
                const bool joined = (faces >> f) & 1;
                if (below0 != joined) {
                    unite(ed[3], ed[0]);
                    unite(ed[1], ed[2]);
                } else {
                    unite(ed[0], ed[1]);
                    unite(ed[2], ed[3]);
                }
            }
        }
        std::array<int, 12> id;
        id.fill(-1);
        for (int e = 0; e < 12; ++e) {
            if (!crosses(e))
                continue;
            int& sheet = id[find(e)];
            if (sheet < 0)
                sheet = out.count++;
            out.edgeSheet |= uint32_t(sheet) << (2 * e);
        }
        for (int f = 0; f < 6; ++f) {
            const auto& ed = faceEdge[f];
            if (((ambiguous[signs] >> f) & 1) && find(ed[0]) == find(ed[1]) &&
                find(ed[1]) == find(ed[2]))
                out.joined |= uint8_t(1 << f);
        }
        return out;
    }
};

inline const CubeTables& cubeTables() {
    static const CubeTables tables;
    return tables;
}

// ---- The mesher ----

/// Meshes one tree's isosurface into points (world space) and polygons; see VolumeToMesh.h.
template <typename TreeT>
class VolumeMesher {
public:
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    using TopT = typename TreeT::TopNodeType;
    using Accessor = tree::ValueAccessor<const TreeT>;

    static constexpr Index LOG2 = LeafT::LOG2DIM;
    static constexpr Int32 B = Int32(LeafT::DIM);  ///< cells along a block's edge
    static constexpr Int32 L = B + 1;              ///< lattice points along a block's edge
    static constexpr Index CELLS = LeafT::NUM_VALUES;
    static constexpr Index LATTICE = Index(L) * Index(L) * Index(L);
    static constexpr uint32_t NONE = ~uint32_t(0);
    using CellMask = util::BitMask<CELLS>;

    VolumeMesher(const TreeT& tree, const math::Transform& xform, double isovalue,
                 double adaptivity, bool inverted, bool relax)
        : mTree(tree),
          mXform(xform),
          mIso(isovalue),
          mAdaptivity(std::min(adaptivity, 1.0)),
          mAdaptive(adaptivity > 1e-6),
          mInverted(inverted),
          mRelax(relax),
          mTables(cubeTables()) {}

    void run(std::vector<Vec3s>& points, std::vector<Vec3I>& triangles, std::vector<Vec4I>& quads);

private:
    // A surface cell: the block index of its first vertex, its sign and face bytes.
    struct Cell {
        uint32_t vertex;
        uint8_t signs, faces;
    };

    // One block: the surface cells whose lowest corner lies in one leaf-sized region, their
    // sheets' vertices (index space, relative to the origin) and what the quads need.
    struct Block {
        Coord origin;
        CellMask surface;                                   // surface cells
        std::array<uint32_t, CellMask::WORD_COUNT> rank{};  // surface cells before each word
        std::vector<Cell> cell;                             // per surface cell, in offset order
        std::vector<Vec3s> points;      // block vertices, relative to the origin
        std::vector<uint32_t> doubled;  // (cell offset << 3 | face) of faces joined on one sheet
        std::vector<Coord> extras;      // non-leaf lower neighbours that hold surface cells
        std::vector<Vec4I> quads;       // adaptive meshing: polygons, before they are gathered
        std::vector<Vec3I> triangles;
        uint32_t edges = 0;  // surface-crossing edges the block owns
        uint64_t pointOffset = 0, quadOffset = 0, triangleOffset = 0;
        std::array<uint32_t, 8> lower{};  // block index at origin - DIM * (d & 1, d >> 1 & 1,
                                          // d >> 2 & 1), NONE when there is none
        bool isLeaf = false;

        uint32_t slotOf(Index offset) const {
            const Index w = offset >> 6;
            const uint64_t below = (uint64_t(1) << (offset & 63)) - 1;
            return rank[w] + uint32_t(std::popcount(surface.getWord(w) & below));
        }
    };

    // Per-thread scratch space.
    static constexpr Index ROW_WORDS = (Index(L) + 63) / 64;
    struct Scratch {
        std::vector<ValueT> value = std::vector<ValueT>(LATTICE);  // the block's lattice
        // Per lattice row (i, j), ROW_WORDS words: bit k set when point (i, j, k) lies below.
        std::vector<uint64_t> below = std::vector<uint64_t>(size_t(L) * size_t(L) * ROW_WORDS);
        std::vector<Index> cellOffset;     // surface cells in offset order
        std::vector<uint8_t> cellSigns;    // and their sign bytes
        std::vector<Vec3d> sheetPoint;     // every sheet's point, per cell in order
        std::vector<uint32_t> firstPoint;  // per surface cell: its first entry in sheetPoint
        std::vector<Vec3d> normal;         // per surface cell (adaptive meshing)
        std::vector<uint32_t> slot;        // per cell offset: surface cell index or NONE
        std::vector<uint32_t> region;      // per surface cell: merged region or NONE
        std::vector<Vec3d> gathered;       // normals of one group
    };

    using FlipMap = std::map<Coord, uint8_t>;

    static bool belowAt(const Scratch& s, Int32 i, Int32 j, Int32 k) {
        return (s.below[(Index(i) * Index(L) + Index(j)) * ROW_WORDS + Index(k >> 6)] >> (k & 63)) &
               1;
    }
    Index latticeIndex(Int32 i, Int32 j, Int32 k) const {
        return (Index(i) * Index(L) + Index(j)) * Index(L) + Index(k);
    }
    static Index cellOffsetOf(Int32 i, Int32 j, Int32 k) {
        return (Index(i) << (2 * LOG2)) | (Index(j) << LOG2) | Index(k);
    }

    void gather(const Coord& origin, Scratch& s, Accessor& acc) const;
    void extract(Block& blk, Scratch& s, Accessor& acc, const FlipMap* flips) const;
    void findExtras(Block& blk, const Scratch& s, Accessor& acc) const;
    void merge(Block& blk, Scratch& s) const;
    bool coarseCellIsSimple(const Scratch& s, Int32 gi, Int32 gj, Int32 gk, Int32 dim) const;
    bool normalsAgree(Scratch& s, Int32 gi, Int32 gj, Int32 gk, Int32 dim) const;
    Vec3d projectToSurface(const Scratch& s, const Vec3d& start, Int32 gi, Int32 gj, Int32 gk,
                           Int32 dim) const;
    std::vector<Coord> tileBorderBlocks() const;
    template <typename NodeT>
    void tileBordersOfNode(const NodeT& node, std::vector<Coord>& out) const;
    void addTileBorder(const CoordBBox& tile, int face, const CoordBBox& region,
                       std::vector<Coord>& out) const;
    void linkBlocks();
    void fixDoubledFaces();
    uint32_t vertexOf(const Block& blk, const uint32_t* slots, Int32 i, Int32 j, Int32 k,
                      int edge) const;
    bool buildPolygons(Block& blk, std::vector<uint32_t>& slots, Vec4I* quadsOut) const;
    void relaxDisoriented(std::vector<Vec3s>& points, const std::vector<Vec3I>& triangles,
                          const std::vector<Vec4I>& quads) const;
    bool isBelow(double v) const { return v < mIso; }

    const TreeT& mTree;
    const math::Transform& mXform;
    const double mIso;
    const double mAdaptivity;
    const bool mAdaptive, mInverted, mRelax;
    const CubeTables& mTables;
    std::vector<Block> mBlocks;
    tree::detail::RootTable<uint32_t, LOG2, tree::HashTable> mIndex;  // origin -> block
};

// ---- Gathering values ----

template <typename TreeT>
void VolumeMesher<TreeT>::gather(const Coord& origin, Scratch& s, Accessor& acc) const {
    // The block itself (d = 0) and the first layer of its seven upper neighbours.
    for (int d = 0; d < 8; ++d) {
        const Int32 dx = d & 1, dy = (d >> 1) & 1, dz = (d >> 2) & 1;
        const Coord src = origin.offsetBy(dx * B, dy * B, dz * B);
        const Int32 i0 = dx * B, i1 = dx ? L : B;
        const Int32 j0 = dy * B, j1 = dy ? L : B;
        const Int32 k0 = dz * B, k1 = dz ? L : B;
        if (const LeafT* leaf = acc.probeConstLeaf(src)) {
            const ValueT* data = &leaf->getValue(Index(0));
            for (Int32 i = i0; i < i1; ++i) {
                for (Int32 j = j0; j < j1; ++j) {
                    const ValueT* row = data + cellOffsetOf(i - i0, j - j0, 0) - k0;
                    ValueT* out = &s.value[latticeIndex(i, j, 0)];
                    for (Int32 k = k0; k < k1; ++k)
                        out[k] = row[k];
                }
            }
        } else {
            const ValueT v = acc.getValue(src);
            for (Int32 i = i0; i < i1; ++i)
                for (Int32 j = j0; j < j1; ++j)
                    for (Int32 k = k0; k < k1; ++k)
                        s.value[latticeIndex(i, j, k)] = v;
        }
    }
    for (Index row = 0; row < Index(L) * Index(L); ++row) {
        const ValueT* v = &s.value[row * Index(L)];
        for (Index w = 0; w < ROW_WORDS; ++w) {
            uint64_t bits = 0;
            const Index end = std::min(Index(L), 64 * w + 64);
            for (Index k = 64 * w; k < end; ++k)
                bits |= uint64_t(isBelow(double(v[k]))) << (k & 63);
            s.below[row * ROW_WORDS + w] = bits;
        }
    }
}

// ---- One block's cells and vertices ----

template <typename TreeT>
void VolumeMesher<TreeT>::extract(Block& blk, Scratch& s, Accessor& acc,
                                  const FlipMap* flips) const {
    gather(blk.origin, s, acc);
    blk.surface.setOff();
    blk.cell.clear();
    blk.points.clear();
    blk.doubled.clear();
    blk.edges = 0;
    s.cellOffset.clear();
    s.cellSigns.clear();

    // The cells with corners on both sides hold surface: per row of cells along z, the points
    // of the four lattice rows around it, a word at a time.
    const Index LL = Index(L) * Index(L);
    for (Int32 i = 0; i < B; ++i) {
        for (Int32 j = 0; j < B; ++j) {
            const uint64_t* r00 = &s.below[(Index(i) * Index(L) + Index(j)) * ROW_WORDS];
            const uint64_t* r10 = r00 + Index(L) * ROW_WORDS;
            const uint64_t* r01 = r00 + ROW_WORDS;
            const uint64_t* r11 = r10 + ROW_WORDS;
            const auto all = [&](Index w) { return r00[w] & r10[w] & r01[w] & r11[w]; };
            const auto any = [&](Index w) { return r00[w] | r10[w] | r01[w] | r11[w]; };
            for (Index w = 0; w < ROW_WORDS && Int32(64 * w) < B; ++w) {
                // Bit k of a word and bit k + 1 (the next point along z).
                const uint64_t a = all(w), o = any(w);
                const uint64_t a1 = (a >> 1) | (w + 1 < ROW_WORDS ? all(w + 1) << 63 : 0);
                const uint64_t o1 = (o >> 1) | (w + 1 < ROW_WORDS ? any(w + 1) << 63 : 0);
                const Index cellsHere = std::min(Index(64), Index(B) - 64 * w);
                const uint64_t valid =
                    cellsHere == 64 ? ~uint64_t(0) : (uint64_t(1) << cellsHere) - 1;
                for (uint64_t cross = (o | o1) & ~(a & a1) & valid; cross != 0;
                     cross &= cross - 1) {
                    const Int32 k = Int32(64 * w) + Int32(std::countr_zero(cross));
                    const auto at = [&](const uint64_t* r, Int32 kk) {
                        return unsigned((r[Index(kk) >> 6] >> (kk & 63)) & 1);
                    };
                    const unsigned signs = at(r00, k) | at(r10, k) << 1 | at(r01, k) << 2 |
                                           at(r11, k) << 3 | at(r00, k + 1) << 4 |
                                           at(r10, k + 1) << 5 | at(r01, k + 1) << 6 |
                                           at(r11, k + 1) << 7;
                    const Index offset = cellOffsetOf(i, j, k);
                    blk.surface.setOn(offset);
                    s.cellOffset.push_back(offset);
                    s.cellSigns.push_back(uint8_t(signs));
                    // The three owned edges: corner 0 to corners 1 (x), 2 (y) and 4 (z).
                    blk.edges += ((signs ^ (signs >> 1)) & 1) + ((signs ^ (signs >> 2)) & 1) +
                                 ((signs ^ (signs >> 4)) & 1);
                }
            }
        }
    }
    uint32_t count = 0;
    for (Index w = 0; w < CellMask::WORD_COUNT; ++w) {
        blk.rank[w] = count;
        count += uint32_t(std::popcount(blk.surface.getWord(w)));
    }
    if (blk.isLeaf)
        findExtras(blk, s, acc);
    const size_t n = s.cellOffset.size();
    if (n == 0)
        return;

    // Face resolutions, sheets and the sheets' points.
    blk.cell.resize(n);
    s.sheetPoint.clear();
    s.firstPoint.resize(n);
    if (mAdaptive)
        s.normal.resize(n);
    std::array<double, 8> v;
    for (size_t c = 0; c < n; ++c) {
        const Index offset = s.cellOffset[c];
        const Coord local = LeafT::offsetToLocalCoord(offset);
        const unsigned signs = s.cellSigns[c];
        blk.cell[c].signs = uint8_t(signs);
        const Index base = latticeIndex(local[0], local[1], local[2]);
        for (int corner = 0; corner < 8; ++corner)
            v[corner] = double(s.value[base + Index(corner & 1) * LL +
                                       Index((corner >> 1) & 1) * Index(L) + Index(corner >> 2)]);
        unsigned faces = 0;
        const unsigned ambiguous = mTables.ambiguous[signs];
        for (int f = 0; f < 6; ++f) {
            if (!((ambiguous >> f) & 1))
                continue;
            // The bilinear interpolant's saddle lies below the isovalue (and joins the two
            // corners below) when the product over the lower diagonal exceeds the other's.
            const auto& q = mTables.faceCorner[f];
            const double p02 = (v[q[0]] - mIso) * (v[q[2]] - mIso);
            const double p13 = (v[q[1]] - mIso) * (v[q[3]] - mIso);
            const bool below02 = (signs >> q[0]) & 1;
            if (below02 ? p02 > p13 : p13 > p02)
                faces |= 1u << f;
        }
        if (flips) {
            const auto it = flips->find(blk.origin + local);
            if (it != flips->end())
                faces ^= it->second;
        }
        blk.cell[c].faces = uint8_t(faces);
        const CellSheets& sheets = mTables.of(signs, faces);
        for (int f = 0; f < 6; ++f)
            if ((sheets.joined >> f) & 1)
                blk.doubled.push_back(uint32_t(offset) << 3 | uint32_t(f));

        // Each sheet's vertex: the mean of its edges' crossing points.
        s.firstPoint[c] = uint32_t(s.sheetPoint.size());
        const Vec3d corner0(local);
        const auto crossing = [&](int e) {
            const int a = mTables.edgeLow[e], b = mTables.edgeHigh[e];
            const double va = v[a], vb = v[b];
            if (std::isnan(va) || std::isnan(vb)) {
                std::ostringstream msg;
                msg << "volumeToMesh: the grid holds a NaN value next to the surface, in the cell "
                    << "at " << (blk.origin + local);
                throw ValueError(msg.str());
            }
            double t = (mIso - va) / (vb - va);
            if (!(t >= 0.0 && t <= 1.0))  // an infinite value: the crossing is at the other end
                t = std::isinf(va) ? (std::isinf(vb) ? 0.5 : 1.0) : 0.0;
            // A voxel whose value equals the isovalue would put the crossings of every cell
            // around it, and so their vertices, on its centre: keep them a little apart.
            t = std::clamp(t, kCrossingMargin, 1.0 - kCrossingMargin);
            Vec3d p(double(a & 1), double((a >> 1) & 1), double(a >> 2));
            p[size_t(e >> 2)] += t;
            return p;
        };
        const auto crosses = [&](int e) {
            return ((signs >> mTables.edgeLow[e]) & 1) != ((signs >> mTables.edgeHigh[e]) & 1);
        };
        if (sheets.count == 1) {
            Vec3d sum(0.0);
            int hits = 0;
            for (int e = 0; e < 12; ++e) {
                if (crosses(e)) {
                    sum += crossing(e);
                    ++hits;
                }
            }
            s.sheetPoint.push_back(corner0 + sum / double(hits));
        } else {
            std::array<Vec3d, 4> sum{};
            std::array<int, 4> hits{};
            for (int e = 0; e < 12; ++e) {
                if (crosses(e)) {
                    const unsigned sheet = sheets.sheetOf(e);
                    sum[sheet] += crossing(e);
                    ++hits[sheet];
                }
            }
            for (int sheet = 0; sheet < sheets.count; ++sheet)
                s.sheetPoint.push_back(corner0 + sum[size_t(sheet)] / double(hits[size_t(sheet)]));
        }
        if (mAdaptive) {
            // The surface normal of the cell: the central-difference gradient at its lowest
            // corner, as OpenVDB estimates it (the neighbour below comes from the tree at the
            // block's lower faces).
            Vec3d g;
            for (int axis = 0; axis < 3; ++axis) {
                Coord lo = local;
                lo[size_t(axis)] -= 1;
                const double below = lo[size_t(axis)] >= 0
                                         ? double(s.value[latticeIndex(lo[0], lo[1], lo[2])])
                                         : double(acc.getValue(blk.origin + lo));
                g[axis] = 0.5 * (v[size_t(1) << axis] - below);
            }
            const double len = g.length();
            s.normal[c] = len > 0.0 && std::isfinite(len) ? g / len : Vec3d(0.0);
        }
    }

    // Vertices: one per sheet, or one per merged region of simple cells.
    if (mAdaptive) {
        merge(blk, s);
        return;
    }
    blk.points.reserve(s.sheetPoint.size());
    for (size_t c = 0; c < n; ++c) {
        blk.cell[c].vertex = uint32_t(blk.points.size());
        const uint32_t end = c + 1 < n ? s.firstPoint[c + 1] : uint32_t(s.sheetPoint.size());
        for (uint32_t p = s.firstPoint[c]; p < end; ++p)
            blk.points.push_back(Vec3s(s.sheetPoint[p]));
    }
}

template <typename TreeT>
void VolumeMesher<TreeT>::findExtras(Block& blk, const Scratch& s, Accessor& acc) const {
    // A lower neighbour without a leaf holds one value; its cells next to this block cross the
    // surface when a point of this block's shared face, edge or corner lies on the other side.
    for (int d = 1; d < 8; ++d) {
        const Int32 dx = d & 1, dy = (d >> 1) & 1, dz = (d >> 2) & 1;
        const Coord other = blk.origin.offsetBy(-dx * B, -dy * B, -dz * B);
        if (acc.probeConstLeaf(other))
            continue;
        const bool below = isBelow(double(acc.getValue(other)));
        bool differs = false;
        for (Int32 i = 0; i < (dx ? 1 : B) && !differs; ++i)
            for (Int32 j = 0; j < (dy ? 1 : B) && !differs; ++j)
                for (Int32 k = 0; k < (dz ? 1 : B) && !differs; ++k)
                    differs = belowAt(s, i, j, k) != below;
        if (differs)
            blk.extras.push_back(other);
    }
}

// ---- Adaptivity ----

template <typename TreeT>
bool VolumeMesher<TreeT>::coarseCellIsSimple(const Scratch& s, Int32 gi, Int32 gj, Int32 gk,
                                             Int32 dim) const {
    // Signs at the 3x3x3 points of the coarse cell, spaced dim / 2 apart.
    const Int32 h = dim / 2;
    const auto at = [&](int a, int b, int c) {
        return belowAt(s, gi + a * h, gj + b * h, gk + c * h);
    };
    const auto cornerSign = [&](int n) {
        return at(2 * (n & 1), 2 * ((n >> 1) & 1), 2 * (n >> 2));
    };
    unsigned signs = 0;
    for (int n = 0; n < 8; ++n)
        signs |= unsigned(cornerSign(n)) << n;
    if (signs == 0 || signs == 255 || !mTables.isSimple(signs))
        return false;
    // Every coarse edge's midpoint agrees with one of its ends; the centre of every coarse face
    // with one of its corners; the cell's centre with one of its corners (Ju et al. 2002).
    for (int e = 0; e < 12; ++e) {
        const int a = mTables.edgeLow[e], b = mTables.edgeHigh[e];
        const int axis = e >> 2;
        int m[3] = {2 * (a & 1), 2 * ((a >> 1) & 1), 2 * (a >> 2)};
        m[axis] = 1;
        const bool mid = at(m[0], m[1], m[2]);
        if (mid != cornerSign(a) && mid != cornerSign(b))
            return false;
    }
    for (int f = 0; f < 6; ++f) {
        int m[3] = {1, 1, 1};
        m[f >> 1] = 2 * (f & 1);
        const bool mid = at(m[0], m[1], m[2]);
        bool agrees = false;
        for (int i = 0; i < 4; ++i)
            agrees = agrees || mid == cornerSign(mTables.faceCorner[f][i]);
        if (!agrees)
            return false;
    }
    const bool centre = at(1, 1, 1);
    return signs != (centre ? 0u : 255u);
}

template <typename TreeT>
bool VolumeMesher<TreeT>::normalsAgree(Scratch& s, Int32 gi, Int32 gj, Int32 gk, Int32 dim) const {
    if (mAdaptivity >= 1.0)
        return true;
    // Pairwise 1 - n_i.n_j <= adaptivity, that is an angle of at most `limit` between any two
    // normals. Every normal lies within `limit` of their mean when that holds (the cone of
    // half-angle limit <= 90 degrees around each normal is convex), and it holds when every
    // normal lies within limit / 2 of the mean; only between the two are all pairs compared.
    s.gathered.clear();
    Vec3d mean(0.0);
    for (Int32 i = gi; i < gi + dim; ++i)
        for (Int32 j = gj; j < gj + dim; ++j)
            for (Int32 k = gk; k < gk + dim; ++k) {
                const uint32_t c = s.slot[cellOffsetOf(i, j, k)];
                if (c == NONE)
                    continue;
                const Vec3d& n = s.normal[c];
                if (n.lengthSqr() == 0.0)
                    return false;
                s.gathered.push_back(n);
                mean += n;
            }
    const double len = mean.length();
    if (!(len > 0.0))
        return false;
    mean /= len;
    const double cosLimit = 1.0 - mAdaptivity;
    const double cosHalf = std::sqrt(0.5 * (1.0 + cosLimit));
    double worst = 1.0;
    for (const Vec3d& n : s.gathered)
        worst = std::min(worst, n.dot(mean));
    if (worst >= cosHalf)
        return true;
    if (worst < cosLimit)
        return false;
    for (size_t a = 0; a < s.gathered.size(); ++a)
        for (size_t b = a + 1; b < s.gathered.size(); ++b)
            if (s.gathered[a].dot(s.gathered[b]) < cosLimit)
                return false;
    return true;
}

template <typename TreeT>
Vec3d VolumeMesher<TreeT>::projectToSurface(const Scratch& s, const Vec3d& start, Int32 gi,
                                            Int32 gj, Int32 gk, Int32 dim) const {
    // Newton steps along the gradient of the trilinear interpolant, kept in the merged block.
    const Vec3d lo{double(gi), double(gj), double(gk)};
    const Vec3d hi = lo + double(dim);
    const auto sample = [&](const Vec3d& x, Vec3d& grad) {
        Int32 c[3];
        double f[3];
        for (int a = 0; a < 3; ++a) {
            c[a] = std::clamp(Int32(std::floor(x[a])), Int32(0), B - 1);
            f[a] = x[a] - double(c[a]);
        }
        const Index LL = Index(L) * Index(L);
        const Index base = latticeIndex(c[0], c[1], c[2]);
        double v[8];
        for (int n = 0; n < 8; ++n)
            v[n] = double(
                s.value[base + Index(n & 1) * LL + Index((n >> 1) & 1) * Index(L) + Index(n >> 2)]);
        const double x0 = 1.0 - f[0], y0 = 1.0 - f[1], z0 = 1.0 - f[2];
        const double v00 = v[0] * x0 + v[1] * f[0], v10 = v[2] * x0 + v[3] * f[0];
        const double v01 = v[4] * x0 + v[5] * f[0], v11 = v[6] * x0 + v[7] * f[0];
        const double w0 = v00 * y0 + v10 * f[1], w1 = v01 * y0 + v11 * f[1];
        grad[0] = ((v[1] - v[0]) * y0 + (v[3] - v[2]) * f[1]) * z0 +
                  ((v[5] - v[4]) * y0 + (v[7] - v[6]) * f[1]) * f[2];
        grad[1] = (v10 - v00) * z0 + (v11 - v01) * f[2];
        grad[2] = w1 - w0;
        return w0 * z0 + w1 * f[2] - mIso;
    };
    Vec3d x = start, grad;
    double r = sample(x, grad);
    const double r0 = std::abs(r);
    for (int it = 0; it < 4 && r != 0.0; ++it) {
        const double gg = grad.lengthSqr();
        if (!(gg > 0.0) || !std::isfinite(gg))
            break;
        x = Vec3d::maxComponent(lo, Vec3d::minComponent(hi, x - grad * (r / gg)));
        r = sample(x, grad);
    }
    return std::abs(r) < r0 && std::isfinite(r) ? x : start;
}

template <typename TreeT>
void VolumeMesher<TreeT>::merge(Block& blk, Scratch& s) const {
    const size_t n = s.cellOffset.size();
    s.slot.assign(CELLS, NONE);
    for (size_t c = 0; c < n; ++c)
        s.slot[s.cellOffset[c]] = uint32_t(c);

    // Status of each aligned group, bottom-up: 0 not mergeable, 1 mergeable, 2 no surface.
    // A level's status array is kept for the region assignment below.
    std::vector<std::vector<uint8_t>> levels;
    for (Int32 dim = 2; dim <= B; dim *= 2) {
        const Int32 groups = B / dim;
        std::vector<uint8_t> status(size_t(groups) * size_t(groups) * size_t(groups), 0);
        for (Int32 gi = 0; gi < groups; ++gi) {
            for (Int32 gj = 0; gj < groups; ++gj) {
                for (Int32 gk = 0; gk < groups; ++gk) {
                    bool surface = false, children = true;
                    for (int ch = 0; ch < 8 && children; ++ch) {
                        const Int32 ci = 2 * gi + (ch & 1), cj = 2 * gj + ((ch >> 1) & 1),
                                    ck = 2 * gk + (ch >> 2);
                        if (dim == 2) {
                            const uint32_t c = s.slot[cellOffsetOf(ci, cj, ck)];
                            if (c == NONE)
                                continue;
                            surface = true;
                            children = mTables.isSimple(blk.cell[c].signs);
                        } else {
                            const Int32 cg = 2 * groups;
                            const uint8_t st =
                                levels.back()[(size_t(ci) * size_t(cg) + size_t(cj)) * size_t(cg) +
                                              size_t(ck)];
                            surface = surface || st != 2;
                            children = st != 0;
                        }
                    }
                    uint8_t& st =
                        status[(size_t(gi) * size_t(groups) + size_t(gj)) * size_t(groups) +
                               size_t(gk)];
                    if (!surface && children) {
                        st = 2;
                    } else if (children &&
                               coarseCellIsSimple(s, gi * dim, gj * dim, gk * dim, dim) &&
                               normalsAgree(s, gi * dim, gj * dim, gk * dim, dim)) {
                        st = 1;
                    }
                }
            }
        }
        levels.push_back(std::move(status));
    }

    // Regions, top-down: each surface cell joins the largest mergeable group holding it.
    s.region.assign(n, NONE);
    std::vector<std::array<Int32, 4>> regions;  // (i, j, k, dim) of each region
    for (Int32 level = Int32(levels.size()) - 1; level >= 0; --level) {
        const Int32 dim = Int32(2) << level, groups = B / dim;
        const auto& status = levels[size_t(level)];
        for (Int32 gi = 0; gi < groups; ++gi)
            for (Int32 gj = 0; gj < groups; ++gj)
                for (Int32 gk = 0; gk < groups; ++gk) {
                    if (status[(size_t(gi) * size_t(groups) + size_t(gj)) * size_t(groups) +
                               size_t(gk)] != 1)
                        continue;
                    const uint32_t id = uint32_t(regions.size());
                    bool fresh = false;
                    for (Int32 i = gi * dim; i < (gi + 1) * dim; ++i)
                        for (Int32 j = gj * dim; j < (gj + 1) * dim; ++j)
                            for (Int32 k = gk * dim; k < (gk + 1) * dim; ++k) {
                                const uint32_t c = s.slot[cellOffsetOf(i, j, k)];
                                if (c != NONE && s.region[c] == NONE) {
                                    s.region[c] = id;
                                    fresh = true;
                                }
                            }
                    if (fresh)
                        regions.push_back({gi * dim, gj * dim, gk * dim, dim});
                }
    }

    // Vertices in cell order; a region's vertex comes with its first cell.
    std::vector<Vec3d> sum(regions.size(), Vec3d(0.0));
    std::vector<uint32_t> members(regions.size(), 0), vertexOf(regions.size(), NONE);
    for (size_t c = 0; c < n; ++c) {
        const uint32_t r = s.region[c];
        if (r == NONE)
            continue;
        sum[r] += s.sheetPoint[s.firstPoint[c]];
        ++members[r];
    }
    for (size_t c = 0; c < n; ++c) {
        const uint32_t r = s.region[c];
        if (r != NONE) {
            if (vertexOf[r] == NONE) {
                vertexOf[r] = uint32_t(blk.points.size());
                const auto& g = regions[r];
                const Vec3d mean = sum[r] / double(members[r]);
                blk.points.push_back(Vec3s(
                    members[r] > 1 ? projectToSurface(s, mean, g[0], g[1], g[2], g[3]) : mean));
            }
            blk.cell[c].vertex = vertexOf[r];
            continue;
        }
        blk.cell[c].vertex = uint32_t(blk.points.size());
        const uint32_t end = c + 1 < n ? s.firstPoint[c + 1] : uint32_t(s.sheetPoint.size());
        for (uint32_t p = s.firstPoint[c]; p < end; ++p)
            blk.points.push_back(Vec3s(s.sheetPoint[p]));
    }
}

// ---- Tiles next to the other side ----

/// The layer of voxels just outside face `face` of `box`.
inline CoordBBox borderLayer(const CoordBBox& box, int face) {
    const size_t axis = size_t(face >> 1);
    Coord unit(0);
    unit[axis] = 1;
    CoordBBox layer = box;
    layer.min()[axis] = layer.max()[axis] =
        (face & 1) ? (box.max() + unit)[axis] : (box.min() - unit)[axis];
    return layer;
}

template <typename TreeT>
void VolumeMesher<TreeT>::addTileBorder(const CoordBBox& tile, int face, const CoordBBox& region,
                                        std::vector<Coord>& out) const {
    // The cells whose edges cross from the tile through `face` into `region` (a part of the
    // layer of voxels beyond that face).
    const int axis = face >> 1;
    Coord lo = region.min().offsetBy(-1), hi = region.max();
    lo[size_t(axis)] = hi[size_t(axis)] =
        (face & 1) ? tile.max()[size_t(axis)] : tile.min()[size_t(axis)] - 1;
    tree::forEachAlignedCube(CoordBBox(lo, hi), LOG2,
                             [&](const Coord& origin, const CoordBBox&) { out.push_back(origin); });
}

template <typename TreeT>
template <typename NodeT>
void VolumeMesher<TreeT>::tileBordersOfNode(const NodeT& node, std::vector<Coord>& out) const {
    using ChildT = typename NodeT::ChildNodeType;
    constexpr Index D = NodeT::LOG2DIM;
    constexpr Index N = NodeT::NUM_VALUES;
    constexpr Index DIM = Index(1) << D;  // entries per axis
    constexpr size_t WORDS = (N + 63) / 64;
    const auto tileBox = [&](Index n) {
        return CoordBBox::createCube(node.offsetToGlobalCoord(n), Int32(ChildT::DIM));
    };
    const auto entryAxis = [](Index n, int axis) {
        return (n >> (D * Index(2 - axis))) & (DIM - 1);
    };

    // Tiles below and above the isovalue, one bit per entry.
    std::vector<uint64_t> below(WORDS + 1, 0), above(WORDS + 1, 0);
    for (Index n = 0; n < N; ++n) {
        if (node.isChild(n))
            continue;
        auto& bits = isBelow(double(node.getTileValue(n))) ? below : above;
        bits[n >> 6] |= uint64_t(1) << (n & 63);
    }

    // Neighbouring tiles on opposite sides, within the node: entry n and entry n + stride
    // (stride 1 along z, DIM along y, DIM^2 along x), a word at a time.
    for (int axis = 0; axis < 3; ++axis) {
        const Index stride = Index(1) << (D * Index(2 - axis));
        const size_t q = stride >> 6, r = stride & 63;
        const auto shifted = [&](const std::vector<uint64_t>& bits, size_t w) {
            const uint64_t lo = w + q < WORDS ? bits[w + q] : 0;
            const uint64_t hi = r && w + q + 1 < WORDS ? bits[w + q + 1] << (64 - r) : 0;
            return (lo >> r) | hi;
        };
        for (size_t w = 0; w < WORDS; ++w) {
            uint64_t pairs = (below[w] & shifted(above, w)) | (above[w] & shifted(below, w));
            for (; pairs != 0; pairs &= pairs - 1) {
                const Index n = Index(w * 64) + Index(std::countr_zero(pairs));
                if (n >= N || entryAxis(n, axis) == DIM - 1)
                    continue;  // no neighbour along the axis inside the node
                const CoordBBox tile = tileBox(n);
                addTileBorder(tile, 2 * axis + 1, borderLayer(tile, 2 * axis + 1), out);
            }
        }
    }

    // Tiles next to branches (children that are not leaves) of the node: the branch's tiles
    // that face them. Leaves find the tiles next to them themselves.
    if constexpr (ChildT::LEVEL > 0) {
        for (Index c = 0; c < N; ++c) {
            const ChildT* child = node.getChild(c);
            if (!child)
                continue;
            for (int face = 0; face < 6; ++face) {
                const int axis = face >> 1;
                const Index at = entryAxis(c, axis);
                if ((face & 1) ? at == DIM - 1 : at == 0)
                    continue;
                const Index stride = Index(1) << (D * Index(2 - axis));
                const Index m = (face & 1) ? c + stride : c - stride;
                if (node.isChild(m))
                    continue;
                const CoordBBox tile = tileBox(m);
                const bool tileBelow = isBelow(double(node.getTileValue(m)));
                const int tileFace = face ^ 1;  // from the tile towards the child
                tree::forEachTileIn(*child, borderLayer(tile, tileFace),
                                    [&](const CoordBBox& part, const ValueT& v) {
                                        if (isBelow(double(v)) != tileBelow)
                                            addTileBorder(tile, tileFace, part, out);
                                    });
            }
        }
    }

    // Tiles on the node's faces against whatever lies beyond: a node of the same level, a tile
    // above this level, or the background.
    const CoordBBox bounds = node.getNodeBoundingBox();
    for (int face = 0; face < 6; ++face) {
        const int axis = face >> 1;
        const CoordBBox layer = borderLayer(bounds, face);
        ValueT beyondValue{};
        const NodeT* beyond = nullptr;
        if constexpr (NodeT::LEVEL == TopT::LEVEL) {
            beyondValue = mTree.background();  // the domain's faces of a bounded tree
        } else {
            beyond = mTree.template get<tree::ops::ProbeNode<NodeT>>(layer.min(), beyondValue);
        }
        const bool beyondBelow = isBelow(double(beyondValue));
        const Index mine = (face & 1) ? DIM - 1 : 0, theirs = DIM - 1 - mine;
        const int a1 = kOtherAxes[axis][0], a2 = kOtherAxes[axis][1];
        for (Index u = 0; u < DIM; ++u) {
            for (Index v = 0; v < DIM; ++v) {
                Index idx[3];
                idx[axis] = mine;
                idx[a1] = u;
                idx[a2] = v;
                const Index n = (idx[0] << (2 * D)) | (idx[1] << D) | idx[2];
                if (node.isChild(n))
                    continue;
                const bool tileBelow = ((below[n >> 6] >> (n & 63)) & 1) != 0;
                const CoordBBox tile = tileBox(n);
                if (!beyond) {
                    if (beyondBelow != tileBelow)
                        addTileBorder(tile, face, borderLayer(tile, face), out);
                    continue;
                }
                idx[axis] = theirs;
                const Index m = (idx[0] << (2 * D)) | (idx[1] << D) | idx[2];
                if (const ChildT* child = beyond->getChild(m)) {
                    if constexpr (ChildT::LEVEL > 0)
                        tree::forEachTileIn(*child, borderLayer(tile, face),
                                            [&](const CoordBBox& part, const ValueT& v) {
                                                if (isBelow(double(v)) != tileBelow)
                                                    addTileBorder(tile, face, part, out);
                                            });
                } else if (isBelow(double(beyond->getTileValue(m))) != tileBelow) {
                    addTileBorder(tile, face, borderLayer(tile, face), out);
                }
            }
        }
    }
}

template <typename TreeT>
std::vector<Coord> VolumeMesher<TreeT>::tileBorderBlocks() const {
    std::vector<Coord> out;
    const TopT& top = mTree.topNode();
    if constexpr (tree::IS_ROOT_NODE<TopT>) {
        // The root's tiles, against whatever lies beyond each face.
        tree::forEachTile(top, [&](const auto& rootTile) {
            const CoordBBox tile = rootTile.bbox();
            const bool below = isBelow(double(rootTile.value));
            for (int face = 0; face < 6; ++face) {
                tree::forEachTileIn(top, borderLayer(tile, face),
                                    [&](const CoordBBox& part, const ValueT& v) {
                                        if (isBelow(double(v)) != below)
                                            addTileBorder(tile, face, part, out);
                                    });
            }
        });
    } else {
        tileBordersOfNode(top, out);
    }
    // The tiles of every internal node below the top, one task per node.
    const NodeLists<const TreeT> lists(mTree, 1);
    const auto level = [&](auto levelTag) {
        constexpr Index Level = decltype(levelTag)::value;
        const auto& nodes = lists.template nodes<Level>();
        std::vector<std::vector<Coord>> found(nodes.size());
        util::parallelFor(
            nodes.size(), [&](size_t i) { tileBordersOfNode(*nodes[i], found[i]); }, true, 1);
        for (const auto& f : found)
            out.insert(out.end(), f.begin(), f.end());
    };
    [&]<Index... Ls>(std::integer_sequence<Index, Ls...>) {
        (level(std::integral_constant<Index, Ls + 1>{}), ...);
    }
    (std::make_integer_sequence<Index, TopT::LEVEL - 1>{});
    return out;
}

// ---- Linking blocks and resolving faces ----

template <typename TreeT>
void VolumeMesher<TreeT>::linkBlocks() {
    mIndex.clear();
    for (uint32_t b = 0; b < uint32_t(mBlocks.size()); ++b)
        mIndex.insert(mBlocks[b].origin) = b;
    util::parallelFor(mBlocks.size(), [&](size_t b) {
        Block& blk = mBlocks[b];
        blk.lower[0] = uint32_t(b);
        for (int d = 1; d < 8; ++d) {
            const Coord o = blk.origin.offsetBy(-(d & 1) * B, -((d >> 1) & 1) * B, -(d >> 2) * B);
            const uint32_t* found = mIndex.find(o);
            blk.lower[size_t(d)] = found ? *found : NONE;
        }
    });
}

template <typename TreeT>
void VolumeMesher<TreeT>::fixDoubledFaces() {
    // A face whose two segments lie on one sheet in both of its cells would give the two cells'
    // vertices one polygon edge shared by four quads. Resolving such a face the other way splits
    // the sheet in both cells (an oriented reconnection of two strands of one cycle splits it),
    // so no other face becomes doubled: one pass in a fixed order settles every face.
    FlipMap flips;
    std::vector<uint32_t> dirty;
    const auto cellAt = [&](const Coord& ijk, uint32_t& block, uint32_t& slot) {
        const uint32_t* b = mIndex.find(ijk.alignedDown(LOG2));
        if (!b)
            return false;
        const Index offset = LeafT::coordToOffset(ijk);
        if (!mBlocks[*b].surface.isOn(offset))
            return false;
        block = *b;
        slot = mBlocks[*b].slotOf(offset);
        return true;
    };
    const auto facesOf = [&](const Coord& ijk, uint32_t block, uint32_t slot) {
        const auto it = flips.find(ijk);
        return unsigned(mBlocks[block].cell[slot].faces) ^ (it == flips.end() ? 0u : it->second);
    };
    for (uint32_t b = 0; b < uint32_t(mBlocks.size()); ++b) {
        for (const uint32_t code : mBlocks[b].doubled) {
            const int face = int(code & 7);
            const Coord ijk = mBlocks[b].origin + LeafT::offsetToLocalCoord(Index(code >> 3));
            const uint32_t slot = mBlocks[b].slotOf(Index(code >> 3));
            const unsigned signs = mBlocks[b].cell[slot].signs;
            const unsigned faces = facesOf(ijk, b, slot);
            if (!((mTables.of(signs, faces).joined >> face) & 1))
                continue;
            Coord next = ijk;
            next[size_t(face >> 1)] += (face & 1) ? 1 : -1;
            uint32_t nb = 0, nslot = 0;
            if (!cellAt(next, nb, nslot))
                continue;
            const int otherFace = face ^ 1;
            const unsigned nfaces = facesOf(next, nb, nslot);
            if (!((mTables.of(mBlocks[nb].cell[nslot].signs, nfaces).joined >> otherFace) & 1))
                continue;
            flips[ijk] ^= uint8_t(1 << face);
            flips[next] ^= uint8_t(1 << otherFace);
            dirty.push_back(b);
            dirty.push_back(nb);
        }
    }
    if (dirty.empty())
        return;
    std::sort(dirty.begin(), dirty.end());
    dirty.erase(std::unique(dirty.begin(), dirty.end()), dirty.end());
    tbb::enumerable_thread_specific<Scratch> scratch;
    util::parallelForRange(
        dirty.size(),
        [&](size_t begin, size_t end) {
            Scratch& s = scratch.local();
            Accessor acc(mTree);
            for (size_t i = begin; i < end; ++i) {
                Block& blk = mBlocks[dirty[i]];
                blk.extras.clear();
                extract(blk, s, acc, &flips);
                blk.extras.clear();
            }
        },
        true, 1);
}

// ---- Polygons ----

template <typename TreeT>
uint32_t VolumeMesher<TreeT>::vertexOf(const Block& blk, const uint32_t* slots, Int32 i, Int32 j,
                                       Int32 k, int edge) const {
    // The vertex of the sheet of `edge` in cell (i, j, k) of `blk` (whose surface cells'
    // indices `slots` holds) or, for a coordinate of -1, of a lower neighbour.
    if ((i | j | k) >= 0) {
        const uint32_t slot = slots[cellOffsetOf(i, j, k)];
        const Cell& cell = blk.cell[slot];
        return uint32_t(blk.pointOffset) + cell.vertex +
               mTables.of(cell.signs, cell.faces).sheetOf(edge);
    }
    int d = 0;
    if (i < 0) {
        d |= 1;
        i += B;
    }
    if (j < 0) {
        d |= 2;
        j += B;
    }
    if (k < 0) {
        d |= 4;
        k += B;
    }
    const uint32_t b = blk.lower[size_t(d)];
    VDB_ASSERT(b != NONE);
    if (b == NONE)
        return NONE;
    const Block& other = mBlocks[b];
    const Index offset = cellOffsetOf(i, j, k);
    VDB_ASSERT(other.surface.isOn(offset));
    if (!other.surface.isOn(offset))
        return NONE;
    const uint32_t slot = other.slotOf(offset);
    const Cell& cell = other.cell[slot];
    return uint32_t(other.pointOffset) + cell.vertex +
           mTables.of(cell.signs, cell.faces).sheetOf(edge);
}

template <typename TreeT>
bool VolumeMesher<TreeT>::buildPolygons(Block& blk, std::vector<uint32_t>& slots,
                                        Vec4I* quadsOut) const {
    // With `quadsOut` (adaptivity 0) every owned crossing edge writes one quad there, a quad
    // of NONE where a cell was missing; otherwise the polygons go to the block's lists.
    blk.quads.clear();
    blk.triangles.clear();
    size_t written = 0;
    bool complete = true;
    slots.resize(CELLS);
    uint32_t slot = 0;
    for (Index w = 0; w < CellMask::WORD_COUNT; ++w)
        for (uint64_t word = blk.surface.getWord(w); word != 0; word &= word - 1)
            slots[(w << 6) | Index(std::countr_zero(word))] = slot++;
    slot = 0;
    for (Index w = 0; w < CellMask::WORD_COUNT; ++w) {
        for (uint64_t word = blk.surface.getWord(w); word != 0; word &= word - 1, ++slot) {
            const Index offset = (w << 6) | Index(std::countr_zero(word));
            const Coord p = LeafT::offsetToLocalCoord(offset);
            const unsigned signs = blk.cell[slot].signs;
            for (int axis = 0; axis < 3; ++axis) {
                if (((signs ^ (signs >> (1 << axis))) & 1) == 0)
                    continue;
                // The four cells around the edge from p along `axis`, counter-clockwise about
                // the axis u x v: p, p - u, p - u - v, p - v.
                const int u = kOtherAxes[axis][0], v = kOtherAxes[axis][1];
                Coord du(0), dv(0);
                du[size_t(u)] = 1;
                dv[size_t(v)] = 1;
                const Coord c1 = p - du, c2 = p - du - dv, c3 = p - dv;
                const uint32_t* sl = slots.data();
                Vec4I q(vertexOf(blk, sl, p[0], p[1], p[2], 4 * axis),
                        vertexOf(blk, sl, c1[0], c1[1], c1[2], 4 * axis + 1),
                        vertexOf(blk, sl, c2[0], c2[1], c2[2], 4 * axis + 3),
                        vertexOf(blk, sl, c3[0], c3[1], c3[2], 4 * axis + 2));
                // That order's normal points along +axis for x and z and -axis for y. The
                // normal must point to the inside: below the isovalue for level sets (against
                // the axis when p is below), above it for the other grid classes.
                const bool pBelow = signs & 1;
                const bool wantPlus = pBelow == mInverted;
                if ((axis != 1) != wantPlus)
                    q = Vec4I(q[3], q[2], q[1], q[0]);
                if (q[0] == NONE || q[1] == NONE || q[2] == NONE || q[3] == NONE) {
                    complete = false;
                    q = Vec4I(NONE);
                }
                if (quadsOut) {
                    quadsOut[written++] = q;
                    continue;
                }
                if (q[0] == NONE)
                    continue;
                // Adaptive: corners of merged regions may coincide.
                const bool e01 = q[0] == q[1], e12 = q[1] == q[2], e23 = q[2] == q[3],
                           e30 = q[3] == q[0], e02 = q[0] == q[2], e13 = q[1] == q[3];
                const int equal = int(e01) + int(e12) + int(e23) + int(e30) + int(e02) + int(e13);
                if (equal == 0) {
                    blk.quads.push_back(q);
                } else if (equal == 1 && !e02 && !e13) {
                    if (e01)
                        blk.triangles.emplace_back(q[0], q[2], q[3]);
                    else if (e12)
                        blk.triangles.emplace_back(q[0], q[1], q[3]);
                    else
                        blk.triangles.emplace_back(q[0], q[1], q[2]);
                }
            }
        }
    }
    return complete;
}

template <typename TreeT>
void VolumeMesher<TreeT>::relaxDisoriented(std::vector<Vec3s>& points,
                                           const std::vector<Vec3I>& triangles,
                                           const std::vector<Vec4I>& quads) const {
    // Triangles whose normal points away from the inside by more than 60 degrees mark their
    // corners; each marked point moves to the mean of the corners of its polygons.
    std::unique_ptr<std::atomic<uint8_t>[]> marked(new std::atomic<uint8_t>[points.size()]);
    for (size_t i = 0; i < points.size(); ++i)
        marked[i].store(0, std::memory_order_relaxed);
    const bool any = util::parallelReduce(
        triangles.size(), false,
        [&](size_t begin, size_t end) {
            Accessor acc(mTree);
            bool found = false;
            for (size_t t = begin; t < end; ++t) {
                const Vec3I& tri = triangles[t];
                const Vec3d a = mXform.worldToIndex(Vec3d(points[tri[0]]));
                const Vec3d b = mXform.worldToIndex(Vec3d(points[tri[1]]));
                const Vec3d c = mXform.worldToIndex(Vec3d(points[tri[2]]));
                const Vec3d normal = (b - a).cross(c - a);
                const Vec3d centre = (a + b + c) / 3.0;
                const Coord ijk(Int32(std::floor(centre[0] + 0.5)),
                                Int32(std::floor(centre[1] + 0.5)),
                                Int32(std::floor(centre[2] + 0.5)));
                Vec3d grad;
                for (int axis = 0; axis < 3; ++axis) {
                    Coord hi = ijk, lo = ijk;
                    hi[size_t(axis)] += 1;
                    lo[size_t(axis)] -= 1;
                    grad[axis] = 0.5 * (double(acc.getValue(hi)) - double(acc.getValue(lo)));
                }
                // The inward normal runs against the gradient for level sets, along it
                // otherwise.
                const double nl = normal.length() * grad.length();
                if (!(nl > 0.0))
                    continue;
                const double cosine = normal.dot(grad) / nl * (mInverted ? -1.0 : 1.0);
                if (cosine > 0.5) {
                    for (int i = 0; i < 3; ++i)
                        marked[tri[i]].store(1, std::memory_order_relaxed);
                    found = true;
                }
            }
            return found;
        },
        [](bool a, bool b) { return a || b; });
    if (!any)
        return;
    std::vector<Vec3d> sum(points.size(), Vec3d(0.0));
    std::vector<uint32_t> count(points.size(), 0);
    const auto add = [&](const auto& poly, int corners) {
        Vec3d total(0.0);
        for (int i = 0; i < corners; ++i)
            total += Vec3d(points[poly[i]]);
        for (int i = 0; i < corners; ++i) {
            if (marked[poly[i]].load(std::memory_order_relaxed)) {
                sum[poly[i]] += total;
                count[poly[i]] += uint32_t(corners);
            }
        }
    };
    for (const Vec4I& q : quads)
        add(q, 4);
    for (const Vec3I& t : triangles)
        add(t, 3);
    for (size_t i = 0; i < points.size(); ++i)
        if (count[i] > 0)
            points[i] = Vec3s(sum[i] / double(count[i]));
}

// ---- The whole run ----

template <typename TreeT>
void VolumeMesher<TreeT>::run(std::vector<Vec3s>& points, std::vector<Vec3I>& triangles,
                              std::vector<Vec4I>& quads) {
    points.clear();
    triangles.clear();
    quads.clear();

    // 1. Every leaf is a block; extracting them finds the tile regions next to them that also
    //    hold surface cells.
    const NodeLists<const TreeT> lists(mTree, 0);
    const auto& leaves = lists.template nodes<0>();
    mBlocks.resize(leaves.size());
    tbb::enumerable_thread_specific<Scratch> scratch;
    const auto extractRange = [&](size_t first, size_t last) {
        util::parallelForRange(
            last - first,
            [&](size_t begin, size_t end) {
                Scratch& s = scratch.local();
                Accessor acc(mTree);
                for (size_t i = first + begin; i < first + end; ++i)
                    extract(mBlocks[i], s, acc, nullptr);
            },
            true, 4);
    };
    for (size_t i = 0; i < leaves.size(); ++i) {
        mBlocks[i].origin = leaves[i]->origin();
        mBlocks[i].isLeaf = true;
    }
    extractRange(0, mBlocks.size());

    // 2. Tile regions: next to leaves, and next to tiles of the other side.
    std::vector<Coord> extras = tileBorderBlocks();
    for (Block& blk : mBlocks) {
        extras.insert(extras.end(), blk.extras.begin(), blk.extras.end());
        blk.extras = {};
    }
    std::sort(extras.begin(), extras.end());
    extras.erase(std::unique(extras.begin(), extras.end()), extras.end());
    {
        Accessor acc(mTree);
        std::erase_if(extras, [&](const Coord& o) { return acc.probeConstLeaf(o) != nullptr; });
    }
    const size_t leafBlocks = mBlocks.size();
    mBlocks.resize(leafBlocks + extras.size());
    for (size_t i = 0; i < extras.size(); ++i)
        mBlocks[leafBlocks + i].origin = extras[i];
    extractRange(leafBlocks, mBlocks.size());

    // 3. Neighbours, and the faces that would make a polygon edge shared by four quads.
    linkBlocks();
    fixDoubledFaces();

    // 4. Offsets into the output.
    uint64_t pointCount = 0, edgeCount = 0;
    for (Block& blk : mBlocks) {
        blk.pointOffset = pointCount;
        blk.quadOffset = edgeCount;
        pointCount += blk.points.size();
        edgeCount += blk.edges;
    }
    if (pointCount >= uint64_t(NONE))
        throw ValueError("volumeToMesh: the mesh would have " + std::to_string(pointCount) +
                         " points, more than 32-bit indices can address");
    if (pointCount == 0)
        return;

    // 5. Points in world space, and the polygons.
    points.resize(size_t(pointCount));
    util::parallelFor(
        mBlocks.size(),
        [&](size_t b) {
            const Block& blk = mBlocks[b];
            const Vec3d origin(blk.origin);
            for (size_t i = 0; i < blk.points.size(); ++i)
                points[blk.pointOffset + i] =
                    Vec3s(mXform.indexToWorld(origin + Vec3d(blk.points[i])));
        },
        true, 16);
    if (!mAdaptive) {
        quads.resize(size_t(edgeCount));
        std::atomic<bool> complete{true};
        util::parallelFor(
            mBlocks.size(),
            [&](size_t b) {
                if (!buildPolygons(mBlocks[b], scratch.local().slot,
                                   quads.data() + mBlocks[b].quadOffset))
                    complete.store(false, std::memory_order_relaxed);
            },
            true, 16);
        // Every cell of a crossing edge is a surface cell of a block, so the lookups succeed;
        // should one fail, its quad is dropped rather than left pointing nowhere.
        if (!complete.load())
            std::erase_if(quads, [](const Vec4I& q) { return q[0] == NONE; });
        return;
    }
    util::parallelFor(
        mBlocks.size(), [&](size_t b) { buildPolygons(mBlocks[b], scratch.local().slot, nullptr); },
        true, 16);
    uint64_t quadCount = 0, triangleCount = 0;
    for (Block& blk : mBlocks) {
        blk.quadOffset = quadCount;
        blk.triangleOffset = triangleCount;
        quadCount += blk.quads.size();
        triangleCount += blk.triangles.size();
    }
    quads.resize(size_t(quadCount));
    triangles.resize(size_t(triangleCount));
    util::parallelFor(
        mBlocks.size(),
        [&](size_t b) {
            Block& blk = mBlocks[b];
            std::copy(blk.quads.begin(), blk.quads.end(), quads.begin() + blk.quadOffset);
            std::copy(blk.triangles.begin(), blk.triangles.end(),
                      triangles.begin() + blk.triangleOffset);
            blk.quads = {};
            blk.triangles = {};
        },
        true, 64);
    if (mRelax && !triangles.empty())
        relaxDisoriented(points, triangles, quads);
}

}  // namespace vdb::tools::detail

// ---- The entry points ----

namespace vdb::tools {

template <ScalarGrid GridT>
void volumeToMesh(const GridT& grid, std::vector<Vec3s>& points, std::vector<Vec3I>& triangles,
                  std::vector<Vec4I>& quads, double isovalue, double adaptivity,
                  bool relaxDisorientedTriangles) {
    if (!std::isfinite(isovalue))
        throw ValueError("volumeToMesh: the isovalue " + std::to_string(isovalue) +
                         " is not finite");
    if (!(adaptivity >= 0.0) || !std::isfinite(adaptivity))
        throw ValueError("volumeToMesh: the adaptivity " + std::to_string(adaptivity) +
                         " is not a number from 0 to 1");
    const bool inverted = grid.getGridClass() != GRID_LEVEL_SET;
    detail::VolumeMesher<typename GridT::TreeType> mesher(
        grid.tree(), grid.transform(), isovalue, adaptivity, inverted, relaxDisorientedTriangles);
    mesher.run(points, triangles, quads);
}

template <ScalarGrid GridT>
void volumeToMesh(const GridT& grid, std::vector<Vec3s>& points, std::vector<Vec4I>& quads,
                  double isovalue) {
    std::vector<Vec3I> triangles;
    volumeToMesh(grid, points, triangles, quads, isovalue, 0.0, false);
}

}  // namespace vdb::tools
