// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery of tools/MeshToVolume.h: the point-triangle distance kernel, the scanline
/// crossings of the flood-fill sign, the winding-number hierarchy, and the block-by-block
/// builder. Included by MeshToVolume.h after its declarations. Not API.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/detail/BlockRaster.h>
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
#include <utility>
#include <vector>

namespace vdb::tools::detail {

// ---- Point-triangle distance ----

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

// ---- Scanline crossings (MeshSign::FloodFill) ----

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

/// True when the z-line through (x, y) crosses triangle (p0, p1, p2); `z` receives where.
inline bool scanlineCrossing(const Vec3d& p0, const Vec3d& p1, const Vec3d& p2, double x, double y,
                             double& z) {
    double e2 = 0, e0 = 0, e1 = 0;
    const int s2 = scanlineEdgeSide(p0, p1, x, y, e2);
    const int s0 = scanlineEdgeSide(p1, p2, x, y, e0);
    const int s1 = scanlineEdgeSide(p2, p0, x, y, e1);
    if (s0 == 0 || s0 != s1 || s0 != s2)
        return false;
    // Barycentric weights: e0 belongs to p0 (the edge opposite it), and so on.
    const double sum = e0 + e1 + e2;
    z = sum != 0.0 ? (e0 * p0[2] + e1 * p1[2] + e2 * p2[2]) / sum : p0[2];
    return true;
}

/// The surface crossings of the z-lines of one block: per column (x, y) of the block, the
/// sorted z of the crossings that lie in the block, and the parity of their count.
struct BlockCrossings {
    std::vector<uint32_t> start;  // crossings of column c: z[start[c], start[c + 1])
    std::vector<double> z;
    std::vector<uint64_t> parity;  // bit c: column c crosses an odd number of times here
};

// ---- Generalized winding number (MeshSign::WindingNumber) ----

/// A bounding volume hierarchy over triangles that evaluates the generalized winding number
/// (sum of signed solid angles over 4 pi) at a point: clusters farther than `ACCURACY` times
/// their radius count as dipoles, the rest triangle by triangle.
/// Threads: build once, then evaluate() concurrently.
class WindingNumberTree {
public:
    static constexpr double ACCURACY = 2.5;
    static constexpr uint32_t LEAF_SIZE = 8;

    WindingNumberTree(const std::vector<Vec3d>& points, const std::vector<Vec3I>& triangles)
        : mPoints(points), mTriangles(triangles) {
        if (triangles.empty())
            return;
        mOrder.resize(triangles.size());
        std::vector<Vec3d> centroid(triangles.size());
        for (size_t t = 0; t < triangles.size(); ++t) {
            mOrder[t] = uint32_t(t);
            const Vec3I& v = triangles[t];
            centroid[t] = (points[v[0]] + points[v[1]] + points[v[2]]) / 3.0;
        }
        mNodes.reserve(4 * triangles.size() / LEAF_SIZE + 2);
        mNodes.push_back({});
        fill(0, 0, uint32_t(triangles.size()), centroid);
    }

    /// The winding number at `q` (about 1 inside a closed mesh whose triangles turn
    /// counter-clockwise seen from outside, -1 for the opposite orientation, 0 outside).
    double evaluate(const Vec3d& q) const {
        if (mNodes.empty())
            return 0.0;
        double omega = 0.0;
        std::array<uint32_t, 64> stack;
        size_t top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = mNodes[stack[--top]];
            const Vec3d d = node.center - q;
            const double dd = d.dot(d);
            if (dd > ACCURACY * ACCURACY * node.radius * node.radius) {
                omega += d.dot(node.areaNormal) / (dd * std::sqrt(dd));
            } else if (node.count > 0) {
                for (uint32_t n = node.first; n < node.first + node.count; ++n)
                    omega += solidAngle(mTriangles[mOrder[n]], q);
            } else {
                stack[top++] = node.left;
                stack[top++] = node.left + 1;
            }
        }
        return omega / (4.0 * std::numbers::pi);
    }

private:
    struct Node {
        Vec3d center;           // area-weighted centroid
        Vec3d areaNormal;       // sum of the triangles' area vectors
        double radius;          // of the ball around `center` that holds the triangles
        uint32_t first, count;  // a leaf's triangles: mOrder[first, first + count)
        uint32_t left;          // an inner node's children: left and left + 1
    };

    double solidAngle(const Vec3I& v, const Vec3d& q) const {
        const Vec3d a = mPoints[v[0]] - q, b = mPoints[v[1]] - q, c = mPoints[v[2]] - q;
        const double la = a.length(), lb = b.length(), lc = c.length();
        const double det = a.dot(b.cross(c));
        const double div = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        return 2.0 * std::atan2(det, div);
    }

    // Fills node `index` for the triangles mOrder[first, last), splitting it when it holds
    // more than LEAF_SIZE; children are made in pairs so that one index names both.
    void fill(uint32_t index, uint32_t first, uint32_t last, std::vector<Vec3d>& centroid) {
        Vec3d areaNormal(0.0), weighted(0.0), mean(0.0);
        double area = 0.0;
        Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (uint32_t n = first; n < last; ++n) {
            const Vec3I& v = mTriangles[mOrder[n]];
            const Vec3d& a = mPoints[v[0]];
            const Vec3d& b = mPoints[v[1]];
            const Vec3d& c = mPoints[v[2]];
            const Vec3d an = (b - a).cross(c - a) * 0.5;
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
            const Vec3I& v = mTriangles[mOrder[n]];
            for (int k = 0; k < 3; ++k)
                radius = std::max(radius, (mPoints[v[k]] - center).lengthSqr());
        }
        Node node{center, areaNormal, std::sqrt(radius), first, last - first, 0};
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

    const std::vector<Vec3d>& mPoints;
    const std::vector<Vec3I>& mTriangles;
    std::vector<uint32_t> mOrder;
    std::vector<Node> mNodes;
};

// ---- The builder ----

/// Writes the band of a mesh (index-space points, triangles) into an empty tree and signs it.
/// One class per tree type so that the standard trees are instantiated once
/// (src/instantiate/MeshToVolume.cpp).
template <typename TreeT>
struct MeshToVolumeBuilder {
    static void build(TreeT& tree, const std::vector<Vec3d>& points,
                      const std::vector<Vec3I>& triangles, double voxelSize,
                      const MeshToVolumeOptions& options);
};

template <typename TreeT>
void MeshToVolumeBuilder<TreeT>::build(TreeT& tree, const std::vector<Vec3d>& points,
                                       const std::vector<Vec3I>& triangles, double voxelSize,
                                       const MeshToVolumeOptions& options) {
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    constexpr Int32 LEAF_DIM = Int32(LeafT::DIM);
    constexpr Index BLOCK_LOG2 = blockLog2<TreeT>();
    constexpr Int32 BLOCK_DIM = Int32(1) << BLOCK_LOG2;
    using Leaves = BlockLeaves<LeafT, BLOCK_LOG2>;
    constexpr Index COLUMNS = Index(1) << (2 * BLOCK_LOG2);

    const bool threaded = options.threaded;
    const bool isSigned = options.sign != MeshSign::Unsigned;
    const double exBand = double(options.exteriorBandWidth);
    const double inBand = isSigned ? double(options.interiorBandWidth) : exBand;
    const double band = std::max(exBand, inBand);
    const double band2 = band * band;
    const ValueT outsideValue = ValueT(exBand * voxelSize);
    const ValueT insideValue = ValueT(-inBand * voxelSize);

    // Bucket the triangles by the blocks their bands reach.
    const BlockBuckets buckets = bucketByBlock(
        triangles.size(), BLOCK_LOG2,
        [&](size_t t, CoordBBox& box) {
            const Vec3I& v = triangles[t];
            const Vec3d& a = points[v[0]];
            const Vec3d& b = points[v[1]];
            const Vec3d& c = points[v[2]];
            box =
                voxelReach(Vec3d::minComponent(a, Vec3d::minComponent(b, c)),
                           Vec3d::maxComponent(a, Vec3d::maxComponent(b, c)), band, "meshToVolume");
            return true;
        },
        threaded);
    const size_t blockCount = buckets.size();

    // Flood-fill sign: the crossings of every block's z-lines, then the parity below each block.
    std::vector<BlockCrossings> crossings;
    std::vector<std::vector<uint64_t>> parityBelow;
    if (options.sign == MeshSign::FloodFill) {
        crossings.resize(blockCount);
        util::parallelFor(
            blockCount,
            [&](size_t b) {
                const Coord origin = buckets.origins[b];
                std::vector<std::pair<uint32_t, double>> hits;
                for (uint32_t t : buckets.primitives(b)) {
                    const Vec3I& v = triangles[t];
                    const Vec3d& p0 = points[v[0]];
                    const Vec3d& p1 = points[v[1]];
                    const Vec3d& p2 = points[v[2]];
                    const Vec3d lo = Vec3d::minComponent(p0, Vec3d::minComponent(p1, p2));
                    const Vec3d hi = Vec3d::maxComponent(p0, Vec3d::maxComponent(p1, p2));
                    const Int32 i0 = std::max(origin[0], Int32(std::ceil(lo[0])));
                    const Int32 i1 = std::min(origin[0] + BLOCK_DIM - 1, Int32(std::floor(hi[0])));
                    const Int32 j0 = std::max(origin[1], Int32(std::ceil(lo[1])));
                    const Int32 j1 = std::min(origin[1] + BLOCK_DIM - 1, Int32(std::floor(hi[1])));
                    for (Int32 i = i0; i <= i1; ++i) {
                        for (Int32 j = j0; j <= j1; ++j) {
                            double z = 0.0;
                            if (!scanlineCrossing(p0, p1, p2, double(i), double(j), z))
                                continue;
                            // A crossing belongs to the block holding floor(z).
                            if ((Int32(std::floor(z)) & ~(BLOCK_DIM - 1)) != origin[2])
                                continue;
                            const uint32_t col =
                                (uint32_t(i - origin[0]) << BLOCK_LOG2) | uint32_t(j - origin[1]);
                            hits.emplace_back(col, z);
                        }
                    }
                }
                std::sort(hits.begin(), hits.end());
                BlockCrossings& out = crossings[b];
                out.start.assign(COLUMNS + 1, 0);
                out.parity.assign(COLUMNS / 64, 0);
                out.z.resize(hits.size());
                for (size_t n = 0; n < hits.size(); ++n) {
                    ++out.start[hits[n].first + 1];
                    out.z[n] = hits[n].second;
                    out.parity[hits[n].first >> 6] ^= uint64_t(1) << (hits[n].first & 63);
                }
                for (Index c = 0; c < COLUMNS; ++c)
                    out.start[c + 1] += out.start[c];
            },
            threaded, 1);
        // Blocks are sorted by (x, y, z): each stack of blocks along z is one run.
        parityBelow.resize(blockCount);
        for (size_t b = 0; b < blockCount; ++b) {
            const bool sameStack = b > 0 && buckets.origins[b][0] == buckets.origins[b - 1][0] &&
                                   buckets.origins[b][1] == buckets.origins[b - 1][1];
            parityBelow[b].assign(COLUMNS / 64, 0);
            if (sameStack) {
                for (Index w = 0; w < COLUMNS / 64; ++w)
                    parityBelow[b][w] = parityBelow[b - 1][w] ^ crossings[b - 1].parity[w];
            }
        }
    }

    std::unique_ptr<WindingNumberTree> winding;
    if (options.sign == MeshSign::WindingNumber)
        winding = std::make_unique<WindingNumberTree>(points, triangles);

    // Distances and signs, block by block, leaf by leaf.
    const double halfDiagonal = 0.5 * double(LEAF_DIM - 1) * std::sqrt(3.0);
    const double leafReach2 = (band + halfDiagonal) * (band + halfDiagonal) * (1.0 + 1e-12) + 1e-9;
    buildLeavesByBlock(
        tree, blockCount,
        [&](size_t b, std::vector<std::unique_ptr<LeafT>>& out) {
            const Coord origin = buckets.origins[b];
            const auto ids = buckets.primitives(b);
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

            std::array<double, LeafT::NUM_VALUES> dist2;
            for (size_t p = 0; p < pairs.size();) {
                const uint32_t leafIndex = pairs[p].first;
                size_t q = p;
                while (q < pairs.size() && pairs[q].first == leafIndex)
                    ++q;
                const Coord leafOrigin = Leaves::leafOrigin(origin, leafIndex);
                const CoordBBox leafBox = CoordBBox::createCube(leafOrigin, LEAF_DIM);

                // Minimum squared distance over the leaf's triangles, voxel by voxel, visiting
                // for each triangle only the voxels that can lie within the band of it.
                dist2.fill(band2);
                for (size_t r = p; r < q; ++r) {
                    const DistanceTriangle& tri = tris[pairs[r].second];
                    CoordBBox box = reach[pairs[r].second];
                    box.min() = Coord::maxComponent(box.min(), leafBox.min());
                    box.max() = Coord::minComponent(box.max(), leafBox.max());
                    const double nLen = tri.hasFace ? std::sqrt(1.0 / tri.invNN) : 0.0;
                    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i) {
                        const double ax = double(i) - tri.a[0];
                        const double gx =
                            std::max({tri.lo[0] - double(i), 0.0, double(i) - tri.hi[0]});
                        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j) {
                            const double ay = double(j) - tri.a[1];
                            const double gy =
                                std::max({tri.lo[1] - double(j), 0.0, double(j) - tri.hi[1]});
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

                // Signs: the parity of crossings below each voxel on its z-line, the winding
                // number at its centre, or none.
                std::array<bool, LeafT::NUM_VALUES> inside{};
                if (options.sign == MeshSign::FloodFill) {
                    const BlockCrossings& cr = crossings[b];
                    const auto& below = parityBelow[b];
                    for (Int32 x = 0; x < LEAF_DIM; ++x) {
                        for (Int32 y = 0; y < LEAF_DIM; ++y) {
                            const uint32_t col =
                                (uint32_t(leafOrigin[0] - origin[0] + x) << BLOCK_LOG2) |
                                uint32_t(leafOrigin[1] - origin[1] + y);
                            bool in = (below[col >> 6] >> (col & 63)) & 1;
                            uint32_t h = cr.start[col];
                            const uint32_t end = cr.start[col + 1];
                            const Index row = LeafT::coordToOffset(Coord(x, y, 0));
                            for (Int32 z = 0; z < LEAF_DIM; ++z) {
                                const double k = double(leafOrigin[2] + z);
                                while (h < end && cr.z[h] < k) {
                                    in = !in;
                                    ++h;
                                }
                                inside[row + Index(z)] = in;
                            }
                        }
                    }
                } else if (options.sign == MeshSign::WindingNumber) {
                    for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                        if (dist2[n] < band2) {
                            const Vec3d xyz(leafOrigin + LeafT::offsetToLocalCoord(n));
                            inside[n] = std::abs(winding->evaluate(xyz)) > 0.5;
                        }
                    }
                }

                auto leaf = std::make_unique<LeafT>(leafOrigin, outsideValue, false);
                bool active = false;
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                    if (!(dist2[n] < band2))
                        continue;
                    const double d = std::sqrt(dist2[n]);
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
    signedFloodFillWithValues(tree, outsideValue, insideValue, threaded);
    if (winding) {
        // A flood fill leaks through holes, so every inactive value, voxel or tile, takes the
        // sign of the winding number at its centre instead.
        std::vector<Vec3d> centers;
        for (auto it = tree.cbeginValueOff(); it; ++it) {
            CoordBBox box;
            it.getBoundingBox(box);
            centers.push_back(Vec3d(box.min()) + 0.5 * double(box.extents()[0] - 1));
        }
        std::vector<uint8_t> in(centers.size());
        util::parallelFor(
            centers.size(),
            [&](size_t n) { in[n] = std::abs(winding->evaluate(centers[n])) > 0.5; }, threaded,
            256);
        size_t n = 0;
        for (auto it = tree.beginValueOff(); it; ++it)
            it.setValue(in[n++] ? insideValue : outsideValue);
    }
}

}  // namespace vdb::tools::detail

namespace vdb::tools {

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToVolume(const math::Transform& xform, const std::vector<Vec3s>& points,
                                 const std::vector<Vec3I>& triangles,
                                 const std::vector<Vec4I>& quads,
                                 const MeshToVolumeOptions& options) {
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

    const bool isSigned = options.sign != MeshSign::Unsigned;
    auto grid = GridT::create(ValueT(double(options.exteriorBandWidth) * voxelSize));
    grid->setTransform(xform.copy());
    grid->setGridClass(isSigned ? GRID_LEVEL_SET : GRID_UNKNOWN);
    detail::MeshToVolumeBuilder<typename GridT::TreeType>::build(grid->tree(), indexPoints, tris,
                                                                 voxelSize, options);
    return grid;
}

}  // namespace vdb::tools
