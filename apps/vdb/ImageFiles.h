// SPDX-License-Identifier: Apache-2.0
/// @file
/// Picture files of `vdb render`: the format chosen by the file name's extension (PNG, and EXR
/// when the tool is built with OpenEXR).

#pragma once

#include <vdb/render/Image.h>

#include <string>

namespace vdb::app {

enum class ImageFormat { Png, Exr };

/// The format named by the extension of `path` (case-insensitive): ".png" or ".exr".
/// @throw UsageError naming the path and the extensions this build writes, for any other.
ImageFormat imageFormatFor(const std::string& path);

/// The extensions this build writes, for messages and --help: ".png or .exr" or ".png".
std::string imageExtensions();

/// Writes `image` to `path` in the format its extension names (see writePng, writeExr).
/// @throw UsageError for an unknown extension, vdb::IoError when the file cannot be written.
void writeImage(const std::string& path, const render::Image& image);

}  // namespace vdb::app
