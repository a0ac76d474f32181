// SPDX-License-Identifier: Apache-2.0
/// @file
/// Writes a render::Image as an 8-bit RGBA PNG file (libpng), sRGB-encoded, with straight
/// (not premultiplied) alpha.

#pragma once

#include <vdb/render/Image.h>

#include <string>

namespace vdb::app {

/// Writes `image` to `path` as an 8-bit sRGB RGBA PNG, alpha being the image's alpha. The bytes
/// go to a temporary file in the same directory, which is renamed to `path` once complete
/// (replaceFile), so an interrupted write never leaves a partial file at `path`.
/// @throw vdb::IoError naming the file when it cannot be written, or for an empty image.
void writePng(const std::string& path, const render::Image& image);

}  // namespace vdb::app
