// SPDX-License-Identifier: Apache-2.0
// Oracles: Beer-Lambert transmittance and single-scattered sunlight through a box of constant
// density, computed by hand from the box's length (exact for the trilinear model along axes);
// a brute-force march of the density model (every 0.01 voxel, no tree walk, no skipping) for
// the hierarchical walk and its empty-space skipping; a march in world space through
// Transform::worldToIndex for non-cubic and sheared voxels; the values themselves for the
// statistics; renders with one and with many threads compared bit for bit.

#include <vdb/render/Camera.h>
#include <vdb/render/Renderer.h>
#include <vdb/render/VolumeRenderer.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/vdb.h>

#include <Oracles.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

namespace vdb::render {
namespace {

using RayD = math::Ray<double>;

/// A fog grid holding `density` on the index box `box` (active), zero elsewhere.
FloatGrid::Ptr makeFogBox(const CoordBBox& box, float density, math::Transform::Ptr xform) {
    auto grid = FloatGrid::create(0.0f);
    grid->setTransform(xform);
    grid->setGridClass(GRID_FOG_VOLUME);
    grid->tree().fill(box, density, true);
    return grid;
}

/// The density model of the renderer, written out directly: the trilinear interpolant of the
/// voxel values inside the cubes [v - 0.5, v + 0.5) of voxels that lie in leaves, the value of
/// an active tile inside its voxels, zero elsewhere; negative densities count as zero.
double modelDensity(const FloatGrid& grid, const Vec3d& ijk) {
    const auto& tree = grid.tree();
    const Coord v(Int32(std::floor(ijk[0] + 0.5)), Int32(std::floor(ijk[1] + 0.5)),
                  Int32(std::floor(ijk[2] + 0.5)));
    double d = 0.0;
    if (tree.probeConstLeaf(v)) {
        const Coord c(Int32(std::floor(ijk[0])), Int32(std::floor(ijk[1])),
                      Int32(std::floor(ijk[2])));
        const Vec3d u = ijk - Vec3d(c);
        // Trilinear by hand from the eight corner values.
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int k = 0; k < 2; ++k)
                    d += double(tree.getValue(c.offsetBy(a, b, k))) * (a ? u[0] : 1 - u[0]) *
                         (b ? u[1] : 1 - u[1]) * (k ? u[2] : 1 - u[2]);
    } else if (tree.isValueOn(v)) {
        d = double(tree.getValue(v));
    }
    return std::max(0.0, d);
}

/// The integral of the model density along `wRay` (unit direction) in world units, marched in
/// world space every `dt` world units (midpoints) over the part of the ray inside the world box
/// around the active voxels (two voxels wider), each point taken to index space by the
/// transform.
double bruteForceIntegral(const FloatGrid& grid, const RayD& wRay, double dt) {
    CoordBBox active = grid.evalActiveVoxelBoundingBox();
    active.expand(2);
    const BBoxd box = grid.transform().indexToWorld(active);
    double t0, t1;
    if (!wRay.intersects(box, t0, t1))
        return 0.0;
    t0 = std::max(t0, 0.0);
    double sum = 0.0;
    for (double t = t0 + 0.5 * dt; t < t1; t += dt)
        sum += modelDensity(grid, grid.transform().worldToIndex(wRay(t))) * dt;
    return sum;
}

/// A fog volume that exercises every kind of region: a smooth ball of leaves, active tiles
/// (constant), leaves whose values are all zero, negative values, and empty space between.
FloatGrid::Ptr makeMixedFog(double voxelSize) {
    auto grid = FloatGrid::create(0.0f);
    grid->setTransform(math::Transform::createLinearTransform(voxelSize));
    grid->setGridClass(GRID_FOG_VOLUME);
    auto acc = grid->getAccessor();
    for (int i = -20; i <= 20; ++i)
        for (int j = -20; j <= 20; ++j)
            for (int k = -20; k <= 20; ++k) {
                const double r = std::sqrt(double(i * i + j * j + k * k));
                if (r < 20.0)
                    acc.setValue(Coord(i, j, k), float((1.0 - r / 20.0) *
                                                       (1.0 + 0.3 * std::sin(0.7 * i + 0.3 * j))));
            }
    for (int i = 30; i < 54; ++i)  // active zeros: leaves without density
        for (int j = -12; j < 12; ++j)
            for (int k = -12; k < 12; ++k)
                acc.setValueOn(Coord(i, j, k), 0.0f);
    for (int i = -40; i < -30; ++i)  // negative values: no density either
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k)
                acc.setValue(Coord(i, j, k), -0.5f);
    grid->tree().fill(CoordBBox(Coord(-64, 32, -16), Coord(-1, 47, 15)), 0.6f, true);  // tiles
    return grid;
}

TEST(FogVolumeStats, RangeAndPositiveBoxMatchTheValues) {
    auto grid = makeMixedFog(0.1);
    ASSERT_GT(grid->tree().activeTileCount(), 0u);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    CoordBBox positive;
    for (auto it = grid->tree().cbeginValueOn(); it; ++it) {
        lo = std::min(lo, double(*it));
        hi = std::max(hi, double(*it));
        CoordBBox box;
        it.getBoundingBox(box);
        if (*it > 0.0f)
            positive.expand(box);
    }
    const FogVolumeStats stats = evalFogVolumeStats(*grid);
    EXPECT_EQ(stats.minValue, lo);
    EXPECT_EQ(stats.maxValue, hi);
    EXPECT_EQ(stats.positiveBBox, positive);
    EXPECT_EQ(stats.activeValues, grid->tree().activeVoxelCount());
    EXPECT_EQ(lo, -0.5);
    // The zero leaves lie outside the positive box, which the active box includes.
    EXPECT_LT(stats.positiveBBox.max()[0], 30);
    EXPECT_GE(grid->evalActiveVoxelBoundingBox().max()[0], 53);

    auto empty = FloatGrid::create(0.0f);
    empty->tree().fill(CoordBBox(Coord(0), Coord(20)), 0.0f, true);
    EXPECT_TRUE(evalFogVolumeStats(*empty).empty());
}

// An orthographic camera looking down -z at the centre of the index box `box` of `grid`,
// pixel (x, y) centred on index (x0 + (x + 0.5) * pixel, y0 - (y + 0.5) * pixel) in x and y.
struct BoxView {
    OrthographicCamera camera;
    double x0, y0, pixel;  // index units
};
BoxView lookDownZ(const CoordBBox& box, double dx, size_t n, double margin) {
    const double cx = 0.5 * (box.min()[0] + box.max()[0]), cy = 0.5 * (box.min()[1] + box.max()[1]);
    const double extent = double(box.dim()[0]) + 2.0 * margin;  // index units across the image
    const Vec3d eye(cx * dx, cy * dx, (box.max()[2] + 50) * dx);
    OrthographicCamera camera(n, n, eye, eye - Vec3d(0, 0, 1), Vec3d(0, 1, 0), extent * dx);
    return {camera, cx - 0.5 * extent, cy + 0.5 * extent, extent / double(n)};
}

TEST(VolumeRenderer, ConstantBoxAlphaIsBeerLambertPerPixel) {
    // Faces inside leaves, so the trilinear ramp at each face lies in a leaf: along z the
    // density integral is exactly density * (k1 - k0 + 1) voxels.
    const CoordBBox box(Coord(-13, -11, -13), Coord(12, 10, 12));
    const double dx = 0.1, density = 0.75;
    const double depth = 1.5;  // optical depth across the box along z
    const double sigma = depth / (density * 26 * dx);
    auto grid = makeFogBox(box, float(density), math::Transform::createLinearTransform(dx));
    const BoxView view = lookDownZ(box, dx, 64, 4.0);
    for (const double step : {0.05, 0.5}) {
        VolumeRenderSettings settings;
        settings.extinction = sigma;
        settings.step = step;
        settings.shadows = false;
        settings.lightColor = Rgba{0.7f, 0.5f, 0.3f, 1.0f};
        settings.ambientColor = Rgba{0.1f, 0.2f, 0.3f, 1.0f};
        const Image image = renderFogVolume(*grid, view.camera, settings);
        // Midpoint steps are exact on the plateau; where a step straddles a kink of the ramps
        // the error is at most a slope of 1 over step^2 / 8, at four kinks.
        const double tol = 4.0 * sigma * dx * density * step * step / 8.0 + 1e-5;
        int inside = 0, outside = 0;
        for (size_t y = 0; y < 64; ++y)
            for (size_t x = 0; x < 64; ++x) {
                const double i = view.x0 + (double(x) + 0.5) * view.pixel;
                const double j = view.y0 - (double(y) + 0.5) * view.pixel;
                const Rgba& p = image(x, y);
                if (i >= box.min()[0] && i <= box.max()[0] && j >= box.min()[1] &&
                    j <= box.max()[1]) {
                    ++inside;
                    ASSERT_NEAR(p.a, 1.0 - std::exp(-depth), tol) << x << "," << y;
                    // Unshadowed: the straight colour is the light reaching every point.
                    ASSERT_NEAR(p.r, 0.8, 1e-5);
                    ASSERT_NEAR(p.g, 0.7, 1e-5);
                    ASSERT_NEAR(p.b, 0.6, 1e-5);
                } else if (i < box.min()[0] - 1 || i > box.max()[0] + 1 || j < box.min()[1] - 1 ||
                           j > box.max()[1] + 1) {
                    ++outside;
                    ASSERT_EQ(p, (Rgba{0, 0, 0, 0})) << "transparent background at " << x;
                }
            }
        EXPECT_GT(inside, 1000);
        EXPECT_GT(outside, 100);
    }
}

// The profile of the trilinear interpolant of a box of voxels [lo, hi] along one axis: 1 on
// [lo, hi], falling linearly to 0 over the voxel beyond each end.
double boxProfile(double x, int lo, int hi) {
    return std::clamp(std::min(x - (lo - 1), (hi + 1) - x), 0.0, 1.0);
}

TEST(VolumeRenderer, SunlightThroughABoxFallsExponentiallyWithDepth) {
    // Camera down -z, sun towards +x. The density factors as density * r(x) r(y) r(z) (r the
    // box profile), so at a point (i, j, z) of the plateau in x and y the sun's optical depth
    // is sigma * dx * density * r(z) * (12.5 - i), and the pixel's straight colour is that
    // transmittance averaged along z with the weights T(z) sigma d(z) dz; a 1D integral.
    const CoordBBox box(Coord(-13, -11, -13), Coord(12, 10, 12));
    const double dx = 0.1, density = 0.5, sigma = 1.2;
    auto grid = makeFogBox(box, float(density), math::Transform::createLinearTransform(dx));
    const auto sunlit = [&](double i) {
        double T = 1.0, colour = 0.0;
        const double dz = 1e-3;
        for (double z = box.max()[2] + 1.0; z > box.min()[2] - 1.0; z -= dz) {
            const double d = density * boxProfile(z - 0.5 * dz, box.min()[2], box.max()[2]);
            const double stepT = std::exp(-sigma * dx * d * dz);
            colour += T * (1.0 - stepT) * std::exp(-sigma * dx * d * (12.5 - i));
            T *= stepT;
        }
        return colour / (1.0 - T);
    };
    const BoxView view = lookDownZ(box, dx, 32, 2.0);
    for (const bool cache : {true, false}) {
        VolumeRenderSettings settings;
        settings.extinction = sigma;
        settings.lightDirection = Vec3d(1, 0, 0);
        settings.lightCache = cache ? LightCache::On : LightCache::Off;
        settings.step = 0.2;
        // Steps short enough that the midpoint error at the ramp's kinks is below 1e-3.
        settings.shadowStep = cache ? 0.25 : 0.1;
        settings.cutoff = 1e-6;
        const Image image = renderFogVolume(*grid, view.camera, settings);
        int checked = 0;
        for (size_t y = 0; y < 32; ++y)
            for (size_t x = 0; x < 32; ++x) {
                const double i = view.x0 + (double(x) + 0.5) * view.pixel;
                const double j = view.y0 - (double(y) + 0.5) * view.pixel;
                if (i < box.min()[0] + 1 || i > box.max()[0] - 1 || j < box.min()[1] ||
                    j > box.max()[1])
                    continue;
                ++checked;
                // Cached, the light is interpolated linearly between voxel centres; across the
                // ramps at the z faces it rises from about 0.25 to 1 within one voxel, where a
                // line is off by up to 0.1, and those voxels weigh about 4% of the pixel.
                ASSERT_NEAR(image(x, y).r, sunlit(i), cache ? 6e-3 : 1e-3)
                    << "cache " << cache << " at index x " << i;
            }
        EXPECT_GT(checked, 250);
    }
}

TEST(VolumeRenderer, EmptySpaceSkippingMatchesABruteForceMarch) {
    const double dx = 0.05, sigma = 3.0;
    auto grid = makeMixedFog(dx);
    VolumeRenderSettings settings;
    settings.extinction = sigma;
    settings.step = 0.05;
    settings.shadows = false;
    VolumeRenderer<FloatGrid> renderer(*grid, settings);
    std::mt19937 rng(4711);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int crossing = 0;
    const int rays = test::scaledBatchCount(60);
    for (int n = 0; n < rays; ++n) {
        Vec3d dir(u(rng), u(rng), u(rng));
        if (dir.length() < 0.1)
            continue;
        dir = dir.unit();
        // Aim at the ball, the tiles or the zero leaves.
        const Vec3d targets[3] = {Vec3d(0, 0, 0), Vec3d(-32, 40, 0), Vec3d(42, 0, 0)};
        const Vec3d target = (targets[n % 3] + Vec3d(u(rng), u(rng), u(rng)) * 15.0) * dx;
        const RayD ray(target - dir * 5.0, dir, 0.0);
        const double expected = sigma * bruteForceIntegral(*grid, ray, 0.02 * dx);
        const double depth = renderer.opticalDepth(ray);
        crossing += expected > 0.01;
        ASSERT_NEAR(depth, expected, 2e-3 * expected + 1e-4) << ray;
    }
    EXPECT_GT(crossing, rays / 3);
}

TEST(VolumeRenderer, LightTreeMatchesMarchingTowardsTheSun) {
    const double dx = 0.05, sigma = 4.0;
    auto grid = makeMixedFog(dx);
    for (const Vec3d& light : {Vec3d(0.3, 1.0, -0.2), Vec3d(-1, -0.5, 0.7)}) {
        VolumeRenderSettings settings;
        settings.extinction = sigma;
        settings.lightDirection = light;
        settings.shadowStep = 0.05;
        settings.cutoff = 1e-9;
        VolumeRenderer<FloatGrid> renderer(*grid, settings);
        std::mt19937 rng(99);
        std::uniform_int_distribution<int> c(-18, 18);
        for (int n = 0; n < 40; ++n) {
            const Vec3d ijk(c(rng), c(rng), c(rng));
            // The brute-force march starts at the voxel centre and runs towards the sun.
            const Vec3d start = grid->transform().indexToWorld(ijk);
            const double expected = std::exp(
                -sigma * bruteForceIntegral(*grid, RayD(start, light.unit(), 0.0), 0.01 * dx));
            ASSERT_NEAR(renderer.lightTransmittance(ijk), expected, 2e-3) << ijk;
        }
        // Rendered with the light tree and with a march per sample: the same picture, up to
        // the interpolation of the light between voxel centres.
        const auto box = evalFogVolumeStats(*grid).worldBBox(grid->transform());
        const auto camera = PerspectiveCamera::frame(box, 40, 30, Vec3d(-1, -0.4, -0.8));
        settings.shadowStep = 0.5;
        settings.lightCache = LightCache::On;
        const Image cached = renderFogVolume(*grid, camera, settings);
        settings.lightCache = LightCache::Off;
        const Image marched = renderFogVolume(*grid, camera, settings);
        double worst = 0.0;
        for (size_t i = 0; i < cached.pixels().size(); ++i) {
            const Rgba &a = cached.pixels()[i], &b = marched.pixels()[i];
            ASSERT_EQ(a.a, b.a);  // alpha is the primary rays' alone
            worst = std::max(worst, double(std::abs(a.r - b.r) * a.a));
        }
        EXPECT_LT(worst, 0.03);
        EXPECT_GT(worst, 0.0);  // two different methods
    }
}

TEST(VolumeRenderer, NonCubicAndShearedVoxelsGiveTheWorldSpaceAnswer) {
    const CoordBBox box(Coord(-13, -11, -12), Coord(12, 10, 11));
    const double density = 0.8, sigma = 1.7;
    // A scale map with unequal sides, and an affine map with a rotation and a shear.
    auto scale = math::Transform::createLinearTransform(0.1);
    scale->preScale(Vec3d(1.0, 2.0, 0.5));
    ASSERT_FALSE(scale->hasUniformScale());
    Mat4d m = Mat4d::identity();
    m(0, 0) = 0.08;
    m(1, 0) = 0.03;  // shear: index y moves world x
    m(1, 1) = 0.15;
    m(2, 2) = 0.06;
    m(2, 1) = 0.02;
    auto affine = math::Transform::createLinearTransform(m);
    affine->postRotate(0.4, math::Axis::Y);
    affine->postTranslate(Vec3d(0.3, -0.2, 0.1));
    for (const auto& xform : {scale, affine}) {
        auto grid = makeFogBox(box, float(density), xform);
        VolumeRenderSettings settings;
        settings.extinction = sigma;
        settings.step = 0.05;
        settings.shadows = false;
        VolumeRenderer<FloatGrid> renderer(*grid, settings);
        std::mt19937 rng(17);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        const Vec3d centre = xform->indexToWorld(Vec3d(0.0));
        for (int n = 0; n < 60; ++n) {
            Vec3d dir(u(rng), u(rng), u(rng));
            if (dir.length() < 0.1)
                continue;
            dir = dir.unit();
            const RayD ray(centre + Vec3d(u(rng), u(rng), u(rng)) * 0.6 - dir * 6.0, dir, 0.0);
            const double expected = sigma * bruteForceIntegral(*grid, ray, 0.001);
            ASSERT_NEAR(renderer.opticalDepth(ray), expected, 2e-3 * expected + 1e-4) << ray;
        }
        // Along a world axis through a scale map's box, the length is the box's in world units.
        if (xform == scale) {
            const Vec3d eye = xform->indexToWorld(Vec3d(0.0, 0.0, 40.0));
            const double world = 24.0 * 0.05;  // 24 voxels of 0.05 along z
            EXPECT_NEAR(renderer.opticalDepth(RayD(eye, Vec3d(0, 0, -1), 0.0)),
                        sigma * density * world, 1e-3);
        }
    }
}

TEST(VolumeRenderer, ImagesDoNotDependOnTheThreadCountWithEitherLight) {
    auto grid = makeMixedFog(0.05);
    grid->transform().preScale(Vec3d(1.0, 1.5, 0.8));
    const auto box = evalFogVolumeStats(*grid).worldBBox(grid->transform());
    const PerspectiveCamera camera = PerspectiveCamera::frame(box, 53, 41, Vec3d(-1, -0.4, -1));
    for (const bool cache : {true, false}) {
        VolumeRenderSettings settings;
        settings.extinction = 6.0;
        settings.tileSize = 8;
        settings.lightCache = cache ? LightCache::On : LightCache::Off;
        settings.ambientColor = Rgba{0.2f, 0.2f, 0.2f, 1.0f};
        Image image[3];
        for (int run = 0; run < 3; ++run) {
            const size_t threads = run == 0 ? 1 : 8;
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
            settings.threaded = run != 2;
            image[run] = renderFogVolume(*grid, camera, settings);
        }
        size_t covered = 0;
        for (const Rgba& p : image[0].pixels())
            covered += p.a > 0.1f;
        EXPECT_GT(covered, 100u);
        EXPECT_TRUE(image[1] == image[0]);
        EXPECT_TRUE(image[2] == image[0]);
    }
}

TEST(VolumeRenderer, CopiesOnThreadsFillTheSharedLightTreeAlike) {
    // Renderer copies on plain threads (no oneTBB, so that ThreadSanitizer sees every access)
    // shade the same rays at once, racing to march the same voxels of the light tree; each
    // must see what one renderer alone sees.
    auto grid = makeMixedFog(0.05);
    VolumeRenderSettings settings;
    settings.extinction = 5.0;
    settings.lightCache = LightCache::On;
    settings.threaded = false;
    const auto box = evalFogVolumeStats(*grid, false).worldBBox(grid->transform());
    const PerspectiveCamera camera = PerspectiveCamera::frame(box, 24, 18, Vec3d(-1, -0.4, -1));
    std::vector<Rgba> alone;
    {
        VolumeRenderer<FloatGrid> renderer(*grid, settings);
        for (size_t y = 0; y < 18; ++y)
            for (size_t x = 0; x < 24; ++x)
                alone.push_back(renderer.shade(camera.ray(x + 0.5, y + 0.5)));
    }
    const VolumeRenderer<FloatGrid> prototype(*grid, settings);
    std::vector<std::vector<Rgba>> seen(4);
    std::vector<std::thread> threads;
    for (size_t t = 0; t < seen.size(); ++t)
        threads.emplace_back([&, t] {
            VolumeRenderer<FloatGrid> renderer(prototype);
            for (size_t y = 0; y < 18; ++y)
                for (size_t x = 0; x < 24; ++x)
                    seen[t].push_back(renderer.shade(camera.ray(x + 0.5, y + 0.5)));
        });
    for (auto& thread : threads)
        thread.join();
    for (const auto& s : seen)
        EXPECT_TRUE(s == alone);
}

TEST(VolumeRenderer, BackgroundIsCompositedBehindAStraightColour) {
    const CoordBBox box(Coord(-5), Coord(5));
    auto grid = makeFogBox(box, 1.0f, math::Transform::createLinearTransform(0.1));
    const BoxView view = lookDownZ(box, 0.1, 16, 3.0);
    VolumeRenderSettings settings;
    settings.extinction = 1.0;  // optical depth 1.1 through the 11 voxels of 0.1
    settings.step = 0.05;
    settings.shadows = false;
    settings.lightColor = Rgba{1.0f, 0.0f, 0.0f, 1.0f};
    settings.background = Rgba{0.0f, 0.0f, 1.0f, 0.5f};
    const Image image = renderFogVolume(*grid, view.camera, settings);
    const Rgba& centre = image(8, 8);
    const double T = std::exp(-1.1);
    // Premultiplied: red (1 - T) over blue with alpha 0.5 seen through T.
    const double alpha = (1.0 - T) + T * 0.5;
    EXPECT_NEAR(centre.a, alpha, 1e-3);
    EXPECT_NEAR(centre.r, (1.0 - T) / alpha, 1e-3);
    EXPECT_NEAR(centre.b, T * 0.5 / alpha, 1e-3);
    EXPECT_EQ(image(0, 0), (Rgba{0.0f, 0.0f, 1.0f, 0.5f}));  // the background alone
}

TEST(VolumeRenderer, SuggestedExtinctionMakesTheQuantileRayReachTheDepth) {
    // Two slabs side by side along x: density 1 and 3, 20 voxels deep along z. Looking down z,
    // the rays that meet density have integral 2 (world) or 6; the 90th percentile is 6.
    const double dx = 0.1;
    auto grid = makeFogBox(CoordBBox(Coord(-20, -10, -10), Coord(-1, 9, 9)), 1.0f,
                           math::Transform::createLinearTransform(dx));
    grid->tree().fill(CoordBBox(Coord(0, -10, -10), Coord(19, 9, 9)), 3.0f, true);
    const auto box = evalFogVolumeStats(*grid).worldBBox(grid->transform());
    const OrthographicCamera camera(100, 100, Vec3d(0, 0, 5), Vec3d(0, 0, 0), Vec3d(0, 1, 0),
                                    box.extents()[0] * 1.2);
    const double sigma = suggestExtinction(*grid, camera, 4.0, 0.9, 50);
    EXPECT_NEAR(sigma, 4.0 / (3.0 * 20 * dx), 0.02 * sigma);
    EXPECT_NEAR(suggestExtinction(*grid, camera, 4.0, 0.2, 50), 4.0 / (1.0 * 20 * dx), 0.02 * 2);
    // No probe meets the volume: 0.
    const OrthographicCamera away(10, 10, Vec3d(0, 0, 5), Vec3d(0, 0, 10), Vec3d(0, 1, 0), 1.0);
    EXPECT_EQ(suggestExtinction(*grid, away), 0.0);
    EXPECT_THROW(suggestExtinction(*grid, camera, std::nan("")), ValueError);
    EXPECT_THROW(suggestExtinction(*grid, camera, 4.0, 0.0), ValueError);
}

TEST(VolumeRenderer, RejectsSettingsThatAreNotFiniteOrInRange) {
    auto grid = makeFogBox(CoordBBox(Coord(0), Coord(3)), 1.0f,
                           math::Transform::createLinearTransform(1.0));
    const auto bad = [&](auto edit) {
        VolumeRenderSettings s;
        edit(s);
        EXPECT_THROW((VolumeRenderer<FloatGrid>(*grid, s)), ValueError);
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    bad([&](VolumeRenderSettings& s) { s.step = nan; });
    bad([&](VolumeRenderSettings& s) { s.step = 0.0; });
    bad([&](VolumeRenderSettings& s) { s.shadowStep = inf; });
    bad([&](VolumeRenderSettings& s) { s.extinction = nan; });
    bad([&](VolumeRenderSettings& s) { s.extinction = -1.0; });
    bad([&](VolumeRenderSettings& s) { s.cutoff = 1.0; });
    bad([&](VolumeRenderSettings& s) { s.lightDirection = Vec3d(nan, 0, 0); });
    bad([&](VolumeRenderSettings& s) { s.lightDirection = Vec3d(0.0); });
    // A frustum transform.
    grid->setTransform(
        math::Transform::createFrustumTransform(BBoxd(Vec3d(0.0), Vec3d(10.0)), 0.5, 2.0, 0.1));
    EXPECT_THROW((VolumeRenderer<FloatGrid>(*grid, VolumeRenderSettings{})), ValueError);
}

}  // namespace
}  // namespace vdb::render
