// SPDX-License-Identifier: Apache-2.0
// Oracles: the analytic ray-sphere and ray-box intersections (quadratic formula, slab test) and
// their normals; the analytic ellipsoid that a sphere becomes under a scale map, and normals
// measured by neighbouring hits under a sheared map; the active box of a fog volume for the
// spans of the volume intersector.

#include <vdb/render/Renderer.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/RayIntersector.h>
#include <vdb/vdb.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace vdb::tools {
namespace {

using RayD = math::Ray<double>;

constexpr double kDegree = std::numbers::pi / 180.0;

// The first time > 0 at which `ray` (unit direction) meets the sphere, and the closest approach
// of the line to the centre.
bool raySphere(const RayD& ray, const Vec3d& center, double radius, double& t, double& closest) {
    const Vec3d oc = ray.eye() - center;
    const double b = oc.dot(ray.dir());
    const double c = oc.lengthSqr() - radius * radius;
    closest = std::sqrt(std::max(0.0, oc.lengthSqr() - b * b));
    const double disc = b * b - c;
    if (disc < 0.0)
        return false;
    t = -b - std::sqrt(disc);
    if (t < 0.0)
        t = -b + std::sqrt(disc);
    return t >= 0.0;
}

struct SphereCase {
    float radius, voxelSize;
    Vec3f center;
};

TEST(LevelSetRayIntersector, HitsASphereWithinAVigesimalOfAVoxel) {
    for (const SphereCase& c : {SphereCase{4.0f, 0.1f, Vec3f(0.3f, -0.2f, 1.1f)},
                                SphereCase{1.5f, 0.05f, Vec3f(-2.0f, 0.0f, 0.5f)}}) {
        auto grid = createLevelSetSphere<FloatGrid>(c.radius, c.center, c.voxelSize, 3.0f);
        const LevelSetRayIntersector<FloatGrid> intersector(*grid);
        const Vec3d center(c.center);
        const double r = c.radius, dx = c.voxelSize;
        std::mt19937 rng(17);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        int hits = 0, misses = 0;
        double worstAngle = 0.0;
        const int rays = test::scaledBatchCount(3000);
        for (int n = 0; n < rays; ++n) {
            Vec3d dir(u(rng), u(rng), u(rng)), aim(u(rng), u(rng), u(rng));
            if (dir.length() < 0.1)
                continue;
            dir = dir.unit();
            // Eyes outside, and some inside the sphere; aims across a box 1.3 radii wide.
            const double eyeDistance = n % 5 == 0 ? 0.5 * r : 2.5 * r;
            const Vec3d eye = center + dir * eyeDistance;
            const Vec3d target = center + aim * (1.3 * r);
            const RayD ray(eye, (target - eye).unit());
            double t = 0.0, closest = 0.0;
            const bool expect = raySphere(ray, center, r, t, closest);
            if (std::abs(closest - r) < 1.5 * dx)
                continue;  // grazing: within a voxel and a half of the silhouette
            Vec3d xyz, normal;
            double wt = 0.0;
            const bool hit = intersector.intersectsWS(ray, xyz, normal, wt);
            ASSERT_EQ(hit, expect) << ray << " closest approach " << closest;
            if (!hit) {
                ++misses;
                continue;
            }
            ++hits;
            ASSERT_NEAR(wt, t, 0.05 * dx) << ray;
            ASSERT_TRUE(math::isApproxEqual(xyz, ray(wt), 1e-9));
            const Vec3d expectedNormal = (ray(t) - center) / r;
            const double angle = std::acos(std::clamp(normal.dot(expectedNormal), -1.0, 1.0));
            worstAngle = std::max(worstAngle, angle);
            ASSERT_LT(angle, 3.0 * kDegree) << ray;
        }
        // Both outcomes are well represented (each is about a third or more of the rays).
        EXPECT_GT(hits, rays / 30);
        EXPECT_GT(misses, rays / 30);
        RecordProperty("worst normal angle (degrees)", std::to_string(worstAngle / kDegree));
    }
}

TEST(LevelSetRayIntersector, IndexAndWorldEntryPointsAgree) {
    auto grid = createLevelSetSphere<FloatGrid>(2.0f, Vec3f(1.0f, 2.0f, 3.0f), 0.1f);
    const LevelSetRayIntersector<FloatGrid> intersector(*grid);
    const RayD wRay(Vec3d(1.0, 2.0, -5.0), Vec3d(0.0, 0.0, 2.0));  // not unit length
    Vec3d world, index;
    double wTime, iTime;
    ASSERT_TRUE(intersector.intersectsWS(wRay, world, wTime));
    EXPECT_NEAR(world[2], 1.0, 0.005);
    EXPECT_NEAR(wTime, 3.0, 0.0025);  // (1 - -5) / 2
    const RayD iRay = wRay.worldToIndex(grid->transform());
    ASSERT_TRUE(intersector.intersectsIS(iRay, index, iTime));
    EXPECT_TRUE(math::isApproxEqual(grid->indexToWorld(index), world, 1e-9));
    EXPECT_NEAR(iTime, 60.0, 0.05);  // index units: 6 world units at voxel size 0.1
    EXPECT_TRUE(intersector.intersectsWS(wRay));
    EXPECT_FALSE(intersector.intersectsWS(RayD(Vec3d(1.0, 2.0, -5.0), Vec3d(0, 0, -1))));
    // A ray that stops short of the surface misses.
    EXPECT_FALSE(intersector.intersectsWS(RayD(Vec3d(1.0, 2.0, -5.0), Vec3d(0, 0, 1), 0.0, 5.5)));
    EXPECT_TRUE(intersector.intersectsWS(RayD(Vec3d(1.0, 2.0, -5.0), Vec3d(0, 0, 1), 0.0, 6.5)));
}

// A narrow-band level set of the axis-aligned box [lo, hi] (world), exact signed distance.
FloatGrid::Ptr makeBoxLevelSet(const Vec3d& lo, const Vec3d& hi, double dx, double halfWidth) {
    const float background = float(halfWidth * dx);
    auto grid = FloatGrid::create(background);
    grid->setTransform(math::Transform::createLinearTransform(dx));
    grid->setGridClass(GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    const Coord a = floorToCoord(lo / dx - (halfWidth + 1)),
                b = floorToCoord(hi / dx + halfWidth + 1);
    for (int i = a.x(); i <= b.x(); ++i)
        for (int j = a.y(); j <= b.y(); ++j)
            for (int k = a.z(); k <= b.z(); ++k) {
                const Vec3d p = Vec3d(i, j, k) * dx;
                const Vec3d q = Vec3d::maxComponent(lo - p, p - hi);  // per-axis outside distance
                const double outside = Vec3d::maxComponent(q, Vec3d(0.0)).length();
                const double inside = std::min(q.maxComponent(), 0.0);
                const double d = outside + inside;
                if (std::abs(d) < halfWidth * dx) {
                    acc.setValue(Coord(i, j, k), float(d));
                } else {
                    acc.setValueOff(Coord(i, j, k), d < 0 ? -background : background);
                }
            }
    return grid;
}

TEST(LevelSetRayIntersector, HitsABoxOnItsFacesWithTheFaceNormal) {
    const Vec3d lo(-1.0, -0.5, -0.8), hi(1.2, 0.7, 0.6);
    const double dx = 0.05;
    auto grid = makeBoxLevelSet(lo, hi, dx, 3.0);
    const LevelSetRayIntersector<FloatGrid> intersector(*grid);
    const BBoxd box(lo, hi);
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hits = 0, misses = 0;
    const int rays = test::scaledBatchCount(2000);
    for (int n = 0; n < rays; ++n) {
        Vec3d dir(u(rng), u(rng), u(rng));
        if (dir.length() < 0.1)
            continue;
        const Vec3d eye = box.center() + dir.unit() * 3.0;
        const Vec3d target = box.center() + Vec3d(u(rng), u(rng), u(rng)) * 1.3;
        const RayD ray(eye, (target - eye).unit());
        double t0 = 0.0, t1 = 0.0;
        const bool expect = ray.intersects(box, t0, t1);
        // Skip rays within 1.5 voxels of an edge at entry, or grazing the box.
        BBoxd inner(box), outer(box);
        inner.expand(-1.5 * dx);
        outer.expand(1.5 * dx);
        double a, b;
        const bool nearMiss = !expect && ray.intersects(outer, a, b);
        if (nearMiss)
            continue;
        if (expect) {
            const Vec3d p = ray(t0);
            int onFaces = 0;  // coordinates within 1.5 voxels of a face
            for (int i = 0; i < 3; ++i)
                onFaces += std::min(std::abs(p[i] - lo[i]), std::abs(p[i] - hi[i])) < 1.5 * dx;
            if (onFaces > 1)
                continue;
        }
        Vec3d xyz, normal;
        double t = 0.0;
        const bool hit = intersector.intersectsWS(ray, xyz, normal, t);
        ASSERT_EQ(hit, expect) << ray;
        if (!hit) {
            ++misses;
            continue;
        }
        ++hits;
        ASSERT_NEAR(t, t0, 0.05 * dx) << ray;
        // The normal of the face that was hit.
        const Vec3d p = ray(t0);
        Vec3d face(0.0);
        for (int i = 0; i < 3; ++i) {
            if (std::abs(p[i] - lo[i]) < 1e-9)
                face[i] = -1.0;
            if (std::abs(p[i] - hi[i]) < 1e-9)
                face[i] = 1.0;
        }
        ASSERT_GT(normal.dot(face), std::cos(2.0 * kDegree)) << ray << " normal " << normal;
    }
    EXPECT_GT(hits, rays / 20);
    EXPECT_GT(misses, rays / 20);
}

TEST(LevelSetRayIntersector, RejectsFogVolumesAndFrustumTransforms) {
    auto fog = FloatGrid::create(0.0f);
    fog->tree().setValue(Coord(0), 1.0f);
    EXPECT_THROW(LevelSetRayIntersector<FloatGrid>{*fog}, ValueError);
    auto sphere = createLevelSetSphere<FloatGrid>(2.0f, Vec3f(0.0f), 0.1f);
    sphere->setTransform(
        math::Transform::createFrustumTransform(BBoxd(Vec3d(-30.0), Vec3d(30.0)), 0.5, 2.0, 0.1));
    EXPECT_THROW(LevelSetRayIntersector<FloatGrid>{*sphere}, ValueError);
}

TEST(LevelSetRayIntersector, HitsAnEllipsoidOfNonCubicVoxelsWithItsNormal) {
    // A sphere of radius r under a scale map (1, 2, 0.7) x dx: index space is unchanged (the
    // hit's index point lies on the sphere as for cubic voxels) and the world surface is the
    // ellipsoid with semi-axes r * (1, 2, 0.7), whose normal at p is p / axes^2.
    const double r = 2.0, dx = 0.1;
    const Vec3d axes(1.0, 2.0, 0.7);
    auto grid = createLevelSetSphere<FloatGrid>(float(r), Vec3f(0.0f), float(dx), 3.0f);
    grid->transform().postScale(axes);
    const LevelSetRayIntersector<FloatGrid> intersector(*grid);
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hits = 0;
    const int rays = test::scaledBatchCount(400);
    for (int n = 0; n < rays; ++n) {
        Vec3d dir(u(rng), u(rng), u(rng));
        if (dir.length() < 0.1)
            continue;
        dir = dir.unit();
        const Vec3d target = Vec3d(u(rng) * axes[0], u(rng) * axes[1], u(rng) * axes[2]) * r;
        Vec3d xyz, normal;
        if (!intersector.intersectsWS(RayD(target - dir * 10.0, dir), xyz, normal))
            continue;
        ++hits;
        const Vec3d ijk(xyz[0] / (dx * axes[0]), xyz[1] / (dx * axes[1]), xyz[2] / (dx * axes[2]));
        ASSERT_NEAR(ijk.length(), r / dx, 0.05) << xyz;
        const Vec3d expected = Vec3d(xyz[0] / (axes[0] * axes[0]), xyz[1] / (axes[1] * axes[1]),
                                     xyz[2] / (axes[2] * axes[2]))
                                   .unit();
        // Two degrees in index space, as for cubic voxels, stretched by at most the ratio of
        // the longest to the shortest axis on the way to world space.
        ASSERT_GT(normal.dot(expected), std::cos(2.0 * (2.0 / 0.7) * kDegree)) << xyz;
    }
    EXPECT_GT(hits, rays / 4);
}

TEST(LevelSetRayIntersector, NormalsOfShearedVoxelsAreSurfaceNormals) {
    // An affine map with shear and rotation: the reported normal must be perpendicular to the
    // surface, measured by the hits of two neighbouring rays (the chords span the tangent plane).
    auto grid = createLevelSetSphere<FloatGrid>(3.0f, Vec3f(0.0f), 0.1f, 3.0f);
    Mat4d m = Mat4d::identity();
    m(0, 0) = 0.1;
    m(1, 0) = 0.05;
    m(1, 1) = 0.12;
    m(2, 2) = 0.08;
    m(2, 1) = -0.03;
    grid->setTransform(math::Transform::createLinearTransform(m));
    grid->transform().postRotate(0.6, math::Axis::X);
    grid->setGridClass(GRID_LEVEL_SET);
    const LevelSetRayIntersector<FloatGrid> intersector(*grid);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hits = 0;
    const int rays = test::scaledBatchCount(200);
    for (int n = 0; n < rays; ++n) {
        Vec3d dir(u(rng), u(rng), u(rng));
        if (dir.length() < 0.1)
            continue;
        dir = dir.unit();
        const Vec3d eye = Vec3d(u(rng), u(rng), u(rng)) * 0.5 - dir * 10.0;
        // Two directions across the ray, for the neighbours.
        const Vec3d side =
            dir.cross(std::abs(dir[0]) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0)).unit();
        const Vec3d side2 = dir.cross(side);
        Vec3d p0, p1, p2, normal, unused;
        const double h = 0.02;  // world units, a fifth of a voxel
        if (!intersector.intersectsWS(RayD(eye, dir), p0, normal) ||
            !intersector.intersectsWS(RayD(eye + side * h, dir), p1, unused) ||
            !intersector.intersectsWS(RayD(eye + side2 * h, dir), p2, unused))
            continue;
        // Grazing rays: the neighbours' hits are far apart; skip them.
        if ((p1 - p0).length() > 4 * h || (p2 - p0).length() > 4 * h)
            continue;
        ++hits;
        const Vec3d chordNormal = (p1 - p0).cross(p2 - p0).unit();
        ASSERT_GT(std::abs(normal.dot(chordNormal)), std::cos(3.0 * kDegree)) << p0;
    }
    EXPECT_GT(hits, rays / 4);
}

TEST(LevelSetRayIntersector, WorksOnBoundedTrees) {
    using GridT = Grid<tree::FixedTree643<float>>;
    auto grid = createLevelSetSphere<GridT>(3.0f, Vec3f(-1.0f, 0.0f, 0.0f), 0.1f);
    const LevelSetRayIntersector<GridT> intersector(*grid);
    double t;
    ASSERT_TRUE(intersector.intersectsWS(RayD(Vec3d(-1.0, 0.0, 10.0), Vec3d(0, 0, -1)), t));
    EXPECT_NEAR(t, 7.0, 0.005);
    ASSERT_TRUE(intersector.intersectsWS(RayD(Vec3d(-10.0, 0.0, 0.0), Vec3d(1, 0, 0)), t));
    EXPECT_NEAR(t, 6.0, 0.005);
}

// ---- Volumes

// A fog volume holding `density` on the voxels of `box`, as tiles where the box covers whole
// nodes and leaves elsewhere.
FloatGrid::Ptr makeFogBox(const CoordBBox& box, float density, double dx) {
    auto grid = FloatGrid::create(0.0f);
    grid->setTransform(math::Transform::createLinearTransform(dx));
    grid->setGridClass(GRID_FOG_VOLUME);
    grid->tree().fill(box, density, true);
    return grid;
}

TEST(VolumeRayIntersector, SpansCoverTheActiveBoxExactly) {
    const CoordBBox box(Coord(-130, -20, -7), Coord(300, 40, 33));
    auto grid = makeFogBox(box, 0.5f, 1.0);
    ASSERT_GT(grid->tree().activeTileCount(), 0u);  // the spans cross tiles
    VolumeRayIntersector<FloatGrid> volume(*grid);
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    // Voxel-centred: voxel v covers [v - 0.5, v + 0.5].
    const BBoxd cover(Vec3d(box.min()) - 0.5, Vec3d(box.max()) + 0.5);
    int tiles = 0;
    for (int n = 0; n < test::scaledBatchCount(500); ++n) {
        Vec3d dir(u(rng), u(rng), u(rng));
        if (dir.length() < 0.1)
            continue;
        const Vec3d target = cover.center() + Vec3d(u(rng) * 250, u(rng) * 40, u(rng) * 30);
        const Vec3d eye = target - dir.unit() * 600.0;
        const RayD ray(eye, dir.unit());
        double a, b;
        const bool expect = ray.intersects(cover, a, b) && b - a > 1e-6;
        if (!volume.setIndexRay(ray)) {
            ASSERT_FALSE(expect) << ray;
            continue;
        }
        typename VolumeRayIntersector<FloatGrid>::Segment s;
        double first = -1, last = -1;
        while (volume.march(s)) {
            if (first < 0)
                first = s.t0;
            else
                ASSERT_NEAR(s.t0, last, 1e-9) << "a gap inside the box";
            last = s.t1;
            if (s.constant) {
                ++tiles;
                ASSERT_EQ(s.value, 0.5f);
                ASSERT_GT(s.level, 0u);
            }
        }
        if (!expect)
            continue;
        ASSERT_NEAR(first, a, 1e-6) << ray;
        ASSERT_NEAR(last, b, 1e-6) << ray;
        // The merged form gives one span.
        ASSERT_TRUE(volume.setIndexRay(ray));
        double t0, t1;
        ASSERT_TRUE(volume.march(t0, t1));
        EXPECT_NEAR(t0, a, 1e-6);
        EXPECT_NEAR(t1, b, 1e-6);
        EXPECT_FALSE(volume.march(t0, t1));
    }
    EXPECT_GT(tiles, 10);
}

}  // namespace
}  // namespace vdb::tools
