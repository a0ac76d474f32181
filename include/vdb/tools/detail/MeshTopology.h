// SPDX-License-Identifier: Apache-2.0
/// @file
/// The edge structure of a triangle mesh, from which tools/MeshToVolume.h chooses and computes
/// the signs of a scan conversion: coincident points are welded, each edge is matched with
/// the faces that use it, faces are turned over where their neighbours disagree, and the edges
/// left open are split into loops and each loop is capped by a patch of small area. Not API.
///
/// The algebra behind the patches: a mesh M is a sum of oriented triangles; its boundary
/// dM (each directed edge counted +1 per face that runs along it, -1 per face that runs
/// against it) is empty exactly when every edge is matched. A patch S with dS = dM closes it:
/// C = M - S is a closed surface, so its winding number w_C is an integer (the signed count of
/// crossings along any ray), and the generalized winding number of the mesh itself is
/// w_M = w_C + w_S everywhere. Patches that hug the holes keep w_S small away from them.
///
/// Cost: a sort of the points for welding, and two passes over the 3 T edge uses of T
/// triangles bucketed by their smaller end point; faces are turned over (a breadth-first walk
/// over the faces) only when some edge has two faces that run the same way round it.
/// Threads: the sorts and the per-vertex work run in parallel when asked; the results do not
/// depend on the thread count.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Vec3.h>
#include <vdb/util/Parallel.h>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

/// For every point, the index of the first point at exactly the same position (its own index
/// when no earlier point shares it); `merged` receives the number of points that are not
/// their own representative. 0 and -0 count as the same coordinate.
inline std::vector<uint32_t> weldPoints(const std::vector<Vec3d>& points, bool threaded,
                                        size_t& merged) {
    const auto key = [&](size_t i) {
        uint64_t h = 0x9E3779B97F4A7C15ull;
        for (int k = 0; k < 3; ++k) {
            const double c = points[i][k] == 0.0 ? 0.0 : points[i][k];
            h = (h ^ std::bit_cast<uint64_t>(c)) * 0xFF51AFD7ED558CCDull;
            h ^= h >> 32;
        }
        return h;
    };
    struct Entry {
        uint64_t hash;
        uint32_t index;
        bool operator<(const Entry& o) const {
            return hash < o.hash || (hash == o.hash && index < o.index);
        }
    };
    std::vector<Entry> entries(points.size());
    util::parallelFor(
        points.size(),
        [&](size_t i) {
            entries[i] = {key(i), uint32_t(i)};
        },
        threaded, 4096);
    // Entries are unique, so the order is the same however the sort runs.
    if (threaded) {
        tbb::parallel_sort(entries.begin(), entries.end());
    } else {
        std::sort(entries.begin(), entries.end());
    }
    std::vector<uint32_t> rep(points.size());
    merged = 0;
    std::vector<uint32_t> distinct;  // representatives met so far in one run of equal hashes
    for (size_t s = 0; s < entries.size();) {
        size_t e = s + 1;
        while (e < entries.size() && entries[e].hash == entries[s].hash)
            ++e;
        distinct.clear();
        for (size_t n = s; n < e; ++n) {
            const uint32_t i = entries[n].index;
            rep[i] = i;
            for (uint32_t d : distinct) {
                if (points[d] == points[i]) {
                    rep[i] = d;
                    ++merged;
                    break;
                }
            }
            if (rep[i] == i)
                distinct.push_back(i);
        }
        s = e;
    }
    return rep;
}

/// What the edge analysis found (MeshToVolumeReport shows it to users).
struct MeshEdgeCounts {
    size_t mergedPoints = 0;      // points welded to an earlier point at the same position
    size_t boundaryEdges = 0;     // edges of exactly one face
    size_t nonManifoldEdges = 0;  // edges of three or more faces
    size_t misorientedEdges = 0;  // edges of two faces that run the same way round them
    size_t flippedFaces = 0;      // faces turned over to agree with their neighbours
    size_t holes = 0;             // open loops whose patch has an area
};

/// The topology of a triangle mesh: welding, edge matching, orientation and hole patches
/// (see the file comment).
class MeshTopology {
public:
    /// Analyses `triangles` over `points` (index space). With `orient`, faces are turned over
    /// in place so that each connected piece (faces joined by edges of exactly two faces)
    /// agrees with the orientation of most of its area.
    /// @pre every index is below points.size(), and there are fewer than 2^31 triangles.
    MeshTopology(const std::vector<Vec3d>& points, std::vector<Vec3I>& triangles, bool orient,
                 bool threaded)
        : mPoints(points) {
        mRep = weldPoints(points, threaded, mCounts.mergedPoints);
        buildEdgeTable(triangles, threaded);
        countEdges();
        if (orient && mCounts.misorientedEdges > 0)
            orientFaces(triangles);
        buildPatches();
        // The edge table is only needed up to here.
        std::vector<uint64_t>().swap(mUses);
        std::vector<size_t>().swap(mFirst);
    }

    const MeshEdgeCounts& counts() const { return mCounts; }

    /// True when the edges left open (if any) bound no area: the mesh encloses its volume.
    bool closed() const { return mCounts.holes == 0; }

    /// The patch triangles over the open loops, whose boundary is the mesh's. Empty when
    /// closed().
    const std::vector<std::array<Vec3d, 3>>& patches() const { return mPatches; }

private:
    // An edge use, in the list of the edge's smaller end point `lo`:
    // (other end << 32) | (face << 1) | (1 when the face runs from the other end to lo).
    static uint32_t otherEnd(uint64_t use) { return uint32_t(use >> 32); }
    static uint32_t faceOf(uint64_t use) { return uint32_t(use >> 1) & 0x7FFFFFFFu; }
    static bool backward(uint64_t use) { return use & 1; }

    /// Buckets the edge uses of every face by their smaller (welded) end point, each bucket
    /// sorted, so that the uses of one edge are adjacent.
    void buildEdgeTable(const std::vector<Vec3I>& triangles, bool threaded) {
        const size_t n = mPoints.size();
        mFirst.assign(n + 1, 0);
        const auto forEachEdge = [&](size_t t, const auto& op) {
            const Vec3I& v = triangles[t];
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = mRep[v[k]], b = mRep[v[(k + 1) % 3]];
                if (a != b)
                    op(std::min(a, b), std::max(a, b), a > b);
            }
        };
        for (size_t t = 0; t < triangles.size(); ++t)
            forEachEdge(t, [&](uint32_t lo, uint32_t, bool) { ++mFirst[lo + 1]; });
        for (size_t i = 0; i < n; ++i)
            mFirst[i + 1] += mFirst[i];
        mUses.resize(mFirst[n]);
        std::vector<size_t> fill(mFirst.begin(), mFirst.end() - 1);
        for (size_t t = 0; t < triangles.size(); ++t) {
            forEachEdge(t, [&](uint32_t lo, uint32_t hi, bool back) {
                mUses[fill[lo]++] = (uint64_t(hi) << 32) | (uint64_t(t) << 1) | uint64_t(back);
            });
        }
        util::parallelFor(
            n,
            [&](size_t i) { std::sort(mUses.begin() + mFirst[i], mUses.begin() + mFirst[i + 1]); },
            threaded, 1024);
    }

    /// Calls `op(lo, hi, begin, end)` for every edge, with its uses mUses[begin, end).
    template <typename OpT>
    void forEachEdge(const OpT& op) const {
        for (size_t lo = 0; lo + 1 < mFirst.size(); ++lo) {
            for (size_t s = mFirst[lo], end = mFirst[lo + 1]; s < end;) {
                size_t e = s + 1;
                while (e < end && otherEnd(mUses[e]) == otherEnd(mUses[s]))
                    ++e;
                op(uint32_t(lo), otherEnd(mUses[s]), s, e);
                s = e;
            }
        }
    }

    /// The number of times the faces run from lo to hi minus the times they run back, each
    /// face turned over where mFlipped says so.
    int netUse(size_t begin, size_t end) const {
        int net = 0;
        for (size_t u = begin; u < end; ++u) {
            const bool flip = !mFlipped.empty() && mFlipped[faceOf(mUses[u])];
            net += backward(mUses[u]) != flip ? -1 : 1;
        }
        return net;
    }

    void countEdges() {
        forEachEdge([&](uint32_t, uint32_t, size_t s, size_t e) {
            const size_t uses = e - s;
            if (uses == 1) {
                ++mCounts.boundaryEdges;
            } else if (uses > 2) {
                ++mCounts.nonManifoldEdges;
            } else if (netUse(s, e) != 0) {
                ++mCounts.misorientedEdges;
            }
        });
    }

    /// Turns faces over so that the two faces of every edge of exactly two faces run opposite
    /// ways where the pieces allow it (a breadth-first walk per piece); each piece keeps the
    /// orientation of most of its area.
    void orientFaces(std::vector<Vec3I>& triangles) {
        const size_t faces = triangles.size();
        // Neighbours across edges of two faces: (face << 1) | (1 when both run the same way).
        std::vector<size_t> first(faces + 1, 0);
        std::vector<uint64_t> links;
        const auto forEachPair = [&](const auto& op) {
            forEachEdge([&](uint32_t, uint32_t, size_t s, size_t e) {
                if (e - s != 2 || faceOf(mUses[s]) == faceOf(mUses[s + 1]))
                    return;
                const bool same = backward(mUses[s]) == backward(mUses[s + 1]);
                op(faceOf(mUses[s]), faceOf(mUses[s + 1]), same);
                op(faceOf(mUses[s + 1]), faceOf(mUses[s]), same);
            });
        };
        forEachPair([&](uint32_t f, uint32_t, bool) { ++first[f + 1]; });
        for (size_t f = 0; f < faces; ++f)
            first[f + 1] += first[f];
        links.resize(first[faces]);
        std::vector<size_t> fill(first.begin(), first.end() - 1);
        forEachPair([&](uint32_t f, uint32_t g, bool same) {
            links[fill[f]++] = (uint64_t(g) << 1) | uint64_t(same);
        });

        const auto area = [&](size_t f) {
            const Vec3I& v = triangles[f];
            return (mPoints[v[1]] - mPoints[v[0]]).cross(mPoints[v[2]] - mPoints[v[0]]).length();
        };
        constexpr uint8_t UNSEEN = 2;
        std::vector<uint8_t> side(faces, UNSEEN);
        mFlipped.assign(faces, 0);
        std::vector<uint32_t> piece;
        for (size_t seed = 0; seed < faces; ++seed) {
            if (side[seed] != UNSEEN)
                continue;
            piece.assign(1, uint32_t(seed));
            side[seed] = 0;
            double areas[2] = {0.0, 0.0};
            for (size_t q = 0; q < piece.size(); ++q) {
                const uint32_t f = piece[q];
                areas[side[f]] += area(f);
                for (size_t l = first[f]; l < first[f + 1]; ++l) {
                    const uint32_t g = uint32_t(links[l] >> 1);
                    if (side[g] == UNSEEN) {
                        side[g] = side[f] ^ uint8_t(links[l] & 1);
                        piece.push_back(g);
                    }
                }
            }
            // Turn over the side with less area (the seed's side on a tie stays).
            const uint8_t turn = areas[1] > areas[0] ? 0 : 1;
            for (uint32_t f : piece) {
                if (side[f] == turn) {
                    mFlipped[f] = 1;
                    std::swap(triangles[f][1], triangles[f][2]);
                    ++mCounts.flippedFaces;
                }
            }
        }
    }

    /// Splits the open edges (each `net` times, in the direction the faces run) into closed
    /// loops and caps each loop (capLoop()).
    void buildPatches() {
        const size_t n = mPoints.size();
        std::vector<size_t> first(n + 1, 0);
        std::vector<uint32_t> heads;
        const auto forEachOpen = [&](const auto& op) {
            forEachEdge([&](uint32_t lo, uint32_t hi, size_t s, size_t e) {
                const int net = netUse(s, e);
                for (int k = 0; k < std::abs(net); ++k)
                    net > 0 ? op(lo, hi) : op(hi, lo);
            });
        };
        forEachOpen([&](uint32_t a, uint32_t) { ++first[a + 1]; });
        for (size_t i = 0; i < n; ++i)
            first[i + 1] += first[i];
        if (first[n] == 0)
            return;
        heads.resize(first[n]);
        std::vector<size_t> left(first.begin(),
                                 first.end() - 1);  // unused out-edges: [first, left)
        forEachOpen([&](uint32_t a, uint32_t b) { heads[left[a]++] = b; });

        // Every point has as many open edges in as out, so a walk from any point can always
        // go on; each time it meets a point already on the path, the loop it closed is capped.
        constexpr uint32_t OFF_PATH = 0xFFFFFFFFu;
        std::vector<uint32_t> position(n, OFF_PATH);
        std::vector<uint32_t> path;
        for (uint32_t start = 0; start < n; ++start) {
            if (left[start] == first[start])
                continue;
            path.assign(1, start);
            position[start] = 0;
            while (!path.empty()) {
                const uint32_t u = path.back();
                if (left[u] == first[u]) {
                    position[u] = OFF_PATH;
                    path.pop_back();
                    continue;
                }
                const uint32_t w = heads[--left[u]];
                if (position[w] == OFF_PATH) {
                    position[w] = uint32_t(path.size());
                    path.push_back(w);
                    continue;
                }
                capLoop(path.data() + position[w], path.size() - position[w]);
                for (size_t k = position[w] + 1; k < path.size(); ++k)
                    position[path[k]] = OFF_PATH;
                path.resize(position[w] + 1);
            }
        }
    }

    /// Adds a patch over the loop loop[0] -> loop[1] -> ... -> loop[count - 1] -> loop[0]
    /// (counted in holes when it has an area).
    void capLoop(const uint32_t* loop, size_t count) {
        const size_t before = mPatches.size();
        std::vector<uint32_t> vertices(loop, loop + count);
        triangulate(vertices);
        bool hasArea = false;
        for (size_t t = before; t < mPatches.size() && !hasArea; ++t) {
            const auto& p = mPatches[t];
            hasArea = (p[1] - p[0]).cross(p[2] - p[0]) != Vec3d(0.0);
        }
        // A loop without area (its points on one line) changes neither crossings nor
        // winding numbers.
        if (hasArea) {
            ++mCounts.holes;
        } else {
            mPatches.resize(before);
        }
    }

    /// Triangulates the loop v[0] -> ... -> v[n - 1] -> v[0] with triangles whose boundary is
    /// the loop and whose total area is small, so that the patch hugs the hole (a long narrow
    /// slit is closed across, not by a fan from its middle). Up to MAX_EXACT points: the
    /// triangulation of least area over the loop's own points (dynamic programming, Liepa
    /// 2003, n^3 / 6 steps). Longer loops are first cut along the shortest chord between
    /// points at least a quarter of the loop apart.
    void triangulate(const std::vector<uint32_t>& v) {
        constexpr size_t MAX_EXACT = 128;
        const size_t n = v.size();
        const auto at = [&](size_t i) -> const Vec3d& { return mPoints[v[i]]; };
        if (n > MAX_EXACT) {
            // Candidate ends on a stride, so that the search stays near MAX_EXACT^2 pairs.
            const size_t stride = std::max<size_t>(1, n / MAX_EXACT);
            size_t bestI = 0, bestJ = n / 2;
            double best = std::numeric_limits<double>::max();
            for (size_t i = 0; i < n; i += stride) {
                for (size_t j = i + n / 4; j + n / 4 <= i + n && j < n; j += stride) {
                    const double d = (at(i) - at(j)).lengthSqr();
                    if (d < best) {
                        best = d;
                        bestI = i;
                        bestJ = j;
                    }
                }
            }
            triangulate(std::vector<uint32_t>(v.begin() + bestI, v.begin() + bestJ + 1));
            std::vector<uint32_t> rest(v.begin() + bestJ, v.end());
            rest.insert(rest.end(), v.begin(), v.begin() + bestI + 1);
            triangulate(rest);
            return;
        }
        if (n < 3)
            return;
        // area[i * n + j]: least area of the loop v[i] -> ... -> v[j] -> v[i]; split[...]: the
        // third corner of its triangle on the chord (i, j).
        std::vector<double> area(n * n, 0.0);
        std::vector<uint32_t> split(n * n, 0);
        for (size_t len = 2; len < n; ++len) {
            for (size_t i = 0; i + len < n; ++i) {
                const size_t j = i + len;
                double best = std::numeric_limits<double>::max();
                for (size_t m = i + 1; m < j; ++m) {
                    const double a = area[i * n + m] + area[m * n + j] +
                                     (at(m) - at(i)).cross(at(j) - at(i)).length();
                    if (a < best) {
                        best = a;
                        split[i * n + j] = uint32_t(m);
                    }
                }
                area[i * n + j] = best;
            }
        }
        // Triangles (v[i], v[m], v[j]) run round their loop the way the loop does.
        std::vector<std::pair<uint32_t, uint32_t>> todo{{0u, uint32_t(n - 1)}};
        while (!todo.empty()) {
            const auto [i, j] = todo.back();
            todo.pop_back();
            if (j - i < 2)
                continue;
            const uint32_t m = split[i * n + j];
            mPatches.push_back({at(i), at(m), at(j)});
            todo.emplace_back(i, m);
            todo.emplace_back(m, j);
        }
    }

    const std::vector<Vec3d>& mPoints;
    std::vector<uint32_t> mRep;  // welded representative of each point
    std::vector<size_t> mFirst;  // uses of edges whose smaller end is i: mUses[mFirst[i], ...)
    std::vector<uint64_t> mUses;
    std::vector<uint8_t> mFlipped;  // per face: turned over (empty when none was)
    MeshEdgeCounts mCounts;
    std::vector<std::array<Vec3d, 3>> mPatches;
};

}  // namespace vdb::tools::detail
