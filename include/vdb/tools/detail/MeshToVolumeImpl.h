// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery of tools/MeshToVolume.h: the point-triangle distance kernel, the signed
/// crossing counts along scanlines, the winding-number hierarchy of the hole patches, the
/// block-by-block builder, and meshToVolume() itself, which chooses the sign rule from the
/// mesh's topology (detail/MeshTopology.h). Included by MeshToVolume.h after its
/// declarations. Not API.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/detail/BlockRaster.h>
#include <vdb/tools/detail/MeshTopology.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

// ---- Point-triangle distance ----

/// How far x lies outside [lo, hi] (lo <= hi); 0 within.
inline double intervalGap(double x, double lo, double hi) {
    const double below = lo - x, above = x - hi;
    const double g = below < above ? above : below;
    return g < 0.0 ? 0.0 : g;
}

/// A triangle (a, b, c) prepared for squared-distance queries, in index space. Queries pass
/// the query point relative to `a`, so that far from the origin no precision is lost.
struct DistanceTriangle {
    Vec3d a, ab, ac, bc, n;            // n = ab x ac
    double abab, acac, abac, bcbc;     // Gram entries
    double abbc;                       // ab . bc
    double invAbab, invAcac, invBcbc;  // 1 / |edge|^2, or 0 for a zero-length edge
    double invDet;                     // 1 / (abab acac - abac^2)
    double invNN;                      // 1 / |n|^2
    bool hasFace;                      // false for degenerate triangles: only the edges count
    Vec3d lo, hi;                      // bounding box

    DistanceTriangle(const Vec3d& va, const Vec3d& vb, const Vec3d& vc)
        : a(va),
          ab(vb - va),
          ac(vc - va),
          bc(vc - vb),
          n(ab.cross(ac)),
          abab(ab.dot(ab)),
          acac(ac.dot(ac)),
          abac(ab.dot(ac)),
          bcbc(bc.dot(bc)),
          abbc(ab.dot(bc)) {
        invAbab = abab > 0.0 ? 1.0 / abab : 0.0;
        invAcac = acac > 0.0 ? 1.0 / acac : 0.0;
        invBcbc = bcbc > 0.0 ? 1.0 / bcbc : 0.0;
        const double det = abab * acac - abac * abac;
        const double nn = n.dot(n);
        // A face whose area is negligible next to its edges is treated as its edges alone.
        hasFace = det > 1e-12 * abab * acac && nn > 0.0;
        invDet = hasFace ? 1.0 / det : 0.0;
        invNN = hasFace ? 1.0 / nn : 0.0;
        lo = Vec3d::minComponent(va, Vec3d::minComponent(vb, vc));
        hi = Vec3d::maxComponent(va, Vec3d::maxComponent(vb, vc));
    }

    /// Squared distance from the point `a + ap` to the triangle.
    double sqrDistance(const Vec3d& ap) const {
        const double d1 = ab.dot(ap), d2 = ac.dot(ap);
        const double pp = ap.dot(ap);
        if (hasFace) {
            // Barycentric coordinates of the projection onto the plane.
            const double s = (acac * d1 - abac * d2) * invDet;
            const double t = (abab * d2 - abac * d1) * invDet;
            if (s >= 0.0 && t >= 0.0 && s + t <= 1.0) {
                const double pn = n.dot(ap);
                return pn * pn * invNN;
            }
        }
        // The projection lies outside: the closest point is on the nearest edge.
        const double uab = std::clamp(d1 * invAbab, 0.0, 1.0);
        const double eab = pp - uab * (2.0 * d1 - uab * abab);
        const double uac = std::clamp(d2 * invAcac, 0.0, 1.0);
        const double eac = pp - uac * (2.0 * d2 - uac * acac);
        const double d3 = bc.dot(ap) - abbc;  // (p - b) . bc
        const double ubc = std::clamp(d3 * invBcbc, 0.0, 1.0);
        const double ebc = (pp - 2.0 * d1 + abab) - ubc * (2.0 * d3 - ubc * bcbc);
        return std::max(0.0, std::min(eab, std::min(eac, ebc)));
    }
};

/// A bounding volume hierarchy over a set of DistanceTriangles for nearest-distance queries:
/// axis-aligned boxes, split at the median centre along the longest axis, up to LEAF_SIZE
/// triangles a leaf. Where many small triangles fall within the band of each voxel (a dense
/// mesh at a coarse voxel size), a query per voxel visits only the triangles whose boxes come
/// closer than the best distance found so far, instead of every triangle within the band.
/// Threads: build once, then query concurrently.
class TriangleBvh {
public:
    static constexpr uint32_t LEAF_SIZE = 4;

    explicit TriangleBvh(const std::vector<DistanceTriangle>& tris) : mTris(&tris) {
        mOrder.resize(tris.size());
        for (uint32_t t = 0; t < mOrder.size(); ++t)
            mOrder[t] = t;
        mNodes.reserve(2 * (tris.size() / LEAF_SIZE + 1));
        mNodes.emplace_back();
        if (!tris.empty())
            split(0, 0, uint32_t(tris.size()));
        // The triangles in the order of the leaves, so that a leaf's lie side by side.
        mSorted.reserve(tris.size());
        for (uint32_t t : mOrder)
            mSorted.push_back(tris[t]);
    }

    /// min(bound2, the smallest squared distance from `p` to a triangle). Every triangle whose
    /// box may come within the bound is evaluated with DistanceTriangle::sqrDistance(p - a),
    /// so the result equals the minimum over all triangles of that same expression.
    /// `hint` (in and out): a triangle to evaluate first (as returned by an earlier query; any
    /// value out of range for none), the closest one on return (unchanged when none comes
    /// within the bound); a neighbour's closest triangle makes the bound tight from the start.
    double minSqrDistance(const Vec3d& p, double bound2, uint32_t& hint) const {
        if (mOrder.empty())
            return bound2;
        double best = bound2;
        if (hint < mSorted.size()) {
            const DistanceTriangle& tri = mSorted[hint];
            best = std::min(best, tri.sqrDistance(p - tri.a));
        }
        // Nodes to visit with their lower bounds, computed once: a node is skipped when its
        // bound exceeds the best distance found so far.
        std::array<std::pair<uint32_t, double>, 96> stack;
        size_t top = 0;
        stack[top++] = {0u, lowerBound(mNodes[0], p)};
        while (top > 0) {
            const auto [index, bound] = stack[--top];
            if (prunes(bound, best))
                continue;
            const Node& node = mNodes[index];
            if (node.count > 0) {
                for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                    const DistanceTriangle& tri = mSorted[i];
                    const double d2 = tri.sqrDistance(p - tri.a);
                    if (d2 < best) {
                        best = d2;
                        hint = i;
                    }
                }
                continue;
            }
            // The nearer child is visited first: pushed last.
            const double l0 = lowerBound(mNodes[node.first], p);
            const double l1 = lowerBound(mNodes[node.first + 1], p);
            const bool firstNear = l0 <= l1;
            const std::pair<uint32_t, double> nearChild{node.first + (firstNear ? 0u : 1u),
                                                        firstNear ? l0 : l1};
            const std::pair<uint32_t, double> farChild{node.first + (firstNear ? 1u : 0u),
                                                       firstNear ? l1 : l0};
            if (!prunes(farChild.second, best))
                stack[top++] = farChild;
            if (!prunes(nearChild.second, best))
                stack[top++] = nearChild;
        }
        return best;
    }

private:
    struct Node {
        Vec3d lo, hi;  // axis-aligned box
        // Oriented box: orthonormal axes, the first along the triangles' mean normal, and the
        // range of (vertex - center) . axis[i] over the vertices, padded for rounding. Where
        // the triangles of a node form a nearly flat patch (small triangles of a smooth
        // surface), this box is thin and bounds the distance far better than the axis-aligned
        // one once the patch is tilted.
        Vec3d center;
        std::array<Vec3d, 3> axis;
        Vec3d olo, ohi;
        uint32_t first = 0;  // a leaf: the first index into mOrder; else the first child
        uint32_t count = 0;  // triangles of a leaf; 0 for an inner node
    };

    void orient(Node& node, uint32_t first, uint32_t last) const {
        const auto& tris = *mTris;
        node.center = 0.5 * (node.lo + node.hi);
        // The mean normal, each triangle's normal (length twice its area) turned towards the
        // largest one's.
        Vec3d ref(0.0);
        for (uint32_t i = first; i < last; ++i) {
            const Vec3d& n = tris[mOrder[i]].n;
            if (n.lengthSqr() > ref.lengthSqr())
                ref = n;
        }
        Vec3d mean(0.0);
        for (uint32_t i = first; i < last; ++i) {
            const Vec3d& n = tris[mOrder[i]].n;
            mean += n.dot(ref) < 0.0 ? -n : n;
        }
        const double len = mean.length();
        if (!(len > 0.0) || !std::isfinite(len)) {
            node.axis = {Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1)};
        } else {
            const Vec3d w = mean / len;
            const Vec3d t = std::abs(w[0]) < 0.6 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
            const Vec3d u = w.cross(t).unitSafe();
            node.axis = {w, u, w.cross(u)};
        }
        node.olo = Vec3d(std::numeric_limits<double>::max());
        node.ohi = Vec3d(-std::numeric_limits<double>::max());
        for (uint32_t i = first; i < last; ++i) {
            const DistanceTriangle& t = tris[mOrder[i]];
            for (const Vec3d& v : {t.a, t.a + t.ab, t.a + t.ac}) {
                const Vec3d q = v - node.center;
                for (int k = 0; k < 3; ++k) {
                    const double x = node.axis[k].dot(q);
                    node.olo[k] = std::min(node.olo[k], x);
                    node.ohi[k] = std::max(node.ohi[k], x);
                }
            }
        }
        // Rounding in the projections of the vertices and of query points: a margin far above
        // it, relative to the node's size and to its distance from the origin.
        double reach = 0.0;
        for (int k = 0; k < 3; ++k)
            reach = std::max({reach, std::abs(node.lo[k]), std::abs(node.hi[k])});
        const double pad = 1e-9 * (1.0 + (node.hi - node.lo).length() + reach);
        node.olo -= Vec3d(pad);
        node.ohi += Vec3d(pad);
    }

    // The larger of the squared distances from `p` to the node's axis-aligned box and to its
    // oriented box: both hold every triangle of the node.
    static double lowerBound(const Node& node, const Vec3d& p) {
        double d2 = 0.0, e2 = 0.0;
        const Vec3d q = p - node.center;
        for (int i = 0; i < 3; ++i) {
            const double g = intervalGap(p[i], node.lo[i], node.hi[i]);
            d2 += g * g;
            const double h = intervalGap(node.axis[i].dot(q), node.olo[i], node.ohi[i]);
            e2 += h * h;
        }
        return d2 < e2 ? e2 : d2;
    }
    // A node is skipped when its box is farther than the best distance; the relative margin
    // keeps a triangle whose computed distance rounds below its box's computed bound.
    static bool prunes(double bound, double best) { return bound * (1.0 - 1e-12) > best; }

    void split(uint32_t index, uint32_t first, uint32_t last) {
        const auto& tris = *mTris;
        Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        Vec3d clo = lo, chi = hi;
        for (uint32_t i = first; i < last; ++i) {
            const DistanceTriangle& t = tris[mOrder[i]];
            lo = Vec3d::minComponent(lo, t.lo);
            hi = Vec3d::maxComponent(hi, t.hi);
            const Vec3d c = 0.5 * (t.lo + t.hi);
            clo = Vec3d::minComponent(clo, c);
            chi = Vec3d::maxComponent(chi, c);
        }
        mNodes[index].lo = lo;
        mNodes[index].hi = hi;
        orient(mNodes[index], first, last);
        if (last - first <= LEAF_SIZE) {
            mNodes[index].first = first;
            mNodes[index].count = last - first;
            return;
        }
        const Vec3d extent = chi - clo;
        const int axis = extent[0] >= extent[1] ? (extent[0] >= extent[2] ? 0 : 2)
                                                : (extent[1] >= extent[2] ? 1 : 2);
        const uint32_t mid = first + (last - first) / 2;
        std::nth_element(mOrder.begin() + first, mOrder.begin() + mid, mOrder.begin() + last,
                         [&](uint32_t x, uint32_t y) {
                             return tris[x].lo[axis] + tris[x].hi[axis] <
                                    tris[y].lo[axis] + tris[y].hi[axis];
                         });
        const uint32_t child = uint32_t(mNodes.size());
        mNodes[index].first = child;
        mNodes.emplace_back();
        mNodes.emplace_back();
        split(child, first, mid);
        split(child + 1, mid, last);
    }

    const std::vector<DistanceTriangle>* mTris;
    std::vector<Node> mNodes;
    std::vector<uint32_t> mOrder;
    std::vector<DistanceTriangle> mSorted;
};

// ---- Scanline crossings ----

/// Lexicographic order of points, which names one end of every edge its first, so that the two
/// triangles sharing an edge evaluate it with the same arithmetic.
inline bool lexLess(const Vec3d& p, const Vec3d& q) {
    return p[0] < q[0] || (p[0] == q[0] && (p[1] < q[1] || (p[1] == q[1] && p[2] < q[2])));
}

/// The side of the directed xy edge (p, q) on which the z-line through (x, y) passes: the sign
/// of the 2D orientation, with a zero broken as for the line moved by (e, e^2) for a tiny e.
/// Both triangles of a shared edge get opposite answers, so a line through the edge (or a
/// vertex) crosses exactly one of them. `raw` receives the unbroken orientation.
inline int scanlineEdgeSide(const Vec3d& p, const Vec3d& q, double x, double y, double& raw) {
    const bool swap = lexLess(q, p);
    const Vec3d& a = swap ? q : p;
    const Vec3d& b = swap ? p : q;
    double e = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
    raw = swap ? -e : e;
    if (e == 0.0) {
        e = -(b[1] - a[1]);
        if (e == 0.0)
            e = b[0] - a[0];
    }
    const int side = e > 0.0 ? 1 : (e < 0.0 ? -1 : 0);
    return swap ? -side : side;
}

/// How the z-line through (x, y) crosses triangle (p0, p1, p2): +1 through a triangle that turns
/// counter-clockwise seen from +z, -1 through one that turns clockwise, 0 when it misses (a
/// line through a shared edge or vertex crosses exactly one of the triangles that share it);
/// `z` receives where it crosses.
inline int scanlineCrossing(const Vec3d& p0, const Vec3d& p1, const Vec3d& p2, double x, double y,
                            double& z) {
    double e2 = 0, e0 = 0, e1 = 0;
    const int s2 = scanlineEdgeSide(p0, p1, x, y, e2);
    const int s0 = scanlineEdgeSide(p1, p2, x, y, e0);
    const int s1 = scanlineEdgeSide(p2, p0, x, y, e1);
    if (s0 == 0 || s0 != s1 || s0 != s2)
        return 0;
    // Barycentric weights: e0 belongs to p0 (the edge opposite it), and so on.
    const double sum = e0 + e1 + e2;
    z = sum != 0.0 ? (e0 * p0[2] + e1 * p1[2] + e2 * p2[2]) / sum : p0[2];
    return s0;
}

/// Signed crossing counts along the z-lines through voxel centres, block by block: the count
/// below a point is the sum over the surface crossings below it on its line of -1 where the
/// surface faces up (+z side out) and +1 where it faces down, each times the weight of its
/// triangle. For a closed surface that is the winding number of the point.
///
/// Every block of the buckets keeps, per column (x, y), the crossings that lie in it (the
/// block holding floor(z)) sorted by z, and the count below the block, summed over the
/// blocks under it in its stack (blocks with the same x and y).
/// Threads: built in parallel per block; then read concurrently.
template <Index BlockLog2>
class ScanlineCounts {
public:
    static constexpr Int32 BLOCK_DIM = Int32(1) << BlockLog2;
    static constexpr Index COLUMNS = Index(1) << (2 * BlockLog2);

    /// `corners(id, p)` stores the corners of primitive `id` in p[0..2] and returns its weight.
    template <typename CornersT>
    ScanlineCounts(const BlockBuckets& buckets, const CornersT& corners, bool threaded)
        : mOrigins(buckets.origins), mBlocks(buckets.size()) {
        util::parallelFor(
            mBlocks.size(),
            [&](size_t b) {
                const Coord origin = mOrigins[b];
                struct Hit {
                    uint32_t col;
                    double z;
                    int8_t delta;
                    bool operator<(const Hit& o) const {
                        return col < o.col ||
                               (col == o.col && (z < o.z || (z == o.z && delta < o.delta)));
                    }
                };
                std::vector<Hit> hits;
                std::array<Vec3d, 3> p;
                for (uint32_t id : buckets.primitives(b)) {
                    const int weight = corners(id, p);
                    const Vec3d lo = Vec3d::minComponent(p[0], Vec3d::minComponent(p[1], p[2]));
                    const Vec3d hi = Vec3d::maxComponent(p[0], Vec3d::maxComponent(p[1], p[2]));
                    const Int32 i0 = std::max(origin[0], Int32(std::ceil(lo[0])));
                    const Int32 i1 = std::min(origin[0] + BLOCK_DIM - 1, Int32(std::floor(hi[0])));
                    const Int32 j0 = std::max(origin[1], Int32(std::ceil(lo[1])));
                    const Int32 j1 = std::min(origin[1] + BLOCK_DIM - 1, Int32(std::floor(hi[1])));
                    for (Int32 i = i0; i <= i1; ++i) {
                        for (Int32 j = j0; j <= j1; ++j) {
                            double z = 0.0;
                            const int side =
                                scanlineCrossing(p[0], p[1], p[2], double(i), double(j), z);
                            // A crossing belongs to the block holding floor(z).
                            if (side == 0 ||
                                (Int32(std::floor(z)) & ~(BLOCK_DIM - 1)) != origin[2]) {
                                continue;
                            }
                            const uint32_t col =
                                (uint32_t(i - origin[0]) << BlockLog2) | uint32_t(j - origin[1]);
                            hits.push_back({col, z, int8_t(-side * weight)});
                        }
                    }
                }
                std::sort(hits.begin(), hits.end());
                Block& out = mBlocks[b];
                out.start.assign(COLUMNS + 1, 0);
                out.z.resize(hits.size());
                out.delta.resize(hits.size());
                for (size_t n = 0; n < hits.size(); ++n) {
                    ++out.start[hits[n].col + 1];
                    out.z[n] = hits[n].z;
                    out.delta[n] = hits[n].delta;
                }
                for (Index c = 0; c < COLUMNS; ++c)
                    out.start[c + 1] += out.start[c];
            },
            threaded, 1);
        // Blocks are sorted by (x, y, z): each stack of blocks along z is one run.
        for (size_t b = 0; b < mBlocks.size(); ++b) {
            std::vector<int32_t>& below = mBlocks[b].below;
            below.assign(COLUMNS, 0);
            if (b == 0 || mOrigins[b][0] != mOrigins[b - 1][0] ||
                mOrigins[b][1] != mOrigins[b - 1][1]) {
                continue;
            }
            const Block& prev = mBlocks[b - 1];
            for (Index c = 0; c < COLUMNS; ++c) {
                int32_t k = prev.below[c];
                for (uint32_t h = prev.start[c]; h < prev.start[c + 1]; ++h)
                    k += prev.delta[h];
                below[c] = k;
            }
        }
    }

    /// The counts below the voxels of the leaf of `leafOrigin` in block `b`, in the leaf's
    /// offset order.
    template <typename LeafT>
    void leafCounts(size_t b, const Coord& leafOrigin, int32_t* counts) const {
        constexpr Int32 DIM = Int32(LeafT::DIM);
        const Coord origin = mOrigins[b];
        const Block& block = mBlocks[b];
        for (Int32 x = 0; x < DIM; ++x) {
            for (Int32 y = 0; y < DIM; ++y) {
                const uint32_t col = (uint32_t(leafOrigin[0] - origin[0] + x) << BlockLog2) |
                                     uint32_t(leafOrigin[1] - origin[1] + y);
                int32_t k = block.below[col];
                uint32_t h = block.start[col];
                const uint32_t end = block.start[col + 1];
                const Index row = LeafT::coordToOffset(Coord(x, y, 0));
                for (Int32 z = 0; z < DIM; ++z) {
                    const double at = double(leafOrigin[2] + z);
                    while (h < end && block.z[h] < at)
                        k += block.delta[h++];
                    counts[row + Index(z)] = k;
                }
            }
        }
    }

    /// The count below (i, j, z), anywhere: 0 outside the stacks of the blocks.
    int32_t countAt(Int32 i, Int32 j, double z) const {
        constexpr Int32 LOW = ~(BLOCK_DIM - 1);
        const Coord key(i & LOW, j & LOW, Int32(std::floor(z)) & LOW);
        // The highest block at or below `key` in its stack.
        auto it = std::upper_bound(mOrigins.begin(), mOrigins.end(), key);
        if (it == mOrigins.begin())
            return 0;
        --it;
        if ((*it)[0] != key[0] || (*it)[1] != key[1])
            return 0;
        const Block& block = mBlocks[size_t(it - mOrigins.begin())];
        const uint32_t col = (uint32_t(i - key[0]) << BlockLog2) | uint32_t(j - key[1]);
        const bool below = (*it)[2] < key[2];
        int32_t k = block.below[col];
        for (uint32_t h = block.start[col]; h < block.start[col + 1]; ++h) {
            if (below || block.z[h] < z)
                k += block.delta[h];
        }
        return k;
    }

private:
    struct Block {
        std::vector<uint32_t> start;  // crossings of column c: [start[c], start[c + 1])
        std::vector<double> z;        // ascending within a column
        std::vector<int8_t> delta;    // what each crossing adds to the count above it
        std::vector<int32_t> below;   // per column: the count below the block
    };
    const std::vector<Coord>& mOrigins;
    std::vector<Block> mBlocks;
};

// ---- Generalized winding number of the hole patches ----

/// A bounding volume hierarchy over triangles that evaluates their generalized winding number
/// (sum of signed solid angles over 4 pi) at a point, after Barill et al. 2018: clusters
/// farther than `ACCURACY` times their radius count as dipoles (area-weighted normal at the
/// area-weighted centroid), the rest triangle by triangle (van Oosterom and Strackee's
/// formula). Triangles are first bisected until no edge exceeds `maxEdge`, so that clusters
/// stay small where the triangles are long. isBelow() bounds the winding number over a ball.
/// Threads: build once, then call the const members concurrently.
class WindingNumberTree {
public:
    static constexpr double ACCURACY = 2.0;
    static constexpr uint32_t LEAF_SIZE = 2;
    using Triangle = std::array<Vec3d, 3>;

    WindingNumberTree(const std::vector<Triangle>& triangles, double maxEdge) {
        for (const Triangle& t : triangles)
            addPieces(t, maxEdge * maxEdge, 0);
        if (mTriangles.empty())
            return;
        mOrder.resize(mTriangles.size());
        std::vector<Vec3d> centroid(mTriangles.size());
        for (size_t t = 0; t < mTriangles.size(); ++t) {
            mOrder[t] = uint32_t(t);
            centroid[t] = (mTriangles[t][0] + mTriangles[t][1] + mTriangles[t][2]) / 3.0;
        }
        mNodes.reserve(4 * mTriangles.size() / LEAF_SIZE + 2);
        mNodes.push_back({});
        fill(0, 0, uint32_t(mTriangles.size()), centroid);
    }

    /// The clusters that are far (dipoles) for every point within `radius` of `center`, and
    /// the triangles of the others, for evaluating many points of one ball (evaluate(q, local)).
    struct Local {
        std::vector<uint32_t> far, near;
    };

    void gather(const Vec3d& center, double radius, Local& local) const {
        local.far.clear();
        local.near.clear();
        if (mNodes.empty())
            return;
        std::array<uint32_t, 64> stack;
        size_t top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const uint32_t index = stack[--top];
            const Node& node = mNodes[index];
            if ((node.center - center).length() - radius > ACCURACY * node.radius) {
                local.far.push_back(index);
            } else if (node.count > 0) {
                for (uint32_t n = node.first; n < node.first + node.count; ++n)
                    local.near.push_back(mOrder[n]);
            } else {
                stack[top++] = node.left;
                stack[top++] = node.left + 1;
            }
        }
    }

    /// The winding number at a point `q` of the ball `local` was gathered for (about 1 inside
    /// a closed surface whose triangles turn counter-clockwise seen from outside, -1 for the
    /// opposite orientation, 0 outside).
    double evaluate(const Vec3d& q, const Local& local) const {
        double variation = 0.0;
        return evaluate(q, local, 0.0, variation);
    }

    /// As above, and in `variation` a bound on how far the same sum moves within `radius` of
    /// q (the gradient of a dipole, and of a triangle's solid angle, is at most twice the area
    /// over the cubed distance); infinite when a near triangle reaches into that ball.
    double evaluate(const Vec3d& q, const Local& local, double radius, double& variation) const {
        double omega = 0.0, vary = 0.0;
        for (uint32_t index : local.far) {
            const Node& node = mNodes[index];
            const Vec3d d = node.center - q;
            const double dd = d.dot(d);
            const double dist = std::sqrt(dd);
            omega += d.dot(node.areaNormal) / (dd * dist);
            if (radius > 0.0) {
                const double g = dist - radius;
                vary += 2.0 * node.area * radius / (g * g * g);
            }
        }
        // The near triangles' solid angles, 2 atan2(det, div) each (van Oosterom and Strackee),
        // add up as twice the argument of the product of the numbers (div + i det) / scale,
        // with the turns the product makes round 0 counted: one atan2 for them all.
        double re = 1.0, im = 0.0;
        int turns = 0;
        for (uint32_t t : local.near) {
            const Triangle& tri = mTriangles[t];
            const Vec3d a = tri[0] - q, b = tri[1] - q, c = tri[2] - q;
            const double det = a.dot(b.cross(c));
            const double la = a.length(), lb = b.length(), lc = c.length();
            const double scale = la * lb * lc;
            if (det != 0.0 && scale > 0.0) {
                const double div = scale + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
                const double zr = div / scale, zi = det / scale;
                const double nr = re * zr - im * zi, ni = re * zi + im * zr;
                // A positive angle (below pi) crosses the negative real axis when the product
                // goes from the upper half plane to the lower one, a negative angle the other way.
                turns += int(det > 0.0 && im >= 0.0 && ni < 0.0) -
                         int(det < 0.0 && im < 0.0 && ni >= 0.0);
                re = nr;
                im = ni;
                const double size = std::abs(re) + std::abs(im);
                if (size > 1e100 || size < 1e-100) {
                    re /= size;
                    im /= size;
                }
            }
            if (radius > 0.0) {
                const Vec3d m = (tri[0] + tri[1] + tri[2]) / 3.0;
                const double r =
                    std::sqrt(std::max({(tri[0] - m).lengthSqr(), (tri[1] - m).lengthSqr(),
                                        (tri[2] - m).lengthSqr()}));
                const double g = (m - q).length() - r - radius;
                vary += g > 0.0 ? (tri[1] - tri[0]).cross(tri[2] - tri[0]).length() * radius /
                                      (g * g * g)
                                : std::numeric_limits<double>::infinity();
            }
        }
        omega += 2.0 * (std::atan2(im, re) + 2.0 * std::numbers::pi * double(turns));
        variation = vary / (4.0 * std::numbers::pi);
        return omega / (4.0 * std::numbers::pi);
    }

    /// True when the winding number is certainly below `limit` in magnitude at every point
    /// within `radius` of `center`. A cluster whose bounding sphere is at a distance g from
    /// the ball adds the smaller of two bounds on its solid angle: its area over g^2, and its
    /// dipole term at the centre plus the dipole's error and variation over the ball,
    /// 2 area (cluster radius + radius) / g^3 (the gradient of a triangle's solid-angle kernel
    /// is at most 2 / distance^3). Near clusters are opened; a triangle within the ball fails.
    bool isBelow(const Vec3d& center, double radius, double limit) const {
        if (mNodes.empty())
            return true;
        const double budget = limit * 4.0 * std::numbers::pi;
        double bound = 0.0;
        std::array<uint32_t, 64> stack;
        size_t top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = mNodes[stack[--top]];
            const Vec3d d = node.center - center;
            const double dist = d.length();
            const double gap = dist - node.radius - radius;
            if (gap > 2.0 * (node.radius + radius)) {
                const double dipole = std::abs(d.dot(node.areaNormal)) / (dist * dist * dist);
                bound +=
                    std::min(node.area / (gap * gap),
                             dipole + 2.0 * node.area * (node.radius + radius) / (gap * gap * gap));
            } else if (node.count > 0) {
                for (uint32_t n = node.first; n < node.first + node.count; ++n) {
                    const Triangle& t = mTriangles[mOrder[n]];
                    const Vec3d m = (t[0] + t[1] + t[2]) / 3.0;
                    const double r = std::sqrt(std::max(
                        {(t[0] - m).lengthSqr(), (t[1] - m).lengthSqr(), (t[2] - m).lengthSqr()}));
                    const double g = (m - center).length() - r - radius;
                    if (!(g > 0.0))
                        return false;
                    bound += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length() / (g * g);
                }
            } else {
                stack[top++] = node.left;
                stack[top++] = node.left + 1;
            }
            if (bound >= budget)
                return false;
        }
        return true;
    }

private:
    /// Adds t, bisected across its longest edge until every edge is at most sqrt(maxEdge2);
    /// triangles without area are left out (their solid angle is 0).
    void addPieces(const Triangle& t, double maxEdge2, int depth) {
        const Vec3d e[3] = {t[1] - t[0], t[2] - t[1], t[0] - t[2]};
        if (e[0].cross(e[2]) == Vec3d(0.0))
            return;
        const double l[3] = {e[0].lengthSqr(), e[1].lengthSqr(), e[2].lengthSqr()};
        const int k = l[0] >= l[1] && l[0] >= l[2] ? 0 : (l[1] >= l[2] ? 1 : 2);
        if (l[k] <= maxEdge2 || depth >= 40) {
            mTriangles.push_back(t);
            return;
        }
        // Corners k and k + 1 bound the longest edge; the opposite corner is k + 2.
        const Vec3d& a = t[k];
        const Vec3d& b = t[(k + 1) % 3];
        const Vec3d& c = t[(k + 2) % 3];
        const Vec3d m = 0.5 * (a + b);
        addPieces({a, m, c}, maxEdge2, depth + 1);
        addPieces({m, b, c}, maxEdge2, depth + 1);
    }

    struct Node {
        Vec3d center;           // area-weighted centroid
        Vec3d areaNormal;       // sum of the triangles' area vectors
        double radius;          // of the ball around `center` that holds the triangles
        double area;            // sum of the triangles' areas
        uint32_t first, count;  // a leaf's triangles: mOrder[first, first + count)
        uint32_t left;          // an inner node's children: left and left + 1
    };

    // Fills node `index` for the triangles mOrder[first, last), splitting it when it holds
    // more than LEAF_SIZE; children are made in pairs so that one index names both.
    void fill(uint32_t index, uint32_t first, uint32_t last, std::vector<Vec3d>& centroid) {
        Vec3d areaNormal(0.0), weighted(0.0), mean(0.0);
        double area = 0.0;
        Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (uint32_t n = first; n < last; ++n) {
            const Triangle& t = mTriangles[mOrder[n]];
            const Vec3d an = (t[1] - t[0]).cross(t[2] - t[0]) * 0.5;
            const double ar = an.length();
            areaNormal += an;
            area += ar;
            weighted += centroid[mOrder[n]] * ar;
            mean += centroid[mOrder[n]];
            lo = Vec3d::minComponent(lo, centroid[mOrder[n]]);
            hi = Vec3d::maxComponent(hi, centroid[mOrder[n]]);
        }
        const Vec3d center = area > 0.0 ? weighted / area : mean / double(last - first);
        double radius = 0.0;
        for (uint32_t n = first; n < last; ++n) {
            for (const Vec3d& p : mTriangles[mOrder[n]])
                radius = std::max(radius, (p - center).lengthSqr());
        }
        Node node{center, areaNormal, std::sqrt(radius), area, first, last - first, 0};
        if (last - first > LEAF_SIZE) {
            // Split at the median centroid along the longest axis of the centroids' box.
            const Vec3d ext = hi - lo;
            const int axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : (ext[1] >= ext[2] ? 1 : 2);
            const uint32_t mid = first + (last - first) / 2;
            std::nth_element(mOrder.begin() + first, mOrder.begin() + mid, mOrder.begin() + last,
                             [&](uint32_t s, uint32_t t) {
                                 return centroid[s][axis] < centroid[t][axis] ||
                                        (centroid[s][axis] == centroid[t][axis] && s < t);
                             });
            node.count = 0;
            node.left = uint32_t(mNodes.size());
            mNodes.push_back({});
            mNodes.push_back({});
            mNodes[index] = node;
            fill(node.left, first, mid, centroid);
            fill(node.left + 1, mid, last, centroid);
            return;
        }
        mNodes[index] = node;
    }

    std::vector<Triangle> mTriangles;
    std::vector<uint32_t> mOrder;
    std::vector<Node> mNodes;
};

// ---- The builder ----

/// How the builder decides which voxels are inside, from the crossing count k below a voxel
/// (ScanlineCounts) and the winding number w of the hole patches at its centre.
enum class SignRule {
    None,           // unsigned distances
    Parity,         // k odd
    NonZero,        // k != 0: the winding number of a closed mesh
    WindingNumber,  // |k + w| > 1/2: the generalized winding number of a mesh with holes
};

/// The sign rule and the hole patches (crossed with weight -1, so that mesh minus patches is
/// closed) that meshToVolume() chose from the mesh's topology.
struct MeshSigning {
    SignRule rule = SignRule::None;
    std::vector<std::array<Vec3d, 3>> patches;
};

/// Writes the band of a mesh (index-space points, triangles) into an empty tree and signs it.
/// One class per tree type so that the standard trees are instantiated once
/// (src/instantiate/MeshToVolume.cpp).
template <typename TreeT>
struct MeshToVolumeBuilder {
    static void build(TreeT& tree, const std::vector<Vec3d>& points,
                      const std::vector<Vec3I>& triangles, const MeshSigning& signing,
                      double voxelSize, const MeshToVolumeOptions& options);
};

template <typename TreeT>
void MeshToVolumeBuilder<TreeT>::build(TreeT& tree, const std::vector<Vec3d>& points,
                                       const std::vector<Vec3I>& triangles,
                                       const MeshSigning& signing, double voxelSize,
                                       const MeshToVolumeOptions& options) {
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    constexpr Int32 LEAF_DIM = Int32(LeafT::DIM);
    constexpr Index BLOCK_LOG2 = blockLog2<TreeT>();
    using Leaves = BlockLeaves<LeafT, BLOCK_LOG2>;

    const bool threaded = options.threaded;
    const SignRule rule = signing.rule;
    const bool isSigned = rule != SignRule::None;
    const double exBand = double(options.exteriorBandWidth);
    const double inBand = isSigned ? double(options.interiorBandWidth) : exBand;
    const double band = std::max(exBand, inBand);
    const double band2 = band * band;
    const ValueT outsideValue = ValueT(exBand * voxelSize);
    const ValueT insideValue = ValueT(-inBand * voxelSize);
    const size_t triangleCount = triangles.size();
    const auto& patches = signing.patches;

    // Primitive ids: the triangles, then the patch triangles (whose crossings alone matter).
    const auto corners = [&](size_t id, std::array<Vec3d, 3>& p) {
        if (id < triangleCount) {
            const Vec3I& v = triangles[id];
            p = {points[v[0]], points[v[1]], points[v[2]]};
            return 1;
        }
        p = patches[id - triangleCount];
        return -1;
    };

    // Bucket the triangles by the blocks their bands reach, the patches by the blocks they
    // cross.
    const BlockBuckets buckets = bucketByBlock(
        triangleCount + patches.size(), BLOCK_LOG2,
        [&](size_t id, CoordBBox& box) {
            std::array<Vec3d, 3> p;
            corners(id, p);
            box = voxelReach(Vec3d::minComponent(p[0], Vec3d::minComponent(p[1], p[2])),
                             Vec3d::maxComponent(p[0], Vec3d::maxComponent(p[1], p[2])),
                             id < triangleCount ? band : 1.0, "meshToVolume");
            return true;
        },
        threaded);
    const size_t blockCount = buckets.size();

    std::unique_ptr<ScanlineCounts<BLOCK_LOG2>> counts;
    if (isSigned)
        counts = std::make_unique<ScanlineCounts<BLOCK_LOG2>>(buckets, corners, threaded);
    std::unique_ptr<WindingNumberTree> holes;
    if (rule == SignRule::WindingNumber)
        holes = std::make_unique<WindingNumberTree>(patches, double(LEAF_DIM));

    // Inside or not from the count k below a point (the patches' winding number aside).
    const auto fromCount = [&](int32_t k) {
        return rule == SignRule::Parity ? (k & 1) != 0 : k != 0;
    };
    // With holes, the signs of the voxels of the leaf at `origin` from their counts `below`:
    // inside where |k + w| > 1/2, w the patches' winding number. Where a bound keeps |w| below
    // 1/2 over the leaf, the count alone decides. Otherwise w is evaluated at the centre of each
    // cube of 4^3 voxels, with a bound on how far it moves within the cube; the voxels it
    // leaves open are settled in cubes of 2^3 the same way, and the rest one by one.
    const auto signWithHoles = [&](const Coord& origin, const auto& below, auto& inside,
                                   WindingNumberTree::Local& local) {
        const auto cube = [&](const auto& self, const Coord& min, Int32 size) -> void {
            const Vec3d center = Vec3d(origin + min) + 0.5 * double(size - 1);
            const double radius = 0.5 * double(size - 1) * std::sqrt(3.0);
            const Int32 half = size / 2;
            const auto eighths = [&] {
                for (Int32 c = 0; c < 8; ++c)
                    self(self, min.offsetBy(c & 4 ? half : 0, c & 2 ? half : 0, c & 1 ? half : 0),
                         half);
            };
            if (size == LEAF_DIM) {
                if (!holes->isBelow(center, radius, 0.5)) {
                    eighths();
                    return;
                }
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                    inside[n] = fromCount(below[n]);
                return;
            }
            holes->gather(center, radius, local);
            double variation = 0.0;
            const double w = holes->evaluate(center, local, radius, variation);
            bool refine = false;
            for (Int32 x = min[0]; x < min[0] + size; ++x) {
                for (Int32 y = min[1]; y < min[1] + size; ++y) {
                    for (Int32 z = min[2]; z < min[2] + size; ++z) {
                        const Index n = LeafT::coordToOffset(Coord(x, y, z));
                        const double a = std::abs(double(below[n]) + w);
                        inside[n] = a > 0.5;
                        if (std::abs(a - 0.5) > variation)
                            continue;
                        if (size > 2) {
                            refine = true;
                        } else {
                            const Vec3d xyz(origin + Coord(x, y, z));
                            inside[n] =
                                std::abs(double(below[n]) + holes->evaluate(xyz, local)) > 0.5;
                        }
                    }
                }
            }
            if (refine)
                eighths();
        };
        cube(cube, Coord(0), LEAF_DIM);
    };

    // Distances and signs, block by block, leaf by leaf.
    // Rows of voxels a leaf's triangles would visit one by one, above which the leaf's
    // distances come from per-voxel queries of the block's triangle hierarchy instead.
    constexpr uint64_t RASTER_ROW_LIMIT = 16 * LeafT::NUM_VALUES;
    const double halfDiagonal = 0.5 * double(LEAF_DIM - 1) * std::sqrt(3.0);
    const double leafReach2 = (band + halfDiagonal) * (band + halfDiagonal) * (1.0 + 1e-12) + 1e-9;
    buildLeavesByBlock(
        tree, blockCount,
        [&](size_t b, std::vector<std::unique_ptr<LeafT>>& out) {
            const Coord origin = buckets.origins[b];
            const auto all = buckets.primitives(b);
            const auto ids = all.first(size_t(
                std::lower_bound(all.begin(), all.end(), uint32_t(triangleCount)) - all.begin()));
            std::vector<DistanceTriangle> tris;
            std::vector<CoordBBox> reach;
            tris.reserve(ids.size());
            reach.reserve(ids.size());
            for (uint32_t t : ids) {
                const Vec3I& v = triangles[t];
                tris.emplace_back(points[v[0]], points[v[1]], points[v[2]]);
                reach.push_back(voxelReach(tris.back().lo, tris.back().hi, band, "meshToVolume"));
            }

            // The triangles each leaf of the block must consider, as (leaf, triangle) pairs
            // sorted by leaf.
            std::vector<std::pair<uint32_t, uint32_t>> pairs;
            for (uint32_t t = 0; t < tris.size(); ++t) {
                Leaves::forEachTouched(origin, reach[t], [&](uint32_t leaf, const Vec3d& c) {
                    if (tris[t].sqrDistance(c - tris[t].a) <= leafReach2)
                        pairs.emplace_back(leaf, t);
                });
            }
            std::sort(pairs.begin(), pairs.end());

            std::unique_ptr<TriangleBvh> bvh;  // made when a leaf of the block needs it
            std::array<double, LeafT::NUM_VALUES> dist2;
            std::array<int32_t, LeafT::NUM_VALUES> below;
            std::array<bool, LeafT::NUM_VALUES> inside{};
            WindingNumberTree::Local local;
            for (size_t p = 0; p < pairs.size();) {
                const uint32_t leafIndex = pairs[p].first;
                size_t q = p;
                while (q < pairs.size() && pairs[q].first == leafIndex)
                    ++q;
                const Coord leafOrigin = Leaves::leafOrigin(origin, leafIndex);
                const CoordBBox leafBox = CoordBBox::createCube(leafOrigin, LEAF_DIM);

                // Minimum squared distance over the leaf's triangles. Where they are few or
                // large, triangle by triangle, visiting for each only the voxels that can lie
                // within the band of it; where many small triangles reach the leaf (the rows
                // visited exceed RASTER_ROW_LIMIT), voxel by voxel through the block's triangle
                // hierarchy, each query bounded by the previous voxel's distance plus one.
                // Both give the minimum of the same distances.
                uint64_t rows = 0;
                for (size_t r = p; r < q; ++r) {
                    const CoordBBox& box = reach[pairs[r].second];
                    const Int64 nx = Int64(std::min(box.max()[0], leafBox.max()[0])) -
                                     std::max(box.min()[0], leafBox.min()[0]) + 1;
                    const Int64 ny = Int64(std::min(box.max()[1], leafBox.max()[1])) -
                                     std::max(box.min()[1], leafBox.min()[1]) + 1;
                    if (nx > 0 && ny > 0)
                        rows += uint64_t(nx * ny);
                }
                const bool byVoxel = rows > RASTER_ROW_LIMIT;
                if (byVoxel) {
                    if (!bvh)
                        bvh = std::make_unique<TriangleBvh>(tris);
                    uint32_t hint = ~uint32_t(0);
                    // Cubes of SUB^3 voxels whose centre lies farther than the band plus the
                    // cube's half diagonal from every triangle hold no voxel of the band: one
                    // query settles them.
                    constexpr Int32 SUB = LEAF_DIM >= 4 ? LEAF_DIM / 2 : LEAF_DIM;
                    const double cubeReach = band + 0.5 * double(SUB - 1) * std::sqrt(3.0) + 1e-6;
                    const double cubeReach2 = cubeReach * cubeReach;
                    for (Int32 si = 0; si < LEAF_DIM; si += SUB) {
                        for (Int32 sj = 0; sj < LEAF_DIM; sj += SUB) {
                            for (Int32 sk = 0; sk < LEAF_DIM; sk += SUB) {
                                const Vec3d center = Vec3d(leafOrigin.offsetBy(si, sj, sk)) +
                                                     Vec3d(0.5 * double(SUB - 1));
                                const bool empty =
                                    bvh->minSqrDistance(center, cubeReach2, hint) >= cubeReach2;
                                for (Int32 i = si; i < si + SUB; ++i) {
                                    for (Int32 j = sj; j < sj + SUB; ++j) {
                                        const Index row = LeafT::coordToOffset(Coord(i, j, 0));
                                        double previous = band2;
                                        for (Int32 k = sk; k < sk + SUB; ++k) {
                                            if (empty) {
                                                dist2[row + Index(k)] = band2;
                                                continue;
                                            }
                                            const Vec3d xyz(leafOrigin.offsetBy(i, j, k));
                                            // |d(v) - d(u)| <= 1 for neighbours: a bound that
                                            // holds with room for rounding.
                                            const double root = std::sqrt(previous) + 1.0 + 1e-6;
                                            const double lipschitz =
                                                previous < band2 ? std::min(band2, root * root)
                                                                 : band2;
                                            double d2 = bvh->minSqrDistance(xyz, lipschitz, hint);
                                            if (d2 >= lipschitz && lipschitz < band2)
                                                d2 = bvh->minSqrDistance(xyz, band2, hint);
                                            dist2[row + Index(k)] = d2;
                                            previous = d2;
                                        }
                                    }
                                }
                            }
                        }
                    }
                } else {
                    dist2.fill(band2);
                }
                for (size_t r = byVoxel ? q : p; r < q; ++r) {
                    const DistanceTriangle& tri = tris[pairs[r].second];
                    CoordBBox box = reach[pairs[r].second];
                    box.min() = Coord::maxComponent(box.min(), leafBox.min());
                    box.max() = Coord::minComponent(box.max(), leafBox.max());
                    const double nLen = tri.hasFace ? std::sqrt(1.0 / tri.invNN) : 0.0;
                    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i) {
                        const double ax = double(i) - tri.a[0];
                        const double gx = intervalGap(double(i), tri.lo[0], tri.hi[0]);
                        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j) {
                            const double ay = double(j) - tri.a[1];
                            const double gy = intervalGap(double(j), tri.lo[1], tri.hi[1]);
                            // The z range within reach of the triangle's box...
                            const double rest = band2 - gx * gx - gy * gy;
                            if (rest <= 0.0)
                                continue;
                            const double rz = std::sqrt(rest);
                            double zLo = tri.lo[2] - rz, zHi = tri.hi[2] + rz;
                            // ... and within the slab of the band around the triangle's plane.
                            if (tri.hasFace) {
                                const double off = tri.n[0] * ax + tri.n[1] * ay;
                                const double half = band * nLen;
                                if (tri.n[2] != 0.0) {
                                    double s0 = tri.a[2] + (-half - off) / tri.n[2];
                                    double s1 = tri.a[2] + (half - off) / tri.n[2];
                                    if (s1 < s0)
                                        std::swap(s0, s1);
                                    zLo = std::max(zLo, s0 - 1e-6);
                                    zHi = std::min(zHi, s1 + 1e-6);
                                } else if (std::abs(off) >= half) {
                                    continue;
                                }
                            }
                            const Int32 k0 = std::max(box.min()[2], Int32(std::ceil(zLo)));
                            const Int32 k1 = std::min(box.max()[2], Int32(std::floor(zHi)));
                            const Index row = LeafT::coordToOffset(Coord(i, j, 0));
                            for (Int32 k = k0; k <= k1; ++k) {
                                const double d2 =
                                    tri.sqrDistance(Vec3d(ax, ay, double(k) - tri.a[2]));
                                double& slot = dist2[row + Index(k - leafOrigin[2])];
                                slot = std::min(slot, d2);
                            }
                        }
                    }
                }
                p = q;

                bool any = false;
                for (double d2 : dist2)
                    any = any || d2 < band2;
                if (!any)
                    continue;

                // Signs of every voxel of the leaf, from the crossing counts below them and,
                // where the hole patches may matter, their winding number.
                if (isSigned) {
                    counts->template leafCounts<LeafT>(b, leafOrigin, below.data());
                    if (holes) {
                        signWithHoles(leafOrigin, below, inside, local);
                    } else {
                        for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                            inside[n] = fromCount(below[n]);
                    }
                }

                auto leaf = std::make_unique<LeafT>(leafOrigin, outsideValue, false);
                bool active = false;
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                    const double d = dist2[n] < band2 ? std::sqrt(dist2[n]) : band;
                    if (inside[n]) {
                        if (d < inBand) {
                            leaf->setValueOn(n, ValueT(-d * voxelSize));
                            active = true;
                        } else {
                            leaf->setValueOff(n, insideValue);
                        }
                    } else if (d < exBand) {
                        leaf->setValueOn(n, ValueT(d * voxelSize));
                        active = true;
                    }
                }
                if (active)
                    out.push_back(std::move(leaf));
            }
        },
        threaded);

    if (!isSigned)
        return;
    // The leaves are signed voxel by voxel; the tiles take their signs from them (hierarchical
    // flood fill), which is exact where the surface closes...
    signedFloodFillImpl<1>(tree, outsideValue, insideValue, threaded);
    if (rule != SignRule::WindingNumber)
        return;
    // ... but leaks through holes, so with holes every inactive tile takes the sign at its
    // centre instead. Outside the box of the points (which holds the patches too) every count
    // is 0.
    Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec3d& p : points) {
        lo = Vec3d::minComponent(lo, p);
        hi = Vec3d::maxComponent(hi, p);
    }
    const auto tileValue = [&](const Coord& min, Int32 dim, WindingNumberTree::Local& local) {
        const Vec3d c = Vec3d(min) + 0.5 * double(dim - 1);
        const bool inBox = c[0] >= lo[0] && c[0] <= hi[0] && c[1] >= lo[1] && c[1] <= hi[1] &&
                           c[2] >= lo[2] && c[2] <= hi[2];
        const int32_t k =
            inBox ? counts->countAt(Int32(std::floor(c[0])), Int32(std::floor(c[1])), c[2]) : 0;
        bool in = k != 0;
        if (!holes->isBelow(c, 0.0, 0.5)) {
            holes->gather(c, 0.0, local);
            in = std::abs(double(k) + holes->evaluate(c, local)) > 0.5;
        }
        return in ? insideValue : outsideValue;
    };
    const auto signTiles = [&](auto& node) {
        using NodeT = std::remove_cvref_t<decltype(node)>;
        WindingNumberTree::Local local;
        tree::forEachTile<ValueFilter::Off>(node, [&](auto& tile) {
            tile.value = tileValue(tile.origin, Int32(NodeT::ChildNodeType::DIM), local);
        });
    };
    using TopT = typename TreeT::TopNodeType;
    {
        const NodeLists<TreeT> lists(tree, 1);
        floodFillLevels<1, TopT::LEVEL>(lists, signTiles, threaded);
    }
    signTiles(tree.topNode());
}

}  // namespace vdb::tools::detail

namespace vdb::tools {

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToVolume(const math::Transform& xform, const std::vector<Vec3s>& points,
                                 const std::vector<Vec3I>& triangles,
                                 const std::vector<Vec4I>& quads,
                                 const MeshToVolumeOptions& options, MeshToVolumeReport* report) {
    using ValueT = typename GridT::ValueType;
    const char* who = "meshToVolume";
    if (!xform.isLinear() || !xform.hasUniformScale())
        throw ValueError(std::string(who) + ": the transform must be linear with a uniform scale");
    const double voxelSize = xform.voxelSize()[0];
    for (float w : {options.exteriorBandWidth, options.interiorBandWidth}) {
        if (!(w >= 1.0f) || !std::isfinite(w))
            throw ValueError(std::string(who) + ": band widths must be finite and at least 1");
    }
    if (points.size() >= size_t(0xFFFFFFFFu))
        throw ValueError(std::string(who) + ": too many points");
    if (triangles.size() + 2 * quads.size() >= size_t(0x7FFFFFFFu))
        throw ValueError(std::string(who) + ": too many triangles");

    // Triangles, with each quad split along its (0, 2) diagonal.
    std::vector<Vec3I> tris;
    tris.reserve(triangles.size() + 2 * quads.size());
    const auto checked = [&](Index32 i) {
        if (i >= points.size()) {
            throw ValueError(std::string(who) + ": vertex index " + std::to_string(i) +
                             " is out of range (" + std::to_string(points.size()) + " points)");
        }
        return i;
    };
    for (const Vec3I& t : triangles)
        tris.emplace_back(checked(t[0]), checked(t[1]), checked(t[2]));
    for (const Vec4I& q : quads) {
        tris.emplace_back(checked(q[0]), checked(q[1]), checked(q[2]));
        if (q[3] != 0xFFFFFFFFu)
            tris.emplace_back(q[0], q[2], checked(q[3]));
    }

    // Points in index space, in double precision.
    std::vector<Vec3d> indexPoints(points.size());
    util::parallelFor(
        points.size(), [&](size_t i) { indexPoints[i] = xform.worldToIndex(Vec3d(points[i])); },
        options.threaded, 4096);
    for (const Vec3d& p : indexPoints) {
        if (!(std::abs(p[0]) < detail::MAX_INDEX_COORD &&
              std::abs(p[1]) < detail::MAX_INDEX_COORD &&
              std::abs(p[2]) < detail::MAX_INDEX_COORD)) {
            throw ValueError(std::string(who) +
                             ": a point is not finite or lies more than 2^30 voxels from the "
                             "origin in index space");
        }
    }

    // The sign rule, from the mesh's edges: closed meshes count crossings, meshes with holes
    // add the winding number of the patches that close them.
    MeshToVolumeReport found;
    found.sign = options.sign;
    detail::MeshSigning signing;
    if (options.sign != MeshSign::Unsigned) {
        // WindingNumber keeps the faces as given; the other modes orient them.
        detail::MeshTopology topology(indexPoints, tris, options.sign != MeshSign::WindingNumber,
                                      options.threaded);
        const detail::MeshEdgeCounts& c = topology.counts();
        found.mergedPoints = c.mergedPoints;
        found.boundaryEdges = c.boundaryEdges;
        found.nonManifoldEdges = c.nonManifoldEdges;
        found.misorientedEdges = c.misorientedEdges;
        found.flippedFaces = c.flippedFaces;
        found.holes = c.holes;
        if (options.sign == MeshSign::Auto)
            found.sign = topology.closed() ? MeshSign::FloodFill : MeshSign::WindingNumber;
        if (topology.closed()) {
            signing.rule = detail::SignRule::NonZero;
        } else if (found.sign == MeshSign::FloodFill) {
            signing.rule = detail::SignRule::Parity;
        } else {
            signing.rule = detail::SignRule::WindingNumber;
            signing.patches = topology.patches();
        }
    }
    if (report)
        *report = found;

    auto grid = GridT::create(ValueT(double(options.exteriorBandWidth) * voxelSize));
    grid->setTransform(xform.copy());
    grid->setGridClass(signing.rule != detail::SignRule::None ? GRID_LEVEL_SET : GRID_UNKNOWN);
    detail::MeshToVolumeBuilder<typename GridT::TreeType>::build(grid->tree(), indexPoints, tris,
                                                                 signing, voxelSize, options);
    return grid;
}

}  // namespace vdb::tools
