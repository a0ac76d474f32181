// SPDX-License-Identifier: Apache-2.0
// Oracle: analytic surfaces. Narrow bands of the exact signed distances to a sphere, a torus, a
// box and two disjoint spheres are sampled voxel by voxel; their measured area and volume must
// be within 0.5% of the closed forms at 256^3 (the box's area within 1%: the smeared delta
// that OpenVDB's measure and ours integrate with averages level sets rounded outside the box's
// edges and sharp inside, which is a bias of first order in the voxel size, about 0.7% here),
// and the Euler characteristic and genus must be those of the shapes (2, 0, 2, 4 and 0, 1, 0)
// from 64^3 up.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/LevelSetMeasure.h>
#include <vdb/tools/LevelSetSphere.h>

#include "ToolboxTestUtil.h"
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace vdb {
namespace {

constexpr double kPi = std::numbers::pi;

struct Shape {
    std::string name;
    test::Sdf sdf;        // voxel units, for a resolution `res` over the unit box
    CoordBBox box;        // voxels to sample
    double area, volume;  // world units, voxel size 1 / res
    int euler;
};

/// The shapes of the test at `res` voxels per unit length (world box [0, 1]^3).
std::vector<Shape> shapes(int res) {
    const double r = res;
    std::vector<Shape> out;
    const CoordBBox all(Coord(-4), Coord(res + 4));
    {
        const double radius = 0.3;
        out.push_back({"sphere", test::sphereSdf(0.5 * r, 0.5 * r, 0.5 * r, radius * r), all,
                       4 * kPi * radius * radius, 4.0 / 3.0 * kPi * radius * radius * radius, 2});
    }
    {
        const double major = 0.3, minor = 0.1;
        out.push_back({"torus", test::torusSdf(0.5 * r, 0.5 * r, 0.5 * r, major * r, minor * r),
                       all, 4 * kPi * kPi * major * minor, 2 * kPi * kPi * major * minor * minor,
                       0});
    }
    {
        const double hx = 0.3, hy = 0.25, hz = 0.2;
        out.push_back({"box", test::boxSdf(0.5 * r, 0.5 * r, 0.5 * r, hx * r, hy * r, hz * r), all,
                       8 * (hx * hy + hy * hz + hx * hz), 8 * hx * hy * hz, 2});
    }
    {
        const double radius = 0.18;
        const auto a = test::sphereSdf(0.27 * r, 0.5 * r, 0.5 * r, radius * r);
        const auto b = test::sphereSdf(0.73 * r, 0.5 * r, 0.5 * r, radius * r);
        out.push_back(
            {"two spheres",
             [a, b](double x, double y, double z) { return std::min(a(x, y, z), b(x, y, z)); }, all,
             2 * 4 * kPi * radius * radius, 2 * 4.0 / 3.0 * kPi * radius * radius * radius, 4});
    }
    return out;
}

TEST(LevelSetMeasure, AreaAndVolumeWithinHalfAPercentAt256) {
    const int res = 256;
    for (const Shape& s : shapes(res)) {
        auto grid = test::levelSetFromSdf(s.sdf, s.box, 1.0 / res);
        tools::LevelSetMeasure<FloatGrid> m(*grid);
        EXPECT_NEAR(m.area(), s.area, (s.name == "box" ? 0.01 : 0.005) * s.area) << s.name;
        EXPECT_NEAR(m.volume(), s.volume, 0.005 * s.volume) << s.name;
        // Voxel units: the same numbers scaled by powers of the resolution.
        EXPECT_NEAR(m.area(false), m.area() * res * res, 1e-9 * m.area(false)) << s.name;
        EXPECT_NEAR(m.volume(false), m.volume() * res * res * res, 1e-9 * m.volume(false));
        EXPECT_NEAR(tools::levelSetArea(*grid), m.area(), 1e-12 * m.area());
        EXPECT_NEAR(tools::levelSetVolume(*grid), m.volume(), 1e-12 * m.volume());
    }
}

TEST(LevelSetMeasure, EulerCharacteristicAndGenusOfTheShapes) {
    for (int res : {64, 128}) {
        for (const Shape& s : shapes(res)) {
            auto grid = test::levelSetFromSdf(s.sdf, s.box, 1.0 / res);
            EXPECT_EQ(tools::levelSetEulerCharacteristic(*grid), s.euler) << s.name << " " << res;
            if (s.name != "two spheres") {
                EXPECT_EQ(tools::levelSetGenus(*grid), 1 - s.euler / 2) << s.name << " " << res;
            }
        }
    }
}

TEST(LevelSetMeasure, CurvaturesOfASphere) {
    const double radius = 0.75, dx = 0.02;
    auto sphere = tools::createLevelSetSphere<FloatGrid>(radius, Vec3d(0.1, 0.2, -0.3), dx);
    tools::LevelSetMeasure<FloatGrid> m(*sphere);
    EXPECT_NEAR(m.avgMeanCurvature(), 1.0 / radius, 0.01 / radius);
    EXPECT_NEAR(m.totMeanCurvature(), 4 * kPi * radius, 0.01 * 4 * kPi * radius);
    EXPECT_NEAR(m.totMeanCurvature(false) * dx, m.totMeanCurvature(), 1e-6 * m.totMeanCurvature());
    EXPECT_NEAR(m.totGaussianCurvature(), 4 * kPi, 0.01 * 4 * kPi);
    EXPECT_NEAR(m.avgGaussianCurvature(), 1.0 / (radius * radius), 0.02 / (radius * radius));
    EXPECT_EQ(m.eulerCharacteristic(), 2);
    EXPECT_EQ(m.genus(), 0);
    // Serial and threaded sums are identical.
    m.setGrainSize(0);
    m.init(*sphere);
    const double serial = m.area();
    EXPECT_EQ(serial, tools::levelSetArea(*sphere));
}

TEST(LevelSetMeasure, RefusesWhatIsNotAMeasurableLevelSet) {
    auto vectors = Vec3SGrid::create();
    vectors->setName("velocity");
    try {
        tools::levelSetArea(*vectors);
        FAIL() << "expected TypeError";
    } catch (const TypeError& e) {
        EXPECT_NE(std::string(e.what()).find("vec3s"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("velocity"), std::string::npos) << e.what();
    }
    EXPECT_THROW(tools::levelSetGenus(*Int32Grid::create()), TypeError);
    auto empty = FloatGrid::create(0.3f);
    empty->setGridClass(GRID_LEVEL_SET);
    EXPECT_THROW(tools::levelSetVolume(*empty), ValueError);
    auto fog = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.1f);
    fog->setGridClass(GRID_FOG_VOLUME);
    EXPECT_THROW(tools::levelSetArea(*fog), ValueError);
    auto stretched = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.1f);
    stretched->transform().preScale(Vec3d(1.0, 2.0, 1.0));
    EXPECT_THROW(tools::levelSetArea(*stretched), ValueError);
}

TEST(LevelSetMeasure, SmearedHeavisideVolumeOfASphere) {
    const double radius = 0.5, dx = 0.01;
    auto sphere = tools::createLevelSetSphere<FloatGrid>(radius, Vec3d(0.0), dx, 5.0);
    const double exact = 4.0 / 3.0 * kPi * radius * radius * radius;
    EXPECT_NEAR(tools::smearedHeavisideVolume(*sphere), exact, 1e-3 * exact);
    EXPECT_EQ(tools::smearedHeavisideVolume(*sphere, 1.5, false),
              tools::smearedHeavisideVolume(*sphere, 1.5, true));
}

}  // namespace
}  // namespace vdb
