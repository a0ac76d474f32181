// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of how the `vdb` tool treats what is on disk and what it is asked to do:
// outputs onto devices, FIFOs, sockets, links, read-only files and long names; outputs that
// must not change when a command fails; work refused before it starts when its estimated
// memory or step count is over the limit; NaN, infinite and out-of-range numbers; messages that
// name the real problem. Oracles: the file system itself (stat, lstat, readlink, file bytes),
// the library reading the outputs back, and analytic distances.

#include <vdb/io/File.h>
#include <vdb/tools/LevelSetSphere.h>

#include "CliFixture.h"
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;
using test::Result;

class CliSafety : public test::ToolTest {
protected:
    void SetUp() override {
        ToolTest::SetUp();
        // Output files and folders get their permissions from the tool, not from this umask.
        ::umask(022);
    }
    void TearDown() override {
        std::error_code ec;  // a test may have made the folder read-only
        fs::permissions(mDir, fs::perms::owner_all, fs::perm_options::add, ec);
        ToolTest::TearDown();
    }

    /// A failed run: `status`, one error line containing every needle.
    Result failsWith(const std::vector<std::string>& args, int status,
                     const std::vector<std::string>& needles) {
        Result r = run(args);
        EXPECT_EQ(r.status, status) << "stderr: " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        for (const auto& needle : needles)
            EXPECT_NE(r.err.find(needle), std::string::npos)
                << "expected '" << needle << "' in: " << r.err;
        return r;
    }
    /// The names in the test folder other than the captured output files.
    std::vector<std::string> listing() const { return test::folderNames(mDir); }
    /// A small sphere file written by the library; returns its grid.
    FloatGrid::Ptr writeSphere(const std::string& name, float radius = 1.0f) {
        auto grid = tools::createLevelSetSphere<FloatGrid>(radius, Vec3f(0.0f), 0.1f, 3.0f);
        grid->setName("sphere");
        io::File(path(name)).write(GridPtrVec{grid});
        return grid;
    }
    static FloatGrid::Ptr readSphere(const std::string& file) {
        io::File in(file);
        in.open(false);
        return gridPtrCast<FloatGrid>(in.getGrids()->front());
    }
    static bool isRoot() { return ::geteuid() == 0; }
};

// ---- Outputs on special files ------------------------------------------------------------------

TEST_F(CliSafety, DevNullIsWrittenNotReplaced) {
    writeSphere("s.vdb");
    ok({"convert", path("s.vdb"), "-o", "/dev/null", "--quiet"});
    struct stat st {};
    ASSERT_EQ(::stat("/dev/null", &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null is no longer a device";
    // A device has no size to report (it once printed "-> 1.8e+19 B").
    const Result r = run({"convert", path("s.vdb"), "-o", "/dev/null"});
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ((r.out + r.err).find(" -> "), std::string::npos) << r.out << r.err;
}

TEST_F(CliSafety, DeviceNodeInAFolderIsWrittenInPlace) {
    if (!isRoot())
        GTEST_SKIP() << "creating a device node needs root; /dev/null is tested instead";
    writeSphere("s.vdb");
    // Null devices (major 1, minor 3) in the test folder, named as outputs.
    for (const char* name : {"null.vdb", "null.png"})
        ASSERT_EQ(::mknod(path(name).c_str(), S_IFCHR | 0666, makedev(1, 3)), 0) << name;
    ok({"convert", path("s.vdb"), "-o", path("null.vdb"), "--quiet"});
    ok({"render", path("s.vdb"), "-o", path("null.png"), "--width", "8", "--height", "8",
        "--quiet"});
    for (const char* name : {"null.vdb", "null.png"}) {
        struct stat st {};
        ASSERT_EQ(::stat(path(name).c_str(), &st), 0);
        EXPECT_TRUE(S_ISCHR(st.st_mode)) << name;
        EXPECT_EQ(st.st_rdev, makedev(1, 3)) << name;
    }
}

TEST_F(CliSafety, FifoIsWrittenInPlaceAndCarriesTheWholeFile) {
    writeSphere("s.vdb");
    ASSERT_EQ(::mkfifo(path("pipe.vdb").c_str(), 0644), 0);
    // Read the FIFO into a regular file while the tool writes it.
    std::vector<char> received;
    std::thread reader([&] {
        std::ifstream in(path("pipe.vdb"), std::ios::binary);
        received.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    });
    const Result r = run({"convert", path("s.vdb"), "-o", path("pipe.vdb"), "--quiet"});
    reader.join();
    EXPECT_EQ(r.status, 0) << r.err;
    struct stat st {};
    ASSERT_EQ(::lstat(path("pipe.vdb").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    {
        std::ofstream out(path("received.vdb"), std::ios::binary);
        out.write(received.data(), std::streamsize(received.size()));
    }
    EXPECT_EQ(test::treeContents(readSphere(path("received.vdb"))->tree()),
              test::treeContents(readSphere(path("s.vdb"))->tree()));
}

TEST_F(CliSafety, SocketIsRefused) {
    writeSphere("s.vdb");
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ASSERT_GE(fd, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    const std::string name = path("sock");
    if (name.size() >= sizeof(addr.sun_path)) {
        ::close(fd);
        GTEST_SKIP() << "the test folder's path is too long for a socket";
    }
    std::strcpy(addr.sun_path, name.c_str());
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    failsWith({"convert", path("s.vdb"), "-o", name}, 2, {"sock", "socket"});
    ::close(fd);
    struct stat st {};
    ASSERT_EQ(::lstat(name.c_str(), &st), 0);
    EXPECT_TRUE(S_ISSOCK(st.st_mode));
}

TEST_F(CliSafety, SymbolicLinksAreWrittenThrough) {
    writeSphere("s.vdb");
    writeSphere("target.vdb", 0.5f);
    fs::create_symlink("target.vdb", path("link.vdb"));
    ok({"convert", path("s.vdb"), "-o", path("link.vdb"), "--quiet"});
    EXPECT_TRUE(fs::is_symlink(path("link.vdb")));
    EXPECT_EQ(fs::read_symlink(path("link.vdb")), fs::path("target.vdb"));
    EXPECT_EQ(test::treeContents(readSphere(path("target.vdb"))->tree()),
              test::treeContents(readSphere(path("s.vdb"))->tree()));
    // A chain of links, the last one dangling: the file it names is created.
    fs::create_directories(path("sub"));
    fs::create_symlink("sub/new.vdb", path("chain2.vdb"));
    fs::create_symlink(path("chain2.vdb"), path("chain1.vdb"));
    ok({"convert", path("s.vdb"), "-o", path("chain1.vdb"), "--quiet"});
    EXPECT_TRUE(fs::is_symlink(path("chain1.vdb")));
    EXPECT_TRUE(fs::is_symlink(path("chain2.vdb")));
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(path("sub/new.vdb"))));
    // A loop of links is an error, not a hang.
    fs::create_symlink("loop2.vdb", path("loop1.vdb"));
    fs::create_symlink("loop1.vdb", path("loop2.vdb"));
    failsWith({"convert", path("s.vdb"), "-o", path("loop1.vdb")}, 2, {"loop1.vdb", "links"});
}

TEST_F(CliSafety, ReplacedFileKeepsItsModeAndANewFileGetsTheUmask) {
    writeSphere("s.vdb");
    writeSphere("out.vdb", 0.5f);
    fs::permissions(path("out.vdb"), fs::perms(0640));
    ok({"convert", path("s.vdb"), "-o", path("out.vdb"), "--quiet"});
    EXPECT_EQ(fs::status(path("out.vdb")).permissions() & fs::perms::mask, fs::perms(0640));
    fs::permissions(path("out.vdb"), fs::perms(0600));
    ok({"render", path("s.vdb"), "-o", path("out.png"), "--width", "8", "--height", "8", "-q"});
    ok({"sphere", "-o", path("out.vdb"), "--radius", "0.3", "--voxel-size", "0.1", "-q"});
    EXPECT_EQ(fs::status(path("out.vdb")).permissions() & fs::perms::mask, fs::perms(0600));
    // New files: 0666 less the umask (022 here).
    EXPECT_EQ(fs::status(path("out.png")).permissions() & fs::perms::mask, fs::perms(0644));
    ok({"convert", path("s.vdb"), "-o", path("fresh.vdb"), "--quiet"});
    EXPECT_EQ(fs::status(path("fresh.vdb")).permissions() & fs::perms::mask, fs::perms(0644));
}

TEST_F(CliSafety, LongestLegalFileNameWorks) {
    writeSphere("s.vdb");
    const std::string name = std::string(251, 'n') + ".vdb";  // 255 bytes, NAME_MAX
    ok({"convert", path("s.vdb"), "-o", path(name), "--quiet"});
    EXPECT_TRUE(fs::is_regular_file(path(name)));
    EXPECT_EQ(listing(), (std::vector<std::string>{name, "s.vdb"}));
}

TEST_F(CliSafety, ReadOnlyFilesAndFoldersAreLeftAlone) {
    if (isRoot())
        GTEST_SKIP() << "root writes through read-only permissions; run as another user";
    writeSphere("s.vdb");
    writeSphere("ro.vdb", 0.5f);
    fs::permissions(path("ro.vdb"), fs::perms(0444));
    const auto before = test::fileBytes(path("ro.vdb"));
    failsWith({"convert", path("s.vdb"), "-o", path("ro.vdb")}, 2, {"ro.vdb", "read-only"});
    EXPECT_EQ(test::fileBytes(path("ro.vdb")), before);
    fs::create_directories(path("locked"));
    fs::permissions(path("locked"), fs::perms(0555));
    failsWith({"convert", path("s.vdb"), "-o", path("locked/out.vdb")}, 2, {"not writable"});
    EXPECT_TRUE(fs::is_empty(path("locked")));
}

TEST_F(CliSafety, AFileWhereAFolderShouldBeIsNamedAsSuch) {
    writeSphere("s.vdb");
    failsWith({"convert", path("s.vdb"), "-o", path("s.vdb/out.vdb")}, 2,
              {"s.vdb is a file, not a folder"});
    failsWith({"convert", path("s.vdb"), "-o", path("missing/out.vdb")}, 2,
              {"folder", "missing", "does not exist"});
    failsWith({"convert", path("s.vdb"), "-o", mDir.string()}, 2, {"is a folder"});
}

// ---- Temporary files ----------------------------------------------------------------------------

TEST_F(CliSafety, StaleTemporaryFilesOfDeadProcessesAreRemoved) {
    writeSphere("s.vdb");
    // A process id that no longer runs: a child that has exited and been reaped.
    const pid_t child = ::fork();
    if (child == 0)
        ::_exit(0);
    ASSERT_GT(child, 0);
    ::waitpid(child, nullptr, 0);
    const std::string stale = ".vdb-" + std::to_string(child) + "-abc123";
    const std::string live = ".vdb-" + std::to_string(::getpid()) + "-abc123";
    std::ofstream(path(stale)) << "left by a killed process";
    std::ofstream(path(live)) << "being written by a running process";
    ok({"convert", path("s.vdb"), "-o", path("out.vdb"), "--quiet"});
    EXPECT_FALSE(fs::exists(path(stale)));
    EXPECT_TRUE(fs::exists(path(live)));
}

TEST_F(CliSafety, KillingAWriteLeavesTheOldFileOrTheNewOne) {
    // A file large enough that the write takes a while; killed at several moments.
    ok({"sphere", "-o", path("big.vdb"), "--enright", "1024", "--quiet"});
    writeSphere("old.vdb");
    const auto complete = readSphere(path("big.vdb"))->activeVoxelCount();
    for (const int ms : {5, 40, 120, 300}) {
        const auto old = test::fileBytes(path("old.vdb"));
        const pid_t pid = test::spawnTool(
            VDB_TOOL_PATH, {"convert", path("big.vdb"), "-o", path("old.vdb"), "--quiet"},
            mDir.string());
        std::this_thread::sleep_for(std::chrono::milliseconds(ms));
        ::kill(pid, SIGKILL);
        test::waitTool(pid, mDir.string());
        // Either the old bytes or a complete new file.
        if (test::fileBytes(path("old.vdb")) != old) {
            EXPECT_EQ(readSphere(path("old.vdb"))->activeVoxelCount(), complete) << ms;
        }
        writeSphere("old.vdb");
    }
    // Nothing else is left, once a later write has cleaned after the killed processes.
    ok({"convert", path("old.vdb"), "-o", path("old.vdb"), "--quiet"});
    EXPECT_EQ(listing(), (std::vector<std::string>{"big.vdb", "old.vdb"}));
}

// ---- Outputs change only when the command succeeds ---------------------------------------------

TEST_F(CliSafety, FailedCommandsLeaveTheExistingOutputUntouched) {
    writeSphere("s.vdb");
    // A fog volume: flood fill has no level set to work on.
    auto fog = FloatGrid::create(0.0f);
    fog->setName("density");
    fog->setGridClass(GRID_FOG_VOLUME);
    fog->tree().setValueOn(Coord(1, 2, 3), 0.5f);
    io::File(path("fog.vdb")).write(GridPtrVec{fog});
    auto fine = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.05f, 3.0f);
    io::File(path("fine.vdb")).write(GridPtrVec{fine});
    writeSphere("keep.vdb", 0.5f);
    const auto keep = test::fileBytes(path("keep.vdb"));
    const std::string out = path("keep.vdb");
    failsWith({"floodfill", path("fog.vdb"), "-o", out}, 2, {"no level set"});
    failsWith({"csg", "union", path("s.vdb"), path("fine.vdb"), "-o", out}, 2, {"transform"});
    failsWith({"advect", path("fog.vdb"), "-o", out}, 2, {"level set"});
    EXPECT_EQ(test::fileBytes(path("keep.vdb")), keep);
    // A picture that cannot be made leaves the old picture.
    fs::copy_file(path("keep.vdb"), path("keep.png"));
    failsWith({"render", path("fog.vdb"), "-o", path("keep.png"), "--grid", "nope"}, 2, {"nope"});
    EXPECT_EQ(test::fileBytes(path("keep.png")), keep);
}

// ---- Work refused before it starts
// ---------------------------------------------------------------

TEST_F(CliSafety, UnboundedWorkIsRefusedWithTheEstimateAndTheLimit) {
    writeSphere("s.vdb");
    const auto start = std::chrono::steady_clock::now();
    failsWith(
        {"advect", path("s.vdb"), "-o", path("a.vdb"), "--field", "constant", "--time", "1e6"}, 2,
        {"steps", "over the limit of 100,000", "--max-steps"});
    failsWith({"advect", path("s.vdb"), "-o", path("a.vdb"), "--field", "constant", "--velocity",
               "1e30,0,0"},
              2, {"steps"});
    failsWith({"morph", "dilate", "1000", path("s.vdb"), "-o", path("m.vdb")}, 2,
              {"dilating", "GB", "memory", "over the limit of 2.00 GB", "--max-memory"});
    failsWith({"sphere", "-o", path("e.vdb"), "--enright", "16384"}, 2, {"memory", "GB"});
    failsWith({"spheres", "-o", path("h.vdb"), "--count", "100000000"}, 2, {"memory"});
    failsWith({"enright", "--resolution", "4096", "--time", "300"}, 2, {"steps"});
    // Every refusal came before any real work.
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
    EXPECT_EQ(listing(), (std::vector<std::string>{"s.vdb"}));
}

TEST_F(CliSafety, LimitsCanBeLoweredAndRaised) {
    writeSphere("s.vdb");
    failsWith({"sphere", "-o", path("t.vdb"), "--radius", "1", "--voxel-size", "0.01",
               "--max-memory", "100k"},
              2, {"over the limit of 100.0 kB"});
    ok({"sphere", "-o", path("t.vdb"), "--radius", "1", "--voxel-size", "0.01", "--max-memory",
        "1G", "-q"});
    failsWith({"sphere", "-o", path("t.vdb"), "--max-memory", "lots"}, 2, {"--max-memory", "lots"});
    // Twenty steps of one voxel each at CFL 0.5 need about forty steps.
    failsWith({"advect", path("s.vdb"), "-o", path("a.vdb"), "--field", "constant", "--time", "2",
               "--max-steps", "5"},
              2, {"over the limit of 5"});
    ok({"advect", path("s.vdb"), "-o", path("a.vdb"), "--field", "constant", "--time", "0.2",
        "--max-steps", "50", "-q"});
    // The environment sets the default for every command.
    ::setenv("VDB_MAX_MEMORY", "10k", 1);
    const Result r = run({"sphere", "-o", path("u.vdb"), "--radius", "1", "--voxel-size", "0.01"});
    ::unsetenv("VDB_MAX_MEMORY");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("10.0 kB"), std::string::npos) << r.err;
}

// ---- Numbers ------------------------------------------------------------------------------------

TEST_F(CliSafety, NonFiniteAndOutOfRangeNumbersAreRefused) {
    writeSphere("s.vdb");
    const std::string out = path("out.vdb");
    failsWith({"sphere", "-o", out, "--center", "nan,0,0"}, 2, {"finite", "nan"});
    failsWith({"sphere", "-o", out, "--center", "inf,0,0"}, 2, {"finite"});
    failsWith({"sphere", "-o", out, "--radius", "nan"}, 2, {"nan"});
    failsWith({"sphere", "-o", out, "--center", "3e7,0,0"}, 2, {"index space", "2^31"});
    failsWith({"sphere", "-o", out, "--radius", "1e30"}, 2, {"index space"});
    failsWith({"sphere", "-o", out, "--voxel-size", "1e-300"}, 2, {"index space"});
    failsWith({"sphere", "-o", out, "--half-width", "nan"}, 2, {"nan"});
    failsWith({"advect", path("s.vdb"), "-o", out, "--time", "nan"}, 2, {"nan"});
    failsWith({"advect", path("s.vdb"), "-o", out, "--field", "constant", "--velocity", "nan,0,0"},
              2, {"nan"});
    failsWith({"advect", path("s.vdb"), "-o", out, "--cfl", "nan"}, 2, {"nan"});
    failsWith({"prune", path("s.vdb"), "-o", out, "--tolerance", "nan"}, 2, {"nan"});
    failsWith({"prune", path("s.vdb"), "-o", out, "--tolerance", "-1"}, 2, {"-1"});
    failsWith({"spheres", "-o", out, "--voxel-size", "inf"}, 2, {"inf"});
    failsWith({"enright", "--time", "inf"}, 2, {"inf"});
    EXPECT_EQ(listing(), (std::vector<std::string>{"s.vdb"}));
}

TEST_F(CliSafety, SpheresFarFromTheOriginAreRound) {
    // 2e7 world units at voxel size 0.01 is 2e9 voxels out, near the end of the index space,
    // where float has 128-voxel steps: the distances must still be those of a sphere.
    const double c = 2.0e7, radius = 0.5, dx = 0.01;
    ok({"sphere", "-o", path("far.vdb"), "--center", "2e7,-2e7,1e6", "--radius", "0.5",
        "--voxel-size", "0.01", "-q"});
    const auto grid = readSphere(path("far.vdb"));
    EXPECT_DOUBLE_EQ(grid->transform().voxelSize()[0], dx);
    const Vec3d centre(c, -c, 1.0e6);
    size_t n = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it, ++n) {
        const Vec3d xyz = grid->transform().indexToWorld(it.getCoord());
        const double d = (xyz - centre).length() - radius;
        ASSERT_NEAR(double(*it), d, 1e-4 * dx) << it.getCoord();
    }
    const double area = 4.0 * 3.14159265 * (radius / dx) * (radius / dx);
    EXPECT_GT(double(n), 5.0 * area);  // a band about six voxels thick
    EXPECT_LT(double(n), 7.0 * area);
}

TEST_F(CliSafety, VoxelSizeIsStoredWithoutFloatRounding) {
    ok({"sphere", "-o", path("s.vdb"), "--radius", "0.3", "--voxel-size", "0.0125", "-q"});
    EXPECT_EQ(readSphere(path("s.vdb"))->transform().voxelSize()[0], 0.0125);
}

TEST_F(CliSafety, GridsAtTheSameVoxelSizeCombineWhateverTheirRounding) {
    // One grid's voxel size went through float (0.012500000186...), the other's did not.
    auto a = tools::createLevelSetSphere<FloatGrid>(0.3f, Vec3f(0.0f), 0.0125f, 3.0f);
    auto b = tools::createLevelSetSphere<FloatGrid>(0.3, Vec3d(0.1, 0, 0), 0.0125, 3.0);
    ASSERT_NE(a->transform().voxelSize()[0], b->transform().voxelSize()[0]);
    io::File(path("a.vdb")).write(GridPtrVec{a});
    io::File(path("b.vdb")).write(GridPtrVec{b});
    ok({"csg", "union", path("a.vdb"), path("b.vdb"), "-o", path("u.vdb"), "-q"});
    // A voxel size that differs by more than a relative 1e-6 is another grid.
    auto c =
        tools::createLevelSetSphere<FloatGrid>(0.3, Vec3d(0.1, 0, 0), 0.0125 * (1 + 1e-5), 3.0);
    io::File(path("c.vdb")).write(GridPtrVec{c});
    failsWith({"csg", "union", path("a.vdb"), path("c.vdb"), "-o", path("v.vdb")}, 2,
              {"one index space", "0.0125"});
}

// ---- Files the tool reads
// ------------------------------------------------------------------------

TEST_F(CliSafety, NewerFileVersionsAreReadWithAWarning) {
    writeSphere("s.vdb");
    for (const uint32_t version : {226u, 999u}) {
        auto bytes = test::fileBytes(path("s.vdb"));
        std::memcpy(bytes.data() + 8, &version, 4);  // after the 8-byte magic
        std::ofstream(path("v.vdb"), std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        const Result r = ok({"info", path("v.vdb")});
        EXPECT_NE(r.err.find("version " + std::to_string(version)), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
    }
}

TEST_F(CliSafety, ConvertNamesTheCodecOfEachGridAndNeverDropsGridsSilently) {
    auto ls = writeSphere("s.vdb");
    auto labels = Int32Grid::create(0);
    labels->setName("labels");
    labels->tree().setValueOn(Coord(1, 2, 3), 7);
    auto other = FloatGrid::create(0.0f);
    other->setName("other");
    other->tree().setValueOn(Coord(4, 5, 6), 1.5f);
    io::File(path("mixed.vdb")).write(GridPtrVec{ls, labels, other});

    // ZIP is not applied to the level set; the integer grid gets it.
    const Result r =
        ok({"convert", path("mixed.vdb"), "-o", path("zip.vdb"), "--compression", "zip"});
    EXPECT_NE(r.out.find("sphere: active values (zip is not applied to level sets"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("labels: zip + active values"), std::string::npos) << r.out;
    const Result j =
        ok({"convert", path("mixed.vdb"), "-o", path("zip.vdb"), "--compression", "zip", "--json"});
    EXPECT_NE(j.out.find("\"compression\": \"active values\""), std::string::npos) << j.out;

    // A grid of a type this library cannot read (its type name changed in the file) stops
    // convert, which names it; --drop-unsupported writes the others and says what it dropped.
    auto bytes = test::fileBytes(path("mixed.vdb"));
    const std::string from = "Tree_int32_5_4_3", to = "Tree_ptdata_5_43";
    auto at = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
    ASSERT_NE(at, bytes.end());
    std::copy(to.begin(), to.end(), at);
    std::ofstream(path("points.vdb"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    failsWith({"convert", path("points.vdb"), "-o", path("out.vdb")}, 2,
              {"labels", "Tree_ptdata_5_43", "--drop-unsupported"});
    EXPECT_FALSE(fs::exists(path("out.vdb")));
    const Result d =
        ok({"convert", path("points.vdb"), "-o", path("out.vdb"), "--drop-unsupported"});
    EXPECT_NE(d.out.find("dropped \"labels\""), std::string::npos) << d.out;
    io::File out(path("out.vdb"));
    out.open();
    // The grids, in the order getGrids() gives them (sorted by name), without "labels".
    EXPECT_EQ(out.getGridNames(), (std::vector<std::string>{"other", "sphere"}));
    // Choosing only readable grids needs no flag.
    ok({"convert", path("points.vdb"), "-o", path("one.vdb"), "--grid", "other", "-q"});
}

}  // namespace
}  // namespace vdb
