// SPDX-License-Identifier: Apache-2.0
/// @file
/// Meshes generated at test time (sphere, cube, torus, with holes, far away) and independent
/// oracles for them: the exact distance to a triangle mesh by brute force over every triangle
/// (closest point by Voronoi regions, a different method from the library's), a point-in-mesh
/// test by ray casting in three skew directions (Moller-Trumbore), and the exact generalized
/// winding number by brute force over every triangle (L'Huilier's spherical excess). Shared by the
/// mesh tests, the OpenVDB compatibility test and the mesh benchmark; nothing here uses the
/// library beyond its vector types.

#pragma once

#include <vdb/math/Vec3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

namespace vdb::test {

struct TestMesh {
    std::vector<Vec3s> points;
    std::vector<Vec3I> triangles;
    std::vector<Vec4I> quads;

    size_t primitiveCount() const { return triangles.size() + quads.size(); }

    /// The mesh with every quad split into triangles (0, 1, 2) and (0, 2, 3).
    std::vector<Vec3I> allTriangles() const {
        std::vector<Vec3I> out = triangles;
        for (const Vec4I& q : quads) {
            out.emplace_back(q[0], q[1], q[2]);
            out.emplace_back(q[0], q[2], q[3]);
        }
        return out;
    }

    void translate(const Vec3d& t) {
        for (Vec3s& p : points)
            p = Vec3s(Vec3d(p) + t);
    }
};

/// A latitude-longitude sphere: `rings` bands of latitude, `segments` of longitude, triangles
/// counter-clockwise seen from outside (2 * segments * (rings - 1) of them).
inline TestMesh makeSphereMesh(const Vec3d& center, double radius, int rings, int segments) {
    TestMesh mesh;
    const double pi = std::numbers::pi;
    mesh.points.emplace_back(Vec3d(center[0], center[1], center[2] + radius));  // north pole
    for (int r = 1; r < rings; ++r) {
        const double theta = pi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double phi = 2.0 * pi * s / segments;
            mesh.points.emplace_back(center + Vec3d(std::sin(theta) * std::cos(phi),
                                                    std::sin(theta) * std::sin(phi),
                                                    std::cos(theta)) *
                                                  radius);
        }
    }
    mesh.points.emplace_back(Vec3d(center[0], center[1], center[2] - radius));  // south pole
    const auto ring = [&](int r, int s) { return Index32(1 + (r - 1) * segments + s % segments); };
    const Index32 south = Index32(mesh.points.size() - 1);
    for (int s = 0; s < segments; ++s) {
        mesh.triangles.emplace_back(0, ring(1, s), ring(1, s + 1));
        for (int r = 1; r + 1 < rings; ++r) {
            mesh.triangles.emplace_back(ring(r, s), ring(r + 1, s), ring(r + 1, s + 1));
            mesh.triangles.emplace_back(ring(r, s), ring(r + 1, s + 1), ring(r, s + 1));
        }
        mesh.triangles.emplace_back(ring(rings - 1, s), south, ring(rings - 1, s + 1));
    }
    return mesh;
}

/// An axis-aligned cube of edge `size` with its smallest corner at `corner`, each face an
/// n x n grid of quads (or of triangle pairs), vertices shared between faces, quads
/// counter-clockwise seen from outside.
inline TestMesh makeCubeMesh(const Vec3d& corner, double size, int n, bool quads) {
    TestMesh mesh;
    std::map<std::tuple<int, int, int>, Index32> index;
    const auto vertex = [&](int i, int j, int k) {
        const auto key = std::make_tuple(i, j, k);
        auto it = index.find(key);
        if (it != index.end())
            return it->second;
        const Index32 v = Index32(mesh.points.size());
        mesh.points.emplace_back(corner + Vec3d(i, j, k) * (size / n));
        index.emplace(key, v);
        return v;
    };
    // Each face: a fixed axis at 0 or n, and two running axes (u, v) with u x v outward.
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const int u = side == 1 ? (axis + 1) % 3 : (axis + 2) % 3;
            const int v = side == 1 ? (axis + 2) % 3 : (axis + 1) % 3;
            for (int a = 0; a < n; ++a) {
                for (int b = 0; b < n; ++b) {
                    const auto at = [&](int da, int db) {
                        int c[3];
                        c[axis] = side * n;
                        c[u] = a + da;
                        c[v] = b + db;
                        return vertex(c[0], c[1], c[2]);
                    };
                    const Index32 p0 = at(0, 0), p1 = at(1, 0), p2 = at(1, 1), p3 = at(0, 1);
                    if (quads) {
                        mesh.quads.emplace_back(p0, p1, p2, p3);
                    } else {
                        mesh.triangles.emplace_back(p0, p1, p2);
                        mesh.triangles.emplace_back(p0, p2, p3);
                    }
                }
            }
        }
    }
    return mesh;
}

/// A torus around the z axis through `center`: `major` and `minor` radii, a grid of
/// `around` x `tube` quads split into triangles, counter-clockwise seen from outside.
inline TestMesh makeTorusMesh(const Vec3d& center, double major, double minor, int around,
                              int tube) {
    TestMesh mesh;
    const double pi = std::numbers::pi;
    for (int i = 0; i < around; ++i) {
        const double u = 2.0 * pi * i / around;
        for (int j = 0; j < tube; ++j) {
            const double v = 2.0 * pi * j / tube;
            const double rr = major + minor * std::cos(v);
            mesh.points.emplace_back(
                center + Vec3d(rr * std::cos(u), rr * std::sin(u), minor * std::sin(v)));
        }
    }
    const auto at = [&](int i, int j) { return Index32((i % around) * tube + (j % tube)); };
    for (int i = 0; i < around; ++i) {
        for (int j = 0; j < tube; ++j) {
            mesh.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            mesh.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    return mesh;
}

// ---- Meshes with defects ----

/// The mesh without the triangles (quads split first) whose centroid `drop` accepts; points
/// are kept, so the holes' rims keep their vertices.
template <typename PredicateT>
TestMesh withoutTriangles(const TestMesh& mesh, const PredicateT& drop) {
    TestMesh out;
    out.points = mesh.points;
    for (const Vec3I& t : mesh.allTriangles()) {
        const Vec3d c =
            (Vec3d(mesh.points[t[0]]) + Vec3d(mesh.points[t[1]]) + Vec3d(mesh.points[t[2]])) / 3.0;
        if (!drop(c))
            out.triangles.push_back(t);
    }
    return out;
}

/// The mesh with every triangle's corners as points of their own (as STL stores them).
inline TestMesh withDuplicatedPoints(const TestMesh& mesh) {
    TestMesh out;
    for (const Vec3I& t : mesh.allTriangles()) {
        const Index32 base = Index32(out.points.size());
        for (int k = 0; k < 3; ++k)
            out.points.push_back(mesh.points[t[k]]);
        out.triangles.emplace_back(base, base + 1, base + 2);
    }
    return out;
}

/// The union of two meshes as one mesh (their triangles may cross).
inline TestMesh merged(const TestMesh& a, const TestMesh& b) {
    TestMesh out;
    out.points = a.points;
    out.points.insert(out.points.end(), b.points.begin(), b.points.end());
    out.triangles = a.allTriangles();
    const Index32 base = Index32(a.points.size());
    for (const Vec3I& t : b.allTriangles())
        out.triangles.emplace_back(t[0] + base, t[1] + base, t[2] + base);
    return out;
}

// ---- Oracles ----

/// The closest point of triangle (a, b, c) to p, by the Voronoi region of p (vertex, edge or
/// face region, tested in that order).
inline Vec3d closestPointOnTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b,
                                    const Vec3d& c) {
    const Vec3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0)
        return a;
    const Vec3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3)
        return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double t = d1 - d3 != 0.0 ? d1 / (d1 - d3) : 0.0;
        return a + ab * t;
    }
    const Vec3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6)
        return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double t = d2 - d6 != 0.0 ? d2 / (d2 - d6) : 0.0;
        return a + ac * t;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double t = (d4 - d3) + (d5 - d6) != 0.0 ? (d4 - d3) / ((d4 - d3) + (d5 - d6)) : 0.0;
        return b + (c - b) * t;
    }
    const double sum = va + vb + vc;
    if (sum == 0.0) {
        // Degenerate triangle: the nearest of its three edges' closest points.
        const auto onSegment = [&](const Vec3d& s, const Vec3d& e) {
            const Vec3d d = e - s;
            const double len2 = d.dot(d);
            const double t = len2 > 0.0 ? std::clamp((p - s).dot(d) / len2, 0.0, 1.0) : 0.0;
            return s + d * t;
        };
        Vec3d best = onSegment(a, b);
        for (const Vec3d& q : {onSegment(b, c), onSegment(c, a)}) {
            if ((q - p).lengthSqr() < (best - p).lengthSqr())
                best = q;
        }
        return best;
    }
    const double v = vb / sum, w = vc / sum;
    return a + ab * v + ac * w;
}

/// Index-space points and triangles of a mesh, for the oracles.
struct OracleMesh {
    std::vector<Vec3d> points;
    std::vector<Vec3I> triangles;

    /// The distance from p to the nearest triangle, over all of them.
    double distance(const Vec3d& p) const {
        double best = std::numeric_limits<double>::max();
        for (const Vec3I& t : triangles) {
            const Vec3d q = closestPointOnTriangle(p, points[t[0]], points[t[1]], points[t[2]]);
            best = std::min(best, (q - p).lengthSqr());
        }
        return std::sqrt(best);
    }

    /// The number of triangles the ray p + s * dir (s > 0) passes through (Moller-Trumbore).
    int rayHits(const Vec3d& p, const Vec3d& dir) const {
        int hits = 0;
        for (const Vec3I& t : triangles) {
            const Vec3d &a = points[t[0]], &b = points[t[1]], &c = points[t[2]];
            const Vec3d e1 = b - a, e2 = c - a;
            const Vec3d h = dir.cross(e2);
            const double det = e1.dot(h);
            if (std::abs(det) < 1e-15)
                continue;
            const Vec3d s = p - a;
            const double u = s.dot(h) / det;
            if (u < 0.0 || u > 1.0)
                continue;
            const Vec3d q = s.cross(e1);
            const double v = dir.dot(q) / det;
            if (v < 0.0 || u + v > 1.0)
                continue;
            if (e2.dot(q) / det > 0.0)
                ++hits;
        }
        return hits;
    }

    /// The generalized winding number at p (Jacobson et al. 2013): the sum over all triangles
    /// of their signed solid angles seen from p, over 4 pi. Each solid angle is the spherical
    /// excess of the triangle's projection on the unit sphere around p, by L'Huilier's theorem
    /// from the three arc lengths (a different formula from the library's), signed by the
    /// triangle's orientation as seen from p.
    double windingNumber(const Vec3d& p) const {
        const auto arc = [](const Vec3d& u, const Vec3d& v) {
            return std::atan2(u.cross(v).length(), u.dot(v));
        };
        double sum = 0.0;
        for (const Vec3I& t : triangles) {
            const Vec3d a = points[t[0]] - p, b = points[t[1]] - p, c = points[t[2]] - p;
            const double det = a.dot(b.cross(c));
            if (det == 0.0)
                continue;
            const double ta = arc(b, c), tb = arc(a, c), tc = arc(a, b);
            const double s = 0.5 * (ta + tb + tc);
            const double product = std::tan(0.5 * s) * std::tan(0.5 * (s - ta)) *
                                   std::tan(0.5 * (s - tb)) * std::tan(0.5 * (s - tc));
            const double excess = 4.0 * std::atan(std::sqrt(std::max(0.0, product)));
            sum += det > 0.0 ? excess : -excess;
        }
        return sum / (4.0 * std::numbers::pi);
    }

    /// Inside by the generalized winding number: more than 1/2 in magnitude.
    bool insideByWinding(const Vec3d& p) const { return std::abs(windingNumber(p)) > 0.5; }

    /// The distance from p to the nearest open edge: one along which fewer faces run one way
    /// than the other (boundary edges, most non-manifold and misoriented edges), matching
    /// points by position; infinity for a closed mesh.
    double distanceToOpenEdges(const Vec3d& p) const {
        if (!openEdgesFound)
            findOpenEdges();
        double best = std::numeric_limits<double>::infinity();
        for (const auto& [a, b] : openEdges) {
            const Vec3d d = b - a;
            const double len2 = d.dot(d);
            const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
            best = std::min(best, (a + d * t - p).length());
        }
        return best;
    }

    /// Inside by the majority of three rays in skew directions (each counts hits mod 2).
    bool inside(const Vec3d& p) const {
        static const Vec3d dirs[3] = {Vec3d(0.5773, 0.6143, 0.5381), Vec3d(-0.7071, 0.3123, 0.6345),
                                      Vec3d(0.2154, -0.8531, -0.4752)};
        int votes = 0;
        for (const Vec3d& d : dirs)
            votes += rayHits(p, d) % 2;
        return votes >= 2;
    }

private:
    using Key = std::tuple<double, double, double>;
    mutable std::vector<std::pair<Vec3d, Vec3d>> openEdges;
    mutable bool openEdgesFound = false;

    /// Counts, per edge between two positions, the faces running each way along it.
    void findOpenEdges() const {
        openEdgesFound = true;
        const auto key = [](const Vec3d& v) { return Key(v[0], v[1], v[2]); };
        std::map<std::pair<Key, Key>, std::pair<int, int>> uses;  // (lo -> hi, hi -> lo)
        for (const Vec3I& t : triangles) {
            for (int k = 0; k < 3; ++k) {
                const Key a = key(points[t[k]]), b = key(points[t[(k + 1) % 3]]);
                if (a == b)
                    continue;
                auto& u = uses[std::minmax(a, b)];
                (a < b ? u.first : u.second) += 1;
            }
        }
        for (const auto& [edge, u] : uses) {
            if (u.first != u.second) {
                const auto& [a, b] = edge;
                openEdges.emplace_back(Vec3d(std::get<0>(a), std::get<1>(a), std::get<2>(a)),
                                       Vec3d(std::get<0>(b), std::get<1>(b), std::get<2>(b)));
            }
        }
    }
};

/// Sign agreement of a level set with an oracle at sampled points.
struct SignTally {
    int checked = 0;  ///< points compared
    int wrong = 0;    ///< of which the two disagree
};

/// The points of `points` (index space) more than `nearSurface` voxels from the mesh (where a
/// sign is a matter of rounding) and `nearOpenEdges` voxels from its open edges (where the
/// winding number changes smoothly between inside and outside), each with `oracleInside(p)`.
template <typename OracleT>
std::vector<std::pair<Vec3d, bool>> oracleSigns(const OracleMesh& mesh,
                                                const std::vector<Vec3d>& points,
                                                double nearSurface, double nearOpenEdges,
                                                const OracleT& oracleInside) {
    std::vector<std::pair<Vec3d, bool>> out;
    for (const Vec3d& p : points) {
        if (mesh.distance(p) >= nearSurface && mesh.distanceToOpenEdges(p) >= nearOpenEdges)
            out.emplace_back(p, oracleInside(p));
    }
    return out;
}

/// Compares `insideOf(p)` (a level set) with the oracle's signs.
template <typename InsideT>
SignTally compareSigns(const std::vector<std::pair<Vec3d, bool>>& oracle, const InsideT& insideOf) {
    SignTally tally;
    for (const auto& [p, inside] : oracle) {
        ++tally.checked;
        tally.wrong += insideOf(p) != inside;
    }
    return tally;
}

/// Both steps at once.
template <typename InsideT, typename OracleT>
SignTally compareSigns(const OracleMesh& mesh, const std::vector<Vec3d>& points, double nearSurface,
                       double nearOpenEdges, const InsideT& insideOf, const OracleT& oracleInside) {
    return compareSigns(oracleSigns(mesh, points, nearSurface, nearOpenEdges, oracleInside),
                        insideOf);
}

/// Every `stride`-th voxel centre, in each axis, of the box around the mesh grown by `margin`
/// voxels (index space).
inline std::vector<Vec3d> boxSamples(const OracleMesh& mesh, double margin, int stride) {
    Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec3d& p : mesh.points) {
        lo = Vec3d::minComponent(lo, p);
        hi = Vec3d::maxComponent(hi, p);
    }
    std::vector<Vec3d> out;
    for (double x = std::floor(lo[0] - margin); x <= hi[0] + margin; x += stride) {
        for (double y = std::floor(lo[1] - margin); y <= hi[1] + margin; y += stride) {
            for (double z = std::floor(lo[2] - margin); z <= hi[2] + margin; z += stride)
                out.emplace_back(x, y, z);
        }
    }
    return out;
}

/// Points for sign checks (index space): every `stride`-th active voxel of `grid` (of this
/// library or of OpenVDB) and every `boxStride`-th voxel of the box around the mesh grown by 4.
template <typename GridT>
std::vector<Vec3d> signSamples(const GridT& grid, const OracleMesh& mesh, int stride,
                               int boxStride) {
    std::vector<Vec3d> out = boxSamples(mesh, 4.0, boxStride);
    int n = 0;
    for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
        if (n++ % stride == 0)
            out.emplace_back(it.getCoord()[0], it.getCoord()[1], it.getCoord()[2]);
    }
    return out;
}

/// The mesh in the index space of a transform given as world = index * voxelSize + offset.
inline OracleMesh toIndexSpace(const TestMesh& mesh, double voxelSize,
                               const Vec3d& offset = Vec3d(0.0)) {
    OracleMesh out;
    for (const Vec3s& p : mesh.points)
        out.points.push_back((Vec3d(p) - offset) / voxelSize);
    out.triangles = mesh.allTriangles();
    return out;
}

}  // namespace vdb::test
