// SPDX-License-Identifier: Apache-2.0
/// @file
/// Writes a render::Image as an OpenEXR file: 32-bit float R, G, B, A, linear, with the colours
/// premultiplied by alpha as EXR expects, ZIP-compressed.

#pragma once

#include <vdb/render/Image.h>

#include <string>

namespace vdb::app {

/// Whether this build of the tool writes EXR (it was built with OpenEXR).
bool exrSupported();

/// Writes `image` to `path` as an OpenEXR file (see the file comment), through util::OutputFile
/// (the old file stays until the new one is complete).
/// @throw vdb::IoError naming the file when it cannot be written, for an empty image, or when
///   the tool was built without OpenEXR.
void writeExr(const std::string& path, const render::Image& image);

}  // namespace vdb::app
