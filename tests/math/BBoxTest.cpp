// SPDX-License-Identifier: Apache-2.0
// Oracles: per-axis interval arithmetic written out here, and membership of sample points on
// a half-integer lattice for boxes with integer corners.

#include <vdb/math/BBox.h>

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <sstream>

namespace vdb::math {
namespace {

TEST(BBox, DefaultIsEmptyAndExpandingItYieldsThePoint) {
    BBoxd box;
    EXPECT_TRUE(box.empty());
    EXPECT_FALSE(bool(box));
    EXPECT_EQ(box.volume(), 0.0);
    EXPECT_EQ(box.extents(), Vec3d(0.0));
    box.expand(Vec3d(1, -2, 3));
    EXPECT_FALSE(box.empty());
    EXPECT_EQ(box.min(), Vec3d(1, -2, 3));
    EXPECT_EQ(box.max(), Vec3d(1, -2, 3));
    EXPECT_EQ(box.volume(), 0.0);
    EXPECT_TRUE(box.isInside(Vec3d(1, -2, 3)));
    box.expand(BBoxd());  // expanding by an empty box changes nothing
    EXPECT_EQ(box, BBoxd(Vec3d(1, -2, 3), Vec3d(1, -2, 3)));
    box.reset();
    EXPECT_TRUE(box.empty());
}

TEST(BBox, ExtentsCenterAndVolumeFollowFromCorners) {
    const BBoxd box(Vec3d(-1, 0, 2), Vec3d(3, 0.5, 5));
    EXPECT_EQ(box.extents(), Vec3d(4, 0.5, 3));
    EXPECT_EQ(box.center(), Vec3d(1, 0.25, 3.5));
    EXPECT_EQ(box.volume(), 6.0);
    EXPECT_TRUE(BBoxd(Vec3d(0, 0, 0), Vec3d(1, -1, 1)).empty());
    EXPECT_TRUE(BBoxd(Vec3d(std::numeric_limits<double>::quiet_NaN()), Vec3d(1)).empty());
}

TEST(BBox, ConvertsFromCoordBBoxByVoxelCenters) {
    const BBoxd box(CoordBBox(Coord(-2, 0, 5), Coord(3, 0, 7)));
    EXPECT_EQ(box.min(), Vec3d(-2, 0, 5));
    EXPECT_EQ(box.max(), Vec3d(3, 0, 7));
    EXPECT_TRUE(BBoxd(CoordBBox()).empty());
}

// Random boxes with integer corners in [-3, 3]; points on the half-integer lattice decide
// membership and overlap exactly.
TEST(BBox, InsideOverlapAndIntersectMatchLatticeOracle) {
    std::mt19937 rng(20130601);
    std::uniform_int_distribution<int> corner(-3, 3);
    const auto randomBox = [&] {
        Vec3d a(corner(rng), corner(rng), corner(rng)), b(corner(rng), corner(rng), corner(rng));
        return BBoxd(Vec3d::minComponent(a, b), Vec3d::maxComponent(a, b));
    };
    const auto inBox = [](const BBoxd& b, const Vec3d& p) {
        for (size_t i = 0; i < 3; ++i) {
            if (p[i] < b.min()[i] || p[i] > b.max()[i])
                return false;
        }
        return true;
    };
    for (int n = 0; n < 300; ++n) {
        const BBoxd a = randomBox(), b = randomBox();
        BBoxd both = a;
        both.intersect(b);
        BBoxd hull = a;
        hull.expand(b);
        bool anyCommon = false;
        for (int i = -8; i <= 8; ++i) {
            for (int j = -8; j <= 8; ++j) {
                for (int k = -8; k <= 8; ++k) {
                    const Vec3d p(0.5 * i, 0.5 * j, 0.5 * k);
                    ASSERT_EQ(a.isInside(p), inBox(a, p)) << a << " " << p;
                    ASSERT_EQ(both.isInside(p), inBox(a, p) && inBox(b, p)) << a << " & " << b;
                    ASSERT_TRUE(!(inBox(a, p) || inBox(b, p)) || hull.isInside(p));
                    anyCommon |= inBox(a, p) && inBox(b, p);
                }
            }
        }
        ASSERT_EQ(a.hasOverlap(b), anyCommon) << a << " " << b;
        ASSERT_EQ(b.hasOverlap(a), anyCommon);
        ASSERT_EQ(both.empty(), !anyCommon);
        ASSERT_EQ(a.isInside(b), inBox(a, b.min()) && inBox(a, b.max()));
        ASSERT_EQ(hull.min(), Vec3d::minComponent(a.min(), b.min()));
        ASSERT_EQ(hull.max(), Vec3d::maxComponent(a.max(), b.max()));
    }
}

TEST(BBox, TouchingBoxesOverlapBecauseBoxesAreClosed) {
    const BBoxd a(Vec3d(0), Vec3d(1)), b(Vec3d(1, 0, 0), Vec3d(2, 1, 1));
    EXPECT_TRUE(a.hasOverlap(b));
    BBoxd face = a;
    face.intersect(b);
    EXPECT_FALSE(face.empty());
    EXPECT_EQ(face.extents(), Vec3d(0, 1, 1));
    EXPECT_FALSE(a.hasOverlap(BBoxd(Vec3d(1.0 + 1e-12, 0, 0), Vec3d(2))));
}

TEST(BBox, PaddingAndTranslationMoveCorners) {
    BBoxd box(Vec3d(0), Vec3d(1, 2, 3));
    box.expand(0.5);
    EXPECT_EQ(box, BBoxd(Vec3d(-0.5), Vec3d(1.5, 2.5, 3.5)));
    box.translate(Vec3d(1, -1, 0));
    EXPECT_EQ(box, BBoxd(Vec3d(0.5, -1.5, -0.5), Vec3d(2.5, 1.5, 3.5)));
    std::ostringstream os;
    os << BBoxs(Vec3s(0), Vec3s(1));
    EXPECT_EQ(os.str(), "[0, 0, 0] -> [1, 1, 1]");
}

}  // namespace
}  // namespace vdb::math
