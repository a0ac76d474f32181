// SPDX-License-Identifier: Apache-2.0
// Oracles: the analytic distance to a sphere for resampled level sets; brute force (the
// sampler called at every output voxel of a box, activity from its stencil) for the values
// and topology of a resampling; the input's own voxels for copies; the analytic total of a
// smooth density for fog volumes.

#include <vdb/tools/GridTransformer.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/vdb.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace vdb::tools {
namespace {

constexpr double kRadius = 1.0;
const Vec3d kCenter(0.1, -0.2, 0.3);

// Calls f(ijk) for every coordinate of `box`.
template <typename F>
void forEachCoord(const CoordBBox& box, const F& f) {
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                f(Coord(i, j, k));
}

FloatGrid::Ptr makeSphere(double voxelSize) {
    return createLevelSetSphere<FloatGrid>(float(kRadius), Vec3f(kCenter), float(voxelSize));
}

// The largest |value - analytic distance| over the active voxels within one voxel (of the
// smallest edge) of the surface, in units of that edge.
double nearSurfaceError(const FloatGrid& grid) {
    const Vec3d vs = grid.transform().voxelSize();
    const double edge = std::min({vs[0], vs[1], vs[2]});
    double worst = 0.0;
    for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
        const Vec3d xyz = grid.transform().indexToWorld(it.getCoord());
        const double exact = (xyz - kCenter).length() - kRadius;
        if (std::abs(exact) <= edge)
            worst = std::max(worst, std::abs(double(*it) - exact) / edge);
    }
    return worst;
}

// Every voxel within 0.8 of the smallest edge of the surface is active and no active voxel
// lies on the wrong side of it.
void expectBandAroundSurface(const FloatGrid& grid) {
    const Vec3d vs = grid.transform().voxelSize();
    const double edge = std::min({vs[0], vs[1], vs[2]});
    const CoordBBox box = grid.transform().worldToIndexCellCentered(
        BBoxd(kCenter - Vec3d(kRadius + 2 * edge), kCenter + Vec3d(kRadius + 2 * edge)));
    const tree::ValueAccessor<const FloatTree> acc(grid.tree());
    Index64 checked = 0, wrong = 0, inactive = 0;
    forEachCoord(box, [&](const Coord& ijk) {
        const double exact = (grid.transform().indexToWorld(ijk) - kCenter).length() - kRadius;
        const float v = acc.getValue(ijk);
        if (std::abs(exact) < 0.8 * edge) {
            inactive += !acc.isValueOn(ijk);
            ++checked;
        }
        if (std::abs(exact) > 1.5 * edge) {
            wrong += (v > 0) != (exact > 0);
        }
    });
    EXPECT_EQ(inactive, 0u);
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(checked, 100u);
}

TEST(GridTransformer, LevelSetResampledToHalfResolutionStaysNearTheAnalyticDistance) {
    const auto in = makeSphere(0.05);
    auto out = FloatGrid::create();
    out->setTransform(math::Transform::createLinearTransform(0.1));
    resampleToMatch<BoxSampler>(*in, *out);
    EXPECT_EQ(out->getGridClass(), GRID_UNKNOWN);  // out's metadata is kept
    EXPECT_LT(nearSurfaceError(*out), 0.15);
    expectBandAroundSurface(*out);
    // A clean band: 3 voxels of the new size.
    EXPECT_NEAR(out->background(), 0.3f, 1e-6f);
}

TEST(GridTransformer, LevelSetResampledToDoubleResolutionStaysNearTheAnalyticDistance) {
    const auto in = makeSphere(0.1);
    auto out = FloatGrid::create();
    out->setTransform(math::Transform::createLinearTransform(0.05));
    resampleToMatch<BoxSampler>(*in, *out);
    EXPECT_LT(nearSurfaceError(*out), 0.25);
    expectBandAroundSurface(*out);
    EXPECT_NEAR(out->background(), 0.15f, 1e-6f);
}

// A level set resampled to a rotated transform with unequal scales is rebuilt in the output's
// index space, as OpenVDB does: its values are index-space distances to the mapped sphere (an
// ellipsoid) times the first voxel size. Oracle: with W the index-to-world linear map, a world
// displacement of length d along the unit normal n of a plane is d / |W^T n| index units off the
// plane's image, so a point at world distance d from the sphere is between d / smax and
// d / smin index units from the ellipsoid (smin, smax: W's extreme singular values, here the
// scales 0.4 and 0.65, which the rotation after them leaves alone), and d / |W^T n| near it to
// O(d^2 / R) (the sphere's curvature). World distances (what the sampled band held) differ from
// these by up to 35% of the value.
struct NonUniformCase {
    FloatGrid::Ptr in;
    math::Transform::Ptr xform;
    Vec3d center;
    double radius;
};

NonUniformCase nonUniformSphere() {
    NonUniformCase c;
    c.center = Vec3d(0.3, -0.7, 0.4);
    c.radius = 5.0;
    c.in = createLevelSetSphere<FloatGrid>(float(c.radius), Vec3f(c.center), 0.2f, 3.0f);
    Mat4d m = Mat4d::scale(Vec3d(0.4, 0.65, 0.55));
    m.postRotate(math::Axis::X, 0.5);
    m.postRotate(math::Axis::Z, 0.9);
    m.postTranslate(Vec3d(0.11, -0.07, 0.23));
    c.xform = math::Transform::createLinearTransform(m);
    return c;
}

// Checks `out` against the oracle above for a band of `halfWidth` index units.
void expectIndexSpaceBand(const FloatGrid& out, const NonUniformCase& c, double halfWidth) {
    const math::Transform& xform = out.transform();
    const Mat4d& m = xform.affineMatrix();  // rows: the world images of the index axes
    const double vs0 = xform.voxelSize()[0];
    const double smin = 0.4, smax = 0.65;
    const double tol = 0.1;  // index units: the mesh and the curvature
    // Every voxel of a box around the sphere.
    const CoordBBox box = xform.worldToIndexCellCentered(
        BBoxd(c.center - Vec3d(c.radius + 4.0 * smax), c.center + Vec3d(c.radius + 4.0 * smax)));
    const tree::ValueAccessor<const FloatTree> acc(out.tree());
    Index64 nearChecked = 0, mustBeOn = 0, mustBeOff = 0, bad = 0;
    double worstNear = 0.0;
    forEachCoord(box, [&](const Coord& ijk) {
        const Vec3d x = xform.indexToWorld(ijk);
        const double r = (x - c.center).length();
        const double d = r - c.radius;
        const double lo = std::abs(d) / smax, hi = std::abs(d) / smin;  // index distance bounds
        const float v = acc.getValue(ijk);
        const bool on = acc.isValueOn(ijk);
        const double index = double(v) / vs0;  // the value in index units
        if (on) {
            // A band value: its magnitude between the bounds, its sign that of d.
            if (std::abs(index) < lo - tol || std::abs(index) > hi + tol ||
                (std::abs(d) > tol * smax && (v > 0) != (d > 0)))
                ++bad;
            if (std::abs(index) > halfWidth + 1e-5)
                ++bad;
        } else if (std::abs(v) != out.background() || (v > 0) != (d > 0)) {
            ++bad;  // beyond the band: the signed background
        }
        if (hi < halfWidth - tol) {
            ++mustBeOn;
            bad += !on;
        }
        if (lo > halfWidth + tol) {
            ++mustBeOff;
            bad += on;
        }
        if (hi <= 1.0) {
            // Near the surface: the distance to the plane's image.
            const Vec3d n = (x - c.center) / r;
            const Vec3d g(m(0, 0) * n[0] + m(0, 1) * n[1] + m(0, 2) * n[2],
                          m(1, 0) * n[0] + m(1, 1) * n[1] + m(1, 2) * n[2],
                          m(2, 0) * n[0] + m(2, 1) * n[1] + m(2, 2) * n[2]);
            worstNear = std::max(worstNear, std::abs(index - d / g.length()));
            ++nearChecked;
            bad += !on;
        }
    });
    EXPECT_EQ(bad, 0u);
    EXPECT_LT(worstNear, 0.05);
    EXPECT_GT(nearChecked, 1000u);
    EXPECT_GT(mustBeOn, 3000u);
    EXPECT_GT(mustBeOff, 3000u);
    std::cout << "band of " << halfWidth << ": " << out.activeVoxelCount() << " active voxels, "
              << nearChecked << " near the surface within " << worstNear
              << " index unit of the plane estimate\n";
}

TEST(GridTransformer, LevelSetResampledToANonUniformRotatedTransformIsRebuiltInItsIndexSpace) {
    const NonUniformCase c = nonUniformSphere();
    // An output level set: its background (2.5 voxels of its first size) sets the band and is
    // kept.
    auto ls = FloatGrid::create(2.5f * 0.4f);
    ls->setGridClass(GRID_LEVEL_SET);
    ls->setTransform(c.xform->copy());
    resampleToMatch<BoxSampler>(*c.in, *ls);
    EXPECT_EQ(ls->background(), 2.5f * 0.4f);
    EXPECT_EQ(ls->getGridClass(), GRID_LEVEL_SET);
    expectIndexSpaceBand(*ls, c, 2.5);
    // Any other output: the input's 3 voxels, times the output's first voxel size.
    auto plain = FloatGrid::create();
    plain->setTransform(c.xform->copy());
    resampleToMatch<QuadraticSampler>(*c.in, *plain);
    EXPECT_NEAR(plain->background(), 3.0 * 0.4, 1e-6);
    expectIndexSpaceBand(*plain, c, 3.0);
}

TEST(GridTransformer, EqualTransformsAndWholeVoxelTranslationsCopyExactly) {
    auto in = makeSphere(0.1);
    in->tree().fill(CoordBBox(Coord(40, 40, 40), Coord(55, 55, 55)), 0.25f, true);  // tiles
    // Equal transforms: the same tree, tiles included.
    auto same = FloatGrid::create();
    same->setTransform(in->transform().copy());
    resampleToMatch<QuadraticSampler>(*in, *same);
    EXPECT_EQ(same->tree().activeTileCount(), in->tree().activeTileCount());
    EXPECT_EQ(same->activeVoxelCount(), in->activeVoxelCount());
    // A translation by (3, -5, 2) voxels in world space, composed in floating point.
    auto moved = FloatGrid::create();
    moved->setTransform(in->transform().copy());
    moved->transform().postTranslate(Vec3d(0.3, -0.5, 0.2));
    resampleToMatch<BoxSampler>(*in, *moved);
    for (const FloatGrid* out : {same.get(), moved.get()}) {
        const Coord offset = out == same.get() ? Coord(0) : Coord(-3, 5, -2);
        EXPECT_EQ(out->activeVoxelCount(), in->activeVoxelCount());
        const tree::ValueAccessor<const FloatTree> acc(out->tree());
        for (auto it = in->tree().cbeginValueAll(); it; ++it) {
            if (!it.isVoxelValue())
                continue;
            const Coord ijk = it.getCoord() + offset;
            ASSERT_EQ(acc.getValue(ijk), *it) << ijk;
            ASSERT_EQ(acc.isValueOn(ijk), it.isValueOn()) << ijk;
        }
        EXPECT_EQ(acc.getValue(Coord(47, 47, 47) + offset), 0.25f);
        EXPECT_TRUE(acc.isValueOn(Coord(40, 55, 40) + offset));
    }
}

// The output voxels OpenVDB's resampler visits for the input voxels `box` (written out
// independently of the library): the corners of the cell span [min, max + 1] mapped, the
// bounds rounded outward, grown by the sampler's radius.
CoordBBox visitedOracle(const CoordBBox& box, const Mat4d& outFromIn, int radius) {
    BBoxd span;
    for (int c = 0; c < 8; ++c) {
        span.expand(outFromIn.transformPoint(Vec3d((c & 1) ? box.max()[0] + 1 : box.min()[0],
                                                   (c & 2) ? box.max()[1] + 1 : box.min()[1],
                                                   (c & 4) ? box.max()[2] + 1 : box.min()[2])));
    }
    const Vec3d hi = span.max();
    return CoordBBox(
        floorToCoord(span.min()) - Coord(radius),
        Coord(Int32(std::ceil(hi[0])), Int32(std::ceil(hi[1])), Int32(std::ceil(hi[2]))) +
            Coord(radius));
}

// Brute force: every output voxel of a box around the input, sampled directly; a voxel is
// active when it is visited (by the box of an input leaf or tile) and the sampler read an
// active voxel, and then holds the sampler's value.
template <typename SamplerT>
void expectMatchesBruteForce(const FloatTree& in, const Mat4d& outFromIn, float tol) {
    auto inGrid = FloatGrid::create(in.background());
    inGrid->setTree(std::make_shared<FloatTree>(in));
    auto outGrid = FloatGrid::create();
    GridTransformer transformer(outFromIn);
    transformer.transformGrid<SamplerT>(*inGrid, *outGrid);
    const FloatTree& out = outGrid->tree();
    EXPECT_EQ(out.background(), in.background());

    // The leaves, and the tiles that are active or not the background.
    std::set<Coord> leaves;
    std::vector<CoordBBox> visited;
    for (auto it = in.cbeginValueAll(); it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        if (it.isVoxelValue())
            leaves.insert(box.min().alignedDown(3));
        else if (it.isValueOn() || *it != in.background())
            visited.push_back(visitedOracle(box, outFromIn, SamplerT::radius()));
    }
    for (const Coord& origin : leaves) {
        // OpenVDB spans a leaf as [origin, origin + 8], one voxel past its end.
        visited.push_back(
            visitedOracle(CoordBBox::createCube(origin, 9), outFromIn, SamplerT::radius()));
    }
    CoordBBox outBox = visited.front();
    for (const CoordBBox& box : visited)
        outBox.expand(box);
    const Mat4d inFromOut = outFromIn.inverse();
    Index64 active = 0, wrongState = 0, wrongValue = 0;
    const tree::ValueAccessor<const FloatTree> inAcc(in), outAcc(out);
    forEachCoord(outBox, [&](const Coord& ijk) {
        float expected = 0.0f;
        bool on = SamplerT::sample(inAcc, inFromOut.transformPoint(Vec3d(ijk)), expected);
        on = on && std::any_of(visited.begin(), visited.end(),
                               [&](const CoordBBox& box) { return box.isInside(ijk); });
        wrongState += outAcc.isValueOn(ijk) != on;
        if (on) {
            ++active;
            wrongValue += !(std::abs(outAcc.getValue(ijk) - expected) <= tol);
        }
    });
    EXPECT_EQ(wrongState, 0u);
    EXPECT_EQ(wrongValue, 0u);
    EXPECT_EQ(out.activeVoxelCount(), active);
    EXPECT_GT(active, 0u);
}

FloatTree randomSparseTree(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> coord(-20, 20);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    FloatTree tree(0.5f);
    for (int n = 0; n < 400; ++n)
        tree.setValue(Coord(coord(rng), coord(rng), coord(rng)), value(rng));
    tree.fill(CoordBBox(Coord(24, 0, 0), Coord(31, 7, 7)), -0.75f, true);  // an active tile
    return tree;
}

TEST(GridTransformer, ValuesAndTopologyMatchTheSamplerAtEveryOutputVoxel) {
    const FloatTree in = randomSparseTree(7);
    Mat4d rotated = Mat4d::scale(Vec3d(1.3, 0.9, 1.1));
    rotated.postRotate(math::Axis::Y, 0.5);
    rotated.postRotate(math::Axis::X, -0.2);
    rotated.postTranslate(Vec3d(0.3, -1.7, 2.2));
    expectMatchesBruteForce<BoxSampler>(in, rotated, 1e-5f);
    expectMatchesBruteForce<QuadraticSampler>(in, rotated, 1e-4f);
    expectMatchesBruteForce<PointSampler>(in, rotated, 0.0f);
    expectMatchesBruteForce<BoxSampler>(in, Mat4d::scale(Vec3d(2.0)), 1e-5f);
    expectMatchesBruteForce<BoxSampler>(in, Mat4d::scale(Vec3d(0.5, 0.7, 0.6)), 1e-5f);
}

TEST(GridTransformer, ResultDoesNotDependOnTheThreadCount) {
    const auto in = makeSphere(0.04);
    Mat4d m = Mat4d::rotation(math::Axis::Z, 0.6);
    m.postScale(Vec3d(1.4, 0.8, 1.0));
    auto a = FloatGrid::create(), b = FloatGrid::create();
    GridTransformer threaded(m), serial(m);
    serial.setThreaded(false);
    threaded.transformGrid<BoxSampler>(*in, *a);
    serial.transformGrid<BoxSampler>(*in, *b);
    ASSERT_EQ(a->activeVoxelCount(), b->activeVoxelCount());
    ASSERT_EQ(a->tree().leafCount(), b->tree().leafCount());
    const tree::ValueAccessor<const FloatTree> acc(b->tree());
    for (auto it = a->tree().cbeginValueAll(); it; ++it) {
        ASSERT_EQ(acc.getValue(it.getCoord()), *it) << it.getCoord();
        ASSERT_EQ(acc.isValueOn(it.getCoord()), it.isValueOn()) << it.getCoord();
    }
}

// A smooth density: (1 - r^2 / R^2)^2 inside a ball of radius R voxels; its integral is
// 4 pi R^3 * (1/3 - 2/5 + 1/7) = 32 pi R^3 / 105.
FloatGrid::Ptr smoothFog(double voxelSize, double radiusVoxels) {
    auto fog = FloatGrid::create(0.0f);
    fog->setTransform(math::Transform::createLinearTransform(voxelSize));
    fog->setGridClass(GRID_FOG_VOLUME);
    const int r = int(std::ceil(radiusVoxels));
    FloatGrid::Accessor acc = fog->getAccessor();
    for (int i = -r; i <= r; ++i)
        for (int j = -r; j <= r; ++j)
            for (int k = -r; k <= r; ++k) {
                const double q = (i * i + j * j + k * k) / (radiusVoxels * radiusVoxels);
                if (q < 1.0)
                    acc.setValue(Coord(i, j, k), float((1 - q) * (1 - q)));
            }
    return fog;
}

double totalDensity(const FloatGrid& grid) {
    double sum = 0.0;
    for (auto it = grid.tree().cbeginValueOn(); it; ++it)
        sum += double(*it);
    return sum * grid.transform().voxelVolume();
}

TEST(GridTransformer, BoxDownsamplingConservesFogDensity) {
    const double radius = 20.0;
    const auto fog = smoothFog(0.1, radius);
    const double exact = 32.0 * M_PI * std::pow(radius * 0.1, 3) / 105.0;
    EXPECT_NEAR(totalDensity(*fog), exact, 0.01 * exact);
    for (const double scale : {2.0, 3.0, 4.0}) {  // 4: two halvings (mipmapping)
        auto coarse = FloatGrid::create(0.0f);
        coarse->setTransform(math::Transform::createLinearTransform(0.1 * scale));
        resampleToMatch<BoxSampler>(*fog, *coarse);
        EXPECT_NEAR(totalDensity(*coarse), totalDensity(*fog), 0.01 * totalDensity(*fog))
            << "scale " << scale;
    }
    EXPECT_EQ(GridTransformer(Mat4d::scale(Vec3d(0.25, 0.5, 0.2))).getMipLevels(), Vec3i(2, 0, 2));
}

TEST(GridTransformer, PivotScaleRotateTranslateComposeInTheGivenOrder) {
    const Vec3d pivot(1, 2, 3), scale(2, 3, 4), rotate(0.1, 0.2, 0.3), translate(5, 6, 7);
    const GridTransformer t(pivot, scale, rotate, translate, "tsr", "zyx");
    // Row vectors: translate, then scale about the pivot, then rotate (z, then y, then x).
    Mat4d expected = Mat4d::translation(translate);
    expected.postMult(Mat4d::translation(-pivot) * Mat4d::scale(scale) * Mat4d::translation(pivot));
    expected.postMult(Mat4d::translation(-pivot) * Mat4d::rotation(math::Axis::Z, 0.3) *
                      Mat4d::rotation(math::Axis::Y, 0.2) * Mat4d::rotation(math::Axis::X, 0.1) *
                      Mat4d::translation(pivot));
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            EXPECT_NEAR(t.getTransform()(r, c), expected(r, c), 1e-12) << r << c;
    EXPECT_THROW(GridTransformer(pivot, scale, rotate, translate, "tss"), ValueError);
    EXPECT_THROW(GridTransformer(pivot, scale, rotate, translate, "tsr", "xy"), ValueError);
}

TEST(GridTransformer, BadTransformsAndHugeOutputsAreRefused) {
    EXPECT_THROW(GridTransformer(Mat4d::scale(Vec3d(1, 0, 1))), ValueError);
    Mat4d projective = Mat4d::identity();
    projective(0, 3) = 0.5;
    EXPECT_THROW((GridTransformer(projective)), ValueError);
    Mat4d nan = Mat4d::identity();
    nan(1, 1) = std::nan("");
    EXPECT_THROW((GridTransformer(nan)), ValueError);

    const auto in = makeSphere(0.1);
    auto frustum = FloatGrid::create();
    frustum->setTransform(
        math::Transform::createFrustumTransform(BBoxd(Vec3d(0), Vec3d(63)), 0.5, 2.0));
    EXPECT_THROW(resampleToMatch<BoxSampler>(*in, *frustum), ValueError);
    EXPECT_THROW(resampleToMatch<BoxSampler>(*frustum, *in), ValueError);

    // 10^4 times finer: about 10^14 voxels; refused before anything is allocated.
    auto fine = FloatGrid::create();
    fine->setTransform(math::Transform::createLinearTransform(1e-5));
    EXPECT_THROW(resampleToMatch<BoxSampler>(*in, *fine), ValueError);
    const auto fog = smoothFog(0.1, 5.0);
    EXPECT_THROW(resampleToMatch<BoxSampler>(*fog, *fine), ValueError);
    // 10^8 times finer: beyond 64 bits of voxels; the message still gives the magnitude.
    auto finest = FloatGrid::create();
    finest->setTransform(math::Transform::createLinearTransform(1e-9));
    try {
        resampleToMatch<BoxSampler>(*in, *finest);
        ADD_FAILURE() << "a resampling beyond 64 bits of voxels was not refused";
    } catch (const ValueError& e) {
        // The band alone, 10^8 times finer on each axis, is over 10^20 voxels.
        const std::string message = e.what();
        const size_t at = message.find("up to ");
        ASSERT_NE(at, std::string::npos) << message;
        EXPECT_GT(std::stod(message.substr(at + 6)), 1e20) << message;
    }
    // A configurable limit.
    GridTransformer doubling(Mat4d::scale(Vec3d(2.0)));
    doubling.setMaxVoxelCount(1000);
    auto out = FloatGrid::create();
    EXPECT_THROW(doubling.transformGrid<BoxSampler>(*fog, *out), ValueError);
    EXPECT_THROW(resampleToMatch<BoxSampler>(*fog, *out, 1000), ValueError);
    doubling.setMaxVoxelCount(DEFAULT_MAX_RESAMPLE_VOXELS);
    EXPECT_NO_THROW(doubling.transformGrid<BoxSampler>(*fog, *out));
    EXPECT_GT(out->activeVoxelCount(), 7 * fog->activeVoxelCount());
}

}  // namespace
}  // namespace vdb::tools
