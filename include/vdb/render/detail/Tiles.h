// SPDX-License-Identifier: Apache-2.0
/// @file
/// The image loop the renderers share: square tiles of pixels rendered as parallel tasks, each
/// with its own state (intersectors, accessors), so that every pixel depends on its own ray
/// alone and images do not depend on the number of threads. Not API: free to change.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/math/Vec3.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace vdb::render::detail {

/// Calls `shadePixel(x, y, state)` for every pixel of a width x height image, in square tiles
/// of `tileSize` rendered as parallel tasks (when `threaded`); `makeState()` builds the
/// per-task state passed as the third argument.
/// @throw ValueError for a zero tile size.
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

/// `direction` as a unit vector. @throw ValueError when it is zero or not finite.
inline Vec3d unitLight(const Vec3d& direction) {
    Vec3d l = direction;
    if (!(std::isfinite(l[0]) && std::isfinite(l[1]) && std::isfinite(l[2])) || !l.normalize(0.0))
        throw ValueError("render: the light direction must be a finite, non-zero vector");
    return l;
}

}  // namespace vdb::render::detail
