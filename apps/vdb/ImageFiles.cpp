// SPDX-License-Identifier: Apache-2.0

#include "ImageFiles.h"

#include <vdb/Exceptions.h>

#include "Cli.h"
#include "ExrWriter.h"
#include "PngWriter.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace vdb::app {

std::string imageExtensions() {
    return exrSupported() ? ".png or .exr" : ".png";
}

ImageFormat imageFormatFor(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".png")
        return ImageFormat::Png;
    if (ext == ".exr") {
        if (!exrSupported())
            throw UsageError("cannot write " + path +
                             ": this vdb was built without OpenEXR, so it writes only .png");
        return ImageFormat::Exr;
    }
    throw UsageError("cannot write " + path + ": the picture format is chosen by the extension, " +
                     imageExtensions() +
                     (ext.empty() ? std::string(", and the name has none") : ", not " + ext));
}

void writeImage(const std::string& path, const render::Image& image) {
    switch (imageFormatFor(path)) {
        case ImageFormat::Png:
            return writePng(path, image);
        case ImageFormat::Exr:
            return writeExr(path, image);
    }
}

}  // namespace vdb::app
