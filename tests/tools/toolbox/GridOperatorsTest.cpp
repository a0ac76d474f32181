// SPDX-License-Identifier: Apache-2.0
// Oracle: analytic derivatives. Fields are sampled voxel by voxel at the world positions of the
// voxel centres under uniform, non-uniform and rotated transforms; the operators must return
// the exact derivatives of linear and quadratic fields (second-order central differences are
// exact there), and errors that shrink four-fold when the voxel size halves for smooth fields.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/GridOperators.h>
#include <vdb/tools/LevelSetSphere.h>

#include "ToolboxTestUtil.h"
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

namespace vdb {
namespace {

using test::forEachVoxel;
using test::sampleField;

const CoordBBox kBox(Coord(-12, -10, -8), Coord(11, 9, 13));
// Voxels at least two voxels inside the sampled box: every stencil point was sampled.
const CoordBBox kInterior(kBox.min().offsetBy(2), kBox.max().offsetBy(-2));

math::Transform::Ptr uniformXform() {
    auto x = math::Transform::createLinearTransform(0.25);
    x->postTranslate(Vec3d(1.5, -2.0, 0.75));
    return x;
}
math::Transform::Ptr scaledXform() {
    auto x = math::Transform::createLinearTransform(1.0);
    x->preScale(Vec3d(0.5, 0.25, 0.125));
    x->postTranslate(Vec3d(-1.0, 3.0, 2.0));
    return x;
}
math::Transform::Ptr affineXform() {
    auto x = math::Transform::createLinearTransform(0.2);
    x->postRotate(0.4, math::Axis::Z);
    x->postRotate(-0.3, math::Axis::X);
    x->preScale(Vec3d(1.0, 1.5, 0.75));
    x->postTranslate(Vec3d(0.5, 0.25, -1.0));
    return x;
}

class GridOperatorsTransforms : public ::testing::TestWithParam<int> {
protected:
    math::Transform::Ptr xform() const {
        return GetParam() == 0 ? uniformXform() : GetParam() == 1 ? scaledXform() : affineXform();
    }
};
INSTANTIATE_TEST_SUITE_P(Maps, GridOperatorsTransforms, ::testing::Values(0, 1, 2));

// f = 3x - 2y + 0.5z + xy + 2z^2: gradient (3 + y, -2 + x, 0.5 + 4z), Laplacian 4.
double quadratic(const Vec3d& p) {
    return 3 * p[0] - 2 * p[1] + 0.5 * p[2] + p[0] * p[1] + 2 * p[2] * p[2];
}

TEST_P(GridOperatorsTransforms, GradientOfQuadraticIsExactInWorldUnits) {
    const auto x = xform();
    auto grid = sampleField<DoubleGrid>(kBox, x, quadratic);
    auto g = tools::gradient(*grid);
    EXPECT_EQ(g->getVectorType(), VEC_COVARIANT);
    EXPECT_EQ(g->activeVoxelCount(), grid->activeVoxelCount());
    auto acc = g->getConstAccessor();
    forEachVoxel(kInterior, [&](const Coord& ijk) {
        const Vec3d p = x->indexToWorld(ijk);
        const Vec3d expected(3 + p[1], -2 + p[0], 0.5 + 4 * p[2]);
        const Vec3d got = acc.getValue(ijk);
        ASSERT_NEAR(got[0], expected[0], 1e-9) << ijk;
        ASSERT_NEAR(got[1], expected[1], 1e-9) << ijk;
        ASSERT_NEAR(got[2], expected[2], 1e-9) << ijk;
    });
}

TEST_P(GridOperatorsTransforms, LaplacianOfQuadraticIsExact) {
    const auto x = xform();
    auto grid = sampleField<DoubleGrid>(kBox, x, quadratic);
    auto lap = tools::laplacian(*grid);
    auto acc = lap->getConstAccessor();
    forEachVoxel(kInterior,
                 [&](const Coord& ijk) { ASSERT_NEAR(acc.getValue(ijk), 4.0, 1e-8) << ijk; });
}

TEST_P(GridOperatorsTransforms, DivergenceAndCurlOfLinearFieldsAreExact) {
    const auto x = xform();
    // A source x (divergence 3, no curl) plus a rotation w x p (curl 2w, no divergence).
    const Vec3d w(0.3, -1.2, 0.7);
    auto grid = sampleField<Vec3DGrid>(kBox, x, [&](const Vec3d& p) { return p + w.cross(p); });
    auto div = tools::divergence(*grid);
    auto curl = tools::curl(*grid);
    EXPECT_EQ(curl->getVectorType(), VEC_COVARIANT);
    auto dacc = div->getConstAccessor();
    auto cacc = curl->getConstAccessor();
    forEachVoxel(kInterior, [&](const Coord& ijk) {
        ASSERT_NEAR(dacc.getValue(ijk), 3.0, 1e-9) << ijk;
        const Vec3d c = cacc.getValue(ijk);
        ASSERT_NEAR(c[0], 2 * w[0], 1e-9) << ijk;
        ASSERT_NEAR(c[1], 2 * w[1], 1e-9) << ijk;
        ASSERT_NEAR(c[2], 2 * w[2], 1e-9) << ijk;
    });
}

TEST_P(GridOperatorsTransforms, MeanCurvatureOfSphereDistanceIsOneOverRadius) {
    const auto x = xform();
    // Distance to a sphere of radius 2 around c: H = 1/r on each level set r.
    const Vec3d c = x->indexToWorld(Vec3d(0.5, -0.25, 2.0));
    auto grid =
        sampleField<DoubleGrid>(kBox, x, [&](const Vec3d& p) { return (p - c).length() - 2.0; });
    auto h = tools::meanCurvature(*grid);
    auto acc = h->getConstAccessor();
    const double minVoxel = std::min({x->voxelSize()[0], x->voxelSize()[1], x->voxelSize()[2]});
    const double maxVoxel = std::max({x->voxelSize()[0], x->voxelSize()[1], x->voxelSize()[2]});
    int checked = 0;
    forEachVoxel(kInterior, [&](const Coord& ijk) {
        const double r = (x->indexToWorld(ijk) - c).length();
        if (r < 8 * maxVoxel || r < 1.0)
            return;  // too close to the centre for second-order differences
        ++checked;
        // Second-order error: about (h / r)^2 relative.
        ASSERT_NEAR(acc.getValue(ijk) * r, 1.0, 0.5 * std::pow(maxVoxel / r, 2) + 1e-6)
            << ijk << " r " << r;
    });
    EXPECT_GT(checked, 100);
    (void)minVoxel;
}

// Second-order convergence on a trigonometric field: the largest error over the same world
// region must drop by about 4 when the voxel size halves.
TEST(GridOperators, ErrorsOfSmoothFieldsShrinkAtSecondOrder) {
    const double k = 1.3;
    const auto f = [k](const Vec3d& p) {
        return std::sin(k * p[0]) * std::cos(k * p[1]) * std::sin(k * p[2] + 0.4);
    };
    const auto grad = [k](const Vec3d& p) {
        return Vec3d(k * std::cos(k * p[0]) * std::cos(k * p[1]) * std::sin(k * p[2] + 0.4),
                     -k * std::sin(k * p[0]) * std::sin(k * p[1]) * std::sin(k * p[2] + 0.4),
                     k * std::sin(k * p[0]) * std::cos(k * p[1]) * std::cos(k * p[2] + 0.4));
    };
    double gradErr[2], lapErr[2];
    for (int level = 0; level < 2; ++level) {
        const double dx = 0.1 / (1 << level);
        const int n = 10 << level;  // the world box [-1, 1]^3
        auto x = math::Transform::createLinearTransform(dx);
        const CoordBBox box(Coord(-n - 2), Coord(n + 2));
        auto grid = sampleField<DoubleGrid>(box, x, f);
        auto g = tools::gradient(*grid);
        auto lap = tools::laplacian(*grid);
        auto gacc = g->getConstAccessor();
        auto lacc = lap->getConstAccessor();
        gradErr[level] = lapErr[level] = 0.0;
        forEachVoxel(CoordBBox(Coord(-n), Coord(n)), [&](const Coord& ijk) {
            const Vec3d p = x->indexToWorld(ijk);
            gradErr[level] = std::max(gradErr[level], (gacc.getValue(ijk) - grad(p)).length());
            lapErr[level] =
                std::max(lapErr[level], std::abs(lacc.getValue(ijk) + 3 * k * k * f(p)));
        });
    }
    EXPECT_GT(gradErr[0] / gradErr[1], 3.5);
    EXPECT_LT(gradErr[0] / gradErr[1], 4.5);
    EXPECT_GT(lapErr[0] / lapErr[1], 3.5);
    EXPECT_LT(lapErr[0] / lapErr[1], 4.5);
}

// The same under a non-uniform scale and a translation, for every differential operator:
// gradient and Laplacian of a trigonometric field, divergence and curl of a trigonometric
// vector field, and the mean curvature of the distance to a point outside the region (its
// level sets are spheres: H = 1/r). The largest world-unit error over the world box
// [-1, 1]^3 must drop by about 4 when the voxel size halves.
TEST(GridOperators, ErrorsShrinkAtSecondOrderUnderScaleAndTranslation) {
    const double k = 1.1;
    const Vec3d scale(1.0, 0.75, 1.25), shift(0.3, -0.2, 0.1), c(3.0, 0.5, -0.5);
    const auto f = [k](const Vec3d& p) {
        return std::sin(k * p[0]) * std::cos(k * p[1]) + std::sin(k * p[2]);
    };
    const auto grad = [k](const Vec3d& p) {
        return Vec3d(k * std::cos(k * p[0]) * std::cos(k * p[1]),
                     -k * std::sin(k * p[0]) * std::sin(k * p[1]), k * std::cos(k * p[2]));
    };
    const auto lap = [k](const Vec3d& p) {
        return -2 * k * k * std::sin(k * p[0]) * std::cos(k * p[1]) - k * k * std::sin(k * p[2]);
    };
    // u = (sin kx cos ky, sin kz, cos kx sin ky).
    const auto u = [k](const Vec3d& p) {
        return Vec3d(std::sin(k * p[0]) * std::cos(k * p[1]), std::sin(k * p[2]),
                     std::cos(k * p[0]) * std::sin(k * p[1]));
    };
    const auto div = [k](const Vec3d& p) { return k * std::cos(k * p[0]) * std::cos(k * p[1]); };
    const auto curl = [k](const Vec3d& p) {
        const double s = k * std::sin(k * p[0]) * std::sin(k * p[1]);
        return Vec3d(k * std::cos(k * p[0]) * std::cos(k * p[1]) - k * std::cos(k * p[2]), s, s);
    };
    const auto dist = [c](const Vec3d& p) { return (p - c).length(); };
    double err[5][2];
    for (int level = 0; level < 2; ++level) {
        const double dx = 0.1 / (1 << level);
        auto x = math::Transform::createLinearTransform(dx);
        x->preScale(scale);
        x->postTranslate(shift);
        // The voxels inside [-1, 1]^3, and two more on every side for the stencils.
        Coord lo, hi;
        for (int a = 0; a < 3; ++a) {
            const double h = dx * scale[size_t(a)];
            lo[size_t(a)] = Int32(std::ceil((-1.0 - shift[size_t(a)]) / h));
            hi[size_t(a)] = Int32(std::floor((1.0 - shift[size_t(a)]) / h));
        }
        const CoordBBox region(lo, hi), sampled(lo.offsetBy(-2), hi.offsetBy(2));
        auto scalar = sampleField<DoubleGrid>(sampled, x, f);
        auto vector = sampleField<Vec3DGrid>(sampled, x, u);
        auto distance = sampleField<DoubleGrid>(sampled, x, dist);
        auto g = tools::gradient(*scalar);
        auto l = tools::laplacian(*scalar);
        auto d = tools::divergence(*vector);
        auto r = tools::curl(*vector);
        auto h = tools::meanCurvature(*distance);
        for (auto& e : err)
            e[level] = 0.0;
        forEachVoxel(region, [&](const Coord& ijk) {
            const Vec3d p = x->indexToWorld(ijk);
            const double e[5] = {(g->tree().getValue(ijk) - grad(p)).length(),
                                 std::abs(l->tree().getValue(ijk) - lap(p)),
                                 std::abs(d->tree().getValue(ijk) - div(p)),
                                 (r->tree().getValue(ijk) - curl(p)).length(),
                                 std::abs(h->tree().getValue(ijk) - 1.0 / dist(p))};
            for (int i = 0; i < 5; ++i)
                err[i][level] = std::max(err[i][level], e[i]);
        });
    }
    const char* names[5] = {"gradient", "laplacian", "divergence", "curl", "meanCurvature"};
    for (int i = 0; i < 5; ++i) {
        EXPECT_GT(err[i][0], 0.0) << names[i];
        EXPECT_GT(err[i][0] / err[i][1], 3.5) << names[i] << ": " << err[i][0] << " " << err[i][1];
        EXPECT_LT(err[i][0] / err[i][1], 4.5) << names[i] << ": " << err[i][0] << " " << err[i][1];
    }
}

TEST(GridOperators, MeanCurvatureOfLevelSetSphereApproachesOneOverRadius) {
    // Float level set of radius 24 voxels: the curvature of every band voxel whose 19-point
    // stencil lies inside the band (|phi| < 3 - sqrt(3) voxels) is within 1% of 1/r, r its
    // distance from the centre (the radius of its level set). Nearer the band's edge the
    // stencil reads the clamped background, as in OpenVDB.
    const Vec3d c(0.1, -0.2, 0.3);
    const double dx = 0.0625;
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.5, c, dx);
    auto h = tools::meanCurvature(*sphere);
    auto acc = h->getConstAccessor();
    int n = 0;
    for (auto it = sphere->cbeginValueOn(); it; ++it) {
        if (std::abs(*it) >= (3.0 - std::sqrt(3.0)) * dx)
            continue;
        const double r = (sphere->indexToWorld(Vec3d(it.getCoord())) - c).length();
        ++n;
        ASSERT_NEAR(acc.getValue(it.getCoord()) * r, 1.0, 0.01) << it.getCoord();
    }
    EXPECT_GT(n, 10000);
}

TEST(GridOperators, StaggeredDivergenceUsesForwardDifferences) {
    // u = x^2 in component 0 only: forward difference (u(i+1) - u(i)) / dx at i.
    auto x = math::Transform::createLinearTransform(0.5);
    auto grid =
        sampleField<Vec3DGrid>(kBox, x, [](const Vec3d& p) { return Vec3d(p[0] * p[0], 0, 0); });
    auto central = tools::divergence(*grid);
    grid->setGridClass(GRID_STAGGERED);
    auto staggered = tools::divergence(*grid);
    auto cacc = central->getConstAccessor();
    auto sacc = staggered->getConstAccessor();
    forEachVoxel(kInterior, [&](const Coord& ijk) {
        const double px = x->indexToWorld(ijk)[0];
        ASSERT_NEAR(cacc.getValue(ijk), 2 * px, 1e-9);
        ASSERT_NEAR(sacc.getValue(ijk), 2 * px + 0.5, 1e-9);  // (x + dx)^2 - x^2 over dx
    });
}

TEST(GridOperators, MagnitudeAndNormalizeWorkPointwiseAndKeepTiles) {
    auto grid = Vec3SGrid::create(Vec3s(0, 3, 4));
    grid->setVectorType(VEC_COVARIANT);
    grid->tree().fill(CoordBBox::createCube(Coord(0), 128), Vec3s(1, 2, 2), true);  // a tile
    grid->tree().setValue(Coord(200, 0, 0), Vec3s(0, 0, 0));
    grid->tree().setValue(Coord(201, 0, 0), Vec3s(0, 0, -2));
    auto mag = tools::magnitude(*grid);
    auto unit = tools::normalize(*grid);
    EXPECT_FLOAT_EQ(mag->background(), 5.0f);
    EXPECT_EQ(mag->activeVoxelCount(), grid->activeVoxelCount());
    EXPECT_EQ(mag->tree().activeTileCount(), grid->tree().activeTileCount());
    EXPECT_FLOAT_EQ(mag->tree().getValue(Coord(5, 6, 7)), 3.0f);
    EXPECT_FLOAT_EQ(mag->tree().getValue(Coord(201, 0, 0)), 2.0f);
    EXPECT_EQ(unit->tree().getValue(Coord(200, 0, 0)), Vec3s(0, 0, 0));
    EXPECT_EQ(unit->tree().getValue(Coord(201, 0, 0)), Vec3s(0, 0, -1));
    EXPECT_NEAR(unit->tree().getValue(Coord(1, 1, 1))[0], 1.0 / 3.0, 1e-6);
    EXPECT_EQ(unit->getVectorType(), VEC_COVARIANT_NORMALIZE);
    EXPECT_TRUE(mag->transform() == grid->transform());
}

TEST(GridOperators, MagnitudeAndNormalizeOfFullLeavesEqualThePerVoxelDefinition) {
    // Whole active leaves take a row path; it must give Vec3::length() and Vec3::normalize()
    // bit for bit, including vectors too short to normalize, zeros of either sign, infinities
    // and NaNs, and leave inactive voxels at the output's background.
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Vec3s special[] = {
        Vec3s(0, 0, 0),      Vec3s(-0.0f, 0, -0.0f),        Vec3s(1e-9f, 0, 0),
        Vec3s(0, -3e-9f, 0), Vec3s(1e-20f, 1e-20f, 1e-20f), Vec3s(inf, 0, 0),
        Vec3s(nan, 1, 2),    Vec3s(-1e30f, 2e30f, 0),       Vec3s(1e-30f, 0, 0)};
    auto grid = Vec3SGrid::create(Vec3s(0, 3, 4));
    auto acc = grid->getAccessor();
    uint32_t state = 12345;
    const auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return float(int32_t(state >> 8) - (1 << 23)) / float(1 << 20);
    };
    forEachVoxel(CoordBBox(Coord(0), Coord(15)), [&](const Coord& ijk) {
        const size_t k = size_t(ijk[0] * 256 + ijk[1] * 16 + ijk[2]);
        acc.setValue(ijk, k % 7 == 0 ? special[(k / 7) % std::size(special)]
                                     : Vec3s(next(), next(), next()));
    });
    acc.setValueOff(Coord(3, 4, 5));  // one leaf not fully active: the per-voxel path
    auto mag = tools::magnitude(*grid);
    auto unit = tools::normalize(*grid);
    const auto same = [](float a, float b) {
        return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b) ||
               (std::isnan(a) && std::isnan(b));
    };
    auto macc = mag->getConstAccessor();
    auto uacc = unit->getConstAccessor();
    forEachVoxel(CoordBBox(Coord(0), Coord(15)), [&](const Coord& ijk) {
        const Vec3s v = acc.getValue(ijk);
        if (!acc.isValueOn(ijk)) {
            ASSERT_FALSE(macc.isValueOn(ijk));
            ASSERT_EQ(macc.getValue(ijk), mag->background());
            ASSERT_EQ(uacc.getValue(ijk), unit->background());
            return;
        }
        Vec3s n = v;
        if (!n.normalize())
            n = Vec3s(0.0f);
        ASSERT_TRUE(same(macc.getValue(ijk), v.length())) << ijk;
        for (int c = 0; c < 3; ++c)
            ASSERT_TRUE(same(uacc.getValue(ijk)[c], n[c])) << ijk << " " << c;
    });
}

TEST(GridOperators, ActiveTilesAreExpandedAndTheResultPruned) {
    // A constant active tile next to a leaf: the gradient is zero inside the tile, non-zero
    // only on its border towards the leaf's different values; the output prunes back to tiles
    // wherever it is constant.
    auto grid = FloatGrid::create(0.0f);
    grid->tree().fill(CoordBBox::createCube(Coord(0), 128), 1.0f, true);
    grid->tree().setValue(Coord(128, 5, 5), 3.0f);
    auto g = tools::gradient(*grid);
    EXPECT_EQ(g->activeVoxelCount(), grid->activeVoxelCount());
    // Inside the tile, away from its border: zero; at (127, 5, 5): (3 - 1) / 2 along x.
    EXPECT_EQ(g->tree().getValue(Coord(64, 64, 64)), Vec3s(0, 0, 0));
    EXPECT_EQ(g->tree().getValue(Coord(127, 5, 5)), Vec3s(1, 0, 0));
    // The border toward the background (0 outside) has a gradient too.
    EXPECT_EQ(g->tree().getValue(Coord(0, 64, 64)), Vec3s(0.5f, 0, 0));
    EXPECT_GT(g->tree().activeTileCount(), 0u);
    EXPECT_LT(g->tree().leafCount(), 16u * 16u * 16u);
}

TEST(GridOperators, MaskLimitsTheOutputToItsActiveVoxels) {
    auto x = math::Transform::createLinearTransform(0.5);
    auto grid = sampleField<FloatGrid>(kBox, x, [](const Vec3d& p) { return float(p[0] * p[1]); });
    auto mask = MaskGrid::create();
    mask->tree().fill(CoordBBox(Coord(-4), Coord(3)), true, true);
    mask->tree().setValueOn(Coord(100, 100, 100));  // outside the grid: ignored
    auto g = tools::gradient(*grid, *mask);
    auto lap = tools::laplacian(*grid, *mask);
    EXPECT_EQ(g->activeVoxelCount(), 8u * 8u * 8u);
    EXPECT_EQ(lap->activeVoxelCount(), 8u * 8u * 8u);
    EXPECT_FALSE(g->tree().isValueOn(Coord(4, 0, 0)));
    EXPECT_TRUE(g->tree().isValueOn(Coord(3, 3, 3)));
    const Vec3d p = x->indexToWorld(Coord(1, 2, 3));
    EXPECT_NEAR(g->tree().getValue(Coord(1, 2, 3))[0], p[1], 1e-5);
}

TEST(GridOperators, OutputBackgroundIsTheOperatorOfTheInputBackground) {
    auto grid = FloatGrid::create(2.0f);
    grid->tree().setValue(Coord(0), 1.0f);
    EXPECT_EQ(tools::gradient(*grid)->background(), Vec3s(0, 0, 0));
    EXPECT_EQ(tools::laplacian(*grid)->background(), 0.0f);
    EXPECT_EQ(tools::meanCurvature(*grid)->background(), 0.0f);
    // Inactive values of the output are the background: the gradient sees 2 around 1.
    auto g = tools::gradient(*grid);
    EXPECT_EQ(g->tree().getValue(Coord(0)), Vec3s(0, 0, 0));
    EXPECT_EQ(g->tree().getValue(Coord(1, 0, 0)), Vec3s(0, 0, 0));
    EXPECT_EQ(tools::laplacian(*grid)->tree().getValue(Coord(0)), 6.0f);
}

TEST(GridOperators, ResultsDoNotDependOnThreads) {
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.05f);
    auto a = tools::meanCurvature(*sphere, true);
    auto b = tools::meanCurvature(*sphere, false);
    ASSERT_EQ(a->activeVoxelCount(), b->activeVoxelCount());
    auto bacc = b->getConstAccessor();
    for (auto it = a->cbeginValueOn(); it; ++it)
        ASSERT_TRUE(test::sameBits(*it, bacc.getValue(it.getCoord()))) << it.getCoord();
}

TEST(GridOperators, FrustumTransformsAreRefused) {
    auto grid = FloatGrid::create(0.0f);
    grid->setTransform(
        math::Transform::createFrustumTransform(BBoxd(Vec3d(0.0), Vec3d(10.0)), 0.5, 2.0));
    grid->tree().setValue(Coord(1), 1.0f);
    EXPECT_THROW(tools::gradient(*grid), ValueError);
}

}  // namespace
}  // namespace vdb
