// SPDX-License-Identifier: Apache-2.0

#include "PngWriter.h"

#include <vdb/Exceptions.h>

#include "ImageFiles.h"
#include <png.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

namespace vdb::app {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) {
    throw IoError("cannot write PNG file '" + path + "': " + why);
}

}  // namespace

void writePng(const std::string& path, const render::Image& image) {
    if (image.width() == 0 || image.height() == 0)
        fail(path, "the image is empty");
    if (image.width() > std::numeric_limits<png_uint_32>::max() / 4 ||
        image.height() > std::numeric_limits<png_uint_32>::max())
        fail(path, "the image is too large for PNG");
    const std::vector<uint8_t> pixels = image.toRgba8(/*srgb=*/true);
    replaceFile(path, "PNG", [&](const std::string& temporary) {
        std::FILE* file = std::fopen(temporary.c_str(), "wb");
        if (!file)
            fail(path, std::strerror(errno));
        png_image png;
        std::memset(&png, 0, sizeof(png));
        png.version = PNG_IMAGE_VERSION;
        png.width = png_uint_32(image.width());
        png.height = png_uint_32(image.height());
        png.format = PNG_FORMAT_RGBA;
        const bool written =
            png_image_write_to_stdio(&png, file, /*convert_to_8bit=*/0, pixels.data(),
                                     png_int_32(image.width() * 4), /*colormap=*/nullptr) != 0;
        const std::string message = written ? std::string() : std::string(png.message);
        png_image_free(&png);
        const bool flushed = std::fflush(file) == 0;
        const bool closed = std::fclose(file) == 0;
        if (!written)
            fail(path, message);
        if (!flushed || !closed)
            fail(path, std::string("write failed: ") + std::strerror(errno));
    });
}

}  // namespace vdb::app
