// SPDX-License-Identifier: Apache-2.0
/// @file
/// OutputFile: the one way the library and the `vdb` tool write files (`.vdb`, images,
/// meshes), so that an output is either the complete new file or the old one, never a
/// half-written file or a destroyed device.
///
/// - A regular file (or a new name) is replaced atomically: the bytes go to a temporary file in
///   the same folder (an unnamed O_TMPFILE where the file system supports it, else a short name
///   ".vdb-PID-XXXXXX" that does not depend on the target's name), are flushed with fsync, and
///   the temporary file is renamed over the target; the folder is then synced. The replaced
///   file's mode and, where permitted, owner and group are kept; a new file gets 0666 less the
///   umask, as open() would give it.
/// - A symbolic link is written through: its final target is replaced, the link stays.
/// - A character or block device or a FIFO is written directly (`-o /dev/null`,
///   `-o /dev/stdout`, a pipe); a socket is refused.
/// - Nothing is created until the first write(), so work that fails before it leaves the disk
///   untouched; an OutputFile destroyed without commit() removes its temporary file. An
///   unnamed temporary file disappears even when the process is killed; named ones left by a
///   killed process are removed by the next OutputFile that writes into that folder (their
///   process id no longer runs).
/// - A target that exists but that the user may not write (a read-only file) is refused, as
///   cp refuses it, rather than replaced through the folder's permission.
///
/// Hard links to a replaced file keep the old contents (the name gets a new file), as with
/// every atomic replace.
///
/// @code
/// vdb::util::OutputFile out("picture.png");
/// out.write(bytes.data(), bytes.size());  // the temporary file appears here
/// out.commit();                           // picture.png is now the new file
/// @endcode
///
/// Threads: one OutputFile is used by one thread; different OutputFiles may be written
/// concurrently, and removeOutputTemporaries() may run while they are.

#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace vdb::util {

/// A file being written; see the file comment.
class OutputFile {
public:
    /// Prepares to write `path`, resolving symbolic links and deciding between an atomic
    /// replace and a direct write. Creates and opens nothing.
    /// @throw IoError when `path` is empty, names a folder or a socket, lies in a folder that
    ///        does not exist or that is not writable (for a replace), when a link chain is too
    ///        long, or when the target exists but is not writable.
    explicit OutputFile(std::string path);
    /// Discards the output unless commit() was called: the temporary file is removed (a
    /// direct write keeps what was written).
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    /// The path as given, and the file that will be replaced or written (links resolved).
    const std::string& path() const { return mPath; }
    const std::string& target() const { return mTarget; }
    /// True when the target is a device or FIFO, written in place rather than replaced.
    bool isDirect() const { return mDirect; }

    /// Appends `size` bytes, creating the temporary file (or opening the device) first.
    /// @throw IoError naming the path and the system's reason.
    void write(const void* data, size_t size);
    void write(const std::vector<uint8_t>& bytes) { write(bytes.data(), bytes.size()); }
    /// The open descriptor (opening it first), for writers that need one.
    int fd();

    /// Finishes the file: fsync, the old file's mode and owner, rename over the target (or, for
    /// a direct write, nothing more than the flush). An output with no write() still produces
    /// an empty file.
    /// @throw IoError naming the path; the old file is then untouched.
    void commit();

private:
    void open();

    std::string mPath;    // as given
    std::string mTarget;  // links resolved
    std::string mFolder;  // the target's folder
    std::string mTemp;    // the named temporary file, if any
    bool mDirect = false;
    bool mExists = false;  // the target exists (a regular file to replace)
    uint32_t mMode = 0;    // its permission bits
    uint32_t mUid = 0, mGid = 0;
    int mFd = -1;
    bool mUnnamed = false;  // mFd is an O_TMPFILE
    bool mCommitted = false;
    uint64_t mWritten = 0;  // bytes written to the temporary file
    uint64_t mFlushed = 0;  // of those, the bytes whose write-back has been started
};

/// Writes `path` through an OutputFile: calls `write(out)`, then commits. When `write` throws,
/// nothing on disk changes and the exception propagates.
void writeOutputFile(const std::string& path, const std::function<void(OutputFile&)>& write);

/// Checks, before any work starts, that `path` could be written as OutputFile would: throws
/// the IoError OutputFile's constructor would throw. Creates nothing.
void checkOutputFile(const std::string& path);

/// Removes the named temporary files of every OutputFile of this process that is being
/// written, for a handler of SIGINT or SIGTERM running on its own thread before the process
/// exits. Unnamed temporary files need nothing.
void removeOutputTemporaries() noexcept;

}  // namespace vdb::util
