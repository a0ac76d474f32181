// SPDX-License-Identifier: Apache-2.0
// The grid type registry of io/Archive.h, holding the standard grid types (GridTypes) from the
// start, the one instantiation of their tree readers and writers, and the file that out-of-core
// leaves read from.

#include <vdb/GridTypes.h>
#include <vdb/io/Archive.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <typeindex>

namespace vdb::io {
namespace {

struct Registry {
    std::mutex mutex;
    std::map<std::string, GridTypeIo, std::less<>> types;  // readers, by type string
    std::map<std::type_index, GridTypeIo> writers;         // writers, by C++ grid type

    Registry() {
        GridTypes::forEach([&]<typename GridT>() {
            const GridTypeIo t = makeGridTypeIo<GridT>();
            types.emplace(t.typeName, t);
            writers.emplace(std::type_index(*t.gridType), t);
        });
    }
};

Registry& registry() {
    static Registry r;
    return r;
}

}  // namespace

FileSource::FileSource(const std::string& path) : mPath(path) {
    mFd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (mFd < 0)
        throw IoError(path + ": cannot open: " + std::strerror(errno));
}

FileSource::~FileSource() {
    if (mFd >= 0)
        ::close(mFd);
}

void FileSource::read(uint64_t begin, uint64_t end, std::vector<uint8_t>& out) const {
    if (end < begin)
        throw IoError(mPath + ": invalid byte range");
    out.resize(size_t(end - begin));
    size_t done = 0;
    while (done < out.size()) {
        const ssize_t n = ::pread(mFd, out.data() + done, out.size() - done, off_t(begin + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            throw IoError(mPath + ": cannot read: " + std::strerror(errno));
        if (n == 0)
            throw IoError(mPath + ": the file ends at byte " + std::to_string(begin + done) +
                          ", before the " + std::to_string(end - begin) + " bytes at offset " +
                          std::to_string(begin) + " (changed since it was opened?)");
        done += size_t(n);
    }
}

const GridTypeIo* findGridType(std::string_view typeName) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    auto it = r.types.find(typeName);
    // Entries are never erased, only replaced in place, so the pointer stays valid.
    return it == r.types.end() ? nullptr : &it->second;
}

const GridTypeIo* findGridTypeOf(const GridBase& grid) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    auto it = r.writers.find(std::type_index(typeid(grid)));
    return it == r.writers.end() ? nullptr : &it->second;
}

void registerGridType(const GridTypeIo& type) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    r.types.insert_or_assign(type.typeName, type);
    r.writers.insert_or_assign(std::type_index(*type.gridType), type);
}

}  // namespace vdb::io
