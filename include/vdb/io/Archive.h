// SPDX-License-Identifier: Apache-2.0
/// @file
/// Trees in `.vdb` files: the topology section (root, internal nodes, leaf masks) and the
/// buffers section (leaf values), FORMAT.md 1.7, 1.8 and 1.11; and the registry that maps the
/// grid type strings of a file ("Tree_float_5_4_3") to the grid types of this library.
///
/// Writing encodes the leaves in parallel, in blocks whose bytes are concatenated in the
/// tree's depth-first order, so the output does not depend on the thread count. Reading
/// parses the topology serially, finds every leaf's bytes with a cheap serial skip, then
/// decodes the leaves in parallel, or, with delayed loading, gives each leaf a record of where
/// its bytes are (tree::LeafNode::OutOfCore) and decodes it on first access. Every count,
/// length, origin and code is checked against the data before it is used (see ByteReader).

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/io/Compression.h>
#include <vdb/io/Format.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/NodeTraits.h>
#include <vdb/tree/TreeConfigs.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeinfo>
#include <vector>

namespace vdb::io {

/// How a tree is written: the grid's compression flags (ZIP already cleared where the grid
/// class asks for it) and whether real values are stored as halves.
struct TreeWriteOptions {
    uint32_t flags = COMPRESS_ACTIVE_MASK;
    bool half = false;
    /// Leave the leaf buffers out of the writer: TreeWriteInfo::emitBuffers hands them to the
    /// file writer afterwards (to be written right after the topology), so that they are never
    /// copied into one large new buffer. Without a codec they are not even kept: writeTree()
    /// encodes them once to learn their sizes and codes, and emitBuffers() encodes them again,
    /// a few blocks at a time, into buffers it reuses.
    bool buffersApart = false;
};

/// An open file that out-of-core leaves read their bytes from. It stays open as long as a
/// leaf refers to it (through shared pointers), and reads with pread(), so a file removed or
/// replaced by rename after opening keeps serving its original bytes, and a file truncated in
/// place makes the affected loads raise IoError rather than crash.
/// Threads: read() may run concurrently.
class FileSource {
public:
    /// Opens `path` for reading. @throw IoError when it cannot be opened.
    explicit FileSource(const std::string& path);
    ~FileSource();
    FileSource(const FileSource&) = delete;
    FileSource& operator=(const FileSource&) = delete;

    int fd() const { return mFd; }
    const std::string& path() const { return mPath; }
    /// Replaces `out` by the file's bytes [begin, end).
    /// @throw IoError when the file no longer holds them.
    void read(uint64_t begin, uint64_t end, std::vector<uint8_t>& out) const;

private:
    std::string mPath;
    int mFd = -1;
};

/// How a tree is read: the grid's flags, the half flag and the file version; with `delayed`,
/// leaf values are left in that file and loaded on first access (the bytes the reader is given
/// must then start at the file's first byte).
struct TreeReadOptions {
    uint32_t flags = COMPRESS_ACTIVE_MASK;
    bool half = false;
    uint32_t fileVersion = FILE_VERSION;
    std::shared_ptr<const FileSource> delayed;
};

/// What writing a tree tells the file writer: where the buffers start within the tree's bytes
/// and, per leaf in file order, the mask-compression code and the size of its value chunk
/// (the `file_delayed_load` table, FORMAT.md 1.12).
struct TreeWriteInfo {
    /// Receives bytes in file order.
    using Sink = std::function<void(const uint8_t* data, size_t size)>;

    size_t buffersOffset = 0;
    std::vector<int8_t> leafCodes;
    std::vector<uint64_t> leafChunkBytes;
    /// With TreeWriteOptions::buffersApart: the size of the leaf buffers' bytes, and what
    /// hands them to a sink, in blocks in file order. emitBuffers reads the tree's leaves: the
    /// tree must stay unchanged until it has run. @throw IoError when the leaves encode to
    /// other sizes than they did in writeTree() (the tree was changed in between)
    uint64_t bufferBytes = 0;
    std::function<void(const Sink&)> emitBuffers;
};

/// Appends the topology and buffers of `tree` (a tree with a RootNode on top).
template <typename TreeT>
TreeWriteInfo writeTree(ByteWriter& w, const TreeT& tree, const TreeWriteOptions& options);

/// Reads the topology and buffers of a tree into `tree`, which must be empty.
template <typename TreeT>
void readTree(ByteReader& r, TreeT& tree, const TreeReadOptions& options);

/// A grid type a file can hold, with the functions that create, write and read it.
struct GridTypeIo {
    std::string typeName;                      ///< the tree type string, e.g. "Tree_float_5_4_3"
    const std::type_info* gridType = nullptr;  ///< typeid of the Grid class
    bool hasDelayedLoadTable = false;          ///< whether files carry `file_delayed_load` for it
    GridBase::Ptr (*create)() = nullptr;
    TreeWriteInfo (*write)(ByteWriter&, const GridBase&, const TreeWriteOptions&) = nullptr;
    void (*read)(ByteReader&, GridBase&, const TreeReadOptions&) = nullptr;
    /// An identity of the grid's tree: grids that share a tree return the same pointer.
    const void* (*treeIdentity)(const GridBase&) = nullptr;
    /// Makes `instance` share the tree of `parent` (same type).
    void (*shareTree)(GridBase& instance, const GridBase& parent) = nullptr;
};

/// The GridTypeIo of Grid<TreeT>.
template <typename GridT>
GridTypeIo makeGridTypeIo();

/// The type that reads grids of type string `typeName` (without "_HalfFloat"), or null. The
/// nine standard grid types (float, double, int32, int64, bool, mask, vec3s, vec3d, vec3i on
/// [5,4,3] trees) are always registered.
const GridTypeIo* findGridType(std::string_view typeName);
/// The type that writes `grid` (found by its C++ type), or null when it is not registered.
const GridTypeIo* findGridTypeOf(const GridBase& grid);
/// Registers a grid type so files can hold it (for trees of other node dimensions, e.g.
/// Grid<tree::HashTree432<float>>). It becomes the reader of its type string, replacing an
/// earlier registration of the same string, and the writer of its C++ type.
void registerGridType(const GridTypeIo& type);
template <typename GridT>
void registerGridType() {
    registerGridType(makeGridTypeIo<GridT>());
}

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

template <typename MaskT>
void writeMask(ByteWriter& w, const MaskT& mask) {
    w.write(mask.words(), sizeof(typename MaskT::Word) * MaskT::WORD_COUNT);
}
template <typename MaskT>
void readMask(ByteReader& r, MaskT& mask, std::string_view what) {
    const auto bytes = r.take(sizeof(typename MaskT::Word) * MaskT::WORD_COUNT, what);
    std::memcpy(mask.words(), bytes.data(), bytes.size());
}

inline void writeCoord(ByteWriter& w, const Coord& c) {
    w.put(Int32(c[0]));
    w.put(Int32(c[1]));
    w.put(Int32(c[2]));
}
inline Coord readCoord(ByteReader& r, std::string_view what) {
    const auto a = r.read<Int32>(what);
    const auto b = r.read<Int32>(what);
    const auto c = r.read<Int32>(what);
    return Coord(a, b, c);
}

/// Writes the topology of internal node `node` and collects its leaves in file order.
template <typename NodeT, typename LeafT>
void writeInternalTopology(ByteWriter& w, const NodeT& node,
                           const typename NodeT::ValueType& background,
                           const TreeWriteOptions& options, std::vector<const LeafT*>& leaves,
                           CodecScratch& scratch) {
    using ValueT = typename NodeT::ValueType;
    const auto& childMask = node.getChildMask();
    const auto& valueMask = node.getValueMask();
    writeMask(w, childMask);
    writeMask(w, valueMask);
    // A vector<bool> has no data(): an array it is.
    const auto values = std::make_unique<ValueT[]>(NodeT::NUM_VALUES);
    for (Index n = 0; n < NodeT::NUM_VALUES; ++n)
        values[n] = childMask.isOn(n) ? ValueT{} : node.getTileValue(n);
    writeCompressedValues(w, values.get(), valueMask, &childMask, background, options.half,
                          options.flags, scratch);
    for (Index n : childMask.onBits()) {
        const auto* child = node.getChild(n);
        if constexpr (NodeT::ChildNodeType::LEVEL == 0) {
            writeMask(w, child->getValueMask());
            leaves.push_back(child);
        } else {
            writeInternalTopology(w, *child, background, options, leaves, scratch);
        }
    }
}

/// Writes one leaf's buffer record; returns its code and chunk size.
template <typename LeafT>
ArrayInfo writeLeafBuffer(ByteWriter& w, const LeafT& leaf, const typename LeafT::ValueType& bg,
                          const TreeWriteOptions& options, CodecScratch& scratch) {
    writeMask(w, leaf.getValueMask());
    if constexpr (tree::IS_BOOL_NODE<LeafT>) {
        writeCoord(w, leaf.origin());
        writeMask(w, leaf.buffer());
        return {};
    } else if constexpr (tree::IS_MASK_NODE<LeafT>) {
        writeCoord(w, leaf.origin());
        return {};
    } else {
        return writeCompressedValues(w, leaf.buffer(0).data(), leaf.getValueMask(),
                                     static_cast<const typename LeafT::MaskType*>(nullptr), bg,
                                     options.half, options.flags, scratch);
    }
}

/// Topology read state shared by the levels of one tree.
template <typename LeafT>
struct TopologyReader {
    ByteReader& r;
    const TreeReadOptions& options;
    typename LeafT::ValueType background;
    std::vector<LeafT*> leaves;
    CodecScratch scratch;
};

template <typename NodeT, typename LeafT>
void readInternalTopology(TopologyReader<LeafT>& s, NodeT& node) {
    using ValueT = typename NodeT::ValueType;
    using ChildT = typename NodeT::ChildNodeType;
    ByteReader& r = s.r;
    typename NodeT::MaskType childMask, valueMask;
    readMask(r, childMask, "internal node child mask");
    readMask(r, valueMask, "internal node value mask");
    const bool hasCode = s.options.fileVersion >= FILE_VERSION_NODE_MASK_COMPRESSION;
    const Index count = hasCode ? NodeT::NUM_VALUES : childMask.countOff();
    const auto values = std::make_unique<ValueT[]>(count);
    readCompressedValues(r, values.get(), count, valueMask, s.background, s.options.half,
                         s.options.flags, hasCode, s.scratch);
    Index k = 0;
    for (Index n = 0; n < NodeT::NUM_VALUES; ++n) {
        if (childMask.isOn(n)) {
            if (!hasCode)
                continue;
        } else {
            node.setTile(n, values[hasCode ? n : k], valueMask.isOn(n));
        }
        ++k;
    }
    for (Index n : childMask.onBits()) {
        const Coord origin = node.offsetToGlobalCoord(n);
        if constexpr (ChildT::LEVEL == 0) {
            // Value leaves get their buffer when the values are read (or none, when delayed).
            std::unique_ptr<ChildT> leaf;
            if constexpr (tree::IS_BOOL_NODE<ChildT> || tree::IS_MASK_NODE<ChildT>)
                leaf = std::make_unique<ChildT>(origin, false, false);
            else
                leaf = std::make_unique<ChildT>(tree::PartialCreate{}, origin);
            readMask(r, leaf->getValueMask(), "leaf value mask");
            s.leaves.push_back(leaf.get());
            node.setChild(n, leaf.release());
        } else {
            auto child = std::make_unique<ChildT>(origin, s.background, false);
            ChildT* raw = child.get();
            node.setChild(n, child.release());  // owned by the node from here on
            readInternalTopology(s, *raw);
        }
    }
}

/// Skips one leaf's value array (FORMAT.md 1.8) without decoding it.
template <typename LeafT>
void skipLeafValues(ByteReader& r, const LeafT& leaf, const TreeReadOptions& options) {
    using ValueT = typename LeafT::ValueType;
    const bool hasCode = options.fileVersion >= FILE_VERSION_NODE_MASK_COMPRESSION;
    const auto h = readArrayHeader(r, LeafT::NUM_VALUES, leaf.getValueMask(), ValueT{},
                                   options.flags, hasCode);
    skipData<ValueT>(r, h.valueCount, options.half, options.flags);
}

/// Reads the values of a value leaf of mask `mask` into `values`, starting after the mask of
/// its buffer record; checks the stored origin against `origin` unless it is null.
template <typename LeafT>
void readLeafValues(ByteReader& r, typename LeafT::ValueType* values,
                    const typename LeafT::MaskType& mask, const Coord* origin,
                    const typename LeafT::ValueType& background, const TreeReadOptions& options,
                    CodecScratch& scratch) {
    if (options.fileVersion >= FILE_VERSION_NODE_MASK_COMPRESSION) {
        readCompressedValues(r, values, LeafT::NUM_VALUES, mask, background, options.half,
                             options.flags, true, scratch);
        return;
    }
    const Coord stored = readCoord(r, "leaf origin");
    if (origin && stored != *origin)
        r.fail("leaf origin differs from the topology's");
    const int8_t buffers = r.read<int8_t>("leaf buffer count");
    if (buffers < 1)
        r.fail("leaf buffer count " + std::to_string(int(buffers)));
    readCompressedValues(r, values, LeafT::NUM_VALUES, mask, background, options.half,
                         options.flags, false, scratch);
    // Older files could hold extra temporal buffers: read and drop them.
    const auto extra = std::make_unique<typename LeafT::ValueType[]>(LeafT::NUM_VALUES);
    for (int b = 1; b < buffers; ++b) {
        readCompressedValues(r, extra.get(), LeafT::NUM_VALUES, mask, background, options.half,
                             options.flags, false, scratch);
    }
}

/// Reads one leaf's buffer record starting at the reader's position.
template <typename LeafT>
void readLeafBuffer(ByteReader& r, LeafT& leaf, const typename LeafT::ValueType& background,
                    const TreeReadOptions& options, CodecScratch& scratch) {
    // The value mask is repeated here; the topology's copy is the one kept (as OpenVDB does
    // for files).
    r.skip(sizeof(typename LeafT::MaskType::Word) * LeafT::MaskType::WORD_COUNT, "leaf mask");
    if constexpr (tree::IS_BOOL_NODE<LeafT> || tree::IS_MASK_NODE<LeafT>) {
        if (readCoord(r, "leaf origin") != leaf.origin())
            r.fail("leaf origin differs from the topology's");
        if constexpr (tree::IS_BOOL_NODE<LeafT>)
            readMask(r, leaf.buffer(), "bool leaf values");
    } else {
        leaf.setBufferCount(1);  // uninitialised: every value is read below
        readLeafValues<LeafT>(r, leaf.buffer(0).data(), leaf.getValueMask(), &leaf.origin(),
                              background, options, scratch);
    }
}

/// What the out-of-core leaves of one tree share: the file and how to decode.
template <typename ValueT>
struct DelayedTree {
    TreeReadOptions options;
    ValueT background;
};

/// The out-of-core record of a value leaf: the file offsets of its buffer record. Loading
/// decodes with the value mask stored in the record, so state changes made before the load do
/// not change the values.
template <typename LeafT>
class DelayedLeafValues final : public LeafT::OutOfCore {
public:
    using ValueT = typename LeafT::ValueType;
    DelayedLeafValues(std::shared_ptr<const DelayedTree<ValueT>> tree, uint64_t begin, uint64_t end)
        : mTree(std::move(tree)), mBegin(begin), mEnd(end) {}

    void load(ValueT* values) const override {
        thread_local std::vector<uint8_t> bytes;
        thread_local CodecScratch scratch;
        const FileSource& file = *mTree->options.delayed;
        file.read(mBegin, mEnd, bytes);
        const std::string source = file.path() + " (leaf at offset " + std::to_string(mBegin) + ")";
        ByteReader r(bytes, source);
        typename LeafT::MaskType mask;
        readMask(r, mask, "leaf value mask");
        readLeafValues<LeafT>(r, values, mask, nullptr, mTree->background, mTree->options, scratch);
    }
    std::unique_ptr<typename LeafT::OutOfCore> clone() const override {
        return std::make_unique<DelayedLeafValues>(*this);
    }
    Index64 memUsage() const override { return sizeof(DelayedLeafValues); }

private:
    std::shared_ptr<const DelayedTree<ValueT>> mTree;
    uint64_t mBegin, mEnd;  // the leaf's buffer record: file bytes [mBegin, mEnd)
};

/// Finds where the next leaf record ends, without decoding it.
template <typename LeafT>
void skipLeafBuffer(ByteReader& r, const LeafT& leaf, const TreeReadOptions& options) {
    r.skip(sizeof(typename LeafT::MaskType::Word) * LeafT::MaskType::WORD_COUNT, "leaf mask");
    const bool hasCode = options.fileVersion >= FILE_VERSION_NODE_MASK_COMPRESSION;
    if constexpr (tree::IS_BOOL_NODE<LeafT>) {
        r.skip(12 + sizeof(typename LeafT::MaskType::Word) * LeafT::MaskType::WORD_COUNT,
               "bool leaf");
    } else if constexpr (tree::IS_MASK_NODE<LeafT>) {
        r.skip(12, "mask leaf origin");
    } else if (!hasCode) {
        r.skip(12, "leaf origin");
        const int8_t buffers = r.read<int8_t>("leaf buffer count");
        if (buffers < 1)
            r.fail("leaf buffer count " + std::to_string(int(buffers)));
        for (int b = 0; b < buffers; ++b)
            skipLeafValues(r, leaf, options);
    } else {
        skipLeafValues(r, leaf, options);
    }
}

}  // namespace detail

template <typename TreeT>
TreeWriteInfo writeTree(ByteWriter& w, const TreeT& tree, const TreeWriteOptions& options) {
    using RootT = typename TreeT::TopNodeType;
    using ChildT = typename RootT::ChildNodeType;
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    static_assert(!TreeT::BOUNDED, "only trees with a RootNode on top have a file layout");
    const size_t start = w.pos();
    const RootT& root = tree.topNode();
    const ValueT& background = tree.background();
    detail::CodecScratch scratch;

    w.put(Int32(1));  // buffer count
    detail::writeValue(w, options.half ? detail::roundToHalf(background) : background);
    std::vector<Coord> tiles, children;
    for (const Coord& key : root.sortedKeys())
        (root.findEntry(key)->child ? children : tiles).push_back(key);
    w.put(uint32_t(tiles.size()));
    w.put(uint32_t(children.size()));
    for (const Coord& key : tiles) {
        const auto* e = root.findEntry(key);
        detail::writeCoord(w, key);
        detail::writeValue(w, e->tile);  // root tiles keep full precision, even in half grids
        w.putBool(e->active);
    }
    std::vector<const LeafT*> leaves;
    for (const Coord& key : children) {
        detail::writeCoord(w, key);
        detail::writeInternalTopology(w, *static_cast<const ChildT*>(root.findEntry(key)->child),
                                      background, options, leaves, scratch);
    }

    TreeWriteInfo info;
    info.buffersOffset = w.pos() - start;
    info.leafCodes.resize(leaves.size());
    info.leafChunkBytes.resize(leaves.size());
    // Leaves in blocks of BLOCK, each block encoded into its own buffer. The list is shared
    // with emitBuffers, which may run after this function has returned.
    constexpr size_t BLOCK = 64;
    const size_t blocks = (leaves.size() + BLOCK - 1) / BLOCK;
    const auto list = std::make_shared<const std::vector<const LeafT*>>(std::move(leaves));
    const auto encodeBlock = [list, background, options](size_t b, std::vector<uint8_t>& out,
                                                         detail::CodecScratch& local,
                                                         TreeWriteInfo* record) {
        out.clear();
        ByteWriter bw(out);
        const size_t end = std::min(list->size(), (b + 1) * BLOCK);
        for (size_t i = b * BLOCK; i < end; ++i) {
            const auto a = detail::writeLeafBuffer(bw, *(*list)[i], background, options, local);
            if (record) {
                record->leafCodes[i] = a.code;
                record->leafChunkBytes[i] = a.dataBytes;
            }
        }
    };
    const bool codec = (options.flags & (COMPRESS_ZIP | COMPRESS_BLOSC)) != 0;
    if (options.buffersApart && !codec) {
        // Encode once for the sizes and codes, keeping nothing; emitBuffers encodes again.
        auto sizes = std::make_shared<std::vector<uint64_t>>(blocks);
        tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks),
                          [&](const tbb::blocked_range<size_t>& range) {
                              detail::CodecScratch local;
                              std::vector<uint8_t> out;
                              for (size_t b = range.begin(); b != range.end(); ++b) {
                                  encodeBlock(b, out, local, &info);
                                  (*sizes)[b] = out.size();
                              }
                          });
        for (uint64_t size : *sizes)
            info.bufferBytes += size;
        info.emitBuffers = [encodeBlock, sizes, blocks](const TreeWriteInfo::Sink& sink) {
            // A window of blocks at a time, encoded in parallel into buffers that the next
            // window reuses.
            constexpr size_t WINDOW = 16;
            std::vector<std::vector<uint8_t>> window(std::min(WINDOW, blocks));
            for (size_t first = 0; first < blocks; first += WINDOW) {
                const size_t count = std::min(WINDOW, blocks - first);
                tbb::parallel_for(tbb::blocked_range<size_t>(0, count),
                                  [&](const tbb::blocked_range<size_t>& range) {
                                      detail::CodecScratch local;
                                      for (size_t k = range.begin(); k != range.end(); ++k)
                                          encodeBlock(first + k, window[k], local, nullptr);
                                  });
                for (size_t k = 0; k < count; ++k) {
                    if (window[k].size() != (*sizes)[first + k])
                        throw IoError("a tree changed while it was being written");
                    sink(window[k].data(), window[k].size());
                }
            }
        };
        return info;
    }
    std::vector<std::vector<uint8_t>> out(blocks);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks),
                      [&](const tbb::blocked_range<size_t>& range) {
                          detail::CodecScratch local;
                          for (size_t b = range.begin(); b != range.end(); ++b)
                              encodeBlock(b, out[b], local, &info);
                      });
    if (options.buffersApart) {
        for (const auto& block : out)
            info.bufferBytes += block.size();
        auto kept = std::make_shared<std::vector<std::vector<uint8_t>>>(std::move(out));
        info.emitBuffers = [kept](const TreeWriteInfo::Sink& sink) {
            for (const auto& block : *kept)
                sink(block.data(), block.size());
        };
        return info;
    }
    size_t total = 0;
    for (const auto& o : out)
        total += o.size();
    w.buffer().reserve(w.buffer().size() + total);
    for (auto& o : out) {
        w.write(o);
        std::vector<uint8_t>().swap(o);
    }
    return info;
}

template <typename TreeT>
void readTree(ByteReader& r, TreeT& tree, const TreeReadOptions& options) {
    using RootT = typename TreeT::TopNodeType;
    using ChildT = typename RootT::ChildNodeType;
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    static_assert(!TreeT::BOUNDED, "only trees with a RootNode on top have a file layout");

    const Int32 bufferCount = r.read<Int32>("tree buffer count");
    if (bufferCount != 1)
        r.fail("tree buffer count " + std::to_string(bufferCount) + " (1 expected)");
    const ValueT background = detail::readValue<ValueT>(r, "background");
    tree.setBackground(background);
    RootT& root = tree.topNode();

    const uint32_t numTiles = r.read<uint32_t>("root tile count");
    const uint32_t numChildren = r.read<uint32_t>("root child count");
    constexpr uint64_t TILE_BYTES = 12 + sizeof(ValueT) + 1;
    r.checkedCount(numTiles, TILE_BYTES, "root tile");
    // A child holds at least its origin and two node masks.
    r.checkedCount(numChildren, 12 + 2 * (ChildT::NUM_VALUES / 8), "root child");
    constexpr Int32 CHILD_LOW = Int32(ChildT::DIM - 1);
    const auto checkKey = [&](const Coord& key, const char* what) {
        const std::string at = std::string(what) + " origin (" + std::to_string(key[0]) + ", " +
                               std::to_string(key[1]) + ", " + std::to_string(key[2]) + ")";
        if ((key[0] & CHILD_LOW) || (key[1] & CHILD_LOW) || (key[2] & CHILD_LOW))
            r.fail(at + " is not a multiple of " + std::to_string(ChildT::DIM));
        if (root.findEntry(key))
            r.fail(at + " appears twice");
    };
    for (uint32_t i = 0; i < numTiles; ++i) {
        const Coord key = detail::readCoord(r, "root tile origin");
        const ValueT value = detail::readValue<ValueT>(r, "root tile value");
        const bool active = r.readBool("root tile state");
        checkKey(key, "root tile");
        root.setTile(key, value, active);
    }
    detail::TopologyReader<LeafT> state{r, options, background, {}, {}};
    for (uint32_t i = 0; i < numChildren; ++i) {
        const Coord key = detail::readCoord(r, "root child origin");
        checkKey(key, "root child");
        auto child = std::make_unique<ChildT>(key, background, false);
        ChildT* raw = child.get();
        root.setChild(child.release());
        detail::readInternalTopology(state, *raw);
    }

    // Buffers: find each leaf's record serially, then decode them in parallel.
    auto& leaves = state.leaves;
    std::vector<size_t> starts(leaves.size() + 1);
    for (size_t i = 0; i < leaves.size(); ++i) {
        starts[i] = r.pos();
        detail::skipLeafBuffer(r, *leaves[i], options);
    }
    starts[leaves.size()] = r.pos();
    if constexpr (!tree::IS_BOOL_NODE<LeafT> && !tree::IS_MASK_NODE<LeafT>) {
        if (options.delayed) {
            auto shared = std::make_shared<const detail::DelayedTree<ValueT>>(
                detail::DelayedTree<ValueT>{options, background});
            for (size_t i = 0; i < leaves.size(); ++i) {
                leaves[i]->setOutOfCore(std::make_unique<detail::DelayedLeafValues<LeafT>>(
                    shared, starts[i], starts[i + 1]));
            }
            return;
        }
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 32),
                      [&](const tbb::blocked_range<size_t>& range) {
                          detail::CodecScratch local;
                          for (size_t i = range.begin(); i != range.end(); ++i) {
                              // Each leaf reads only its own bytes.
                              ByteReader lr(r.bytes().first(starts[i + 1]), r.source());
                              lr.seek(starts[i]);
                              detail::readLeafBuffer(lr, *leaves[i], background, options, local);
                          }
                      });
}

template <typename GridT>
GridTypeIo makeGridTypeIo() {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename TreeT::BuildType;
    GridTypeIo t;
    t.typeName = GridT::gridType();
    t.gridType = &typeid(GridT);
    t.hasDelayedLoadTable = !std::is_same_v<ValueT, bool> && !std::is_same_v<ValueT, ValueMask>;
    t.create = []() -> GridBase::Ptr { return GridT::create(); };
    t.write = [](ByteWriter& w, const GridBase& g, const TreeWriteOptions& o) {
        return writeTree(w, static_cast<const GridT&>(g).tree(), o);
    };
    t.read = [](ByteReader& r, GridBase& g, const TreeReadOptions& o) {
        readTree(r, static_cast<GridT&>(g).tree(), o);
    };
    t.treeIdentity = [](const GridBase& g) -> const void* {
        return &static_cast<const GridT&>(g).tree();
    };
    t.shareTree = [](GridBase& instance, const GridBase& parent) {
        static_cast<GridT&>(instance).setTree(static_cast<const GridT&>(parent).treePtr());
    };
    return t;
}

}  // namespace vdb::io
