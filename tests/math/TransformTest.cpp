// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic images of points (scale, translation, rotation, the frustum's near and far
// faces), composition of the edits as plain functions on points, inverse round trips, finite
// differences for voxel sizes and volumes, and the byte values quoted in FORMAT.md.

#include <vdb/math/Transform.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <vector>

namespace vdb::math {
namespace {

Vec3d randomVec(std::mt19937& rng, double lo, double hi) {
    std::uniform_real_distribution<double> value(lo, hi);
    return Vec3d(value(rng), value(rng), value(rng));
}

// One transform of every map type, each with non-trivial parameters.
std::vector<Transform> oneOfEachMapType() {
    Mat4d rotation = Mat4d::rotation(Vec3d(1, 2, 3), 0.7);
    Mat4d affine = rotation;
    affine.preScale(Vec3d(0.5, 2, 3));
    affine(1, 0) += 0.25;  // a shear
    affine.setTranslation(Vec3d(-4, 5, 6));

    std::vector<MapParams> params(8);
    params[0].type = MapType::UniformScale;
    params[0].scale = Vec3d(0.25);
    params[1].type = MapType::UniformScaleTranslate;
    params[1].scale = Vec3d(-0.5);
    params[1].translation = Vec3d(1, 2, 3);
    params[2].type = MapType::Scale;
    params[2].scale = Vec3d(1, 2, -3);
    params[3].type = MapType::ScaleTranslate;
    params[3].scale = Vec3d(0.1, 0.2, 0.3);
    params[3].translation = Vec3d(-7, 0, 7);
    params[4].type = MapType::Translation;
    params[4].translation = Vec3d(0.5, -0.5, 100);
    params[5].type = MapType::Affine;
    params[5].matrix = affine;
    params[6].type = MapType::Unitary;
    params[6].matrix = rotation;
    params[7].type = MapType::NonlinearFrustum;
    params[7].frustumBBox = BBoxd(Vec3d(-10, -5, 0), Vec3d(30, 15, 50));
    params[7].frustumTaper = 0.4;
    params[7].frustumDepth = 2.5;
    params[7].matrix = affine;

    std::vector<Transform> result;
    for (const MapParams& p : params)
        result.emplace_back(p);
    return result;
}

TEST(Transform, DefaultIsIdentityUniformScaleMap) {
    const Transform xform;
    EXPECT_EQ(xform.mapType(), MapType::UniformScale);
    EXPECT_EQ(xform.mapTypeName(), "UniformScaleMap");
    EXPECT_TRUE(xform.isIdentity());
    EXPECT_TRUE(xform.isLinear());
    EXPECT_EQ(xform.indexToWorld(Coord(-3, 4, 5)), Vec3d(-3, 4, 5));
    EXPECT_EQ(xform, *Transform::createLinearTransform());
}

TEST(Transform, LinearTransformScalesIndexByVoxelSize) {
    const Transform::Ptr xform = Transform::createLinearTransform(0.5);
    EXPECT_EQ(xform->mapType(), MapType::UniformScale);
    EXPECT_EQ(xform->indexToWorld(Coord(1, -2, 3)), Vec3d(0.5, -1, 1.5));
    EXPECT_EQ(xform->worldToIndex(Vec3d(0.5, -1, 1.5)), Vec3d(1, -2, 3));
    EXPECT_EQ(xform->voxelSize(), Vec3d(0.5));
    EXPECT_EQ(xform->voxelSize(Vec3d(100, 200, 300)), Vec3d(0.5));
    EXPECT_EQ(xform->voxelVolume(), 0.125);
    EXPECT_FALSE(xform->isIdentity());
    EXPECT_TRUE(xform->hasUniformScale());
}

TEST(Transform, PostTranslateMovesWorldAndMakesUniformScaleTranslateMap) {
    const Transform::Ptr xform = Transform::createLinearTransform(0.1);
    xform->postTranslate(Vec3d(1, 2, 3));
    EXPECT_EQ(xform->mapType(), MapType::UniformScaleTranslate);
    EXPECT_EQ(xform->mapTypeName(), "UniformScaleTranslateMap");
    EXPECT_TRUE(isApproxEqual(xform->indexToWorld(Coord(10, 0, 0)), Vec3d(2, 2, 3), 1e-15));
    EXPECT_EQ(xform->worldToIndexCellCentered(Vec3d(2, 2, 3)), Coord(10, 0, 0));
    EXPECT_EQ(xform->voxelSize(), Vec3d(0.1));
    const MapParams p = xform->mapParams();
    EXPECT_EQ(p.scale, Vec3d(0.1));
    EXPECT_EQ(p.translation, Vec3d(1, 2, 3));
}

TEST(Transform, CellCenteredRoundsAndNodeCenteredFloors) {
    const Transform xform;
    EXPECT_EQ(xform.worldToIndexCellCentered(Vec3d(0.49, -0.5, -0.51)), Coord(0, 0, -1));
    EXPECT_EQ(xform.worldToIndexNodeCentered(Vec3d(0.49, -0.5, -0.51)), Coord(0, -1, -1));
    EXPECT_EQ(xform.worldToIndexNodeCentered(Vec3d(3.0, -3.0, 1e30)),
              Coord(3, -3, std::numeric_limits<Int32>::max()));

    const Transform::Ptr coarse = Transform::createLinearTransform(2.0);
    EXPECT_EQ(coarse->worldToIndexCellCentered(Vec3d(2.9, -2.9, 3.0)), Coord(1, -1, 2));
    EXPECT_EQ(coarse->worldToIndexNodeCentered(Vec3d(2.9, -2.9, 3.0)), Coord(1, -2, 1));
}

TEST(Transform, EditsComposeLikeFunctionsOnPoints) {
    // The oracle applies each edit to points directly: a pre-edit acts on the index point
    // before everything else, a post-edit on the world point after everything else.
    std::mt19937 rng(20130601);
    std::uniform_int_distribution<int> pick(0, 7);
    std::uniform_real_distribution<double> value(0.5, 2.0);
    for (int trial = 0; trial < 50; ++trial) {
        Transform xform;
        std::function<Vec3d(const Vec3d&)> oracle = [](const Vec3d& p) { return p; };
        for (int step = 0; step < 6; ++step) {
            const Vec3d v = randomVec(rng, 0.5, 2.0);
            const double s = value(rng);
            const Axis axis = Axis(pick(rng) % 3);
            const auto prev = oracle;
            switch (pick(rng)) {
                case 0:
                    xform.preTranslate(v);
                    oracle = [=](const Vec3d& p) { return prev(p + v); };
                    break;
                case 1:
                    xform.postTranslate(v);
                    oracle = [=](const Vec3d& p) { return prev(p) + v; };
                    break;
                case 2:
                    xform.preScale(v);
                    oracle = [=](const Vec3d& p) { return prev(p * v); };
                    break;
                case 3:
                    xform.postScale(v);
                    oracle = [=](const Vec3d& p) { return prev(p) * v; };
                    break;
                case 4:
                    xform.preScale(s);
                    oracle = [=](const Vec3d& p) { return prev(p * s); };
                    break;
                case 5:
                    xform.postScale(s);
                    oracle = [=](const Vec3d& p) { return prev(p) * s; };
                    break;
                case 6:
                    xform.preRotate(s, axis);
                    oracle = [=](const Vec3d& p) {
                        return prev(Mat4d::rotation(axis, s).transformPoint(p));
                    };
                    break;
                default:
                    xform.postRotate(s, axis);
                    oracle = [=](const Vec3d& p) {
                        return Mat4d::rotation(axis, s).transformPoint(prev(p));
                    };
                    break;
            }
            for (int n = 0; n < 5; ++n) {
                const Vec3d p = randomVec(rng, -100, 100);
                ASSERT_TRUE(isApproxEqual(xform.indexToWorld(p), oracle(p), 1e-9))
                    << xform << " at " << p;
            }
        }
    }
}

TEST(Transform, WorldToIndexInvertsIndexToWorldForEveryMapType) {
    std::mt19937 rng(1);
    for (const Transform& xform : oneOfEachMapType()) {
        for (int n = 0; n < 1000; ++n) {
            // Frustum points stay inside the frustum box, away from the apex.
            const Vec3d ijk = xform.isLinear() ? randomVec(rng, -1000, 1000)
                                               : randomVec(rng, 0, 30) + Vec3d(-10, -5, 0);
            ASSERT_TRUE(isApproxEqual(xform.worldToIndex(xform.indexToWorld(ijk)), ijk, 1e-9))
                << xform << " at " << ijk;
            const Vec3d xyz = xform.indexToWorld(ijk);
            ASSERT_TRUE(isApproxEqual(xform.indexToWorld(xform.worldToIndex(xyz)), xyz, 1e-9))
                << xform << " at " << xyz;
        }
        const Coord ijk(7, -8, 9);
        EXPECT_EQ(xform.indexToWorld(ijk), xform.indexToWorld(Vec3d(ijk)));
    }
}

TEST(Transform, LinearMapsComputeTheirDefiningFormula) {
    const std::vector<Transform> all = oneOfEachMapType();
    std::mt19937 rng(2);
    for (int n = 0; n < 100; ++n) {
        const Vec3d p = randomVec(rng, -50, 50);
        const Vec3d expected[5] = {p * 0.25, p * -0.5 + Vec3d(1, 2, 3), p * Vec3d(1, 2, -3),
                                   p * Vec3d(0.1, 0.2, 0.3) + Vec3d(-7, 0, 7),
                                   p + Vec3d(0.5, -0.5, 100)};
        for (size_t k = 0; k < 5; ++k) {
            EXPECT_TRUE(isApproxEqual(all[k].indexToWorld(p), expected[k], 1e-12)) << all[k];
        }
        // Affine and unitary: the row vector [p 1] times the stored matrix.
        for (int k : {5, 6}) {
            const Mat4d& m = all[size_t(k)].mapParams().matrix;
            const Vec3d expected(p[0] * m(0, 0) + p[1] * m(1, 0) + p[2] * m(2, 0) + m(3, 0),
                                 p[0] * m(0, 1) + p[1] * m(1, 1) + p[2] * m(2, 1) + m(3, 1),
                                 p[0] * m(0, 2) + p[1] * m(1, 2) + p[2] * m(2, 2) + m(3, 2));
            EXPECT_TRUE(isApproxEqual(all[size_t(k)].indexToWorld(p), expected, 1e-12));
        }
    }
}

TEST(Transform, SimplestExactMapTypeIsChosenForMatrices) {
    const auto typeOf = [](const Mat4d& m) {
        return Transform::createLinearTransform(m)->mapType();
    };
    EXPECT_EQ(typeOf(Mat4d::identity()), MapType::UniformScale);
    EXPECT_EQ(typeOf(Mat4d::translation(Vec3d(1, 0, 0))), MapType::UniformScaleTranslate);
    EXPECT_EQ(typeOf(Mat4d::scale(Vec3d(1, 2, 3))), MapType::Scale);
    EXPECT_EQ(typeOf(Mat4d::scale(Vec3d(2, 2, 3))), MapType::Scale);
    EXPECT_EQ(typeOf(Mat4d::scale(Vec3d(2, 3, 2))), MapType::Scale);
    EXPECT_EQ(typeOf(Mat4d::scale(Vec3d(-2))), MapType::UniformScale);
    Mat4d st = Mat4d::scale(Vec3d(1, 2, 3));
    st.setTranslation(Vec3d(0, 0, -1));
    EXPECT_EQ(typeOf(st), MapType::ScaleTranslate);
    EXPECT_EQ(typeOf(Mat4d::rotation(Axis::Y, 0.1)), MapType::Affine);
    Mat4d shear = Mat4d::identity();
    shear(2, 0) = 0.5;
    EXPECT_EQ(typeOf(shear), MapType::Affine);

    // Rotating a scale map and rotating back yields a diagonal matrix only up to rounding;
    // the type then stays Affine rather than dropping the tiny terms.
    Transform xform;
    xform.preScale(Vec3d(1, 2, 3));
    EXPECT_EQ(xform.mapType(), MapType::Scale);
    xform.postRotate(std::numbers::pi / 2, Axis::Z);
    EXPECT_EQ(xform.mapType(), MapType::Affine);
    xform.postMult(Mat4d::identity());
    EXPECT_EQ(xform.mapType(), MapType::Affine);
}

TEST(Transform, MapParamsRoundTripEveryMapTypeAndName) {
    for (const Transform& xform : oneOfEachMapType()) {
        const MapParams p = xform.mapParams();
        const Transform copy(p);
        EXPECT_EQ(copy, xform);
        EXPECT_EQ(copy.mapType(), xform.mapType());
        const MapParams q = copy.mapParams();
        EXPECT_EQ(q.type, p.type);
        EXPECT_EQ(q.scale, p.scale);
        EXPECT_EQ(q.translation, p.translation);
        EXPECT_EQ(q.matrix, p.matrix);
        EXPECT_EQ(q.frustumBBox, p.frustumBBox);
        EXPECT_EQ(q.frustumTaper, p.frustumTaper);
        EXPECT_EQ(q.frustumDepth, p.frustumDepth);
        EXPECT_EQ(mapTypeFromName(xform.mapTypeName()), xform.mapType());
        EXPECT_EQ(*Transform::createFromMap(p), xform);
    }
    const char* names[] = {"UniformScaleMap",   "UniformScaleTranslateMap", "ScaleMap",
                           "ScaleTranslateMap", "TranslationMap",           "AffineMap",
                           "UnitaryMap",        "NonlinearFrustumMap"};
    const std::vector<Transform> all = oneOfEachMapType();
    for (size_t i = 0; i < 8; ++i)
        EXPECT_EQ(all[i].mapTypeName(), names[i]);
    EXPECT_EQ(mapTypeFromName("LinearTransform"), std::nullopt);
    EXPECT_EQ(mapTypeFromName("AffineMap "), std::nullopt);
}

TEST(Transform, UnusedMapParamsKeepTheirDefaults) {
    const std::vector<Transform> all = oneOfEachMapType();
    const MapParams defaults;
    const MapParams uniform = all[0].mapParams();
    EXPECT_EQ(uniform.translation, defaults.translation);
    EXPECT_EQ(uniform.matrix, defaults.matrix);
    const MapParams translation = all[4].mapParams();
    EXPECT_EQ(translation.scale, Vec3d(1.0));
    const MapParams affine = all[5].mapParams();
    EXPECT_EQ(affine.scale, defaults.scale);
    EXPECT_EQ(affine.translation, defaults.translation);
    EXPECT_EQ(affine.frustumBBox, defaults.frustumBBox);
}

TEST(Transform, ScaleVectorsMatchTheFileFormatExamples) {
    // FORMAT.md: UniformScaleMap 0.5 stores (.5,.5,.5) (.5,.5,.5) (2,2,2) (4,4,4) (1,1,1).
    const auto half = Transform::createLinearTransform(0.5)->mapParams().scaleVectors();
    EXPECT_EQ(half[0], Vec3d(0.5));
    EXPECT_EQ(half[1], Vec3d(0.5));
    EXPECT_EQ(half[2], Vec3d(2.0));
    EXPECT_EQ(half[3], Vec3d(4.0));
    EXPECT_EQ(half[4], Vec3d(1.0));
    // The hex dump's unit map: four (1,1,1) vectors, then (0.5,0.5,0.5).
    const auto unit = Transform().mapParams().scaleVectors();
    for (size_t i = 0; i < 4; ++i)
        EXPECT_EQ(unit[i], Vec3d(1.0));
    EXPECT_EQ(unit[4], Vec3d(0.5));

    MapParams p;
    p.type = MapType::Scale;
    p.scale = Vec3d(-2, 4, 0.1);
    const auto v = p.scaleVectors();
    EXPECT_EQ(v[1], Vec3d(2, 4, 0.1));
    EXPECT_EQ(v[2], Vec3d(-0.5, 0.25, 1 / 0.1));
    EXPECT_EQ(v[3], v[2] * v[2]);
    EXPECT_EQ(v[4], v[2] * 0.5);
}

TEST(Transform, InvalidMapParamsThrowValueError) {
    const auto rejects = [](const MapParams& p) {
        EXPECT_THROW(Transform{p}, ValueError) << "type " << mapTypeName(p.type);
    };
    MapParams p;
    p.scale = Vec3d(0);
    rejects(p);
    p.type = MapType::Scale;
    p.scale = Vec3d(1, 1, 0);
    rejects(p);
    p.scale = Vec3d(1, std::numeric_limits<double>::quiet_NaN(), 1);
    rejects(p);
    p.scale = Vec3d(1);
    p.type = MapType::ScaleTranslate;
    p.translation = Vec3d(0, std::numeric_limits<double>::infinity(), 0);
    rejects(p);
    p = MapParams();
    p.scale = Vec3d(1, 2, 2);  // UniformScale with unequal components
    rejects(p);
    p.type = MapType::UniformScaleTranslate;
    rejects(p);
    p = MapParams();
    p.translation = Vec3d(1, 0, 0);  // UniformScale has no translation
    rejects(p);
    p.type = MapType::Scale;
    rejects(p);
    p = MapParams();
    p.type = MapType::Translation;
    p.scale = Vec3d(2);
    rejects(p);
    p = MapParams();
    p.type = MapType::Affine;
    p.matrix = Mat4d::scale(Vec3d(1, 0, 1));
    rejects(p);
    p.matrix = Mat4d::identity();
    p.matrix(0, 3) = 0.5;  // not affine
    rejects(p);
    p.matrix = Mat4d::identity();
    p.matrix(3, 0) = std::numeric_limits<double>::infinity();
    rejects(p);
    p = MapParams();
    p.type = MapType::NonlinearFrustum;
    p.frustumBBox = BBoxd(Vec3d(0), Vec3d(1, 0, 1));
    rejects(p);
    p.frustumBBox = BBoxd(Vec3d(0), Vec3d(1));
    p.frustumTaper = 0;
    rejects(p);
    p.frustumTaper = 1;
    p.frustumDepth = -1;
    rejects(p);
    p.frustumDepth = 1;
    p.matrix = Mat4d::zero();
    rejects(p);

    EXPECT_THROW(Transform::createLinearTransform(0.0), ValueError);
    EXPECT_THROW(Transform::createLinearTransform(Mat4d::zero()), ValueError);
}

TEST(Transform, FailedEditLeavesTransformUnchanged) {
    const Transform::Ptr xform = Transform::createLinearTransform(0.5);
    xform->postTranslate(Vec3d(1, 2, 3));
    const Transform before = *xform;
    EXPECT_THROW(xform->preScale(0.0), ValueError);
    EXPECT_THROW(xform->postScale(Vec3d(1, 0, 1)), ValueError);
    EXPECT_EQ(*xform, before);
    EXPECT_EQ(xform->mapType(), MapType::UniformScaleTranslate);
}

TEST(Transform, EqualityComparesWhatTheMapsCompute) {
    MapParams translation;
    translation.type = MapType::Translation;
    translation.translation = Vec3d(1, 2, 3);
    Transform scaleTranslate;
    scaleTranslate.postTranslate(Vec3d(1, 2, 3));
    EXPECT_EQ(scaleTranslate.mapType(), MapType::UniformScaleTranslate);
    EXPECT_EQ(Transform(translation), scaleTranslate);  // different types, same map

    MapParams affine;
    affine.type = MapType::Affine;
    affine.matrix = Mat4d::scale(Vec3d(2));
    EXPECT_EQ(Transform(affine), *Transform::createLinearTransform(2.0));
    EXPECT_FALSE(Transform(affine) == *Transform::createLinearTransform(2.0000001));

    const std::vector<Transform> all = oneOfEachMapType();
    for (size_t i = 0; i < all.size(); ++i) {
        for (size_t j = 0; j < all.size(); ++j)
            EXPECT_EQ(all[i] == all[j], i == j);
    }
    Transform frustum = all[7];
    frustum.postTranslate(Vec3d(0, 0, 1e-9));
    EXPECT_FALSE(frustum == all[7]);
    // Frustums with the same second map differ by any frustum parameter.
    const MapParams base = all[7].mapParams();
    MapParams other = base;
    other.frustumBBox.max()[2] += 1;
    EXPECT_FALSE(Transform(other) == all[7]);
    other = base;
    other.frustumTaper = 0.5;
    EXPECT_FALSE(Transform(other) == all[7]);
    other = base;
    other.frustumDepth = 3;
    EXPECT_FALSE(Transform(other) == all[7]);
    EXPECT_TRUE(Transform(base) == all[7]);
}

TEST(Transform, ApproximateEqualityIsRelativeToTheVoxelSizeAndTranslation) {
    // A voxel size rounded through float is the same spacing.
    const auto exact = Transform::createLinearTransform(0.0125);
    const auto rounded = Transform::createLinearTransform(double(0.0125f));
    EXPECT_FALSE(*exact == *rounded);
    EXPECT_TRUE(exact->isApproxEqual(*rounded));
    EXPECT_TRUE(rounded->isApproxEqual(*exact));
    // 1e-5 relative is another spacing; so is a tiny voxel size off by the same factor.
    EXPECT_FALSE(exact->isApproxEqual(*Transform::createLinearTransform(0.0125 * (1 + 1e-5))));
    EXPECT_TRUE(Transform::createLinearTransform(1e-9)->isApproxEqual(
        *Transform::createLinearTransform(1e-9 * (1 + 1e-7))));
    EXPECT_FALSE(Transform::createLinearTransform(1e-9)->isApproxEqual(
        *Transform::createLinearTransform(1e-9 * (1 + 1e-5))));
    // A tighter tolerance.
    EXPECT_FALSE(exact->isApproxEqual(*rounded, 1e-12));
    // Translations compare relative to the larger of the voxel size and their magnitude: a far
    // placement rounded through float matches, a shift of a tenth of a voxel does not.
    auto far = Transform::createLinearTransform(0.0125);
    far->postTranslate(Vec3d(1000.1, 0, 0));
    auto farRounded = Transform::createLinearTransform(0.0125);
    farRounded->postTranslate(Vec3d(double(1000.1f), 0, 0));
    EXPECT_TRUE(far->isApproxEqual(*farRounded));
    auto shifted = Transform::createLinearTransform(0.0125);
    shifted->postTranslate(Vec3d(0.00125, 0, 0));
    EXPECT_FALSE(exact->isApproxEqual(*shifted));
    // Map types do not matter; rotations and frustums compare their parameters.
    MapParams affine;
    affine.type = MapType::Affine;
    affine.matrix = Mat4d::scale(Vec3d(0.0125));
    EXPECT_TRUE(Transform(affine).isApproxEqual(*rounded));
    auto rotated = Transform::createLinearTransform(0.0125);
    rotated->postRotate(1e-3, math::Axis::Z);
    EXPECT_FALSE(rotated->isApproxEqual(*exact));
    const std::vector<Transform> all = oneOfEachMapType();
    for (size_t i = 0; i < all.size(); ++i)
        for (size_t j = 0; j < all.size(); ++j)
            EXPECT_EQ(all[i].isApproxEqual(all[j]), i == j) << i << " " << j;
    MapParams taper = all[7].mapParams();
    taper.frustumTaper *= 1 + 1e-9;
    EXPECT_TRUE(Transform(taper).isApproxEqual(all[7]));
    taper.frustumTaper *= 1 + 1e-3;
    EXPECT_FALSE(Transform(taper).isApproxEqual(all[7]));
}

TEST(Transform, VoxelSizeIsTheLengthOfEachAxisImage) {
    Transform xform;
    xform.preScale(Vec3d(2, 3, 4));
    xform.postRotate(0.3, Axis::X);
    xform.postRotate(1.1, Axis::Z);
    xform.postTranslate(Vec3d(5, 6, 7));
    EXPECT_EQ(xform.mapType(), MapType::Affine);
    EXPECT_TRUE(isApproxEqual(xform.voxelSize(), Vec3d(2, 3, 4), 1e-14));
    EXPECT_NEAR(xform.voxelVolume(), 24.0, 1e-12);
    EXPECT_FALSE(xform.hasUniformScale());

    Transform uniform;
    uniform.preScale(0.2);
    uniform.postRotate(0.4, Axis::Y);
    EXPECT_TRUE(uniform.hasUniformScale());
    uniform.preMult(Mat4d::scale(Vec3d(1, 1, 1.001)));
    EXPECT_FALSE(uniform.hasUniformScale());
}

TEST(Transform, DirectionsMapWithoutTranslation) {
    std::mt19937 rng(3);
    for (const Transform& xform : oneOfEachMapType()) {
        if (!xform.isLinear()) {
            EXPECT_THROW((void)xform.indexToWorldDirection(Vec3d(1, 0, 0)), ValueError);
            EXPECT_THROW((void)xform.worldToIndexDirection(Vec3d(1, 0, 0)), ValueError);
            continue;
        }
        for (int n = 0; n < 100; ++n) {
            const Vec3d p = randomVec(rng, -10, 10), v = randomVec(rng, -10, 10);
            const Vec3d image = xform.indexToWorld(p + v) - xform.indexToWorld(p);
            ASSERT_TRUE(isApproxEqual(xform.indexToWorldDirection(v), image, 1e-9)) << xform;
            ASSERT_TRUE(
                isApproxEqual(xform.worldToIndexDirection(xform.indexToWorldDirection(v)), v, 1e-9))
                << xform;
        }
    }
}

TEST(Transform, IndexBoxImageHoldsEveryInteriorPointAndTouchesEachFace) {
    std::mt19937 rng(4);
    for (const Transform& xform : oneOfEachMapType()) {
        const BBoxd indexBox(Vec3d(-10, -5, 0), Vec3d(30, 15, 50));
        const BBoxd worldBox = xform.indexToWorld(indexBox);
        BBoxd padded = worldBox;
        padded.expand(1e-9);
        BBoxd sampled;
        for (int n = 0; n < 2000; ++n) {
            const Vec3d p = indexBox.min() + randomVec(rng, 0, 1) * indexBox.extents();
            ASSERT_TRUE(padded.isInside(xform.indexToWorld(p))) << xform;
        }
        // The corners alone attain the box.
        for (double x : {-10.0, 30.0}) {
            for (double y : {-5.0, 15.0}) {
                for (double z : {0.0, 50.0})
                    sampled.expand(xform.indexToWorld(Vec3d(x, y, z)));
            }
        }
        EXPECT_EQ(sampled, worldBox);
        EXPECT_EQ(xform.indexToWorld(CoordBBox(Coord(-10, -5, 0), Coord(30, 15, 50))), worldBox);
        EXPECT_TRUE(xform.indexToWorld(BBoxd()).empty());
    }
}

TEST(Transform, WorldBoxMapsToIndexBoxesByCorners) {
    const Transform::Ptr xform = Transform::createLinearTransform(0.5);
    xform->postTranslate(Vec3d(0.25));
    const BBoxd world(Vec3d(0.25, 0.25, 0.25), Vec3d(1.5, 2.0, 2.375));
    EXPECT_EQ(xform->worldToIndex(world), BBoxd(Vec3d(0), Vec3d(2.5, 3.5, 4.25)));
    EXPECT_EQ(xform->worldToIndexCellCentered(world), CoordBBox(Coord(0), Coord(3, 4, 4)));
    EXPECT_EQ(xform->worldToIndexNodeCentered(world), CoordBBox(Coord(0), Coord(2, 3, 4)));
    EXPECT_TRUE(xform->worldToIndexCellCentered(BBoxd()).empty());
}

TEST(Transform, FrustumNearFaceIsOneUnitWideAndFarFaceOneOverTaper) {
    // Box 40 x 20 x 50 voxels from (-10, -5, 0); taper 0.4; depth 2.5 near-face widths.
    const BBoxd box(Vec3d(-10, -5, 0), Vec3d(30, 15, 50));
    const Transform::Ptr xform = Transform::createFrustumTransform(box, 0.4, 2.5);
    EXPECT_EQ(xform->mapType(), MapType::NonlinearFrustum);
    EXPECT_FALSE(xform->isLinear());
    const auto at = [&](double x, double y, double z) {
        return xform->indexToWorld(Vec3d(x, y, z));
    };
    // Near face (z = 0): x spans [-0.5, 0.5], y spans [-0.25, 0.25] (aspect 20 / 40), z = 0.
    EXPECT_TRUE(isApproxEqual(at(-10, -5, 0), Vec3d(-0.5, -0.25, 0), 1e-15));
    EXPECT_TRUE(isApproxEqual(at(30, 15, 0), Vec3d(0.5, 0.25, 0), 1e-15));
    EXPECT_TRUE(isApproxEqual(at(10, 5, 0), Vec3d(0, 0, 0), 1e-15));
    // Far face (z = 50): 1 / taper = 2.5 units wide, at depth 2.5.
    EXPECT_TRUE(isApproxEqual(at(-10, -5, 50), Vec3d(-1.25, -0.625, 2.5), 1e-14));
    EXPECT_TRUE(isApproxEqual(at(30, 15, 50), Vec3d(1.25, 0.625, 2.5), 1e-14));
    // Halfway in index z is halfway in depth, with the width interpolated linearly.
    EXPECT_TRUE(isApproxEqual(at(30, 5, 25), Vec3d(0.875, 0, 1.25), 1e-14));
    // The voxel size reported is the one at the center of the near face.
    EXPECT_TRUE(isApproxEqual(xform->voxelSize(), Vec3d(1.0 / 40, 1.0 / 40, 2.5 / 50), 1e-15));

    // The voxelSize argument scales the world after the frustum.
    const Transform::Ptr scaled = Transform::createFrustumTransform(box, 0.4, 2.5, 3.0);
    EXPECT_TRUE(
        isApproxEqual(scaled->indexToWorld(Vec3d(30, 15, 50)), Vec3d(3.75, 1.875, 7.5), 1e-13));
}

TEST(Transform, FrustumVoxelSizeAndVolumeMatchFiniteDifferences) {
    const Transform xform = oneOfEachMapType()[7];
    std::mt19937 rng(5);
    const double h = 1e-5;
    for (int n = 0; n < 100; ++n) {
        const Vec3d ijk = Vec3d(-10, -5, 0) + randomVec(rng, 0, 1) * Vec3d(40, 20, 50);
        const Vec3d p = xform.indexToWorld(ijk);
        const Vec3d ex = xform.indexToWorld(ijk + Vec3d(1, 0, 0)) - p;
        const Vec3d ey = xform.indexToWorld(ijk + Vec3d(0, 1, 0)) - p;
        const Vec3d ez = xform.indexToWorld(ijk + Vec3d(0, 0, 1)) - p;
        ASSERT_TRUE(isApproxEqual(xform.voxelSize(ijk),
                                  Vec3d(ex.length(), ey.length(), ez.length()), 1e-12));
        // Volume: the Jacobian determinant, from central differences with a small step.
        const auto d = [&](const Vec3d& e) {
            return (xform.indexToWorld(ijk + e * h) - xform.indexToWorld(ijk - e * h)) / (2 * h);
        };
        const double volume =
            std::abs(d(Vec3d(1, 0, 0)).cross(d(Vec3d(0, 1, 0))).dot(d(Vec3d(0, 0, 1))));
        ASSERT_NEAR(xform.voxelVolume(ijk), volume, 1e-6 * volume);
    }
}

TEST(Transform, FrustumEditsActOnTheLinearSecondMap) {
    const BBoxd box(Vec3d(0), Vec3d(10));
    const Transform::Ptr xform = Transform::createFrustumTransform(box, 0.5, 1.0);
    const Transform before = *xform;
    const Vec3d ijk(3, 4, 5);
    xform->postTranslate(Vec3d(1, 2, 3));
    EXPECT_TRUE(
        isApproxEqual(xform->indexToWorld(ijk), before.indexToWorld(ijk) + Vec3d(1, 2, 3), 1e-15));
    // As in OpenVDB, a pre-edit of a frustum transform composes before the second map, which
    // is still after the frustum itself.
    xform->preScale(2.0);
    EXPECT_TRUE(isApproxEqual(xform->indexToWorld(ijk),
                              before.indexToWorld(ijk) * 2.0 + Vec3d(1, 2, 3), 1e-15));
    EXPECT_EQ(xform->mapType(), MapType::NonlinearFrustum);
    EXPECT_EQ(xform->mapParams().frustumBBox, box);
}

TEST(Transform, FrustumWithTaperOneAndMatchingBoxIsIdentity) {
    // The unit-wide, unit-deep box centered on the z axis maps to itself when taper is 1.
    const Transform::Ptr xform =
        Transform::createFrustumTransform(BBoxd(Vec3d(-0.5, -0.5, 0), Vec3d(0.5, 0.5, 1)), 1, 1);
    EXPECT_TRUE(xform->isIdentity());
    EXPECT_FALSE(Transform::createFrustumTransform(BBoxd(Vec3d(0), Vec3d(1)), 1, 1)->isIdentity());
    EXPECT_FALSE(xform->hasUniformScale());
}

TEST(Transform, LargeIndexCoordinatesMapExactlyWithUnitScale) {
    const Int32 big = std::numeric_limits<Int32>::max(), small = std::numeric_limits<Int32>::min();
    Transform xform;
    xform.postTranslate(Vec3d(0.5));
    EXPECT_EQ(xform.indexToWorld(Coord(big, small, 0)), Vec3d(big + 0.5, small + 0.5, 0.5));
    EXPECT_EQ(xform.worldToIndexNodeCentered(Vec3d(big + 0.5, small + 0.5, 0.5)),
              Coord(big, small, 0));
}

TEST(Transform, CopyIsIndependentAndStreamsItsMap) {
    const Transform::Ptr a = Transform::createLinearTransform(2.0);
    const Transform::Ptr b = a->copy();
    b->postTranslate(Vec3d(1, 0, 0));
    EXPECT_EQ(a->mapType(), MapType::UniformScale);
    EXPECT_EQ(b->mapType(), MapType::UniformScaleTranslate);
    std::ostringstream os;
    os << *b;
    EXPECT_EQ(os.str(), "UniformScaleTranslateMap: scale [2, 2, 2] translation [1, 0, 0]");
}

}  // namespace
}  // namespace vdb::math
