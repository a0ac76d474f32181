// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of `vdb render` beyond a single picture: the grid it chooses in real files
// (the samples of VDB_SAMPLES_DIR; skipped when that folder is absent) and in files made here,
// NAME[INDEX] for repeated names, alpha (Beer-Lambert opacity of a box of known optical depth,
// transparent misses), the format by extension (EXR read back), non-cubic voxels, frame
// sequences, and option values that must be refused before any work.

#include <vdb/io/File.h>
#include <vdb/tools/LevelSetSphere.h>

#include "CliFixture.h"
#include <gtest/gtest.h>

#ifdef VDB_TEST_OPENEXR
#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfRgbaFile.h>
#endif

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;
using test::Picture;
using test::readPng;
using test::Result;

class RenderCli : public test::ToolTest {
protected:
    /// A fog grid `name` holding `density` on the index box `box`, voxel size `voxel`.
    static FloatGrid::Ptr fogBox(const std::string& name, const CoordBBox& box, float density,
                                 double voxel = 0.1) {
        auto fog = FloatGrid::create(0.0f);
        fog->setTransform(math::Transform::createLinearTransform(voxel));
        fog->setGridClass(GRID_FOG_VOLUME);
        fog->setName(name);
        fog->tree().fill(box, density, true);
        return fog;
    }
    void write(const std::string& file, const GridPtrVec& grids) {
        io::File(path(file)).write(grids);
    }
    /// The value of a string key of the one-line-per-key JSON report, or "".
    static std::string jsonString(const std::string& json, const std::string& key) {
        const size_t k = json.find("\"" + key + "\": \"");
        if (k == std::string::npos)
            return "";
        const size_t start = k + key.size() + 5;
        return json.substr(start, json.find('"', start) - start);
    }
    static double jsonNumber(const std::string& json, const std::string& key) {
        const size_t k = json.find("\"" + key + "\": ");
        return k == std::string::npos ? std::nan("") : std::atof(json.c_str() + k + key.size() + 4);
    }
};

/// The sample folder, or "" when it is absent.
std::string samples() {
    std::error_code ec;
    return fs::is_directory(VDB_SAMPLES_DIR, ec) ? std::string(VDB_SAMPLES_DIR) : std::string();
}

TEST_F(RenderCli, ChoosesTheGridUsersMeanInRealFiles) {
    const std::string dir = samples();
    if (dir.empty())
        GTEST_SKIP() << VDB_SAMPLES_DIR << " is absent";
    struct Case {
        const char* file;
        const char* grid;  // expected choice
        const char* mode;
    };
    // Blender 5 lists empty colour grids first; Mantaflow caches hold dense level sets and an
    // all-zero domain around the smoke; Bifrost names its density differently; grids.vdb
    // repeats one name three times; two files have non-cubic voxels (scale and affine maps).
    const Case cases[] = {
        {"smoke.vdb", "density", "fog"},
        {"wdas_cloud_sixteenth.vdb", "density", "fog"},
        {"fluid_data_0001.vdb", "density", "fog"},
        {"fluid_data_0190.vdb", "density", "fog"},
        {"c42_fluid_data_0001.vdb", "density", "fog"},
        {"densityAndHeat.vdb", "density", "fog"},
        {"grids.vdb", "density[0]", "fog"},
        {"torus01.vdb", "voxel_fog_density", "fog"},
        {"pyro.vdb", "density", "fog"},
        {"test.vdb", "density", "fog"},
        {"sphere.vdb", "ls_sphere", "levelset"},
        {"grid.vdb", "[0]", "levelset"},
    };
    for (const Case& c : cases) {
        const std::string file = dir + "/" + c.file;
        if (!fs::exists(file))
            continue;
        const Result r = ok({"render", file, "-o", path("out.png"), "--width", "48", "--height",
                             "36", "--json", "--threads", "2"});
        EXPECT_EQ(jsonString(r.out, "grid"), c.grid) << c.file;
        EXPECT_EQ(jsonString(r.out, "mode"), c.mode) << c.file;
        const Picture pic = readPng(path("out.png"));
        EXPECT_GT(pic.coveredCount(), 48u * 36u / 20) << c.file << ": too little in the picture";
        if (std::string(c.mode) == "fog") {
            EXPECT_GT(jsonNumber(r.out, "extinction"), 0.0) << c.file;
            EXPECT_NE(r.out.find("\"valueRange\""), std::string::npos) << c.file;
        }
    }
    // Files with nothing to render say so.
    if (fs::exists(dir + "/smoke_000001.vdb"))
        fails({"render", dir + "/smoke_000001.vdb", "-o", path("x.png")}, 2, "empty");
    if (fs::exists(dir + "/sphereCd.vdb"))
        fails({"render", dir + "/sphereCd.vdb", "-o", path("x.png")}, 2, "no float or double");
    // The three grids of grids.vdb one by one; an index too many lists them.
    if (fs::exists(dir + "/grids.vdb")) {
        for (const char* name : {"density[1]", "density[2]"}) {
            const Result r = ok({"render", dir + "/grids.vdb", "-o", path("g.png"), "--grid", name,
                                 "--width", "32", "--height", "24", "--json"});
            EXPECT_EQ(jsonString(r.out, "grid"), name);
        }
        fails({"render", dir + "/grids.vdb", "-o", path("x.png"), "--grid", "density[3]"}, 2,
              "\"density[0]\", \"density[1]\", \"density[2]\"");
    }
}

TEST_F(RenderCli, PrefersDensityToEmptyAndOtherGridsAndFramesPositiveValues) {
    // An empty grid first (as Blender writes color_b), a level set, a dense domain of zeros
    // around a small positive blob named density.
    auto empty = FloatGrid::create(0.0f);
    empty->setName("color_b");
    empty->setGridClass(GRID_FOG_VOLUME);
    auto ls = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.1f, 3.0f);
    ls->setName("phi");
    auto density = fogBox("density", CoordBBox(Coord(-40), Coord(39)), 0.0f);
    density->tree().fill(CoordBBox(Coord(20, 20, 20), Coord(27, 27, 27)), 1.0f, true);
    write("cache.vdb", GridPtrVec{empty, ls, density});
    const Result r = ok({"render", path("cache.vdb"), "-o", path("c.png"), "--width", "64",
                         "--height", "64", "--json", "--extinction", "20"});
    EXPECT_EQ(jsonString(r.out, "grid"), "density");
    // Framed on the blob, not on the domain: the blob fills much of the picture (framing the
    // domain 10 times wider, it would cover about 1% of it).
    const Picture pic = readPng(path("c.png"));
    EXPECT_GT(pic.coveredCount(), 64u * 64u / 8);
    // --mode levelset takes the level set; --mode fog never does.
    const Result l = ok({"render", path("cache.vdb"), "-o", path("l.png"), "--width", "32",
                         "--height", "32", "--json", "--mode", "levelset"});
    EXPECT_EQ(jsonString(l.out, "grid"), "phi");
    fails({"render", path("cache.vdb"), "-o", path("x.png"), "--mode", "levelset", "--grid",
           "density"},
          2, "not a level set");
    fails({"render", path("cache.vdb"), "-o", path("x.png"), "--grid", "color_b"}, 2, "empty");
}

TEST_F(RenderCli, DuplicateNamesAreChosenByIndex) {
    write("dup.vdb", GridPtrVec{fogBox("density", CoordBBox(Coord(0), Coord(7)), 1.0f),
                                fogBox("density", CoordBBox(Coord(0), Coord(15)), 0.5f),
                                fogBox("other", CoordBBox(Coord(0), Coord(3)), 1.0f)});
    for (const char* name : {"density[0]", "density[1]", "other"}) {
        const Result r = ok({"render", path("dup.vdb"), "-o", path("d.png"), "--grid", name,
                             "--width", "16", "--height", "16", "--json"});
        EXPECT_EQ(jsonString(r.out, "grid"), name);
    }
    // Without an index, the first of them.
    const Result r = ok({"render", path("dup.vdb"), "-o", path("d.png"), "--grid", "density",
                         "--width", "16", "--height", "16", "--json"});
    EXPECT_EQ(jsonString(r.out, "grid"), "density[0]");
    fails({"render", path("dup.vdb"), "-o", path("x.png"), "--grid", "density[2]"}, 2,
          "(it has \"density[0]\", \"density[1]\", \"other\")");
    fails({"render", path("dup.vdb"), "-o", path("x.png"), "--grid", "nothing"}, 2, "\"nothing\"");
}

TEST_F(RenderCli, AlphaIsTheOpacityAndMissesAreTransparent) {
    // A box 20 voxels deep of density 0.5 seen along z with extinction 2 per world unit, voxel
    // 0.1: optical depth 2 * 0.5 * 2 = 2, opacity 1 - e^-2 = 0.8647 at the centre.
    write("box.vdb", GridPtrVec{fogBox("density", CoordBBox(Coord(-10), Coord(9)), 0.5f)});
    ok({"render", path("box.vdb"), "-o", path("box.png"), "--camera", "ortho", "--width", "40",
        "--height", "40", "--position", "0,0,5", "--look-at", "0,0,0", "--extinction", "2",
        "--step", "0.1"});
    const Picture fog = readPng(path("box.png"));
    EXPECT_NEAR(double(fog.alpha(20, 20)), 255.0 * (1.0 - std::exp(-2.0)), 1.5);
    EXPECT_EQ(fog.alpha(0, 0), 0);
    EXPECT_FALSE(fog.lit(0, 0));
    // With --background the picture is opaque.
    ok({"render", path("box.vdb"), "-o", path("bg.png"), "--width", "20", "--height", "20",
        "--background", "0.2,0.3,0.4"});
    const Picture bg = readPng(path("bg.png"));
    EXPECT_EQ(bg.coveredCount(), 400u);
    // A level set: hits opaque, misses transparent.
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.05f, 3.0f);
    write("s.vdb", GridPtrVec{sphere});
    ok({"render", path("s.vdb"), "-o", path("s.png"), "--width", "40", "--height", "40"});
    const Picture ls = readPng(path("s.png"));
    EXPECT_EQ(ls.alpha(20, 20), 255);
    EXPECT_EQ(ls.alpha(0, 0), 0);
    size_t partial = 0;
    for (size_t i = 3; i < ls.rgba.size(); i += 4)
        partial += ls.rgba[i] != 0 && ls.rgba[i] != 255;
    EXPECT_EQ(partial, 0u);
}

TEST_F(RenderCli, TheExtensionChoosesTheFormatAndOthersAreRefusedFirst) {
    write("box.vdb", GridPtrVec{fogBox("density", CoordBBox(Coord(-10), Coord(9)), 0.5f)});
    for (const char* bad : {"x.jpg", "x", "x.tiff", "x.png.bak"})
        fails({"render", path("box.vdb"), "-o", path(bad)}, 2, "extension");
    fails({"render", path("box.vdb"), "-o", path("x.png"), "--normals", path("n.bmp")}, 2, ".bmp");
    // Case does not matter.
    ok({"render", path("box.vdb"), "-o", path("upper.PNG"), "--width", "8", "--height", "8"});
    EXPECT_EQ(readPng(path("upper.PNG")).width, 8u);
#ifdef VDB_TEST_OPENEXR
    // EXR: float, premultiplied; its alpha is the PNG's to 8-bit rounding.
    const std::vector<std::string> common{"--camera",  "ortho", "--width",      "24",
                                          "--height",  "24",    "--position",   "0,0,5",
                                          "--look-at", "0,0,0", "--extinction", "2"};
    std::vector<std::string> exr{"render", path("box.vdb"), "-o", path("box.exr")};
    std::vector<std::string> png{"render", path("box.vdb"), "-o", path("box.png")};
    exr.insert(exr.end(), common.begin(), common.end());
    png.insert(png.end(), common.begin(), common.end());
    ok(exr);
    ok(png);
    Imf::RgbaInputFile in(path("box.exr").c_str());
    const auto window = in.dataWindow();
    const int w = window.max.x - window.min.x + 1, h = window.max.y - window.min.y + 1;
    ASSERT_EQ(w, 24);
    ASSERT_EQ(h, 24);
    Imf::Array2D<Imf::Rgba> pixels(h, w);
    in.setFrameBuffer(&pixels[0][0], 1, size_t(w));
    in.readPixels(window.min.y, window.max.y);
    const Picture pic = readPng(path("box.png"));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Imf::Rgba& p = pixels[y][x];
            ASSERT_NEAR(float(p.a) * 255.0f, float(pic.alpha(size_t(x), size_t(y))), 0.75f);
            ASSERT_LE(float(p.r), float(p.a) + 1e-3f);  // premultiplied
        }
    EXPECT_NEAR(float(pixels[12][12].a), 1.0 - std::exp(-2.0), 2e-3);
#else
    fails({"render", path("box.vdb"), "-o", path("x.exr")}, 2, "OpenEXR");
#endif
}

TEST_F(RenderCli, NonCubicVoxelsRender) {
    // Voxels of 0.1 x 0.2 x 0.05: the box of 20^3 voxels is 2 x 4 x 1 world units. Seen along
    // z with an optical depth of 50, pixels are more than half opaque out to the ends of the
    // trilinear ramps, half a voxel past each face: 21 voxels across, 21 down.
    auto fog = fogBox("density", CoordBBox(Coord(-10), Coord(9)), 1.0f);
    fog->transform().preScale(Vec3d(1.0, 2.0, 0.5));
    write("scaled.vdb", GridPtrVec{fog});
    ok({"render", path("scaled.vdb"), "-o", path("scaled.png"), "--camera", "ortho", "--width",
        "64", "--height", "64", "--position", "0,0,5", "--look-at", "0,0,0", "--extinction", "50"});
    const Picture pic = readPng(path("scaled.png"));
    size_t across = 0, down = 0;
    for (size_t i = 0; i < 64; ++i) {
        across += pic.alpha(i, 32) > 128;
        down += pic.alpha(32, i) > 128;
    }
    // An orthographic frame is the bounding sphere's diameter high: sqrt(2^2 + 4^2 + 1^2).
    const double pixel = std::sqrt(21.0) / 64.0;
    EXPECT_NEAR(double(across), 2.1 / pixel, 2.0);
    EXPECT_NEAR(double(down), 4.2 / pixel, 2.0);
    // A level set under the same scale renders too (an ellipsoid).
    auto ls = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.05f, 3.0f);
    ls->transform().preScale(Vec3d(1.0, 2.0, 0.5));
    write("ellipsoid.vdb", GridPtrVec{ls});
    ok({"render", path("ellipsoid.vdb"), "-o", path("e.png"), "--width", "32", "--height", "32"});
    EXPECT_GT(readPng(path("e.png")).coveredCount(), 32u * 32u / 10);
}

TEST_F(RenderCli, SequencesRenderEveryFrameWithOneCamera) {
    // A box moving along +x over frames 1, 2 and 10; and a file that does not match.
    fs::create_directories(mDir / "cache");
    for (const int f : {1, 2, 10}) {
        char name[64];
        std::snprintf(name, sizeof name, "cache/smoke_%04d.vdb", f);
        write(name, GridPtrVec{fogBox(
                        "density", CoordBBox(Coord(4 * f, 0, 0), Coord(4 * f + 7, 7, 7)), 1.0f)});
    }
    write("cache/smoke_final.vdb",
          GridPtrVec{fogBox("density", CoordBBox(Coord(0), Coord(1)), 1.0f)});
    const Result r = ok({"render", path("cache/smoke_#.vdb"), "-o", path("out_#.png"), "--width",
                         "64", "--height", "32", "--json", "--extinction", "30"});
    std::vector<double> centres;
    for (const char* out : {"out_0001.png", "out_0002.png", "out_0010.png"}) {
        ASSERT_TRUE(fs::exists(path(out))) << out;
        const Picture pic = readPng(path(out));
        double sum = 0, n = 0;
        for (size_t y = 0; y < pic.height; ++y)
            for (size_t x = 0; x < pic.width; ++x)
                if (pic.alpha(x, y) > 128) {
                    sum += double(x);
                    n += 1;
                }
        ASSERT_GT(n, 0) << out;
        centres.push_back(sum / n);
    }
    // One camera: the box is seen moving (frames 1, 2, 10), not re-framed each time.
    EXPECT_LT(centres[0], centres[1]);
    EXPECT_LT(centres[1] + 10, centres[2]);
    EXPECT_NE(r.out.find("\"frames\""), std::string::npos);
    EXPECT_NE(r.out.find("out_0010.png"), std::string::npos);
    // A run of # pads to its length; at least that many digits must match.
    ok({"render", path("cache/smoke_####.vdb"), "-o", path("pad_###.png"), "--width", "8",
        "--height", "8", "--quiet"});
    for (const char* out : {"pad_001.png", "pad_002.png", "pad_010.png"})
        EXPECT_TRUE(fs::exists(path(out))) << out;
    fails({"render", path("cache/smoke_#####.vdb"), "-o", path("x_#.png")}, 2, "no file matches");
    fails({"render", path("cache/smoke_#.vdb"), "-o", path("x.png")}, 2, "needs #");
    fails({"render", path("cache/smoke_#_#.vdb"), "-o", path("x#.png")}, 2, "one run of #");
    // An error names the frame.
    write("cache/smoke_0003.vdb", GridPtrVec{fogBox("other", CoordBBox(Coord(0), Coord(1)), 1.0f)});
    fails({"render", path("cache/smoke_#.vdb"), "-o", path("y_#.png"), "--grid", "density"}, 2,
          "frame 3");
}

TEST_F(RenderCli, RefusesOptionValuesThatAreNotFiniteOrInRange) {
    write("box.vdb", GridPtrVec{fogBox("density", CoordBBox(Coord(-4), Coord(3)), 1.0f)});
    const std::string in = path("box.vdb"), out = path("x.png");
    struct Bad {
        std::vector<std::string> options;
        const char* needle;
    };
    const Bad bad[] = {
        {{"--view", "nan,0,0"}, "must be a finite number, not nan"},
        {{"--view", "0,0,0"}, "non-zero"},
        {{"--up", "0,inf,0"}, "inf"},
        {{"--up", "0,1,0", "--view", "0,-2,0"}, "parallel"},
        {{"--light", "1,nan,0"}, "nan"},
        {{"--light", "0,0,0"}, "non-zero"},
        {{"--position", "nan,0,5", "--look-at", "0,0,0"}, "nan"},
        {{"--position", "0,0,5", "--look-at", "0,-inf,0"}, "-inf"},
        {{"--look-at", "0,0,0"}, "--position"},
        {{"--extinction", "nan"}, "must be a finite number within [0, 1e+30], not nan"},
        {{"--extinction", "-1"}, "[0, 1e+30]"},
        {{"--step", "inf"}, "[0.01, 100]"},
        {{"--shadow-step", "0"}, "[0.01, 100]"},
        {{"--fov", "nan"}, "[1, 179]"},
        {{"--ambient", "nan"}, "--ambient"},
        {{"--background", "1,nan,0"}, "--background"},
        {{"--width", "0"}, "--width"},
    };
    for (const Bad& b : bad) {
        std::vector<std::string> args{"render", in, "-o", out};
        args.insert(args.end(), b.options.begin(), b.options.end());
        fails(args, 2, b.needle);
    }
    // A picture too big for the memory the process may use is refused before anything is read.
    if (fs::exists("/usr/bin/prlimit")) {
        const Result r =
            test::runTool("/usr/bin/prlimit",
                          {"--as=2000000000", VDB_TOOL_PATH, "render", path("missing.vdb"), "-o",
                           out, "--width", "16384", "--height", "16384"},
                          mDir.string());
        EXPECT_EQ(r.status, 2) << r.err;
        EXPECT_NE(r.err.find("5,368,709,120 bytes"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("2,000,000,000 bytes"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("ulimit -v"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

}  // namespace
}  // namespace vdb
