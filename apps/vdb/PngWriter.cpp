// SPDX-License-Identifier: Apache-2.0

#include "PngWriter.h"

#include <vdb/Exceptions.h>
#include <vdb/util/OutputFile.h>

#include "ImageFiles.h"
#include <png.h>

#include <cstdint>
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

    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    png.width = png_uint_32(image.width());
    png.height = png_uint_32(image.height());
    png.format = PNG_FORMAT_RGBA;
    const png_int_32 stride = png_int_32(image.width() * 4);
    // Encode into memory (the first call measures), then write through util::OutputFile.
    png_alloc_size_t size = 0;
    bool encoded = png_image_write_to_memory(&png, nullptr, &size, /*convert_to_8bit=*/0,
                                             pixels.data(), stride, nullptr) != 0;
    std::vector<uint8_t> bytes(encoded ? size : 0);
    if (encoded)
        encoded = png_image_write_to_memory(&png, bytes.data(), &size, 0, pixels.data(), stride,
                                            nullptr) != 0;
    const std::string message = encoded ? std::string() : std::string(png.message);
    png_image_free(&png);
    if (!encoded)
        fail(path, message);
    bytes.resize(size);
    util::writeOutputFile(path, [&](util::OutputFile& out) { out.write(bytes); });
}

}  // namespace vdb::app
