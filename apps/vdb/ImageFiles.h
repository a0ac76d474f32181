// SPDX-License-Identifier: Apache-2.0
/// @file
/// Picture files of `vdb render`: the format chosen by the file name's extension (PNG, and EXR
/// when the tool is built with OpenEXR), and the one way such files are replaced.

#pragma once

#include <vdb/render/Image.h>

#include <functional>
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

/// Replaces `path` with what `write(temporary)` writes to a new temporary file beside it,
/// "<path>.tmp-XXXXXX" (so that the rename stays on one file system and writeWatched can
/// remove it on Ctrl-C): the file is created readable by everyone, flushed to disk and renamed
/// into place only when `write` returns, and removed when it throws. `what` names the format
/// in messages ("PNG").
/// @throw vdb::IoError naming `path` when the temporary file cannot be made, written or renamed;
///   what `write` throws, after removing the temporary file.
void replaceFile(const std::string& path, const std::string& what,
                 const std::function<void(const std::string& temporary)>& write);

}  // namespace vdb::app
