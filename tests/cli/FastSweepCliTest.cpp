// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of `vdb redistance` and `vdb extend`: the outputs read back with the library
// equal, bit for bit, what the library's fast sweeping gives on the same grid, and are checked
// against the analytic sphere; bad requests fail with status 2, one error line, no new file and
// the output that was there untouched.

#include <vdb/io/File.h>
#include <vdb/tools/FastSweeping.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/LevelSetUtil.h>

#include "CliFixture.h"
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace vdb {
namespace {

class FastSweepCli : public test::ToolTest {
protected:
    /// A sphere of radius 12 voxels (voxel size 0.5) whose band values are scaled by 1.5.
    FloatGrid::Ptr distortedSphere() {
        auto grid = tools::createLevelSetSphere<FloatGrid>(6.0, Vec3d(0.0), 0.5, 4.0);
        for (auto it = grid->tree().beginValueAll(); it; ++it)
            it.setValue(1.5f * *it);
        grid->setName("surface");
        return grid;
    }
    void write(const std::string& name, const GridBase::Ptr& grid) {
        io::File(path(name)).write(GridPtrVec{grid});
    }
    template <typename GridT>
    typename GridT::Ptr read(const std::string& name) {
        io::File in(path(name));
        in.open();
        auto grid = gridPtrCast<GridT>(in.readGrid(in.getGridNames().front()));
        EXPECT_TRUE(grid != nullptr);
        return grid;
    }
};

TEST_F(FastSweepCli, RedistanceMatchesTheLibrary) {
    const auto grid = distortedSphere();
    write("in.vdb", grid);
    ok({"redistance", path("in.vdb"), "-o", path("out.vdb"), "--iterations", "2"});
    const auto out = read<FloatGrid>("out.vdb");
    EXPECT_EQ(out->getName(), "surface");
    EXPECT_EQ(out->getGridClass(), GRID_LEVEL_SET);
    EXPECT_TRUE(test::sameContents(out->tree(), tools::sdfToSdf(*grid, 0.0f, 2)->tree()));
    for (auto it = out->tree().cbeginValueOn(); it; ++it) {
        const double exact = Vec3d(it.getCoord()).length() - 12.0;
        EXPECT_NEAR(double(*it) / 0.5, exact, 0.45 + 0.045 * std::abs(exact)) << it.getCoord();
    }
}

TEST_F(FastSweepCli, RedistanceTakesTheGridClassForFogOrLevelSet) {
    auto fog = tools::createLevelSetSphere<FloatGrid>(6.0, Vec3d(0.0), 0.5, 4.0);
    tools::sdfToFogVolume(*fog);
    fog->setName("density");
    write("fog.vdb", fog);
    ok({"redistance", path("fog.vdb"), "-o", path("sdf.vdb"), "--isovalue", "0.25"});
    const auto sdf = read<FloatGrid>("sdf.vdb");
    EXPECT_TRUE(test::sameContents(sdf->tree(), tools::fogToSdf(*fog, 0.25f)->tree()));
    EXPECT_LT(sdf->tree().getValue(Coord(0)), 0.0f) << "the fog's dense side is inside";
    // The same values as a level set (no --fog) have the other sign convention.
    fog->setGridClass(GRID_UNKNOWN);
    write("unknown.vdb", fog);
    ok({"redistance", path("unknown.vdb"), "-o", path("a.vdb"), "--isovalue", "0.25"});
    EXPECT_GT(read<FloatGrid>("a.vdb")->tree().getValue(Coord(0)), 0.0f);
    ok({"redistance", path("unknown.vdb"), "-o", path("b.vdb"), "--isovalue", "0.25", "--fog"});
    EXPECT_TRUE(test::sameContents(read<FloatGrid>("b.vdb")->tree(), sdf->tree()));
}

TEST_F(FastSweepCli, ExtendCarriesTheFieldAlongTheNormals) {
    const auto surface = tools::dilateSdf(*distortedSphere(), 4);
    write("in.vdb", surface);
    // A field that is the unit radial direction's z component everywhere near the surface.
    auto field = FloatGrid::create(0.0f);
    field->setTransform(math::Transform::createLinearTransform(0.25));
    field->setName("temperature");
    for (Int32 i = -30; i <= 30; ++i) {
        for (Int32 j = -30; j <= 30; ++j) {
            for (Int32 k = -30; k <= 30; ++k) {
                const double r = std::sqrt(double(i * i + j * j + k * k));
                if (std::abs(r - 24.0) < 3.0)
                    field->tree().setValue(Coord(i, j, k), float(k / r));
            }
        }
    }
    write("field.vdb", field);
    ok({"extend", path("in.vdb"), "--field", path("field.vdb"), "-o", path("out.vdb")});
    const auto out = read<FloatGrid>("out.vdb");
    EXPECT_EQ(out->getName(), "temperature");
    EXPECT_TRUE(out->transform() == surface->transform());
    EXPECT_EQ(out->activeVoxelCount(), surface->activeVoxelCount());
    for (auto it = out->tree().cbeginValueOn(); it; ++it) {
        const Vec3d d(it.getCoord());
        // Within 6 voxels of the surface (deeper, the normals meet at the centre).
        if (std::abs(d.length() - 12.0) <= 6.0) {
            EXPECT_NEAR(double(*it), d[2] / d.length(), 0.06) << it.getCoord();
        }
    }
}

TEST_F(FastSweepCli, BadRequestsFailWithoutTouchingFiles) {
    write("in.vdb", distortedSphere());
    write("old.vdb", distortedSphere());
    const auto before = test::fileBytes(path("old.vdb"));
    fails({"redistance", path("missing.vdb"), "-o", path("out.vdb")}, 1, "missing.vdb");
    fails({"redistance", path("in.vdb"), "-o", path("out.vdb"), "--iterations", "0"}, 2,
          "iterations");
    fails({"redistance", path("in.vdb"), "-o", path("out.vdb"), "--isovalue", "nan"}, 2,
          "isovalue");
    fails({"redistance", path("in.vdb"), "-o", path("old.vdb"), "--isovalue", "1000"}, 2,
          "does not cross");
    fails({"redistance", path("in.vdb"), "-o", path("out.vdb"), "--grid", "nothing"}, 2, "nothing");
    fails({"redistance", path("in.vdb")}, 2, "--output");
    fails({"extend", path("in.vdb"), "-o", path("out.vdb")}, 2, "--field");
    fails({"extend", path("in.vdb"), "--field", path("missing.vdb"), "-o", path("old.vdb")}, 1,
          "missing.vdb");
    auto ints = Int32Grid::create(0);
    ints->tree().setValue(Coord(0), 3);
    write("ints.vdb", ints);
    fails({"extend", path("in.vdb"), "--field", path("ints.vdb"), "-o", path("old.vdb")}, 2,
          "int32");
    auto empty = FloatGrid::create(0.0f);
    write("empty.vdb", empty);
    fails({"extend", path("in.vdb"), "--field", path("empty.vdb"), "-o", path("old.vdb")}, 2,
          "no active values");
    fails({"redistance", path("ints.vdb"), "-o", path("old.vdb")}, 2, "float or double");
    EXPECT_EQ(test::fileBytes(path("old.vdb")), before);
}

}  // namespace
}  // namespace vdb
