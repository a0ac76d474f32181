// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic hit times for axis-aligned rays, and dense sampling of points along random
// rays tested for box membership one by one (no slab arithmetic).

#include <vdb/math/Ray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

namespace vdb::math {
namespace {

using RayD = Ray<double>;

TEST(Ray, DefaultsStartJustAfterEyeAndNeverEnd) {
    const RayD ray;
    EXPECT_EQ(ray.eye(), Vec3d(0.0));
    EXPECT_EQ(ray.dir(), Vec3d(1, 0, 0));
    EXPECT_EQ(ray.t0(), Delta<double>::value());
    EXPECT_EQ(ray.t1(), std::numeric_limits<double>::max());
    EXPECT_TRUE(ray.valid());
    EXPECT_FALSE(ray.test(0.0));
    EXPECT_TRUE(ray.test(1e300));
}

TEST(Ray, PointAtTimeIsEyePlusTimeTimesDirection) {
    const RayD ray(Vec3d(1, 2, 3), Vec3d(0, -2, 0.5), 1.0, 4.0);
    EXPECT_EQ(ray(0.0), Vec3d(1, 2, 3));
    EXPECT_EQ(ray(2.0), Vec3d(1, -2, 4));
    EXPECT_EQ(ray.start(), ray(1.0));
    EXPECT_EQ(ray.end(), ray(4.0));
    EXPECT_EQ(ray.invDir()[1], -0.5);
    EXPECT_EQ(ray.invDir()[0], std::numeric_limits<double>::infinity());
    EXPECT_EQ(ray.dir(), Vec3d(0, -2, 0.5));  // not normalized

    RayD moved = ray;
    moved.setDir(Vec3d(4, 0, 0));
    EXPECT_EQ(moved.invDir()[0], 0.25);
    moved.setEye(Vec3d(0.0));
    moved.setTimes(0, 2);
    EXPECT_EQ(moved.end(), Vec3d(8, 0, 0));
    moved.setMinTime(1);
    moved.setMaxTime(1.5);
    EXPECT_EQ(moved.start(), Vec3d(4, 0, 0));
    EXPECT_FALSE(moved.valid(1.0));
    moved.reset(Vec3d(1), Vec3d(0, 0, 1));
    EXPECT_EQ(moved.start(), Vec3d(1, 1, 1 + Delta<double>::value()));
}

TEST(Ray, AxisAlignedRayHitsUnitBoxAtAnalyticTimes) {
    const BBoxd box(Vec3d(-1), Vec3d(1));
    double t0 = 0, t1 = 0;
    EXPECT_TRUE(RayD(Vec3d(0, 0, -10), Vec3d(0, 0, 1)).intersects(box, t0, t1));
    EXPECT_EQ(t0, 9.0);
    EXPECT_EQ(t1, 11.0);
    // Half-speed direction doubles the times.
    EXPECT_TRUE(RayD(Vec3d(0, 0, -10), Vec3d(0, 0, 0.5)).intersects(box, t0, t1));
    EXPECT_EQ(t0, 18.0);
    EXPECT_EQ(t1, 22.0);
    // From inside, entry is clamped to the ray's own start.
    EXPECT_TRUE(RayD(Vec3d(0.0), Vec3d(-1, 0, 0), 0.0).intersects(box, t0, t1));
    EXPECT_EQ(t0, 0.0);
    EXPECT_EQ(t1, 1.0);
    // Boxes behind the eye or past t1 are missed.
    EXPECT_FALSE(RayD(Vec3d(0, 0, 5), Vec3d(0, 0, 1)).intersects(box));
    EXPECT_FALSE(RayD(Vec3d(0, 0, -10), Vec3d(0, 0, 1), 0.0, 8.9).intersects(box));
    // Crossing the top face diagonally, inside the face's plane.
    EXPECT_TRUE(RayD(Vec3d(-2, -2, 1), Vec3d(1, 1, 0)).intersects(box, t0, t1));
    EXPECT_EQ(t0, 1.0);
    EXPECT_EQ(t1, 3.0);
    // Grazing the corner (-1, 1, 1) touches at one time.
    EXPECT_TRUE(RayD(Vec3d(-2, 0, 1), Vec3d(1, 1, 0)).intersects(box, t0, t1));
    EXPECT_EQ(t0, 1.0);
    EXPECT_EQ(t1, 1.0);
}

TEST(Ray, NearMissOfAnEdgeIsAMiss) {
    // Crosses the plane x = 0 at y = 1 + 1e-4, just above the edge x = 0, y = 1 of the box.
    const BBoxd box(Vec3d(0), Vec3d(1));
    EXPECT_FALSE(RayD(Vec3d(-1, 1e-4, 0.5), Vec3d(1, 1, 0).unit()).intersects(box));
    EXPECT_TRUE(RayD(Vec3d(-1, -1e-4, 0.5), Vec3d(1, 1, 0).unit()).intersects(box));
}

TEST(Ray, RayInsideAFacePlaneCountsAsInside) {
    const BBoxd box(Vec3d(0), Vec3d(1));
    double t0 = 0, t1 = 0;
    // Parallel to x = 0 and lying in it: 0 * infinity is NaN, which must not reject.
    EXPECT_TRUE(RayD(Vec3d(0, 0.5, -1), Vec3d(0, 0, 1)).intersects(box, t0, t1));
    EXPECT_EQ(t0, 1.0);
    EXPECT_EQ(t1, 2.0);
    EXPECT_TRUE(RayD(Vec3d(1, 1, -1), Vec3d(0, 0, 1)).intersects(box));
    // Parallel and just outside.
    EXPECT_FALSE(RayD(Vec3d(-1e-12, 0.5, -1), Vec3d(0, 0, 1)).intersects(box));
    EXPECT_FALSE(RayD(Vec3d(0.5, 1 + 1e-12, -1), Vec3d(0, 0, -1)).intersects(box));
    // A negative zero direction component behaves like a positive one.
    EXPECT_TRUE(RayD(Vec3d(0.5, 0.5, -1), Vec3d(-0.0, 0, 1)).intersects(box));
}

// Random rays against random boxes. The oracle walks the ray in small steps and records where
// the sampled points are inside the box, so it shares no arithmetic with the slab test.
TEST(Ray, SlabTestMatchesBruteForceSampling) {
    std::mt19937 rng(20130601);
    std::uniform_real_distribution<double> coord(-4.0, 4.0), unit(0.0, 1.0);
    std::uniform_int_distribution<int> flat(0, 5);
    constexpr int kSamples = 4000;
    constexpr double kTMax = 20.0;
    int hits = 0, misses = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        Vec3d lo(coord(rng), coord(rng), coord(rng)),
            hi = lo + Vec3d(unit(rng), unit(rng), unit(rng)) * 3.0;
        const BBoxd box(lo, hi);
        // Half the rays aim at a point of the box, half go anywhere; then half of all rays
        // are made parallel to a slab.
        const Vec3d eye = Vec3d(coord(rng), coord(rng), coord(rng)) * 2.0;
        Vec3d dir = unit(rng) < 0.5 ? lo + Vec3d(unit(rng), unit(rng), unit(rng)) * (hi - lo) - eye
                                    : Vec3d(coord(rng), coord(rng), coord(rng));
        const int zeroAxis = flat(rng);
        if (zeroAxis < 3)
            dir[size_t(zeroAxis)] = 0;
        if (dir.lengthSqr() < 1e-6)
            continue;
        dir = dir.unit();
        const double t0 = unit(rng) * 2.0, t1 = t0 + unit(rng) * kTMax;
        const RayD ray(eye, dir, t0, t1);

        const double step = (t1 - t0) / kSamples;
        double first = std::numeric_limits<double>::infinity(), last = -first;
        for (int n = 0; n <= kSamples; ++n) {
            const double t = t0 + n * step;
            if (box.isInside(ray(t))) {
                first = std::min(first, t);
                last = std::max(last, t);
            }
        }
        double a = 0, b = 0;
        const bool hit = ray.intersects(box, a, b);
        if (first <= last) {
            // A sampled point inside means a hit, spanning at least the sampled inside part.
            ASSERT_TRUE(hit) << ray << " box " << box;
            ASSERT_LE(a, first + 1e-12) << ray << " box " << box;
            ASSERT_GE(b, last - 1e-12) << ray << " box " << box;
            ASSERT_GE(a, first - step - 1e-12) << ray << " box " << box;
            ASSERT_LE(b, last + step + 1e-12) << ray << " box " << box;
            ++hits;
        } else if (hit) {
            // A hit that no sample saw must be shorter than one step.
            ASSERT_LE(b - a, step + 1e-12) << ray << " box " << box;
        } else {
            ++misses;
        }
        if (hit) {
            ASSERT_LE(t0, a);
            ASSERT_LE(a, b);
            ASSERT_LE(b, t1);
            BBoxd padded = box;
            padded.expand(1e-9);
            ASSERT_TRUE(padded.isInside(ray(a)) && padded.isInside(ray(b))) << ray << " " << box;
        }
    }
    EXPECT_GT(hits, 100);  // the sample covers both outcomes
    EXPECT_GT(misses, 100);
}

TEST(Ray, ClipShrinksTimeSpanToTheBoxOrLeavesMissesUnchanged) {
    RayD ray(Vec3d(0, 0, -10), Vec3d(0, 0, 1));
    EXPECT_TRUE(ray.clip(BBoxd(Vec3d(-1), Vec3d(1))));
    EXPECT_EQ(ray.t0(), 9.0);
    EXPECT_EQ(ray.t1(), 11.0);
    const RayD before = ray;
    EXPECT_FALSE(ray.clip(BBoxd(Vec3d(5), Vec3d(6))));
    EXPECT_EQ(ray.t0(), before.t0());
    EXPECT_EQ(ray.t1(), before.t1());
}

TEST(Ray, WorldToIndexMapsEveryPointAndKeepsTimesConsistent) {
    Transform xform;
    xform.preScale(Vec3d(0.5, 0.25, 2));
    xform.postRotate(0.7, Axis::Y);
    xform.postTranslate(Vec3d(3, -1, 2));
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> coord(-5.0, 5.0), time(0.0, 10.0);
    for (int n = 0; n < 200; ++n) {
        const Vec3d dir(coord(rng), coord(rng), coord(rng));
        const double t0 = time(rng), t1 = t0 + time(rng);
        const RayD world(Vec3d(coord(rng), coord(rng), coord(rng)), dir, t0, t1);
        const RayD index = world.worldToIndex(xform);
        ASSERT_NEAR(index.dir().length(), 1.0, 1e-14);
        // Same points at the ends, and every world time has an index time naming its image.
        ASSERT_TRUE(isApproxEqual(index.start(), xform.worldToIndex(world.start()), 1e-9));
        ASSERT_TRUE(isApproxEqual(index.end(), xform.worldToIndex(world.end()), 1e-9));
        const double scale = (index.t1() - index.t0()) / (t1 - t0);
        for (double t : {t0, 0.5 * (t0 + t1), t1}) {
            ASSERT_TRUE(isApproxEqual(index(t * scale), xform.worldToIndex(world(t)), 1e-9));
        }
        // Back to world: the same ray up to normalizing the direction.
        const RayD back = index.indexToWorld(xform);
        ASSERT_TRUE(isApproxEqual(back.eye(), world.eye(), 1e-9));
        ASSERT_TRUE(isApproxEqual(back.dir(), dir.unit(), 1e-12));
        ASSERT_TRUE(isApproxEqual(back.start(), world.start(), 1e-9));
        ASSERT_TRUE(isApproxEqual(back.end(), world.end(), 1e-9));
    }
}

TEST(Ray, HitsAgreeBetweenWorldAndIndexSpace) {
    const Transform::Ptr xform = Transform::createLinearTransform(0.1);
    xform->postTranslate(Vec3d(1, 2, 3));
    const BBoxd indexBox(Vec3d(-5, 0, 10), Vec3d(20, 30, 40));
    const BBoxd worldBox = xform->indexToWorld(indexBox);
    const RayD world(Vec3d(0, 2.5, 5), Vec3d(1, 0.2, -0.1).unit(), 0.0, 100.0);
    const RayD index = world.worldToIndex(*xform);
    double wa = 0, wb = 0, ia = 0, ib = 0;
    ASSERT_TRUE(world.intersects(worldBox, wa, wb));
    ASSERT_TRUE(index.intersects(indexBox, ia, ib));
    EXPECT_NEAR(ia, wa * 10.0, 1e-9);  // one world unit is ten voxels
    EXPECT_NEAR(ib, wb * 10.0, 1e-9);
}

TEST(Ray, UnboundedRayStaysUnboundedInIndexSpace) {
    const Transform::Ptr xform = Transform::createLinearTransform(0.01);
    const RayD world(Vec3d(0.0), Vec3d(1, 0, 0));
    const RayD index = world.worldToIndex(*xform);
    EXPECT_EQ(index.t1(), std::numeric_limits<double>::max());
    EXPECT_NEAR(index.t0(), Delta<double>::value() * 100.0, 1e-20);
    // Shrinking times (large voxels) must not turn "unbounded" into a finite end either.
    const RayD coarse = world.worldToIndex(*Transform::createLinearTransform(100.0));
    EXPECT_EQ(coarse.t1(), std::numeric_limits<double>::max());
    EXPECT_EQ(coarse.indexToWorld(*Transform::createLinearTransform(100.0)).t1(),
              std::numeric_limits<double>::max());
    const Ray<float> fworld(Vec3s(0.f), Vec3s(0, 1, 0), 0.f, 3e38f);
    EXPECT_EQ(fworld.worldToIndex(*xform).t1(), std::numeric_limits<float>::max());  // clamped
}

TEST(Ray, FrustumTransformsAreRejected) {
    const Transform::Ptr frustum =
        Transform::createFrustumTransform(BBoxd(Vec3d(0), Vec3d(8)), 0.5, 1.0);
    try {
        (void)RayD().worldToIndex(*frustum);
        FAIL() << "expected ValueError";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("frustum transforms are not supported"),
                  std::string::npos);
    }
    EXPECT_THROW((void)RayD().indexToWorld(*frustum), ValueError);
}

TEST(Ray, FloatRaysIntersectAndStream) {
    const Ray<float> ray(Vec3s(0, 0, -2), Vec3s(0, 0, 1));
    float t0 = 0, t1 = 0;
    EXPECT_TRUE(ray.intersects(BBoxs(Vec3s(-1), Vec3s(1)), t0, t1));
    EXPECT_EQ(t0, 1.f);
    EXPECT_EQ(t1, 3.f);
    std::ostringstream os;
    os << RayD(Vec3d(0.0), Vec3d(2, 0, 0), 1, 2);
    EXPECT_EQ(os.str(), "eye=[0, 0, 0] dir=[2, 0, 0] 1/dir=[0.5, inf, inf] t0=1 t1=2");
}

}  // namespace
}  // namespace vdb::math
