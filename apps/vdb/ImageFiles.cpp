// SPDX-License-Identifier: Apache-2.0

#include "ImageFiles.h"

#include <vdb/Exceptions.h>

#include "Cli.h"
#include "ExrWriter.h"
#include "PngWriter.h"
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace vdb::app {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what, const std::string& why) {
    throw IoError("cannot write " + what + " file '" + path + "': " + why);
}

}  // namespace

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

void replaceFile(const std::string& path, const std::string& what,
                 const std::function<void(const std::string&)>& write) {
    std::string temp = path + ".tmp-XXXXXX";
    const int fd = mkstemp(temp.data());
    if (fd < 0)
        fail(path, what, std::strerror(errno));
    fchmod(fd, 0644);  // mkstemp creates 0600; pictures are for everyone to read
    close(fd);
    try {
        write(temp);
        // Flush to disk before the rename, so that a crash leaves the old file or the new one.
        const int sync = ::open(temp.c_str(), O_RDONLY);
        const bool synced = sync >= 0 && fsync(sync) == 0;
        if (sync >= 0)
            close(sync);
        if (!synced)
            fail(path, what, std::string("write failed: ") + std::strerror(errno));
        std::error_code ec;
        std::filesystem::rename(temp, path, ec);
        if (ec)
            fail(path, what, ec.message());
    } catch (...) {
        std::remove(temp.c_str());
        throw;
    }
}

}  // namespace vdb::app
