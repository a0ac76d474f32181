// SPDX-License-Identifier: Apache-2.0
// Oracles, written from the definition of binary16 and not from Half.h's bit manipulation:
//  - decoding: a half with exponent field e and mantissa m is m * 2^-24 when e == 0 and
//    (1024 + m) * 2^(e - 25) otherwise, computed with ldexp;
//  - encoding by neighbours: a sorted table of every finite non-negative half (plus 65536 for
//    the infinity pattern), a binary search for the two halves around |f|, the nearer one, and
//    on a tie the one with the even mantissa;
//  - encoding by scaling: |f| scaled by a power of two so that the half's spacing becomes 1,
//    rounded with nearbyint (ties to even in the default mode), in double arithmetic.
// The neighbour oracle checks the values where rounding is delicate; the faster scaling oracle,
// itself checked against the neighbour oracle there, covers a strided sweep of all floats.

#include <vdb/math/Half.h>

#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace vdb::math {
namespace {

constexpr uint16_t HALF_INF = 0x7c00;

bool isHalfNan(uint16_t h) {
    return (h & 0x7c00) == 0x7c00 && (h & 0x03ff) != 0;
}

// Exact value of a half bit pattern, from the binary16 definition.
double referenceDecode(uint16_t h) {
    const int e = (h >> 10) & 0x1f;
    const int m = h & 0x3ff;
    const double sign = (h & 0x8000) ? -1.0 : 1.0;
    if (e == 31) {
        return m == 0 ? sign * std::numeric_limits<double>::infinity()
                      : std::numeric_limits<double>::quiet_NaN();
    }
    if (e == 0) {
        return sign * std::ldexp(double(m), -24);
    }
    return sign * std::ldexp(double(1024 + m), e - 25);
}

// Value of every non-negative pattern from 0x0000 to 0x7c00, where 0x7c00 stands for the next
// power of two after 65504: a magnitude at or past the midpoint 65520 rounds to it, i.e. to inf.
const std::vector<double>& halfMagnitudes() {
    static const std::vector<double> table = [] {
        std::vector<double> values(HALF_INF + 1);
        for (uint32_t h = 0; h < HALF_INF; ++h) {
            values[h] = referenceDecode(uint16_t(h));
        }
        values[HALF_INF] = 65536.0;
        return values;
    }();
    return table;
}

// Nearest half by search between neighbours; `f` must not be NaN.
uint16_t referenceEncodeByNeighbours(float f) {
    const uint16_t sign = std::signbit(f) ? 0x8000 : 0;
    const double d = std::fabs(double(f));
    const std::vector<double>& table = halfMagnitudes();
    if (d >= table.back()) {
        return sign | HALF_INF;
    }
    // hi is the first half above d, lo the one at or below it.
    const auto hiIt = std::upper_bound(table.begin(), table.end(), d);
    const auto hi = uint16_t(hiIt - table.begin());
    const auto lo = uint16_t(hi - 1);
    const double below = d - table[lo];
    const double above = table[hi] - d;
    uint16_t h;
    if (below < above) {
        h = lo;
    } else if (above < below) {
        h = hi;
    } else {
        h = (lo & 1) == 0 ? lo : hi;
    }
    return sign | h;
}

// Nearest half by scaling the spacing of halves to 1; `f` must not be NaN.
uint16_t referenceEncodeByScaling(float f) {
    const uint16_t sign = std::signbit(f) ? 0x8000 : 0;
    const double d = std::fabs(double(f));
    if (d >= 65520.0) {
        return sign | HALF_INF;
    }
    if (d < std::ldexp(1.0, -14)) {
        // Subnormal range: spacing 2^-24; 1024 steps is the smallest normal, 0x0400.
        return sign | uint16_t(std::nearbyint(std::ldexp(d, 24)));
    }
    int exponent = 0;
    std::frexp(d, &exponent);  // d = fraction * 2^exponent, fraction in [0.5, 1)
    int e = exponent - 1;      // 2^e <= d < 2^(e+1)
    // The significand in units of the spacing 2^(e-10): an integer in [1024, 2048].
    double n = std::nearbyint(std::ldexp(d, 10 - e));
    if (n == 2048.0) {
        n = 1024.0;
        ++e;
    }
    return sign | uint16_t(((e + 15) << 10) | (int(n) - 1024));
}

TEST(Half, EveryHalfPatternDecodesToItsExactValue) {
    for (uint32_t bits = 0; bits <= 0xffff; ++bits) {
        const auto h = uint16_t(bits);
        const float f = halfBitsToFloat(h);
        if (isHalfNan(h)) {
            ASSERT_TRUE(std::isnan(f)) << std::hex << bits;
            ASSERT_EQ(std::signbit(f), (bits & 0x8000) != 0) << std::hex << bits;
        } else {
            ASSERT_EQ(double(f), referenceDecode(h)) << std::hex << bits;
            ASSERT_EQ(std::signbit(f), (bits & 0x8000) != 0) << std::hex << bits;
        }
    }
}

TEST(Half, EveryHalfPatternRoundTripsThroughFloat) {
    for (uint32_t bits = 0; bits <= 0xffff; ++bits) {
        const auto h = uint16_t(bits);
        const uint16_t back = floatToHalfBits(halfBitsToFloat(h));
        if (isHalfNan(h)) {
            ASSERT_TRUE(isHalfNan(back)) << std::hex << bits;
            ASSERT_EQ(back & 0x8000, h & 0x8000) << std::hex << bits;
            ASSERT_NE(back & 0x0200, 0) << "NaN comes back quiet: " << std::hex << bits;
        } else {
            ASSERT_EQ(back, h) << std::hex << bits;
        }
    }
}

TEST(Half, ScalingOracleAgreesWithNeighbourOracle) {
    // Checks the fast oracle used by the strided sweep on a spread of magnitudes.
    for (uint32_t bits = 0; bits < 0x7f800000u; bits += 4099) {
        const float f = std::bit_cast<float>(bits);
        ASSERT_EQ(referenceEncodeByScaling(f), referenceEncodeByNeighbours(f)) << f;
    }
}

// Every float within 4 ulps of each half value and of each midpoint between adjacent halves,
// where rounding direction and ties are decided.
TEST(Half, FloatsNearHalvesAndMidpointsRoundToNearestEven) {
    const std::vector<double>& table = halfMagnitudes();
    std::vector<float> probes;
    auto addAround = [&](float centre) {
        float below = centre, above = centre;
        probes.push_back(centre);
        for (int i = 0; i < 4; ++i) {
            below = std::nextafter(below, -std::numeric_limits<float>::infinity());
            above = std::nextafter(above, std::numeric_limits<float>::infinity());
            probes.push_back(below);
            probes.push_back(above);
        }
    };
    for (size_t h = 0; h < table.size(); ++h) {
        addAround(float(table[h]));  // every half is exact in float
        if (h + 1 < table.size()) {
            // Midpoints of halves need at most 12 significant bits: exact in float too.
            addAround(float((table[h] + table[h + 1]) / 2));
        }
    }
    for (const float p : probes) {
        for (const float f : {p, -p}) {
            const uint16_t expected = referenceEncodeByNeighbours(f);
            ASSERT_EQ(floatToHalfBits(f), expected) << "f = " << f;
            ASSERT_EQ(referenceEncodeByScaling(f), expected) << "f = " << f;
        }
    }
}

TEST(Half, StridedSweepOfAllFloatsMatchesOracle) {
    constexpr uint64_t STRIDE = 97;
    constexpr uint64_t COUNT = (uint64_t(1) << 32) / STRIDE + 1;
    std::atomic<uint64_t> failures{0};
    std::atomic<uint32_t> firstBad{0};
    tbb::parallel_for(tbb::blocked_range<uint64_t>(0, COUNT, 1 << 16),
                      [&](const tbb::blocked_range<uint64_t>& range) {
                          for (uint64_t i = range.begin(); i != range.end(); ++i) {
                              const auto bits = uint32_t(i * STRIDE);
                              const float f = std::bit_cast<float>(bits);
                              const uint16_t h = floatToHalfBits(f);
                              const bool ok = std::isnan(f)
                                                  ? isHalfNan(h) && (h >> 15) == (bits >> 31)
                                                  : h == referenceEncodeByScaling(f);
                              if (!ok && failures.fetch_add(1) == 0) {
                                  firstBad = bits;
                              }
                          }
                      });
    EXPECT_EQ(failures.load(), 0u)
        << "first mismatch at float bits 0x" << std::hex << firstBad.load();
}

TEST(Half, NamedValuesMatchNumpyFloat16) {
    // Expected patterns as numpy.float16 (and Python's struct format 'e') give them.
    EXPECT_EQ(floatToHalfBits(65504.0f), 0x7bff);
    EXPECT_EQ(floatToHalfBits(65519.99f), 0x7bff);
    EXPECT_EQ(floatToHalfBits(65520.0f), 0x7c00);
    EXPECT_EQ(floatToHalfBits(-65520.0f), 0xfc00);
    EXPECT_EQ(floatToHalfBits(1e9f), 0x7c00);
    EXPECT_EQ(floatToHalfBits(6e-8f), 0x0001);
    EXPECT_EQ(floatToHalfBits(3e-8f), 0x0001);    // just over 2^-25, half of the smallest half
    EXPECT_EQ(floatToHalfBits(2.9e-8f), 0x0000);  // just under it: rounds to zero
    EXPECT_EQ(floatToHalfBits(std::ldexp(1.0f, -25)), 0x0000);  // the tie goes to even zero
    EXPECT_EQ(floatToHalfBits(2049.0f), 0x6800);  // tie between 2048 and 2050: even is 2048
    EXPECT_EQ(floatToHalfBits(2051.0f), 0x6802);  // tie between 2050 and 2052: even is 2052
    EXPECT_EQ(floatToHalfBits(0.1f), 0x2e66);
    EXPECT_EQ(floatToHalfBits(0.0f), 0x0000);
    EXPECT_EQ(floatToHalfBits(-0.0f), 0x8000);
    EXPECT_EQ(floatToHalfBits(std::numeric_limits<float>::infinity()), 0x7c00);
    EXPECT_EQ(floatToHalfBits(-std::numeric_limits<float>::infinity()), 0xfc00);
    EXPECT_EQ(floatToHalfBits(std::numeric_limits<float>::denorm_min()), 0x0000);

    for (const uint32_t nanBits :
         {0x7fc00000u, 0xffc00000u, 0x7f800001u, 0xff800001u, 0x7fbfffffu, 0x7fffe000u}) {
        const uint16_t h = floatToHalfBits(std::bit_cast<float>(nanBits));
        EXPECT_TRUE(isHalfNan(h)) << std::hex << nanBits;
        EXPECT_EQ(h >> 15, nanBits >> 31) << std::hex << nanBits;
        EXPECT_TRUE(std::isnan(halfBitsToFloat(h)));
    }

    EXPECT_EQ(halfBitsToFloat(0x7bff), 65504.0f);
    EXPECT_EQ(halfBitsToFloat(0x0001), std::ldexp(1.0f, -24));
    EXPECT_EQ(halfBitsToFloat(0x03ff), std::ldexp(1023.0f, -24));
    EXPECT_TRUE(std::signbit(halfBitsToFloat(0x8000)));
}

TEST(Half, RoundToHalfMatchesTheStoredBackgroundOfOpenVdb) {
    // A half grid's background 0.1 is stored as the float 00 c0 cc 3d.
    EXPECT_EQ(std::bit_cast<uint32_t>(roundToHalf(0.1f)), 0x3dccc000u);
    EXPECT_EQ(roundToHalf(0.1), double(roundToHalf(0.1f)));
    EXPECT_EQ(doubleToHalfBits(0.1), floatToHalfBits(0.1f));
}

TEST(Half, DoublesRoundThroughFloatFirst) {
    // 1 + 2^-11 + 2^-30 is just above the tie between halves 1 and 1 + 2^-10, so it rounds up
    // when rounded straight to half; through float the 2^-30 is lost and the tie goes to 1.
    const double d = 1.0 + std::ldexp(1.0, -11) + std::ldexp(1.0, -30);
    EXPECT_EQ(doubleToHalfBits(d), 0x3c00);
    EXPECT_EQ(roundToHalf(d), 1.0);
}

TEST(Half, ConversionsAreUsableInConstantExpressions) {
    static_assert(floatToHalfBits(1.0f) == 0x3c00);
    static_assert(floatToHalfBits(-2.0f) == 0xc000);
    static_assert(floatToHalfBits(65520.0f) == 0x7c00);
    static_assert(halfBitsToFloat(0x3555) == 0.333251953125f);
    static_assert(roundToHalf(2049.0f) == 2048.0f);
    SUCCEED();
}

TEST(Half, BulkHelpersMatchScalarConversions) {
    std::vector<float> values;
    for (uint32_t bits = 0; bits < 0xffffffffu - 65537u * 13u; bits += 65537u * 13u) {
        values.push_back(std::bit_cast<float>(bits));
    }
    std::vector<uint16_t> halves(values.size());
    floatsToHalf(values.data(), halves.data(), values.size());
    std::vector<float> back(values.size());
    halfToFloats(halves.data(), back.data(), halves.size());
    for (size_t i = 0; i < values.size(); ++i) {
        ASSERT_EQ(halves[i], floatToHalfBits(values[i])) << i;
        ASSERT_EQ(std::bit_cast<uint32_t>(back[i]),
                  std::bit_cast<uint32_t>(halfBitsToFloat(halves[i])))
            << i;
    }
}

}  // namespace
}  // namespace vdb::math
