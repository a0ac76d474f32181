// SPDX-License-Identifier: Apache-2.0
/// @file
/// Independent measurements of polygon meshes for the tests of volumeToMesh() and the mesh
/// writer: the topology by an edge map and by vertex links (closed, two-manifold, oriented,
/// Euler characteristic), the enclosed signed volume and the area by sums over triangles, and
/// distances from points to a mesh by brute force over the triangles in nearby buckets.
/// Nothing here uses the library beyond its vector types.

#pragma once

#include <vdb/math/Vec3.h>

#include "TestMeshes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vdb::test {

/// What an edge map and the vertex links say about a mesh's topology.
struct MeshTopology {
    size_t polygons = 0;
    size_t edges = 0;          ///< undirected edges
    size_t unpairedEdges = 0;  ///< directed edges whose reverse is missing
    size_t repeatedEdges = 0;  ///< directed edges used by more than one polygon
    size_t degenerate = 0;     ///< polygons with a repeated corner
    size_t badVertices = 0;    ///< points whose polygons do not form one fan around them
    size_t unusedPoints = 0;
    long euler = 0;  ///< V - E + F over the used points

    /// Closed and two-manifold, every polygon oriented consistently with its neighbours:
    /// every edge in exactly two polygons, once in each direction, and one fan per vertex.
    bool closedManifold() const {
        return polygons > 0 && unpairedEdges == 0 && repeatedEdges == 0 && degenerate == 0 &&
               badVertices == 0;
    }
};

inline MeshTopology topologyOf(const TestMesh& mesh) {
    MeshTopology t;
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    // For each point, the (previous, next) corners of every polygon around it.
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> fans(mesh.points.size());
    const auto add = [&](const uint32_t* v, int n) {
        ++t.polygons;
        for (int i = 0; i < n; ++i) {
            const uint32_t a = v[i], b = v[(i + 1) % n];
            if (a == b)
                ++t.degenerate;
            ++directed[{a, b}];
            fans[a].emplace_back(v[(i + n - 1) % n], b);
        }
    };
    for (const Vec3I& tri : mesh.triangles) {
        const uint32_t v[3] = {tri[0], tri[1], tri[2]};
        add(v, 3);
    }
    for (const Vec4I& q : mesh.quads) {
        const uint32_t v[4] = {q[0], q[1], q[2], q[3]};
        add(v, 4);
    }
    size_t undirected2 = 0;
    for (const auto& [edge, count] : directed) {
        if (count > 1)
            ++t.repeatedEdges;
        undirected2 += (edge.first == edge.second) ? 2 : 1;
        if (!directed.count({edge.second, edge.first}))
            ++t.unpairedEdges;
    }
    t.edges = undirected2 / 2;
    // A manifold vertex's fan: following previous -> next links visits every polygon once
    // and returns to the start.
    size_t used = 0;
    for (const auto& fan : fans) {
        if (fan.empty()) {
            ++t.unusedPoints;
            continue;
        }
        ++used;
        std::unordered_map<uint32_t, uint32_t> next;
        for (const auto& [prev, nxt] : fan)
            next[prev] = nxt;
        uint32_t at = fan.front().first;
        size_t steps = 0;
        do {
            const auto it = next.find(at);
            if (it == next.end())
                break;
            at = it->second;
            ++steps;
        } while (at != fan.front().first && steps <= fan.size());
        if (next.size() != fan.size() || steps != fan.size() || at != fan.front().first)
            ++t.badVertices;
    }
    t.euler = long(used) - long(t.edges) + long(t.polygons);
    return t;
}

/// The signed volume enclosed by the mesh: positive when its polygons wind counter-clockwise
/// seen from outside, negative for the clockwise winding of volumeToMesh().
inline double signedVolume(const TestMesh& mesh) {
    double sum = 0.0;
    for (const Vec3I& t : mesh.allTriangles()) {
        const Vec3d a(mesh.points[t[0]]), b(mesh.points[t[1]]), c(mesh.points[t[2]]);
        sum += a.dot(b.cross(c));
    }
    return sum / 6.0;
}

inline double surfaceArea(const TestMesh& mesh) {
    double sum = 0.0;
    for (const Vec3I& t : mesh.allTriangles()) {
        const Vec3d a(mesh.points[t[0]]), b(mesh.points[t[1]]), c(mesh.points[t[2]]);
        sum += 0.5 * (b - a).cross(c - a).length();
    }
    return sum;
}

/// Distances from points to the triangles of a mesh (quads split), up to a search radius:
/// the triangles are bucketed by their bounding boxes in a dense grid of cubes of edge `cell`
/// (the radius by default; larger when the mesh would need more than 2^21 of them) over the
/// mesh's bounds, and a query visits shells of buckets around its own, nearest first, testing
/// each triangle by the Voronoi-region closest point, until no farther bucket can hold anything
/// closer. The bucket size changes only the time, never a distance.
class MeshDistance {
public:
    MeshDistance(const TestMesh& mesh, double radius, double cell = 0.0)
        : mRadius(radius), mCell(cell > 0.0 ? cell : radius), mTriangles(mesh.allTriangles()) {
        for (const Vec3s& p : mesh.points)
            mPoints.emplace_back(p);
        Vec3d lo(std::numeric_limits<double>::max()), hi(-lo[0]);
        for (const Vec3I& t : mTriangles) {
            Vec3d a(std::numeric_limits<double>::max()), b(-a[0]);
            for (int i = 0; i < 3; ++i) {
                a = Vec3d::minComponent(a, mPoints[t[i]]);
                b = Vec3d::maxComponent(b, mPoints[t[i]]);
            }
            mBoxes.push_back({a, b});
            lo = Vec3d::minComponent(lo, a);
            hi = Vec3d::maxComponent(hi, b);
        }
        if (mTriangles.empty())
            return;
        mOrigin = lo;
        constexpr double MAX_BUCKETS = double(1 << 21);
        for (;;) {
            double buckets = 1.0;
            for (int a = 0; a < 3; ++a) {
                mDims[size_t(a)] = int64_t(std::floor((hi[a] - lo[a]) / mCell)) + 1;
                buckets *= double(mDims[size_t(a)]);
            }
            if (buckets <= MAX_BUCKETS)
                break;
            mCell *= std::max(1.01, std::cbrt(buckets / MAX_BUCKETS));
        }
        // Counts per bucket, their prefix sums, then the triangle numbers in bucket order.
        mStarts.assign(size_t(mDims[0] * mDims[1] * mDims[2]) + 1, 0);
        auto forEachBucket = [&](uint32_t t, auto&& op) {
            const Key a = key(mBoxes[t].first), b = key(mBoxes[t].second);
            for (int64_t x = a[0]; x <= b[0]; ++x)
                for (int64_t y = a[1]; y <= b[1]; ++y)
                    for (int64_t z = a[2]; z <= b[2]; ++z)
                        op(index(x, y, z));
        };
        for (uint32_t t = 0; t < mTriangles.size(); ++t)
            forEachBucket(t, [&](size_t i) { ++mStarts[i + 1]; });
        for (size_t i = 1; i < mStarts.size(); ++i)
            mStarts[i] += mStarts[i - 1];
        mEntries.resize(mStarts.back());
        std::vector<uint32_t> next(mStarts.begin(), mStarts.end() - 1);
        for (uint32_t t = 0; t < mTriangles.size(); ++t)
            forEachBucket(t, [&](size_t i) { mEntries[next[i]++] = t; });
    }

    /// The distance from p to the mesh, or the search radius when nothing is closer.
    double distance(const Vec3d& p) const {
        double best = mRadius * mRadius;
        if (mTriangles.empty())
            return mRadius;
        const Key c = key(p);
        // How far p lies from the nearest wall of its own bucket.
        double wall = mCell;
        for (int a = 0; a < 3; ++a) {
            const double f = p[a] - mOrigin[a] - double(c[size_t(a)]) * mCell;
            wall = std::min({wall, f, mCell - f});
        }
        const int64_t rings = int64_t(std::ceil(mRadius / mCell));
        for (int64_t r = 0; r <= rings; ++r) {
            // Buckets of ring r lie at least this far from p.
            const double reach = r == 0 ? 0.0 : double(r - 1) * mCell + wall;
            if (reach * reach >= best)
                break;
            const int64_t x0 = std::max<int64_t>(c[0] - r, 0),
                          x1 = std::min<int64_t>(c[0] + r, mDims[0] - 1);
            const int64_t y0 = std::max<int64_t>(c[1] - r, 0),
                          y1 = std::min<int64_t>(c[1] + r, mDims[1] - 1);
            for (int64_t x = x0; x <= x1; ++x)
                for (int64_t y = y0; y <= y1; ++y) {
                    // Inside the shell's x and y faces only its two z ends are on the shell.
                    const bool face = std::abs(x - c[0]) == r || std::abs(y - c[1]) == r;
                    const int64_t step = face || r == 0 ? 1 : 2 * r;
                    for (int64_t z = c[2] - r; z <= c[2] + r; z += step) {
                        if (z < 0 || z >= mDims[2])
                            continue;
                        const size_t i = index(x, y, z);
                        for (uint32_t e = mStarts[i]; e < mStarts[i + 1]; ++e) {
                            const uint32_t t = mEntries[e];
                            // The triangle's bounding box first: most are farther than the best.
                            const auto& [lo, hi] = mBoxes[t];
                            const Vec3d out = Vec3d::maxComponent(
                                Vec3d::maxComponent(lo - p, p - hi), Vec3d(0.0));
                            if (out.lengthSqr() >= best)
                                continue;
                            const Vec3I& tri = mTriangles[t];
                            const Vec3d q = closestPointOnTriangle(
                                p, mPoints[tri[0]], mPoints[tri[1]], mPoints[tri[2]]);
                            best = std::min(best, (q - p).lengthSqr());
                        }
                    }
                }
        }
        return std::sqrt(best);
    }

private:
    using Key = std::array<int64_t, 3>;
    /// The bucket holding p; outside the grid for points beyond the mesh's bounds.
    Key key(const Vec3d& p) const {
        Key k;
        for (int a = 0; a < 3; ++a) {
            // Clamped far beyond the grid, so that no ring arithmetic overflows.
            const double f = std::floor((p[a] - mOrigin[a]) / mCell);
            k[size_t(a)] = int64_t(std::clamp(f, -double(1 << 30), double(1 << 30)));
        }
        return k;
    }
    size_t index(int64_t x, int64_t y, int64_t z) const {
        return size_t((x * mDims[1] + y) * mDims[2] + z);
    }

    double mRadius, mCell;
    std::vector<Vec3I> mTriangles;
    std::vector<Vec3d> mPoints;
    std::vector<std::pair<Vec3d, Vec3d>> mBoxes;  // per triangle: its bounding box
    Vec3d mOrigin{0.0};
    Key mDims{0, 0, 0};
    std::vector<uint32_t> mStarts;   // per bucket: its first entry; one more at the end
    std::vector<uint32_t> mEntries;  // triangle numbers, bucket by bucket
};

/// Points spread over a mesh no more than about `spacing` apart: its vertices, and on every
/// triangle (quads split) the points of a barycentric grid fine enough for its longest edge.
inline std::vector<Vec3d> surfaceSamples(const TestMesh& mesh, double spacing) {
    std::vector<Vec3d> out;
    for (const Vec3s& p : mesh.points)
        out.emplace_back(p);
    for (const Vec3I& t : mesh.allTriangles()) {
        const Vec3d a(mesh.points[t[0]]), b(mesh.points[t[1]]), c(mesh.points[t[2]]);
        const double longest = std::max({(b - a).length(), (c - b).length(), (a - c).length()});
        const int n = std::max(1, int(std::ceil(longest / spacing)));
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const bool corner = (i == 0 && j == 0) || i == n || j == n;
                if (!corner)
                    out.push_back(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
            }
        out.push_back((a + b + c) / 3.0);
    }
    return out;
}

/// The largest distance from the samples of `from` (`spacing` apart) to `to`, capped at
/// `radius`.
inline double directedHausdorff(const TestMesh& from, const TestMesh& to, double radius,
                                double spacing) {
    const MeshDistance distance(to, radius, std::max(radius / 4.0, 2.0 * spacing));
    double worst = 0.0;
    for (const Vec3d& p : surfaceSamples(from, spacing))
        worst = std::max(worst, distance.distance(p));
    return worst;
}

/// The symmetric Hausdorff distance between two meshes, sampled `spacing` apart, capped at
/// `radius`.
inline double hausdorff(const TestMesh& a, const TestMesh& b, double radius, double spacing) {
    return std::max(directedHausdorff(a, b, radius, spacing),
                    directedHausdorff(b, a, radius, spacing));
}

/// The largest distance from a point of `a` to the nearest point of `b`, capped at `radius`
/// (for meshes whose points should coincide).
inline double largestPointGap(const TestMesh& a, const TestMesh& b, double radius) {
    TestMesh points;
    points.points = b.points;
    for (uint32_t i = 0; i < b.points.size(); ++i)
        points.triangles.emplace_back(i, i, i);  // a degenerate triangle is its point
    const MeshDistance distance(points, radius);
    double worst = 0.0;
    for (const Vec3s& p : a.points)
        worst = std::max(worst, distance.distance(Vec3d(p)));
    return worst;
}

}  // namespace vdb::test
