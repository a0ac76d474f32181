// SPDX-License-Identifier: Apache-2.0
// io::File: header, metadata, transforms, grid descriptors, instancing, statistics and the
// delayed-load table of `.vdb` files (FORMAT.md 1.1 to 1.6, 1.12, 1.15, 1.16). Trees are read
// and written by the templates of Archive.h through the grid type registry.

#include <vdb/io/Archive.h>
#include <vdb/io/Codecs.h>
#include <vdb/io/File.h>
#include <vdb/io/Format.h>
#include <vdb/util/OutputFile.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <functional>
#include <istream>
#include <map>
#include <ostream>
#include <random>
#include <set>
#include <system_error>
#include <utility>

namespace vdb::io {
namespace {

constexpr char UNIQUE_SUFFIX = '\x1e';
constexpr std::string_view HALF_SUFFIX = "_HalfFloat";
constexpr std::string_view META_DELAYED_LOAD = "file_delayed_load";

std::string displayName(std::string_view unique) {
    return std::string(unique.substr(0, unique.find(UNIQUE_SUFFIX)));
}
/// "name\x1eN" as "name[N]" (OpenVDB's printed form of a unique name).
std::string printedName(std::string_view unique) {
    const size_t p = unique.find(UNIQUE_SUFFIX);
    if (p == std::string_view::npos)
        return std::string(unique);
    return std::string(unique.substr(0, p)) + "[" + std::string(unique.substr(p + 1)) + "]";
}

// ---- Metadata (FORMAT.md 1.3)

template <typename T>
T readMetaPayload(ByteReader& r, uint32_t size, std::string_view name) {
    if (size != sizeof(T))
        r.fail("metadata \"" + std::string(name) + "\" has " + std::to_string(size) +
               " bytes, not " + std::to_string(sizeof(T)));
    return r.read<T>("metadata value");
}

void readMetaMap(ByteReader& r, MetaMap& meta) {
    const uint32_t count = r.read<uint32_t>("metadata count");
    r.checkedCount(count, 13, "metadata entry");
    for (uint32_t i = 0; i < count; ++i) {
        std::string name = r.readString("metadata name");
        std::string type = r.readString("metadata type name", 4096);
        const uint32_t size = r.read<uint32_t>("metadata size");
        if (name.empty())
            r.fail("metadata entry with an empty name");
        if (size > r.remaining())
            r.fail("metadata \"" + name + "\" claims " + std::to_string(size) + " bytes");
        if (type.starts_with("__")) {  // private to the writer (e.g. the delayed-load table)
            r.skip(size, "metadata value");
            continue;
        }
        MetaValue value;
        if (type == "string") {
            const auto b = r.take(size, "string metadata");
            value = std::string(reinterpret_cast<const char*>(b.data()), b.size());
        } else if (type == "bool") {
            if (size != 1)
                r.fail("bool metadata \"" + name + "\" has " + std::to_string(size) + " bytes");
            value = r.readBool("bool metadata");
        } else if (type == "int32") {
            value = readMetaPayload<Int32>(r, size, name);
        } else if (type == "int64") {
            value = readMetaPayload<Int64>(r, size, name);
        } else if (type == "float") {
            value = readMetaPayload<float>(r, size, name);
        } else if (type == "double") {
            value = readMetaPayload<double>(r, size, name);
        } else if (type == "vec3i") {
            value = readMetaPayload<Vec3i>(r, size, name);
        } else if (type == "vec3s") {
            value = readMetaPayload<Vec3s>(r, size, name);
        } else if (type == "vec3d") {
            value = readMetaPayload<Vec3d>(r, size, name);
        } else {
            const auto b = r.take(size, "metadata value");
            value = OpaqueMetadata{std::move(type), std::vector<uint8_t>(b.begin(), b.end())};
        }
        meta.insertMeta(name, value);
    }
}

void writeMetaValue(ByteWriter& w, const MetaValue& value) {
    std::visit(
        [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::string>) {
                w.put(uint32_t(v.size()));
                w.write(v.data(), v.size());
            } else if constexpr (std::is_same_v<T, OpaqueMetadata>) {
                w.put(uint32_t(v.bytes.size()));
                w.write(v.bytes);
            } else if constexpr (std::is_same_v<T, bool>) {
                w.put(uint32_t(1));
                w.putBool(v);
            } else {
                w.put(uint32_t(sizeof(T)));
                w.put(v);
            }
        },
        value);
}

/// Writes `meta` plus `extra` entries (a name and its raw type and payload, such as the
/// delayed-load table), all in byte-wise name order.
void writeMetaMap(
    ByteWriter& w, const MetaMap& meta,
    const std::map<std::string, std::pair<std::string, std::vector<uint8_t>>>& extra = {}) {
    w.put(uint32_t(meta.metaCount() + extra.size()));
    auto it = meta.beginMeta();
    auto jt = extra.begin();
    while (it != meta.endMeta() || jt != extra.end()) {
        if (jt == extra.end() || (it != meta.endMeta() && it->first < jt->first)) {
            w.putString(it->first);
            w.putString(metaTypeName(it->second));
            writeMetaValue(w, it->second);
            ++it;
        } else {
            w.putString(jt->first);
            w.putString(jt->second.first);
            w.put(uint32_t(jt->second.second.size()));
            w.write(jt->second.second);
            ++jt;
        }
    }
}

// ---- Transforms (FORMAT.md 1.6)

math::MapParams readMapParams(ByteReader& r, uint32_t version, int depth) {
    const std::string typeName = r.readString("map type", 256);
    const auto type = math::mapTypeFromName(typeName);
    if (!type)
        r.fail("unsupported map type \"" + typeName + "\"");
    math::MapParams p;
    p.type = *type;
    auto vec = [&](const char* what) {
        const double x = r.read<double>(what), y = r.read<double>(what), z = r.read<double>(what);
        return Vec3d(x, y, z);
    };
    switch (*type) {
        case math::MapType::UniformScaleTranslate:
        case math::MapType::ScaleTranslate:
            p.translation = vec("map translation");
            [[fallthrough]];
        case math::MapType::UniformScale:
        case math::MapType::Scale:
            p.scale = vec("map scale");
            r.skip(4 * 3 * sizeof(double), "map derived vectors");
            break;
        case math::MapType::Translation:
            p.translation = vec("map translation");
            break;
        case math::MapType::Affine:
        case math::MapType::Unitary:
            for (int i = 0; i < 16; ++i)
                p.matrix.data()[i] = r.read<double>("map matrix");
            break;
        case math::MapType::NonlinearFrustum: {
            if (depth > 0)
                r.fail("a frustum map nested in a frustum map");
            Vec3d lo, hi;
            if (version < 221) {
                for (int i = 0; i < 3; ++i)
                    lo[i] = r.read<Int32>("frustum box");
                for (int i = 0; i < 3; ++i)
                    hi[i] = r.read<Int32>("frustum box");
            } else {
                lo = vec("frustum box");
                hi = vec("frustum box");
            }
            p.frustumBBox = BBoxd(lo, hi);
            p.frustumTaper = r.read<double>("frustum taper");
            p.frustumDepth = r.read<double>("frustum depth");
            const math::MapParams second = readMapParams(r, version, depth + 1);
            try {
                p.matrix = math::Transform(second).affineMatrix();
            } catch (const Exception& e) {
                r.fail(std::string("invalid frustum second map: ") + e.what());
            }
            break;
        }
    }
    return p;
}

math::Transform::Ptr readTransform(ByteReader& r, uint32_t version) {
    const math::MapParams p = readMapParams(r, version, 0);
    try {
        return math::Transform::createFromMap(p);
    } catch (const Exception& e) {
        r.fail(std::string("invalid transform: ") + e.what());
    }
}

void writeMapBody(ByteWriter& w, const math::MapParams& p) {
    auto vec = [&](const Vec3d& v) {
        w.put(v[0]);
        w.put(v[1]);
        w.put(v[2]);
    };
    switch (p.type) {
        case math::MapType::UniformScaleTranslate:
        case math::MapType::ScaleTranslate:
            vec(p.translation);
            [[fallthrough]];
        case math::MapType::UniformScale:
        case math::MapType::Scale:
            for (const Vec3d& v : p.scaleVectors())
                vec(v);
            break;
        case math::MapType::Translation:
            vec(p.translation);
            break;
        case math::MapType::Affine:
        case math::MapType::Unitary:
            for (int i = 0; i < 16; ++i)
                w.put(p.matrix.data()[i]);
            break;
        case math::MapType::NonlinearFrustum: {
            vec(p.frustumBBox.min());
            vec(p.frustumBBox.max());
            w.put(p.frustumTaper);
            w.put(p.frustumDepth);
            w.putString(math::mapTypeName(math::MapType::Affine));
            for (int i = 0; i < 16; ++i)
                w.put(p.matrix.data()[i]);
            break;
        }
    }
}

void writeTransform(ByteWriter& w, const math::Transform& xform) {
    w.putString(xform.mapTypeName());
    writeMapBody(w, xform.mapParams());
}

// ---- The delayed-load table (FORMAT.md 1.12)

/// An array of the table, blosc-compressed the way OpenVDB does it (more than 48 bytes,
/// padded with zeros to 128, kept only when smaller), else raw with a zero length.
void writeTableArray(ByteWriter& w, std::span<const uint8_t> raw) {
    constexpr size_t MINIMUM = 48, PAD = 128;
    if (raw.size() > MINIMUM) {
        std::vector<uint8_t> padded;
        std::span<const uint8_t> input = raw;
        if (raw.size() < PAD) {
            padded.assign(raw.begin(), raw.end());
            padded.resize(PAD, 0);
            input = padded;
        }
        std::vector<uint8_t> frame;
        const size_t n = bloscCompress(input, frame);
        if (n > 0 && n < raw.size()) {
            w.put(uint32_t(n));
            w.write(frame);
            return;
        }
    }
    w.put(uint32_t(0));
    w.write(raw);
}

std::vector<uint8_t> delayedLoadTable(const TreeWriteInfo& info, uint32_t flags) {
    std::vector<uint8_t> bytes;
    const size_t n = info.leafCodes.size();
    if (n == 0)
        return bytes;
    ByteWriter w(bytes);
    w.put(uint32_t(n));
    writeTableArray(w, {reinterpret_cast<const uint8_t*>(info.leafCodes.data()), n});
    if (!(flags & (COMPRESS_ZIP | COMPRESS_BLOSC))) {
        w.put(uint32_t(0xFFFFFFFF));
    } else {
        std::vector<int64_t> sizes(info.leafChunkBytes.begin(), info.leafChunkBytes.end());
        writeTableArray(w, {reinterpret_cast<const uint8_t*>(sizes.data()), n * sizeof(int64_t)});
    }
    return bytes;
}

std::string makeUuid() {
    std::random_device device;
    std::mt19937_64 rng((uint64_t(device()) << 32) ^ device());
    const uint64_t a = rng(), b = rng();
    uint8_t bytes[16];
    std::memcpy(bytes, &a, 8);
    std::memcpy(bytes + 8, &b, 8);
    bytes[6] = uint8_t((bytes[6] & 0x0F) | 0x40);  // version 4 (random)
    bytes[8] = uint8_t((bytes[8] & 0x3F) | 0x80);  // RFC 4122 variant
    static constexpr char HEX[] = "0123456789abcdef";
    std::string s;
    for (int i = 0; i < 16; ++i) {
        if (i == 4 || i == 6 || i == 8 || i == 10)
            s += '-';
        s += HEX[bytes[i] >> 4];
        s += HEX[bytes[i] & 15];
    }
    return s;
}

[[noreturn]] void throwSystem(const std::string& path, const std::string& what) {
    throw IoError(path + ": " + what + ": " + std::strerror(errno));
}

/// Bytes in the file behind `fd` now.
uint64_t currentSize(int fd, const std::string& path) {
    struct stat st {};
    if (::fstat(fd, &st) != 0)
        throwSystem(path, "cannot stat");
    return uint64_t(st.st_size);
}

/// The bytes of an open file: memory-mapped, read-only.
class MappedFile {
public:
    explicit MappedFile(const FileSource& source) {
        const std::string& path = source.path();
        struct stat st {};
        if (::fstat(source.fd(), &st) != 0)
            throwSystem(path, "cannot stat");
        if (!S_ISREG(st.st_mode))
            throw IoError(path + ": not a regular file");
        mSize = size_t(st.st_size);
        if (mSize > 0) {
            void* p = ::mmap(nullptr, mSize, PROT_READ, MAP_PRIVATE, source.fd(), 0);
            if (p == MAP_FAILED)
                throwSystem(path, "cannot map");
            mData = static_cast<const uint8_t*>(p);
        }
    }
    ~MappedFile() {
        if (mData)
            ::munmap(const_cast<uint8_t*>(mData), mSize);
    }
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    std::span<const uint8_t> bytes() const { return {mData, mSize}; }

private:
    const uint8_t* mData = nullptr;
    size_t mSize = 0;
};

}  // namespace

// ---- Reading

struct File::Impl {
    struct Descriptor {
        std::string uniqueName;
        std::string type;  // without the half suffix
        std::string storedType;
        std::string parent;
        bool half = false;
        uint64_t gridPos = 0, blockPos = 0, endPos = 0;
        const GridTypeIo* io = nullptr;
        GridBase::Ptr preloaded;  // stream files: read at open
    };

    std::string path;
    std::shared_ptr<const FileSource> source;  // shared with out-of-core leaves; null for a Stream
    std::unique_ptr<MappedFile> file;          // the bytes of a File
    std::vector<uint8_t> owned;                // the bytes of a Stream
    bool delayedLoad = true;
    uint32_t version = 0;
    uint32_t libMajor = 0, libMinor = 0;
    bool hasOffsets = true;
    uint32_t headerCompression = COMPRESS_ZIP | COMPRESS_ACTIVE_MASK;
    MetaMap metadata;
    std::vector<Descriptor> grids;  // readable and unsupported, in file order
    std::vector<UnsupportedGrid> unsupported;

    std::span<const uint8_t> bytes() const {
        return file ? file->bytes() : std::span<const uint8_t>(owned);
    }
    /// Reads the header, the file metadata and the grid descriptors from bytes().
    void parse();
    const Descriptor* find(std::string_view name) const;
    GridBase::Ptr readGridAt(ByteReader& r, const Descriptor& d, bool withTree,
                             std::map<std::string, GridBase::Ptr>* loaded) const;
    GridBase::Ptr load(const Descriptor& d, bool withTree,
                       std::map<std::string, GridBase::Ptr>* loaded) const;
};

const File::Impl::Descriptor* File::Impl::find(std::string_view name) const {
    for (const auto& d : grids)
        if (d.io && d.uniqueName == name)
            return &d;
    for (const auto& d : grids)
        if (d.io && printedName(d.uniqueName) == name)
            return &d;
    for (const auto& d : grids)
        if (d.io && displayName(d.uniqueName) == name)
            return &d;
    return nullptr;
}

GridBase::Ptr File::Impl::readGridAt(ByteReader& r, const Descriptor& d, bool withTree,
                                     std::map<std::string, GridBase::Ptr>* loaded) const {
    uint32_t flags = headerCompression;
    if (version >= FILE_VERSION_NODE_MASK_COMPRESSION)
        flags = r.read<uint32_t>("grid compression flags") &
                (COMPRESS_ZIP | COMPRESS_ACTIVE_MASK | COMPRESS_BLOSC);
    GridBase::Ptr grid = d.io->create();
    readMetaMap(r, *grid);
    if (!grid->hasMeta(GridBase::META_GRID_NAME) && !displayName(d.uniqueName).empty())
        grid->setName(displayName(d.uniqueName));
    const bool half = d.half || grid->saveFloatAsHalf();
    grid->setTransform(readTransform(r, version));
    if (!d.parent.empty()) {
        if (!withTree)
            return grid;
        const Descriptor* parent = nullptr;
        for (const auto& p : grids)
            if (p.uniqueName == d.parent)
                parent = &p;
        if (!parent || !parent->io || !parent->parent.empty())
            r.fail("grid \"" + printedName(d.uniqueName) + "\" is an instance of \"" +
                   printedName(d.parent) + "\", which is not a readable grid in this file");
        if (parent->io != d.io)
            r.fail("grid \"" + printedName(d.uniqueName) + "\" has type " + d.type +
                   " but its parent has type " + parent->type);
        GridBase::Ptr source;
        if (loaded && loaded->count(parent->uniqueName))
            source = loaded->at(parent->uniqueName);
        else
            source = load(*parent, true, loaded);
        d.io->shareTree(*grid, *source);
        return grid;
    }
    if (withTree) {
        TreeReadOptions options;
        options.flags = flags;
        options.half = half;
        options.fileVersion = version;
        if (delayedLoad && hasOffsets && source)
            options.delayed = source;
        d.io->read(r, *grid, options);
    }
    if (loaded)
        (*loaded)[d.uniqueName] = grid;
    return grid;
}

GridBase::Ptr File::Impl::load(const Descriptor& d, bool withTree,
                               std::map<std::string, GridBase::Ptr>* loaded) const {
    if (d.preloaded) {
        GridBase::Ptr g =
            withTree ? d.preloaded->deepCopyGrid() : d.preloaded->copyGridWithNewTree();
        if (loaded && withTree)
            (*loaded)[d.uniqueName] = g;
        return g;
    }
    // A file truncated in place since open() would fault in the mapping: refuse it instead.
    if (file && currentSize(source->fd(), path) < file->bytes().size())
        throw IoError(path + ": the file has shrunk since it was opened");
    // The grid's bytes end at endPos: nothing it reads can reach into the next grid.
    ByteReader r(bytes().first(size_t(d.endPos)), path);
    r.seek(d.gridPos);
    return readGridAt(r, d, withTree, loaded);
}

File::File(std::string path) : mPath(std::move(path)) {}
File::~File() = default;

void File::close() {
    mImpl.reset();
}

void File::open(bool delayedLoad) {
    auto impl = std::make_unique<Impl>();
    impl->path = mPath;
    impl->delayedLoad = delayedLoad;
    impl->source = std::make_shared<const FileSource>(mPath);
    impl->file = std::make_unique<MappedFile>(*impl->source);
    impl->parse();
    mImpl = std::move(impl);
}

void File::Impl::parse() {
    ByteReader r(bytes(), path);
    if (r.size() < 8 || r.read<uint64_t>("magic") != FILE_MAGIC)
        throw IoError(path + ": not a .vdb file (bad magic number)");
    version = r.read<uint32_t>("file version");
    if (version < OLDEST_FILE_VERSION)
        r.fail("file version " + std::to_string(version) + " is older than " +
               std::to_string(OLDEST_FILE_VERSION) + " and not supported");
    if (version > 10000)
        r.fail("implausible file version " + std::to_string(version));
    libMajor = r.read<uint32_t>("library major version");
    libMinor = r.read<uint32_t>("library minor version");
    hasOffsets = r.readBool("grid offsets flag");
    if (version < FILE_VERSION_NODE_MASK_COMPRESSION)
        headerCompression = r.readBool("compression flag") ? COMPRESS_ZIP : COMPRESS_NONE;
    r.skip(36, "file UUID");
    readMetaMap(r, metadata);
    const Int32 count = r.read<Int32>("grid count");
    if (count < 0)
        r.fail("negative grid count " + std::to_string(count));
    r.checkedCount(uint64_t(count), 4 * 3 + 24, "grid");

    for (Int32 i = 0; i < count; ++i) {
        Impl::Descriptor d;
        d.uniqueName = r.readString("grid name");
        d.storedType = r.readString("grid type", 4096);
        d.parent = r.readString("instance parent name");
        d.type = d.storedType;
        if (d.type.ends_with(HALF_SUFFIX)) {
            d.type.resize(d.type.size() - HALF_SUFFIX.size());
            d.half = true;
        }
        d.gridPos = uint64_t(r.read<int64_t>("grid position"));
        d.blockPos = uint64_t(r.read<int64_t>("block position"));
        d.endPos = uint64_t(r.read<int64_t>("end position"));
        d.io = findGridType(d.type);
        if (hasOffsets) {
            if (d.gridPos < r.pos() || d.endPos < d.gridPos || d.endPos > r.size() ||
                (d.blockPos != 0 && (d.blockPos < d.gridPos || d.blockPos > d.endPos))) {
                r.fail("grid \"" + printedName(d.uniqueName) + "\" has invalid offsets");
            }
            if (!d.io)
                unsupported.push_back({displayName(d.uniqueName), d.storedType});
            r.seek(d.endPos);
        } else {
            // A stream file: grids follow their descriptors and can only be read in order.
            if (!d.io)
                r.fail("grid \"" + printedName(d.uniqueName) + "\" of unsupported type " +
                       d.storedType + " cannot be skipped in a file without offsets");
            d.gridPos = r.pos();
            std::map<std::string, GridBase::Ptr> loaded;
            for (const auto& p : grids)
                if (p.preloaded)
                    loaded[p.uniqueName] = p.preloaded;
            d.preloaded = readGridAt(r, d, true, &loaded);
            d.endPos = r.pos();
        }
        grids.push_back(std::move(d));
    }
}

namespace {
File::Impl& opened(const std::unique_ptr<File::Impl>& impl, const std::string& path) {
    if (!impl)
        throw IoError(path + ": file is not open");
    return *impl;
}
}  // namespace

uint32_t File::fileVersion() const {
    return opened(mImpl, mPath).version;
}
std::pair<uint32_t, uint32_t> File::libraryVersion() const {
    const Impl& impl = opened(mImpl, mPath);
    return {impl.libMajor, impl.libMinor};
}
MetaMap File::getMetadata() const {
    return opened(mImpl, mPath).metadata;
}

std::vector<std::string> File::getGridNames() const {
    std::vector<std::string> names;
    for (const auto& d : opened(mImpl, mPath).grids)
        if (d.io)
            names.push_back(printedName(d.uniqueName));
    return names;
}

bool File::hasGrid(std::string_view name) const {
    return opened(mImpl, mPath).find(name) != nullptr;
}

std::vector<UnsupportedGrid> File::unsupportedGrids() const {
    return opened(mImpl, mPath).unsupported;
}

namespace {
GridPtrVecPtr readAll(const File::Impl& impl, bool withTree) {
    std::map<std::string, GridBase::Ptr> loaded;
    auto out = std::make_shared<GridPtrVec>();
    std::vector<std::pair<std::string, GridBase::Ptr>> named;
    for (const auto& d : impl.grids) {
        if (!d.io)
            continue;
        GridBase::Ptr g;
        if (withTree && loaded.count(d.uniqueName))
            g = loaded.at(d.uniqueName);
        else
            g = impl.load(d, withTree, withTree ? &loaded : nullptr);
        named.emplace_back(displayName(d.uniqueName), g);
    }
    std::stable_sort(named.begin(), named.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [name, g] : named)
        out->push_back(std::move(g));
    return out;
}
}  // namespace

GridPtrVecPtr File::getGrids() const {
    return readAll(opened(mImpl, mPath), true);
}
GridPtrVecPtr File::readAllGridMetadata() const {
    return readAll(opened(mImpl, mPath), false);
}

GridBase::Ptr File::readGrid(std::string_view name) const {
    const Impl& impl = opened(mImpl, mPath);
    const Impl::Descriptor* d = impl.find(name);
    if (!d)
        throw IoError(mPath + ": no readable grid named \"" + std::string(name) + "\"");
    return impl.load(*d, true, nullptr);
}

GridBase::Ptr File::readGridMetadata(std::string_view name) const {
    const Impl& impl = opened(mImpl, mPath);
    const Impl::Descriptor* d = impl.find(name);
    if (!d)
        throw IoError(mPath + ": no readable grid named \"" + std::string(name) + "\"");
    return impl.load(*d, false, nullptr);
}

// ---- Writing

namespace {

/// Appends the descriptor of one grid to `out`, whose first byte will sit at file offset
/// `base`; its tree follows in the file: the topology in `tree`, then the leaf buffers that
/// the returned info's emitBuffers hands over (nothing for an instance). They are written from
/// where they were encoded, never copied behind the descriptor.
TreeWriteInfo writeGrid(std::vector<uint8_t>& out, std::vector<uint8_t>& tree, uint64_t base,
                        const GridBase& grid, const GridTypeIo& io, const std::string& uniqueName,
                        const std::string& parent, uint32_t compression, bool stats) {
    ByteWriter w(out);
    const bool half = grid.saveFloatAsHalf();
    w.putString(uniqueName);
    w.putString(io.typeName + (half ? std::string(HALF_SUFFIX) : std::string()));
    w.putString(parent);
    const size_t offsets = w.pos();
    w.put(int64_t(0));
    w.put(int64_t(0));
    w.put(int64_t(0));
    const uint64_t gridPos = base + w.pos();

    const uint32_t flags = gridCompression(grid.getGridClass(), compression);
    w.put(flags);

    MetaMap meta = grid;
    meta.removeMeta(META_DELAYED_LOAD);
    if (stats) {
        const CoordBBox bbox = grid.evalActiveVoxelBoundingBox();
        const Vec3i lo = bbox.empty() ? Vec3i(std::numeric_limits<Int32>::max())
                                      : Vec3i(bbox.min()[0], bbox.min()[1], bbox.min()[2]);
        const Vec3i hi = bbox.empty() ? Vec3i(std::numeric_limits<Int32>::min())
                                      : Vec3i(bbox.max()[0], bbox.max()[1], bbox.max()[2]);
        meta.insertMeta("file_bbox_min", lo);
        meta.insertMeta("file_bbox_max", hi);
        meta.insertMeta("file_compression", compressionToString(flags));
        meta.insertMeta("file_mem_bytes", Int64(grid.memUsage()));
        meta.insertMeta("file_voxel_count", Int64(grid.activeVoxelCount()));
    }

    tree.clear();
    TreeWriteInfo info;
    if (parent.empty()) {
        ByteWriter tw(tree);
        TreeWriteOptions options;
        options.flags = flags;
        options.half = half;
        options.buffersApart = true;
        info = io.write(tw, grid, options);
    }
    const uint64_t treeBytes = tree.size() + info.bufferBytes;
    std::map<std::string, std::pair<std::string, std::vector<uint8_t>>> extra;
    if (parent.empty() && io.hasDelayedLoadTable)
        extra[std::string(META_DELAYED_LOAD)] = {"__delayedload", delayedLoadTable(info, flags)};
    writeMetaMap(w, meta, extra);
    writeTransform(w, grid.transform());

    const uint64_t blockPos = parent.empty() ? base + w.pos() + info.buffersOffset : 0;
    const uint64_t endPos = base + w.pos() + treeBytes;
    w.patch(offsets, int64_t(gridPos));
    w.patch(offsets + 8, int64_t(blockPos));
    w.patch(offsets + 16, int64_t(endPos));
    return info;
}

/// Writes the archive of `input` and `metadata` through `sink` (a File's output file or a
/// Stream's std::ostream); `what` names the destination in errors.
void writeArchive(const std::function<void(const uint8_t*, size_t)>& sink, const GridCPtrVec& input,
                  const MetaMap& metadata, uint32_t compression, bool stats,
                  const std::string& what) {
    std::vector<const GridBase*> grids;
    std::vector<const GridTypeIo*> types;
    for (const auto& g : input) {
        if (!g)
            continue;
        const GridTypeIo* io = findGridTypeOf(*g);
        if (!io)
            throw TypeError(what + ": grids of type " + g->type() +
                            " on this tree configuration are not registered for files "
                            "(see io::registerGridType)");
        grids.push_back(g.get());
        types.push_back(io);
    }

    // Unique names: empty or repeated names get "\x1e" and the first unused counter.
    std::map<std::string, int> nameCount;
    for (const GridBase* g : grids)
        ++nameCount[g->getName()];
    std::set<std::string> used;
    std::vector<std::string> unique;
    for (const GridBase* g : grids) {
        const std::string name = g->getName();
        std::string u = name;
        if (name.empty() || nameCount[name] > 1) {
            for (int n = 0;; ++n) {
                u = name + UNIQUE_SUFFIX + std::to_string(n);
                if (!used.count(u))
                    break;
            }
        }
        used.insert(u);
        unique.push_back(u);
    }

    std::vector<uint8_t> bytes;
    {
        ByteWriter w(bytes);
        w.put(FILE_MAGIC);
        w.put(FILE_VERSION);
        w.put(WRITER_LIBRARY_MAJOR);
        w.put(WRITER_LIBRARY_MINOR);
        w.putBool(true);  // grid offsets
        const std::string uuid = makeUuid();
        w.write(uuid.data(), uuid.size());
        writeMetaMap(w, metadata);
        w.put(Int32(grids.size()));
    }
    uint64_t offset = bytes.size();
    sink(bytes.data(), bytes.size());

    // Grids that share a tree (and the half setting) become instances of the first.
    std::vector<std::pair<const void*, size_t>> written;
    std::vector<uint8_t> tree;
    for (size_t i = 0; i < grids.size(); ++i) {
        std::string parent;
        const void* identity = types[i]->treeIdentity(*grids[i]);
        for (const auto& [tree, j] : written) {
            if (tree == identity && types[j] == types[i] &&
                grids[j]->saveFloatAsHalf() == grids[i]->saveFloatAsHalf()) {
                parent = unique[j];
                break;
            }
        }
        if (parent.empty())
            written.emplace_back(identity, i);
        bytes.clear();
        const TreeWriteInfo info = writeGrid(bytes, tree, offset, *grids[i], *types[i], unique[i],
                                             parent, compression, stats);
        sink(bytes.data(), bytes.size());
        sink(tree.data(), tree.size());
        offset += bytes.size() + tree.size();
        if (info.emitBuffers) {
            info.emitBuffers(sink);
            offset += info.bufferBytes;
        }
    }
}

}  // namespace

void File::write(const GridCPtrVec& grids, const MetaMap& metadata) const {
    util::OutputFile out(mPath);
    writeArchive([&](const uint8_t* data, size_t size) { out.write(data, size); }, grids, metadata,
                 mCompression, mStats, mPath);
    out.commit();
}

// ---- Streams

namespace {
constexpr const char* STREAM_NAME = "<stream>";
}

Stream::Stream(std::istream& is) {
    auto impl = std::make_unique<File::Impl>();
    impl->path = STREAM_NAME;
    impl->delayedLoad = false;
    // Read in chunks: a stream does not say its size, and a failing one stops the loop.
    std::vector<uint8_t>& bytes = impl->owned;
    constexpr size_t CHUNK = size_t(1) << 20;
    while (is) {
        const size_t old = bytes.size();
        bytes.resize(old + CHUNK);
        is.read(reinterpret_cast<char*>(bytes.data() + old), std::streamsize(CHUNK));
        bytes.resize(old + size_t(is.gcount()));
    }
    if (is.bad())
        throw IoError(std::string(STREAM_NAME) + ": the input stream failed");
    impl->parse();
    mImpl = std::move(impl);
}

Stream::Stream(std::ostream& os) : mOut(&os) {}
Stream::~Stream() = default;

MetaMap Stream::getMetadata() const {
    return opened(mImpl, STREAM_NAME).metadata;
}

GridPtrVecPtr Stream::getGrids() const {
    return readAll(opened(mImpl, STREAM_NAME), true);
}

std::vector<UnsupportedGrid> Stream::unsupportedGrids() const {
    return opened(mImpl, STREAM_NAME).unsupported;
}

void Stream::write(const GridCPtrVec& grids, const MetaMap& metadata) const {
    if (!mOut)
        throw IoError(std::string(STREAM_NAME) +
                      ": this Stream reads; construct one with an "
                      "std::ostream to write");
    writeArchive(
        [&](const uint8_t* data, size_t size) {
            mOut->write(reinterpret_cast<const char*>(data), std::streamsize(size));
        },
        grids, metadata, mCompression, mStats, STREAM_NAME);
    mOut->flush();
    if (!*mOut)
        throw IoError(std::string(STREAM_NAME) + ": the output stream failed");
}

}  // namespace vdb::io
