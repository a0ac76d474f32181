// SPDX-License-Identifier: Apache-2.0
/// @file
/// Renderers of grids into images: renderLevelSet() ray-traces the zero surface of a level set
/// with diffuse shading from one directional light; renderFogVolume() integrates the
/// emission-absorption model through a fog volume (density grid) lit by one directional light
/// with shadow rays. Both are built on tools/RayIntersector.h, and so on the hierarchical DDA of
/// the paper's section 4.7.
///
/// The image is cut into square tiles rendered in parallel (oneTBB); every pixel is computed
/// from its own camera ray alone, so the image does not depend on the number of threads.
/// Pixels are sampled once, at their centres. The library returns the image; writing files is
/// left to the caller (the vdb tool writes PNG).
///
/// Volume model: with density d(s) along a ray, extinction sigma per world unit at density 1
/// and transmittance T(s) = exp(-integral of sigma d), the colour is the integral of
/// T(s) sigma d(s) albedo L(s) ds, where L(s) is the light's colour times the transmittance of
/// the shadow ray from s towards the light, plus T(end) times the background. The density is
/// taken constant over each step (trilinear at the step's midpoint), and each step's
/// transmittance is integrated exactly: exp(-sigma d ds). Steps are `step` voxels in leaves
/// and, over active tiles, as long as an eighth of the tile's edge (a tile's density is
/// constant, only the light varies). Marching stops once T falls below `cutoff`.
///
/// @code
/// auto camera = vdb::render::PerspectiveCamera::frame(worldBox, 640, 480, vdb::Vec3d(-1, -1, -1));
/// vdb::render::Image color = vdb::render::renderLevelSet(*sphere, camera);
/// vdb::render::Image fog = vdb::render::renderFogVolume(*density, camera);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/render/Camera.h>
#include <vdb/render/Image.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tools/RayIntersector.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace vdb::render {

/// Settings of renderLevelSet().
struct LevelSetRenderSettings {
    Vec3d lightDirection{0.5, 0.8, 0.6};        ///< world space, towards the light
    Rgba surfaceColor{0.85f, 0.78f, 0.66f, 1};  ///< diffuse reflectance (alpha unused)
    float lightIntensity = 1.0f;
    float ambient = 0.12f;                    ///< light reaching every point, shadowed or not
    Rgba background{0.0f, 0.0f, 0.0f, 1.0f};  ///< pixels whose ray misses the surface
    size_t tileSize = 16;                     ///< edge of the square tiles rendered as tasks
    bool threaded = true;
};

/// Settings of renderFogVolume() and VolumeRenderer.
struct VolumeRenderSettings {
    double extinction = 1.0;              ///< sigma: per world unit, at density 1
    Rgba albedo{1.0f, 1.0f, 1.0f, 1.0f};  ///< fraction of extinction that scatters light
    Vec3d lightDirection{0.5, 0.8, 0.6};  ///< world space, towards the light
    Rgba lightColor{1.0f, 1.0f, 1.0f, 1.0f};
    double step = 0.5;                        ///< primary step inside leaves, in voxels
    double shadowStep = 1.0;                  ///< shadow-ray step inside leaves, in voxels
    bool shadows = true;                      ///< cast shadow rays (else the light is unblocked)
    double cutoff = 1e-3;                     ///< transmittance below which marching stops
    Rgba background{0.0f, 0.0f, 0.0f, 1.0f};  ///< seen through the volume
    size_t tileSize = 16;
    bool threaded = true;
};

/// Ray-traces the zero level set of `grid` as seen by `camera`: a hit pixel gets
/// surfaceColor * (ambient + (1 - ambient) * lightIntensity * max(0, n . l)) with alpha 1;
/// other pixels get the background. When `normals` is given it receives, per hit pixel, the
/// world-space unit normal n as colour (n + 1) / 2 with alpha 1, and zero elsewhere.
/// @throw ValueError as LevelSetRayIntersector, or for a zero light direction or tile size.
template <typename GridT>
Image renderLevelSet(const GridT& grid, const Camera& camera,
                     const LevelSetRenderSettings& settings = {}, Image* normals = nullptr);

/// Renders the fog volume `grid` (values are densities, zero outside) as seen by `camera`,
/// with the model in the file comment.
/// @throw ValueError as VolumeRenderer.
template <typename GridT>
Image renderFogVolume(const GridT& grid, const Camera& camera,
                      const VolumeRenderSettings& settings = {});

/// The per-ray part of renderFogVolume(): colour and transmittance along one world-space ray.
///
/// Invariant: the grid outlives the renderer and is not modified while in use.
/// Threads: not thread-safe (intersectors and accessors cache tree paths); copy it per thread.
template <typename GridT>
class VolumeRenderer {
public:
    using RayType = math::Ray<double>;

    /// @throw ValueError for non-cubic voxels, a zero light direction, a step or shadow step
    ///   that is not positive, or a negative extinction.
    VolumeRenderer(const GridT& grid, const VolumeRenderSettings& settings);

    /// The colour seen along `wRay` from its t0 to its t1, composited over the background:
    /// alpha is 1 - T * (1 - background alpha) with T the ray's transmittance.
    Rgba shade(const RayType& wRay);
    /// The transmittance exp(-integral of sigma d) along `wRay` from its t0 to its t1, by the
    /// same steps as shade() (without the cutoff).
    double transmittance(const RayType& wRay);

private:
    using ValueType = typename GridT::ValueType;
    // The optical depth from index point p towards the light (shadow ray).
    double shadowDepth(const Vec3d& p, double maxDepth);
    // Steps of `segment` as (count, length in index units).
    template <typename SegmentT>
    void steps(const SegmentT& segment, double leafStep, size_t& n, double& ds) const;
    double density(const Vec3d& p) const { return double(tools::BoxSampler::sample(mAcc, p)); }

    const GridT* mGrid;
    VolumeRenderSettings mSettings;
    double mVoxelSize;  // world units per index unit
    Vec3d mIndexLight;  // unit, index space, towards the light
    tools::VolumeRayIntersector<GridT> mPrimary, mShadow;
    tree::ValueAccessor<const typename GridT::TreeType> mAcc;
};

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// Calls `shadePixel(x, y)` for every pixel, in square tiles of `tileSize` rendered as
/// parallel tasks; `makeState()` builds the per-task state passed as the third argument.
template <typename MakeStateT, typename ShadeT>
void forEachPixelInTiles(size_t width, size_t height, size_t tileSize, bool threaded,
                         const MakeStateT& makeState, const ShadeT& shadePixel) {
    if (tileSize == 0)
        throw ValueError("render: the tile size must be positive");
    const size_t tilesX = (width + tileSize - 1) / tileSize;
    const size_t tilesY = (height + tileSize - 1) / tileSize;
    util::parallelFor(
        tilesX * tilesY,
        [&](size_t tile) {
            auto state = makeState();
            const size_t x0 = (tile % tilesX) * tileSize, y0 = (tile / tilesX) * tileSize;
            const size_t x1 = std::min(width, x0 + tileSize), y1 = std::min(height, y0 + tileSize);
            for (size_t y = y0; y < y1; ++y)
                for (size_t x = x0; x < x1; ++x)
                    shadePixel(x, y, state);
        },
        threaded, /*grain=*/1);
}

inline Vec3d unitLight(const Vec3d& direction) {
    Vec3d l = direction;
    if (!l.normalize(0.0))
        throw ValueError("render: the light direction is zero");
    return l;
}

}  // namespace detail

template <typename GridT>
Image renderLevelSet(const GridT& grid, const Camera& camera,
                     const LevelSetRenderSettings& settings, Image* normals) {
    const tools::LevelSetRayIntersector<GridT> prototype(grid);
    const Vec3d light = detail::unitLight(settings.lightDirection);
    Image image(camera.width(), camera.height(), settings.background);
    if (normals)
        *normals = Image(camera.width(), camera.height());
    const float ambient = settings.ambient;
    detail::forEachPixelInTiles(
        camera.width(), camera.height(), settings.tileSize, settings.threaded,
        [&] { return prototype; },
        [&](size_t x, size_t y, tools::LevelSetRayIntersector<GridT>& intersector) {
            Vec3d xyz, n;
            if (!intersector.intersectsWS(camera.ray(double(x) + 0.5, double(y) + 0.5), xyz, n))
                return;
            const float diffuse = float(std::max(0.0, n.dot(light))) * settings.lightIntensity;
            const float shade = ambient + (1.0f - ambient) * diffuse;
            const Rgba& c = settings.surfaceColor;
            image(x, y) = Rgba{c.r * shade, c.g * shade, c.b * shade, 1.0f};
            if (normals) {
                (*normals)(x, y) = Rgba{float(0.5 * (n[0] + 1.0)), float(0.5 * (n[1] + 1.0)),
                                        float(0.5 * (n[2] + 1.0)), 1.0f};
            }
        });
    return image;
}

template <typename GridT>
Image renderFogVolume(const GridT& grid, const Camera& camera,
                      const VolumeRenderSettings& settings) {
    const VolumeRenderer<GridT> prototype(grid, settings);
    Image image(camera.width(), camera.height(), settings.background);
    detail::forEachPixelInTiles(
        camera.width(), camera.height(), settings.tileSize, settings.threaded,
        [&] { return prototype; },
        [&](size_t x, size_t y, VolumeRenderer<GridT>& renderer) {
            image(x, y) = renderer.shade(camera.ray(double(x) + 0.5, double(y) + 0.5));
        });
    return image;
}

template <typename GridT>
VolumeRenderer<GridT>::VolumeRenderer(const GridT& grid, const VolumeRenderSettings& settings)
    : mGrid(&grid),
      mSettings(settings),
      mVoxelSize(grid.voxelSize()[0]),
      mPrimary(grid),
      mShadow(grid),
      mAcc(grid.tree()) {
    if (!(settings.step > 0.0) || !(settings.shadowStep > 0.0))
        throw ValueError("VolumeRenderer: the steps must be positive");
    if (!(settings.extinction >= 0.0))
        throw ValueError("VolumeRenderer: the extinction must not be negative");
    const Vec3d light = detail::unitLight(settings.lightDirection);
    mIndexLight = grid.transform().worldToIndexDirection(light).unitSafe(0.0);
    mVoxelSize = grid.transform().indexToWorldDirection(Vec3d(1, 0, 0)).length();
}

template <typename GridT>
template <typename SegmentT>
void VolumeRenderer<GridT>::steps(const SegmentT& segment, double leafStep, size_t& n,
                                  double& ds) const {
    // Tiles are constant: their steps grow with the tile (an eighth of its edge).
    double step = leafStep;
    if (segment.constant)
        step = std::max(leafStep, double(Index64(1) << segment.log2Dim) / 8.0);
    const double length = segment.t1 - segment.t0;
    n = size_t(std::max(1.0, std::ceil(length / step)));
    ds = length / double(n);
}

template <typename GridT>
double VolumeRenderer<GridT>::shadowDepth(const Vec3d& p, double maxDepth) {
    double depth = 0.0;
    if (!mShadow.setIndexRay(RayType(p, mIndexLight, 0.0)))
        return 0.0;
    const double sigma = mSettings.extinction * mVoxelSize;  // per index unit
    typename tools::VolumeRayIntersector<GridT>::Segment seg;
    while (mShadow.march(seg)) {
        if (seg.constant) {
            depth += sigma * double(seg.value) * (seg.t1 - seg.t0);
        } else {
            size_t n;
            double ds;
            steps(seg, mSettings.shadowStep, n, ds);
            const RayType& ray = mShadow.getIndexRay();
            for (size_t k = 0; k < n; ++k)
                depth += sigma * density(ray(seg.t0 + (double(k) + 0.5) * ds)) * ds;
        }
        if (depth > maxDepth)
            break;
    }
    return depth;
}

template <typename GridT>
Rgba VolumeRenderer<GridT>::shade(const RayType& wRay) {
    const Rgba& bg = mSettings.background;
    double T = 1.0, r = 0.0, g = 0.0, b = 0.0;
    if (mPrimary.setWorldRay(wRay)) {
        const RayType ray = mPrimary.getIndexRay();
        const double sigma = mSettings.extinction * mVoxelSize;  // per index unit
        const double maxShadowDepth = -std::log(mSettings.cutoff);
        const Rgba& a = mSettings.albedo;
        const Rgba& lc = mSettings.lightColor;
        typename tools::VolumeRayIntersector<GridT>::Segment seg;
        while (T >= mSettings.cutoff && mPrimary.march(seg)) {
            size_t n;
            double ds;
            steps(seg, mSettings.step, n, ds);
            for (size_t k = 0; k < n && T >= mSettings.cutoff; ++k) {
                const Vec3d p = ray(seg.t0 + (double(k) + 0.5) * ds);
                const double d = seg.constant ? double(seg.value) : density(p);
                if (!(d > 0.0))
                    continue;
                const double stepT = std::exp(-sigma * d * ds);
                double light = 1.0;
                if (mSettings.shadows)
                    light = std::exp(-shadowDepth(p, maxShadowDepth));
                const double w = T * (1.0 - stepT) * light;
                r += w * a.r * lc.r;
                g += w * a.g * lc.g;
                b += w * a.b * lc.b;
                T *= stepT;
            }
        }
    }
    return Rgba{float(r + T * bg.r), float(g + T * bg.g), float(b + T * bg.b),
                float(1.0 - T * (1.0 - bg.a))};
}

template <typename GridT>
double VolumeRenderer<GridT>::transmittance(const RayType& wRay) {
    if (!mPrimary.setWorldRay(wRay))
        return 1.0;
    const RayType ray = mPrimary.getIndexRay();
    const double sigma = mSettings.extinction * mVoxelSize;
    double depth = 0.0;
    typename tools::VolumeRayIntersector<GridT>::Segment seg;
    while (mPrimary.march(seg)) {
        if (seg.constant) {
            depth += sigma * double(seg.value) * (seg.t1 - seg.t0);
            continue;
        }
        size_t n;
        double ds;
        steps(seg, mSettings.step, n, ds);
        for (size_t k = 0; k < n; ++k)
            depth += sigma * density(ray(seg.t0 + (double(k) + 0.5) * ds)) * ds;
    }
    return std::exp(-depth);
}

}  // namespace vdb::render
