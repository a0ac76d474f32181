// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10's tools::Filter and tools::LevelSetFilter. The same grids (a sampled
// density, a vector field and level set spheres) go through every filter of both libraries,
// with and without an alpha mask; the results must have the same active voxels and values
// within 1e-4 (for level sets in voxel units: values over the voxel size).

#include <vdb/Grid.h>
#include <vdb/tools/Filter.h>
#include <vdb/tools/LevelSetFilter.h>

#include "ToolboxCompat.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Filter.h>
#include <openvdb/tools/LevelSetFilter.h>

#include <cmath>
#include <functional>
#include <string>

namespace vdb {
namespace {

using test::sameActiveValues;

test::FloatPair density() {
    return test::sampledPair<test::FloatPair>(
        CoordBBox(Coord(-14), Coord(13)), Vec3d(0.1), Vec3d(0.3, 0.0, -0.2),
        [](const Vec3d& q) { return float(std::exp(-q.lengthSqr()) + 0.2 * std::sin(7 * q[0])); },
        0.0f);
}

/// An alpha mask in both libraries: a ramp along x on a coarser grid (sampled in world space).
test::FloatPair alphaMask() {
    return test::sampledPair<test::FloatPair>(
        CoordBBox(Coord(-10), Coord(10)), Vec3d(0.2), Vec3d(0.0),
        [](const Vec3d& q) { return float(q[0]); }, 0.0f);
}

TEST(FilterCompat, DensityFiltersMatchOpenVdb) {
    struct Case {
        std::string name;
        std::function<void(tools::Filter<FloatGrid>&, const FloatGrid*)> ours;
        std::function<void(openvdb::tools::Filter<openvdb::FloatGrid>&, const openvdb::FloatGrid*)>
            theirs;
    };
    const Case cases[] = {
        {"mean", [](auto& f, auto m) { f.mean(1, 2, m); },
         [](auto& f, auto m) { f.mean(1, 2, m); }},
        {"mean3", [](auto& f, auto m) { f.mean(3, 1, m); },
         [](auto& f, auto m) { f.mean(3, 1, m); }},
        {"gaussian", [](auto& f, auto m) { f.gaussian(2, 1, m); },
         [](auto& f, auto m) { f.gaussian(2, 1, m); }},
        {"median", [](auto& f, auto m) { f.median(1, 2, m); },
         [](auto& f, auto m) { f.median(1, 2, m); }},
        {"offset", [](auto& f, auto m) { f.offset(0.25f, m); },
         [](auto& f, auto m) { f.offset(0.25f, m); }},
    };
    const auto mask = alphaMask();
    for (const Case& c : cases) {
        for (const bool masked : {false, true}) {
            auto p = density();
            tools::Filter<FloatGrid> ours(*p.ours);
            openvdb::tools::Filter<openvdb::FloatGrid> theirs(*p.theirs);
            ours.setMaskRange(-0.5f, 1.0f);
            theirs.setMaskRange(-0.5f, 1.0f);
            c.ours(ours, masked ? mask.ours.get() : nullptr);
            c.theirs(theirs, masked ? mask.theirs.get() : nullptr);
            EXPECT_TRUE(sameActiveValues(*p.ours, *p.theirs, 1e-5))
                << c.name << (masked ? " masked" : "");
        }
    }
}

TEST(FilterCompat, VectorMeanMatchesOpenVdb) {
    auto p = test::sampledPair<test::Vec3SPair>(
        CoordBBox(Coord(-10), Coord(9)), Vec3d(0.1), Vec3d(0.0),
        [](const Vec3d& q) {
            return Vec3s(float(q[1]), float(q[0] * q[2]), float(std::cos(5 * q[0])));
        },
        Vec3s(0.0f));
    tools::Filter<Vec3SGrid> ours(*p.ours);
    openvdb::tools::Filter<openvdb::Vec3SGrid> theirs(*p.theirs);
    ours.gaussian(1, 2);
    theirs.gaussian(1, 2);
    EXPECT_TRUE(sameActiveValues(*p.ours, *p.theirs, 1e-5));
}

TEST(FilterCompat, LevelSetFiltersMatchOpenVdb) {
    const float dx = 0.05f;
    struct Case {
        std::string name;
        std::function<void(tools::LevelSetFilter<FloatGrid>&, const FloatGrid*)> ours;
        std::function<void(openvdb::tools::LevelSetFilter<openvdb::FloatGrid>&,
                           const openvdb::FloatGrid*)>
            theirs;
    };
    const Case cases[] = {
        {"mean", [](auto& f, auto m) { f.mean(1, m); }, [](auto& f, auto m) { f.mean(1, m); }},
        {"gaussian", [](auto& f, auto m) { f.gaussian(1, m); },
         [](auto& f, auto m) { f.gaussian(1, m); }},
        {"median", [](auto& f, auto m) { f.median(1, m); },
         [](auto& f, auto m) { f.median(1, m); }},
        {"meanCurvature", [](auto& f, auto m) { f.meanCurvature(m); },
         [](auto& f, auto m) { f.meanCurvature(m); }},
        {"laplacian", [](auto& f, auto m) { f.laplacian(m); },
         [](auto& f, auto m) { f.laplacian(m); }},
        {"offset", [](auto& f, auto m) { f.offset(0.07f, m); },
         [](auto& f, auto m) { f.offset(0.07f, m); }},
        {"erode", [](auto& f, auto m) { f.offset(-0.04f, m); },
         [](auto& f, auto m) { f.offset(-0.04f, m); }},
    };
    const auto mask = alphaMask();
    for (const Case& c : cases) {
        for (const bool masked : {false, true}) {
            // A sphere with a bump, so that smoothing changes it.
            auto p = test::spheres(0.8f, Vec3f(0.02f, -0.03f, 0.01f), dx);
            p.ours->tree().setValue(Coord(16, 0, 0), 0.0f);
            p.theirs->tree().setValue(openvdb::Coord(16, 0, 0), 0.0f);
            tools::LevelSetFilter<FloatGrid> ours(*p.ours);
            openvdb::tools::LevelSetFilter<openvdb::FloatGrid> theirs(*p.theirs);
            c.ours(ours, masked ? mask.ours.get() : nullptr);
            c.theirs(theirs, masked ? mask.theirs.get() : nullptr);
            EXPECT_TRUE(sameActiveValues(*p.ours, *p.theirs, 1e-4, 1.0 / dx))
                << c.name << (masked ? " masked" : "");
        }
    }
}

}  // namespace
}  // namespace vdb
