// SPDX-License-Identifier: Apache-2.0
/// @file
/// Writes a render::Image as an 8-bit RGBA PNG file (libpng), sRGB-encoded, with straight
/// (not premultiplied) alpha.

#pragma once

#include <vdb/render/Image.h>

#include <string>

namespace vdb::app {

/// Writes `image` to `path` as an 8-bit sRGB RGBA PNG, alpha being the image's alpha, through
/// util::OutputFile (an atomic replace of a regular file, links written through, devices
/// written directly).
/// @throw vdb::IoError naming the file when it cannot be written, or for an empty image.
void writePng(const std::string& path, const render::Image& image);

}  // namespace vdb::app
