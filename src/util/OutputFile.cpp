// SPDX-License-Identifier: Apache-2.0

#include <vdb/Exceptions.h>
#include <vdb/util/OutputFile.h>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <random>
#include <set>
#include <string_view>

namespace vdb::util {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) {
    throw IoError("cannot write " + path + ": " + why);
}
[[noreturn]] void failErrno(const std::string& path, const std::string& what, int err) {
    fail(path, what + (what.empty() ? "" : ": ") + std::strerror(err));
}

std::string folderOf(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos)
        return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

std::string octal(uint32_t mode) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%04o", unsigned(mode & 07777));
    return buf;
}

// ---- Named temporary files of this process, for removeOutputTemporaries() and cleanup

std::mutex& registryMutex() {
    static std::mutex m;
    return m;
}
std::set<std::string>& registry() {
    static std::set<std::string> names;
    return names;
}
std::set<std::string>& cleanedFolders() {
    static std::set<std::string> folders;
    return folders;
}

void registerTemp(const std::string& name) {
    std::lock_guard lock(registryMutex());
    registry().insert(name);
}
void unregisterTemp(const std::string& name) {
    std::lock_guard lock(registryMutex());
    registry().erase(name);
}

constexpr std::string_view kTempPrefix = ".vdb-";

/// The process id in a temporary name ".vdb-PID-XXXXXX", or 0 when `name` is not one.
pid_t tempOwner(std::string_view name) {
    if (name.substr(0, kTempPrefix.size()) != kTempPrefix)
        return 0;
    name.remove_prefix(kTempPrefix.size());
    const size_t dash = name.find('-');
    if (dash == 0 || dash == std::string_view::npos || name.size() - dash - 1 != 6)
        return 0;
    long pid = 0;
    for (char c : name.substr(0, dash)) {
        if (c < '0' || c > '9' || pid > 100000000)
            return 0;
        pid = pid * 10 + (c - '0');
    }
    return pid_t(pid);
}

/// Removes the temporary files that processes no longer running left in `folder` (killed
/// while writing); once per folder and process.
void removeStaleTemporaries(const std::string& folder) {
    {
        std::lock_guard lock(registryMutex());
        if (!cleanedFolders().insert(folder).second)
            return;
    }
    DIR* dir = ::opendir(folder.c_str());
    if (!dir)
        return;
    while (const dirent* entry = ::readdir(dir)) {
        const pid_t pid = tempOwner(entry->d_name);
        if (pid <= 0 || pid == ::getpid())
            continue;
        if (::kill(pid, 0) != 0 && errno == ESRCH)
            ::unlinkat(::dirfd(dir), entry->d_name, 0);
    }
    ::closedir(dir);
}

/// A new name ".vdb-PID-XXXXXX" in `folder`; short whatever the target's name.
std::string tempName(const std::string& folder) {
    static thread_local std::mt19937_64 rng(std::random_device{}() ^ (uint64_t(::getpid()) << 32));
    static constexpr char kDigits[] = "0123456789abcdefghijklmnopqrstuvwxyz";
    std::string name = folder + "/" + std::string(kTempPrefix) + std::to_string(::getpid()) + "-";
    for (int i = 0; i < 6; ++i)
        name += kDigits[rng() % 36];
    return name;
}

/// Syncs the folder's entry list, so that a rename survives a crash; errors are ignored (some
/// file systems refuse fsync on folders).
void syncFolder(const std::string& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
}

}  // namespace

OutputFile::OutputFile(std::string path) : mPath(std::move(path)) {
    if (mPath.empty())
        throw IoError("cannot write an output with an empty path");

    // Follow symbolic links to the file they finally name (which may not exist yet).
    mTarget = mPath;
    struct stat st {};
    for (int hops = 0;; ++hops) {
        if (::lstat(mTarget.c_str(), &st) != 0) {
            if (errno == ENOTDIR) {
                // A file where the path needs a folder: name it.
                std::string up = folderOf(mTarget);
                struct stat parent {};
                while (up != "." && up != "/" && ::stat(up.c_str(), &parent) != 0)
                    up = folderOf(up);
                fail(mPath, up + " is a file, not a folder");
            }
            if (errno != ENOENT)
                failErrno(mPath, "", errno);
            mExists = false;
            break;
        }
        if (!S_ISLNK(st.st_mode)) {
            mExists = true;
            break;
        }
        if (hops == 40)
            fail(mPath, "too many levels of symbolic links");
        std::string link(size_t(st.st_size > 0 ? st.st_size : 256) + 1, '\0');
        const ssize_t n = ::readlink(mTarget.c_str(), link.data(), link.size());
        if (n < 0)
            failErrno(mPath, "cannot read the link " + mTarget, errno);
        link.resize(size_t(n));
        mTarget = (link.front() == '/' || folderOf(mTarget) == ".")
                      ? link
                      : folderOf(mTarget) + "/" + link;
    }
    const std::string where = mTarget == mPath ? mPath : mPath + " (a link to " + mTarget + ")";
    mFolder = folderOf(mTarget);

    if (mExists) {
        if (S_ISDIR(st.st_mode))
            fail(where, "it is a folder, not a file");
        if (S_ISSOCK(st.st_mode))
            fail(where, "it is a socket");
        if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) || S_ISFIFO(st.st_mode)) {
            mDirect = true;
            if (::access(mTarget.c_str(), W_OK) != 0)
                failErrno(where, "", errno);
            return;
        }
        if (!S_ISREG(st.st_mode))
            fail(where, "it is not a regular file, a device or a FIFO");
        if (::access(mTarget.c_str(), W_OK) != 0)
            fail(where, errno == EACCES ? "the file is read-only (mode " + octal(st.st_mode) +
                                              "); it was left as it is"
                                        : std::string(std::strerror(errno)));
        mMode = uint32_t(st.st_mode & 07777);
        mUid = uint32_t(st.st_uid);
        mGid = uint32_t(st.st_gid);
    }
    struct stat folder {};
    if (::stat(mFolder.c_str(), &folder) != 0)
        fail(where, "the folder " + mFolder + " does not exist");
    if (!S_ISDIR(folder.st_mode))
        fail(where, mFolder + " is a file, not a folder");
    if (::access(mFolder.c_str(), W_OK | X_OK) != 0)
        fail(where, "the folder " + mFolder + " is not writable");
}

OutputFile::~OutputFile() {
    if (mFd >= 0)
        ::close(mFd);
    if (!mTemp.empty()) {
        ::unlink(mTemp.c_str());
        unregisterTemp(mTemp);
    }
}

void OutputFile::open() {
    if (mFd >= 0)
        return;
    if (mDirect) {
        mFd = ::open(mTarget.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
        if (mFd < 0)
            failErrno(mPath, "", errno);
        return;
    }
#ifdef O_TMPFILE
    mFd = ::open(mFolder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (mFd >= 0) {
        mUnnamed = true;
        return;
    }
#endif
    // No unnamed temporary files here: a short name of our own, removed on failure.
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = tempName(mFolder);
        registerTemp(name);
        mFd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (mFd >= 0) {
            mTemp = std::move(name);
            return;
        }
        const int err = errno;
        unregisterTemp(name);
        if (err != EEXIST)
            failErrno(mPath, "cannot create a temporary file in " + mFolder, err);
    }
    fail(mPath, "cannot find a free temporary file name in " + mFolder);
}

int OutputFile::fd() {
    open();
    return mFd;
}

void OutputFile::write(const void* data, size_t size) {
    open();
    const auto* bytes = static_cast<const unsigned char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(mFd, bytes, size);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            failErrno(mPath, "", errno);
        }
        bytes += n;
        size -= size_t(n);
        mWritten += uint64_t(n);
    }
    // Start writing back what is written, every few MiB, so that the disk works while the
    // rest is produced and commit()'s fsync has less left to wait for.
    constexpr uint64_t WRITE_BACK = uint64_t(8) << 20;
    if (!mDirect && mWritten - mFlushed >= WRITE_BACK) {
#ifdef SYNC_FILE_RANGE_WRITE
        ::sync_file_range(mFd, off64_t(mFlushed), off64_t(mWritten - mFlushed),
                          SYNC_FILE_RANGE_WRITE);  // a hint: fsync() in commit() is the promise
#endif
        mFlushed = mWritten;
    }
}

void OutputFile::commit() {
    if (mCommitted)
        return;
    open();
    if (mDirect) {
        const int fd = mFd;
        mFd = -1;
        if (::close(fd) != 0)
            failErrno(mPath, "", errno);
        mCommitted = true;
        return;
    }
    if (mExists) {
        // The replaced file's owner where permitted (root, or a group of ours), and its mode;
        // set-id bits only when the owner could be kept.
        bool owner = ::fchown(mFd, uid_t(mUid), gid_t(mGid)) == 0;
        if (!owner)
            owner = ::fchown(mFd, uid_t(-1), gid_t(mGid)) == 0 && ::geteuid() == uid_t(mUid);
        ::fchmod(mFd, mode_t(owner ? mMode : (mMode & 0777)));
    }
    if (::fsync(mFd) != 0)
        failErrno(mPath, "", errno);
    removeStaleTemporaries(mFolder);

    if (mUnnamed) {
        // Give the unnamed file a name: the target itself when it does not exist, else a
        // temporary name renamed over it.
        const std::string proc = "/proc/self/fd/" + std::to_string(mFd);
        const auto link = [&](const std::string& name) {
            if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0)
                return 0;
            if (errno != ENOENT)
                return errno;
            // Without /proc: the descriptor itself (needs CAP_DAC_READ_SEARCH).
            return ::linkat(mFd, "", AT_FDCWD, name.c_str(), AT_EMPTY_PATH) == 0 ? 0 : errno;
        };
        int err = EEXIST;
        if (!mExists)
            err = link(mTarget);
        if (err == EEXIST) {
            for (int attempt = 0; attempt < 100 && err == EEXIST; ++attempt) {
                std::string name = tempName(mFolder);
                registerTemp(name);
                err = link(name);
                if (err == 0)
                    mTemp = std::move(name);
                else
                    unregisterTemp(name);
            }
            if (err == 0 && ::rename(mTemp.c_str(), mTarget.c_str()) != 0)
                err = errno;
        }
        if (err != 0)
            failErrno(mPath, "cannot put the new file in place", err);
    } else if (::rename(mTemp.c_str(), mTarget.c_str()) != 0) {
        failErrno(mPath, "cannot put the new file in place", errno);
    }
    if (!mTemp.empty()) {
        unregisterTemp(mTemp);
        mTemp.clear();
    }
    const int fd = mFd;
    mFd = -1;
    ::close(fd);
    syncFolder(mFolder);
    mCommitted = true;
}

void writeOutputFile(const std::string& path, const std::function<void(OutputFile&)>& write) {
    OutputFile out(path);
    write(out);
    out.commit();
}

void checkOutputFile(const std::string& path) {
    OutputFile check(path);
}

void removeOutputTemporaries() noexcept {
    std::lock_guard lock(registryMutex());
    for (const std::string& name : registry())
        ::unlink(name.c_str());
}

}  // namespace vdb::util
