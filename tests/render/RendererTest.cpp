// SPDX-License-Identifier: Apache-2.0
// Oracles: the analytic silhouette of a sphere (a disc of the sphere's radius under an
// orthographic camera; under a perspective camera on the axis, a disc whose angular radius is
// asin(r / d)); camera geometry from the definitions (ray through the image centre, corners of
// a framed box inside the image); images rendered with one thread and with many compared bit
// for bit.

#include <vdb/render/Camera.h>
#include <vdb/render/Image.h>
#include <vdb/render/Renderer.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/vdb.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>

namespace vdb::render {
namespace {

size_t coveredPixels(const Image& image) {
    size_t n = 0;
    for (const Rgba& p : image.pixels())
        n += p.a > 0.5f;
    return n;
}

LevelSetRenderSettings transparentBackground() {
    LevelSetRenderSettings settings;
    settings.background = Rgba{0, 0, 0, 0};
    return settings;
}

TEST(Camera, CentreRayLooksAtTheTargetAndFramingHoldsTheBox) {
    const PerspectiveCamera camera(64, 48, Vec3d(1, 2, 3), Vec3d(1, 2, -7));
    const math::Ray<double> centre = camera.ray(32.0, 24.0);
    EXPECT_TRUE(math::isApproxEqual(centre.dir(), Vec3d(0, 0, -1), 1e-12));
    EXPECT_EQ(centre.eye(), Vec3d(1, 2, 3));
    // The top-left corner ray leans up and left by the field of view.
    const Vec3d corner = camera.ray(0.0, 0.0).dir();
    EXPECT_LT(corner[0], 0.0);
    EXPECT_GT(corner[1], 0.0);
    EXPECT_NEAR(corner[1] / -corner[2], std::tan(20.0 * std::numbers::pi / 180.0), 1e-12);

    const BBoxd box(Vec3d(-1, 0, 2), Vec3d(3, 1, 2.5));
    for (const Vec3d& view : {Vec3d(0, 0, -1), Vec3d(1, -1, -1), Vec3d(-0.3, 0.2, 1)}) {
        const PerspectiveCamera p = PerspectiveCamera::frame(box, 80, 40, view);
        const OrthographicCamera o = OrthographicCamera::frame(box, 40, 80, view);
        for (int c = 0; c < 8; ++c) {
            const Vec3d corner((c & 1 ? box.max() : box.min())[0],
                               (c & 2 ? box.max() : box.min())[1],
                               (c & 4 ? box.max() : box.min())[2]);
            // Perspective: the corner's direction is inside both fields of view.
            const Vec3d v = corner - p.position();
            const double depth = v.dot(p.forward());
            ASSERT_GT(depth, 0.0);
            EXPECT_LE(std::abs(v.dot(p.up()) / depth), p.tanHalfFov() + 1e-12);
            EXPECT_LE(std::abs(v.dot(p.right()) / depth), p.tanHalfFov() * 2.0 + 1e-12);
            // Orthographic: inside the window, in front of the eye plane.
            const Vec3d w = corner - o.position();
            EXPECT_GT(w.dot(o.forward()), 0.0);
            EXPECT_LE(std::abs(w.dot(o.up())), 0.5 * o.frameHeight() + 1e-12);
            EXPECT_LE(std::abs(w.dot(o.right())), 0.25 * o.frameHeight() + 1e-12);
        }
    }
    EXPECT_THROW(PerspectiveCamera(0, 10, Vec3d(0), Vec3d(1, 0, 0)), ValueError);
    EXPECT_THROW(PerspectiveCamera(10, 10, Vec3d(0), Vec3d(0, 5, 0)), ValueError);  // up along view
    EXPECT_THROW(OrthographicCamera(10, 10, Vec3d(0), Vec3d(0)), ValueError);
    EXPECT_THROW(PerspectiveCamera::frame(BBoxd(), 10, 10), ValueError);
}

TEST(Renderer, OrthographicSphereCoversItsDisc) {
    const float radius = 2.0f, dx = 0.04f;
    auto sphere = tools::createLevelSetSphere<FloatGrid>(radius, Vec3f(0.5f, -0.25f, 1.0f), dx);
    const size_t w = 200, h = 150;
    const double frame = 6.0;  // world units across the image height
    const OrthographicCamera camera(w, h, Vec3d(0.5, -0.25, 10.0), Vec3d(0.5, -0.25, 1.0),
                                    Vec3d(0, 1, 0), frame);
    const Image image = renderLevelSet(*sphere, camera, transparentBackground());
    const double pixel = frame / double(h);
    const double expected = std::numbers::pi * radius * radius / (pixel * pixel);
    EXPECT_NEAR(double(coveredPixels(image)), expected, 0.02 * expected);
}

TEST(Renderer, PerspectiveSphereCoversTheProjectedDisc) {
    const float radius = 1.5f, dx = 0.03f;
    auto sphere = tools::createLevelSetSphere<FloatGrid>(radius, Vec3f(0.0f), dx);
    const size_t w = 240, h = 180;
    const double distance = 6.0, fov = 45.0;
    const PerspectiveCamera camera(w, h, Vec3d(0.0, 0.0, distance), Vec3d(0.0), Vec3d(0, 1, 0),
                                   fov);
    const Image image = renderLevelSet(*sphere, camera, transparentBackground());
    // The silhouette cone has half angle asin(r / d); on the image plane at unit distance that
    // is a disc of radius tan(asin(r / d)), and the image spans 2 tan(fov / 2) vertically.
    const double discRadius = std::tan(std::asin(radius / distance));
    const double pixel = 2.0 * std::tan(0.5 * fov * std::numbers::pi / 180.0) / double(h);
    const double expected = std::numbers::pi * discRadius * discRadius / (pixel * pixel);
    EXPECT_NEAR(double(coveredPixels(image)), expected, 0.02 * expected);
}

TEST(Renderer, NormalsImageHoldsUnitNormalsFacingTheCamera) {
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.05f);
    const PerspectiveCamera camera(48, 48, Vec3d(0.0, 0.0, 4.0), Vec3d(0.0));
    Image normals;
    const Image image = renderLevelSet(*sphere, camera, transparentBackground(), &normals);
    ASSERT_EQ(normals.width(), 48u);
    size_t hits = 0;
    for (size_t y = 0; y < 48; ++y)
        for (size_t x = 0; x < 48; ++x) {
            const Rgba& n = normals(x, y);
            EXPECT_EQ(n.a, image(x, y).a);
            if (n.a == 0.0f)
                continue;
            ++hits;
            const Vec3d v(2.0 * n.r - 1.0, 2.0 * n.g - 1.0, 2.0 * n.b - 1.0);
            EXPECT_NEAR(v.length(), 1.0, 1e-5);
            EXPECT_GT(v[2], -0.05);  // visible points face the camera (+z)
        }
    EXPECT_GT(hits, 300u);
}

// A fog ball: density 1 - |p| / radius inside a radius, tiles in a cube at the centre.
FloatGrid::Ptr makeFogBall(int radius) {
    auto grid = FloatGrid::create(0.0f);
    grid->setTransform(math::Transform::createLinearTransform(0.05));
    grid->setGridClass(GRID_FOG_VOLUME);
    auto acc = grid->getAccessor();
    for (int i = -radius; i <= radius; ++i)
        for (int j = -radius; j <= radius; ++j)
            for (int k = -radius; k <= radius; ++k) {
                const double r = std::sqrt(double(i * i + j * j + k * k));
                if (r < radius)
                    acc.setValue(Coord(i, j, k), float(1.0 - r / radius));
            }
    grid->tree().fill(CoordBBox(Coord(-8), Coord(7)), 1.0f, true);
    return grid;
}

TEST(Renderer, ImagesDoNotDependOnTheThreadCount) {
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.1f), 0.02f);
    auto fog = makeFogBall(24);
    const auto box = sphere->transform().indexToWorld(sphere->evalActiveVoxelBoundingBox());
    const PerspectiveCamera camera = PerspectiveCamera::frame(box, 67, 45, Vec3d(-1, -0.4, -1));
    VolumeRenderSettings fogSettings;
    fogSettings.extinction = 20.0;
    fogSettings.tileSize = 8;
    LevelSetRenderSettings lsSettings;
    lsSettings.tileSize = 8;
    Image ls[3], normals[3], vol[3];
    for (int run = 0; run < 3; ++run) {
        // One thread, the default arena, and single-threaded code.
        const size_t threads = run == 0 ? 1 : 8;
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        lsSettings.threaded = fogSettings.threaded = run != 2;
        ls[run] = renderLevelSet(*sphere, camera, lsSettings, &normals[run]);
        vol[run] = renderFogVolume(*fog, camera, fogSettings);
    }
    EXPECT_GT(coveredPixels(vol[0]), 0u);
    for (int run = 1; run < 3; ++run) {
        EXPECT_TRUE(ls[run] == ls[0]);
        EXPECT_TRUE(normals[run] == normals[0]);
        EXPECT_TRUE(vol[run] == vol[0]);
    }
}

TEST(Renderer, FogIsDarkerWhereShadowed) {
    // Lit from +x: the far (-x) side of the ball, seen from -z... compare a shadowless render.
    auto fog = makeFogBall(20);
    const auto box = fog->transform().indexToWorld(fog->evalActiveVoxelBoundingBox());
    const OrthographicCamera camera = OrthographicCamera::frame(box, 32, 32, Vec3d(0, 0, -1));
    VolumeRenderSettings settings;
    settings.extinction = 30.0;
    settings.lightDirection = Vec3d(1, 0, 0);
    const Image shadowed = renderFogVolume(*fog, camera, settings);
    settings.shadows = false;
    const Image lit = renderFogVolume(*fog, camera, settings);
    // Without shadows the image is symmetric in x; with them the side towards the light
    // (right, +x) is brighter than the far side.
    const Rgba& right = shadowed(22, 16);
    const Rgba& left = shadowed(9, 16);
    EXPECT_GT(right.r, 1.5f * left.r);
    EXPECT_NEAR(lit(22, 16).r, lit(9, 16).r, 1e-3);
    EXPECT_NEAR(lit(22, 16).a, shadowed(22, 16).a, 1e-6);  // alpha is the primary ray's alone
    for (size_t i = 0; i < lit.pixels().size(); ++i)
        EXPECT_LE(shadowed.pixels()[i].r, lit.pixels()[i].r + 1e-6f);
}

TEST(Image, ConvertsToEightBitSrgb) {
    Image image(2, 1);
    image(0, 0) = Rgba{0.0f, 1.0f, 2.0f, 0.5f};
    image(1, 0) = Rgba{0.5f, 0.0031308f, -1.0f, 1.0f};
    const auto bytes = image.toRgba8();
    ASSERT_EQ(bytes.size(), 8u);
    EXPECT_EQ(bytes[0], 0);
    EXPECT_EQ(bytes[1], 255);
    EXPECT_EQ(bytes[2], 255);  // clamped
    EXPECT_EQ(bytes[3], 128);
    EXPECT_EQ(bytes[4], 188);  // sRGB(0.5) = 0.7354
    EXPECT_EQ(bytes[5], 10);   // 0.0031308 * 12.92 * 255 = 10.3
    EXPECT_EQ(bytes[6], 0);
    EXPECT_EQ(image.toRgba8(false)[4], 128);
    // Transparent pixels carry no colour.
    image(0, 0) = Rgba{1.0f, 1.0f, 1.0f, 0.001f};
    EXPECT_EQ(image.toRgba8()[0], 0);
    EXPECT_EQ(image.toRgba8()[3], 0);
}

}  // namespace
}  // namespace vdb::render
