// SPDX-License-Identifier: Apache-2.0

#include "ExrWriter.h"

#include <vdb/Exceptions.h>
#include <vdb/util/OutputFile.h>

#include "ImageFiles.h"

#ifdef VDB_HAVE_OPENEXR
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#endif

#include <exception>
#include <limits>
#include <string>
#include <vector>

namespace vdb::app {

#ifdef VDB_HAVE_OPENEXR

bool exrSupported() {
    return true;
}

void writeExr(const std::string& path, const render::Image& image) {
    if (image.width() == 0 || image.height() == 0)
        throw IoError("cannot write EXR file '" + path + "': the image is empty");
    constexpr size_t kMax = size_t(std::numeric_limits<int>::max());
    if (image.width() > kMax / 16 || image.height() > kMax / 16)
        throw IoError("cannot write EXR file '" + path + "': the image is too large for EXR");
    // EXR stores colours premultiplied by alpha.
    std::vector<float> rgba(image.pixels().size() * 4);
    for (size_t i = 0; i < image.pixels().size(); ++i) {
        const render::Rgba& p = image.pixels()[i];
        rgba[4 * i + 0] = p.r * p.a;
        rgba[4 * i + 1] = p.g * p.a;
        rgba[4 * i + 2] = p.b * p.a;
        rgba[4 * i + 3] = p.a;
    }
    const int width = int(image.width()), height = int(image.height());
    // Encode into memory, then write through util::OutputFile.
    std::string bytes;
    try {
        Imf::StdOSStream stream;
        {
            Imf::Header header(width, height);
            header.compression() = Imf::ZIP_COMPRESSION;
            Imf::FrameBuffer frame;
            const char* names[4] = {"R", "G", "B", "A"};
            for (int c = 0; c < 4; ++c) {
                header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
                frame.insert(names[c],
                             Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgba.data() + c),
                                        4 * sizeof(float), 4 * sizeof(float) * image.width()));
            }
            Imf::OutputFile file(stream, header);
            file.setFrameBuffer(frame);
            file.writePixels(height);
        }  // the file's destructor writes the line offset table
        bytes = stream.str();
    } catch (const std::exception& e) {
        throw IoError("cannot write EXR file '" + path + "': " + e.what());
    }
    util::writeOutputFile(path,
                          [&](util::OutputFile& out) { out.write(bytes.data(), bytes.size()); });
}

#else

bool exrSupported() {
    return false;
}

void writeExr(const std::string& path, const render::Image&) {
    throw IoError("cannot write EXR file '" + path + "': this vdb was built without OpenEXR");
}

#endif

}  // namespace vdb::app
