// SPDX-License-Identifier: Apache-2.0
// Oracle: the cells whose cubes a ray crosses, found by a slab test against every cell of a box
// around the ray (RayOracle.h).

#include <vdb/math/DDA.h>
#include <vdb/vdb.h>

#include <Oracles.h>
#include <RayOracle.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

namespace vdb::math {
namespace {

using RayD = Ray<double>;
using test::rayCubeOverlap;

// ---- DDA over one lattice

template <Index Log2>
void checkUniformDda(const RayD& ray, double t0, double t1) {
    constexpr Int32 D = Int32(1) << Log2;
    // Oracle: every cell in the box around the segment, slab-tested, ordered by entry time.
    const Vec3d a = ray(t0), b = ray(t1);
    const Coord lo = floorToCoord(Vec3d::minComponent(a, b)).alignedDown(Log2).offsetBy(-D);
    const Coord hi = floorToCoord(Vec3d::maxComponent(a, b)).alignedDown(Log2).offsetBy(D);
    std::map<double, Coord> strict;  // cells crossed for a positive length
    std::set<Coord> touched;         // cells the closed segment touches at all
    for (Int32 x = lo.x(); x <= hi.x(); x += D)
        for (Int32 y = lo.y(); y <= hi.y(); y += D)
            for (Int32 z = lo.z(); z <= hi.z(); z += D) {
                double ta, tb;
                if (!rayCubeOverlap(ray, t0, t1, Coord(x, y, z), D, ta, tb))
                    continue;
                touched.insert(Coord(x, y, z));
                if (rayCubeOverlap(ray, t0, t1, Coord(x, y, z), D, ta, tb, 1e-9) && tb - ta > 1e-9)
                    strict[ta] = Coord(x, y, z);
            }
    DDA<double, Log2> dda(ray, t0, t1);
    std::vector<Coord> walked{dda.voxel()};
    double last = dda.time();
    while (dda.step()) {
        ASSERT_GE(dda.time(), last) << ray;
        last = dda.time();
        walked.push_back(dda.voxel());
    }
    for (const Coord& c : walked)
        EXPECT_TRUE(touched.count(c))
            << "walked a cell the ray does not touch: " << c << ' ' << ray;
    // The positively crossed cells appear in the walk, in order.
    size_t pos = 0;
    for (const auto& [t, c] : strict) {
        while (pos < walked.size() && walked[pos] != c)
            ++pos;
        ASSERT_LT(pos, walked.size()) << "missed or misordered cell " << c << ' ' << ray;
    }
}

TEST(DDA, WalksExactlyTheCellsARayCrossesInOrder) {
    std::mt19937 rng(471);
    std::uniform_real_distribution<double> pos(-40.0, 40.0), dir(-1.0, 1.0);
    const int n = test::scaledBatchCount(300);
    for (int i = 0; i < n; ++i) {
        Vec3d d(dir(rng), dir(rng), dir(rng));
        if (i % 5 == 0)
            d[i % 3] = 0.0;  // parallel to a pair of faces
        if (i % 7 == 0) {
            d = Vec3d(0.0);  // along an axis
            d[i % 3] = i % 2 ? 1.0 : -1.0;
        }
        if (d.length() < 1e-3)
            continue;
        Vec3d eye(pos(rng), pos(rng), pos(rng));
        if (i % 4 == 0)
            eye = Vec3d(std::floor(eye[0]), std::floor(eye[1]) + 0.5, eye[2]);  // on faces
        const RayD ray(eye, d.unit());
        checkUniformDda<0>(ray, 0.0, 30.0);
        checkUniformDda<3>(ray, 0.5, 60.0);
        if (HasFatalFailure())
            return;
    }
}

TEST(DDA, StartsInTheCellHoldingTheStartPoint) {
    const RayD ray(Vec3d(-3.5, 7.25, -0.5), Vec3d(-1, 0, 0));
    DDA<double, 3> dda(ray, 0.0, 100.0);
    EXPECT_EQ(dda.voxel(), Coord(-8, 0, -8));
    EXPECT_DOUBLE_EQ(dda.next(), 4.5);  // x = -8
    ASSERT_TRUE(dda.step());
    EXPECT_EQ(dda.voxel(), Coord(-16, 0, -8));
    EXPECT_DOUBLE_EQ(dda.time(), 4.5);
    EXPECT_DOUBLE_EQ(dda.next(), 12.5);
}

}  // namespace
}  // namespace vdb::math
