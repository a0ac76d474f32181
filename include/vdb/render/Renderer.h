// SPDX-License-Identifier: Apache-2.0
/// @file
/// Renderers of grids into images: renderLevelSet() ray-traces the zero surface of a level set
/// with diffuse shading from one directional light, built on tools/RayIntersector.h and so on
/// the hierarchical DDA of the paper's section 4.7; renderFogVolume() (render/VolumeRenderer.h,
/// included here) renders fog volumes.
///
/// The image is cut into square tiles rendered in parallel (oneTBB); every pixel is computed
/// from its own camera ray alone, so the image does not depend on the number of threads.
/// Pixels are sampled once, at their centres; colours are linear and not premultiplied, and
/// alpha is the coverage (by default the background is transparent). The library returns the
/// image; writing files is left to the caller (the vdb tool writes PNG and EXR).
///
/// Voxels need not be cubes: any linear transform works (frustum transforms do not).
///
/// @code
/// auto camera = vdb::render::PerspectiveCamera::frame(worldBox, 640, 480, vdb::Vec3d(-1, -1, -1));
/// vdb::render::Image color = vdb::render::renderLevelSet(*sphere, camera);
/// vdb::render::Image fog = vdb::render::renderFogVolume(*density, camera);
/// @endcode

#pragma once

#include <vdb/math/Vec3.h>
#include <vdb/render/Camera.h>
#include <vdb/render/Image.h>
#include <vdb/render/VolumeRenderer.h>
#include <vdb/render/detail/Tiles.h>
#include <vdb/tools/RayIntersector.h>

#include <algorithm>
#include <cstddef>

namespace vdb::render {

/// Settings of renderLevelSet().
struct LevelSetRenderSettings {
    Vec3d lightDirection{0.5, 0.8, 0.6};        ///< world space, towards the light
    Rgba surfaceColor{0.85f, 0.78f, 0.66f, 1};  ///< diffuse reflectance (alpha unused)
    float lightIntensity = 1.0f;
    float ambient = 0.12f;                    ///< light reaching every point, shadowed or not
    Rgba background{0.0f, 0.0f, 0.0f, 0.0f};  ///< pixels whose ray misses the surface
    size_t tileSize = 16;                     ///< edge of the square tiles rendered as tasks
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

// ---- Implementation ---------------------------------------------------------------------------

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

}  // namespace vdb::render
