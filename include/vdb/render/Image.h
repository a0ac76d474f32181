// SPDX-License-Identifier: Apache-2.0
/// @file
/// Image: a buffer of RGBA pixels in linear floating point, as the renderers return it (colours
/// not premultiplied by alpha), with a conversion to 8-bit sRGB for files.
///
/// @code
/// vdb::render::Image image(640, 480);
/// image(10, 20) = vdb::render::Rgba{1.0f, 0.5f, 0.0f, 1.0f};   // x = 10 across, y = 20 down
/// std::vector<uint8_t> bytes = image.toRgba8();                 // row-major, 4 bytes a pixel
/// @endcode

#pragma once

#include <vdb/Exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vdb::render {

/// One pixel: red, green, blue (linear, not premultiplied by alpha) and coverage alpha.
struct Rgba {
    float r = 0, g = 0, b = 0, a = 0;
    bool operator==(const Rgba&) const = default;
};

/// A width x height grid of Rgba pixels, row-major from the top-left corner.
/// Threads: a plain value; concurrent writes to distinct pixels are safe.
class Image {
public:
    Image() = default;
    /// @throw ValueError when width * height overflows.
    Image(size_t width, size_t height, const Rgba& fill = Rgba{}) : mWidth(width), mHeight(height) {
        if (height != 0 && width > SIZE_MAX / sizeof(Rgba) / height)
            throw ValueError("Image: width * height is too large");
        mPixels.assign(width * height, fill);
    }

    size_t width() const { return mWidth; }
    size_t height() const { return mHeight; }
    /// The pixel in column x (from the left) and row y (from the top). @pre x < width(), y <
    /// height()
    Rgba& operator()(size_t x, size_t y) { return mPixels[y * mWidth + x]; }
    const Rgba& operator()(size_t x, size_t y) const { return mPixels[y * mWidth + x]; }
    const std::vector<Rgba>& pixels() const { return mPixels; }
    std::vector<Rgba>& pixels() { return mPixels; }

    /// Returns the pixels as 8-bit RGBA, row-major from the top: colours clamped to [0, 1] and
    /// encoded with the sRGB transfer curve when `srgb`, else scaled linearly; alpha linear.
    /// A pixel whose alpha rounds to 0 is written (0, 0, 0, 0): it has no colour to show.
    std::vector<uint8_t> toRgba8(bool srgb = true) const {
        std::vector<uint8_t> out(mPixels.size() * 4);
        auto encode = [srgb](float c) {
            double v = std::clamp(double(c), 0.0, 1.0);
            if (srgb)
                v = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
            return uint8_t(std::lround(v * 255.0));
        };
        for (size_t i = 0; i < mPixels.size(); ++i) {
            const Rgba& p = mPixels[i];
            const uint8_t alpha = uint8_t(std::lround(std::clamp(double(p.a), 0.0, 1.0) * 255.0));
            if (alpha == 0)
                continue;  // left (0, 0, 0, 0)
            out[4 * i + 0] = encode(p.r);
            out[4 * i + 1] = encode(p.g);
            out[4 * i + 2] = encode(p.b);
            out[4 * i + 3] = alpha;
        }
        return out;
    }

    bool operator==(const Image&) const = default;

private:
    size_t mWidth = 0, mHeight = 0;
    std::vector<Rgba> mPixels;
};

}  // namespace vdb::render
