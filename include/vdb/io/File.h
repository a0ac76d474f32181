// SPDX-License-Identifier: Apache-2.0
/// @file
/// io::File: reading and writing `.vdb` files, the format of OpenVDB, Houdini and Blender
/// (FORMAT.md; the paper's section 5.4 and appendix A).
///
/// Reading accepts file versions 220 to 225, seekable files and stream files (no offsets),
/// every map type, metadata of any type (unknown types are kept as opaque bytes), half
/// floats, ZIP and Blosc chunks and every mask-compression case. Grids of a type this library
/// does not hold (points grids, trees of unregistered node dimensions) are listed by
/// unsupportedGrids() and skipped cleanly. Every read is bounds-checked: a truncated,
/// corrupt or hostile file raises IoError naming the file and the problem.
///
/// Delayed loading (out-of-core, the paper's section 5.4): open(true), the default, makes the
/// grids read afterwards hold their topology only; each leaf keeps the file offset of its
/// values and loads them on first access, from any thread (see tree::LeafNode::OutOfCore).
/// Bool and mask leaves, whose values are their bits, are always read at once. Such grids keep
/// the file open, through their leaves, until the last out-of-core leaf is gone, also after
/// close() or after the File is destroyed. They read through the descriptor open() opened: a
/// file deleted or replaced by rename (as write() does) keeps serving the bytes it had when it
/// was opened; a file rewritten or truncated in place serves what it holds at the time of the
/// load: a leaf whose bytes are gone raises IoError from the access that loads it, and changed
/// bytes decode to other values or raise IoError; nothing crashes. (Reading a grid's topology
/// goes through a memory mapping; readGrid() and getGrids() refuse a file that has shrunk since
/// open(), but a truncation during those calls is not guarded against.)
///
/// Writing produces version 224 files that OpenVDB 10 reads, byte-identical to OpenVDB's own
/// output without ZIP or Blosc (apart from the random UUID and `file_mem_bytes`). The file is
/// written to a temporary file next to the target and renamed into place, so an interrupted
/// write never destroys the file that was there.
///
/// @code
/// vdb::io::File out("spheres.vdb");
/// out.setCompression(vdb::io::COMPRESS_BLOSC | vdb::io::COMPRESS_ACTIVE_MASK);
/// out.write({grid});
///
/// vdb::io::File in("spheres.vdb");
/// in.open();
/// for (const auto& g : *in.getGrids()) std::cout << g->getName() << '\n';
/// auto sphere = vdb::gridPtrCast<vdb::FloatGrid>(in.readGrid("sphere"));
/// @endcode

#pragma once

#include <vdb/Grid.h>
#include <vdb/Metadata.h>
#include <vdb/io/Compression.h>

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace vdb::io {

/// A grid a file holds but this library cannot read (e.g. a points grid).
struct UnsupportedGrid {
    std::string name;  ///< display name
    std::string type;  ///< the type string as stored, e.g. "Tree_ptdataidx32_5_4_3"
};

/// The COMPRESS_* flags a grid of class `gridClass` is written with when the file asks for
/// `requested`: ZIP is dropped for level sets and fog volumes, as OpenVDB 10 does (their
/// values compress little under Deflate and read back slowly); every other flag is kept.
/// This is also the grid's `file_compression` metadata.
constexpr uint32_t gridCompression(GridClass gridClass, uint32_t requested) {
    return (gridClass == GRID_LEVEL_SET || gridClass == GRID_FOG_VOLUME)
               ? requested & ~uint32_t(COMPRESS_ZIP)
               : requested;
}

/// The writing side that File and Stream share: the settings grids are written with, and
/// write() for any container of grid pointers.
class ArchiveWriter {
public:
    /// The COMPRESS_* flags grids are written with (default BLOSC | ACTIVE_MASK, as OpenVDB).
    /// ZIP is dropped for level sets and fog volumes, as OpenVDB does (gridCompression()).
    void setCompression(uint32_t flags) { mCompression = flags; }
    uint32_t compression() const { return mCompression; }
    /// Whether written grids carry the `file_bbox_min/max`, `file_voxel_count`,
    /// `file_mem_bytes` and `file_compression` metadata (default on).
    void setGridStatsMetadataEnabled(bool on) { mStats = on; }
    bool isGridStatsMetadataEnabled() const { return mStats; }

    /// Writes `grids` (null entries are skipped) with the archive-level `metadata`.
    virtual void write(const GridCPtrVec& grids, const MetaMap& metadata = MetaMap()) const = 0;
    /// As above, for any container of grid pointers (GridPtrVec, vector<FloatGrid::Ptr>, ...).
    template <typename ContainerT>
    requires(!std::is_same_v<ContainerT, GridCPtrVec>) void write(
        const ContainerT& grids, const MetaMap& metadata = MetaMap()) const {
        write(GridCPtrVec(grids.begin(), grids.end()), metadata);
    }

protected:
    ArchiveWriter() = default;
    ArchiveWriter(const ArchiveWriter&) = default;
    ArchiveWriter& operator=(const ArchiveWriter&) = default;
    ~ArchiveWriter() = default;

    uint32_t mCompression = COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK;
    bool mStats = true;
};

/// A `.vdb` file on disk.
/// Threads: a File is not shared between threads while it is opened, closed or written; the
/// const reading calls (getGrids, readGrid, ...) may run concurrently.
class File : public ArchiveWriter {
public:
    explicit File(std::string path);
    ~File();
    File(const File&) = delete;
    File& operator=(const File&) = delete;

    const std::string& filename() const { return mPath; }

    // ---- Writing (see ArchiveWriter for the settings)
    /// Writes `grids` (null entries are skipped) with the file-level `metadata`, replacing
    /// the file atomically. Grids that share a tree are written once and stored as instances.
    /// @throw IoError when the file cannot be written, TypeError for a grid type that files
    /// cannot hold.
    void write(const GridCPtrVec& grids, const MetaMap& metadata = MetaMap()) const override;
    using ArchiveWriter::write;

    // ---- Reading
    /// Opens the file and reads its header, file metadata and grid descriptors (grid data is
    /// read on demand). With `delayedLoad`, grids read later load their leaf values on first
    /// access (stream files, without offsets, are always read at once).
    /// @throw IoError when the file is missing, not a `.vdb` file or corrupt.
    void open(bool delayedLoad = true);
    bool isOpen() const { return mImpl != nullptr; }
    void close();

    /// The file format version and the writer's library version.
    uint32_t fileVersion() const;
    std::pair<uint32_t, uint32_t> libraryVersion() const;
    /// The file-level metadata.
    MetaMap getMetadata() const;
    /// Names of the readable grids, in file order. Grids written with an empty or repeated
    /// name carry a counter, shown as "name[n]" ("dup[0]", "dup[1]", "[0]"), as OpenVDB does.
    std::vector<std::string> getGridNames() const;
    bool hasGrid(std::string_view name) const;
    /// Grids that are in the file but cannot be read by this library.
    std::vector<UnsupportedGrid> unsupportedGrids() const;

    /// Every readable grid (values delayed or loaded, as open() chose), in the order OpenVDB
    /// returns them (sorted by name; grids of equal names in file order).
    GridPtrVecPtr getGrids() const;
    /// Every readable grid with its metadata and transform but an empty tree.
    GridPtrVecPtr readAllGridMetadata() const;
    /// The grid named `name` (a display name, whose first match is taken, or "name[n]"),
    /// with its tree (values delayed or loaded, as open() chose).
    /// @throw IoError when there is no such grid.
    GridBase::Ptr readGrid(std::string_view name) const;
    /// The grid named `name` with metadata and transform only.
    GridBase::Ptr readGridMetadata(std::string_view name) const;

    struct Impl;

private:
    std::string mPath;
    std::unique_ptr<Impl> mImpl;
};

/// A `.vdb` archive in a C++ stream, as OpenVDB's io::Stream: the bytes File writes, for a
/// pipe, a socket, a database record or Python's pickle. What one Stream writes another reads,
/// and so does File once the bytes are saved; every grid is read at once (no delayed load).
/// Reading accepts what File::open accepts, with the same checks.
///
/// @code
/// std::ostringstream os;
/// vdb::io::Stream(os).write({grid});
/// std::istringstream is(os.str());
/// vdb::GridPtrVecPtr grids = vdb::io::Stream(is).getGrids();
/// @endcode
///
/// Threads: as File.
class Stream : public ArchiveWriter {
public:
    /// Reads the whole archive from `is` (to its end).
    /// @throw IoError when the stream fails or its bytes are not a `.vdb` archive or corrupt.
    explicit Stream(std::istream& is);
    /// A Stream that writes to `os`.
    explicit Stream(std::ostream& os);
    ~Stream();
    Stream(const Stream&) = delete;
    Stream& operator=(const Stream&) = delete;

    // ---- Writing (a Stream made from an std::ostream; see ArchiveWriter for the settings)
    /// Writes `grids` (null entries are skipped) with the archive-level `metadata` to the
    /// stream, as File::write writes a file.
    /// @throw IoError when this Stream reads or the stream fails, TypeError as File::write.
    void write(const GridCPtrVec& grids, const MetaMap& metadata = MetaMap()) const override;
    using ArchiveWriter::write;

    // ---- Reading (a Stream made from an std::istream)
    /// The archive-level metadata. @throw IoError when this Stream writes.
    MetaMap getMetadata() const;
    /// Every readable grid, in the order File::getGrids gives. @throw IoError as getMetadata.
    GridPtrVecPtr getGrids() const;
    /// Grids the archive holds that this library cannot read. @throw IoError as getMetadata.
    std::vector<UnsupportedGrid> unsupportedGrids() const;

private:
    std::ostream* mOut = nullptr;
    std::unique_ptr<File::Impl> mImpl;
};

}  // namespace vdb::io
