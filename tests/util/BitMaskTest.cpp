// SPDX-License-Identifier: Apache-2.0
// Oracle: a std::vector<bool> of the same size, updated by the same random operations, with
// next-set-bit tables built by a backward scan.

#include <vdb/util/BitMask.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace vdb::util {
namespace {

using Oracle = std::vector<bool>;

// For every start in [0, size], the first position >= start whose bit equals `value`, or size.
std::vector<Index> nextTable(const Oracle& bits, bool value) {
    std::vector<Index> next(bits.size() + 1);
    next[bits.size()] = Index(bits.size());
    for (size_t n = bits.size(); n-- > 0;)
        next[n] = bits[n] == value ? Index(n) : next[n + 1];
    return next;
}

// A mask and its oracle with each bit on with probability `density`.
template <typename MaskT>
void randomFill(MaskT& mask, Oracle& oracle, double density, std::mt19937& rng) {
    std::bernoulli_distribution on(density);
    mask.setOff();
    oracle.assign(MaskT::SIZE, false);
    for (Index n = 0; n < MaskT::SIZE; ++n) {
        if (on(rng)) {
            mask.setOn(n);
            oracle[n] = true;
        }
    }
}

template <typename MaskT>
void expectMatches(const MaskT& mask, const Oracle& oracle) {
    Index count = 0;
    for (Index n = 0; n < MaskT::SIZE; ++n) {
        ASSERT_EQ(mask.isOn(n), bool(oracle[n])) << "bit " << n;
        ASSERT_EQ(mask.isOff(n), !oracle[n]) << "bit " << n;
        // Bit n is bit n % 64 of word n / 64.
        ASSERT_EQ((mask.getWord(n >> 6) >> (n & 63)) & 1u, uint64_t(oracle[n])) << "bit " << n;
        count += oracle[n];
    }
    EXPECT_EQ(mask.countOn(), count);
    EXPECT_EQ(mask.countOff(), MaskT::SIZE - count);
    EXPECT_EQ(mask.isOn(), count == MaskT::SIZE);
    EXPECT_EQ(mask.isOff(), count == 0);
}

template <typename MaskT>
class BitMaskTyped : public ::testing::Test {};
using MaskSizes = ::testing::Types<BitMask<64>, BitMask<512>, BitMask<4096>, BitMask<32768>>;
TYPED_TEST_SUITE(BitMaskTyped, MaskSizes);

TYPED_TEST(BitMaskTyped, DefaultIsAllOffAndTrueConstructorIsAllOn) {
    using MaskT = TypeParam;
    const MaskT off, on(true);
    expectMatches(off, Oracle(MaskT::SIZE, false));
    expectMatches(on, Oracle(MaskT::SIZE, true));
    EXPECT_EQ(MaskT::WORD_COUNT * 64, MaskT::SIZE);
    EXPECT_EQ(MaskT::memUsage(), MaskT::SIZE / 8);
    EXPECT_EQ(off.findFirstOn(), MaskT::SIZE);
    EXPECT_EQ(on.findFirstOff(), MaskT::SIZE);
    EXPECT_EQ(~off, on);
}

TYPED_TEST(BitMaskTyped, RandomSetClearToggleMatchesVectorBoolOracle) {
    using MaskT = TypeParam;
    std::mt19937 rng(20130601);
    std::uniform_int_distribution<Index> pos(0, MaskT::SIZE - 1);
    std::uniform_int_distribution<int> op(0, 4);
    MaskT mask;
    Oracle oracle(MaskT::SIZE, false);
    const int steps = 4 * int(MaskT::SIZE);
    for (int s = 0; s < steps; ++s) {
        const Index n = pos(rng);
        switch (op(rng)) {
            case 0:
                mask.setOn(n);
                oracle[n] = true;
                break;
            case 1:
                mask.setOff(n);
                oracle[n] = false;
                break;
            case 2:
                mask.set(n, true);
                oracle[n] = true;
                break;
            case 3:
                mask.set(n, false);
                oracle[n] = false;
                break;
            default:
                mask.toggle(n);
                oracle[n] = !oracle[n];
                break;
        }
    }
    expectMatches(mask, oracle);

    mask.toggle();
    oracle.flip();
    expectMatches(mask, oracle);
    mask.setOn();
    expectMatches(mask, Oracle(MaskT::SIZE, true));
    mask.set(false);
    expectMatches(mask, Oracle(MaskT::SIZE, false));
}

TYPED_TEST(BitMaskTyped, FindNextOnAndOffFromEveryStartMatchOracle) {
    using MaskT = TypeParam;
    std::mt19937 rng(42);
    MaskT mask;
    Oracle oracle;
    for (double density : {0.0, 0.001, 0.05, 0.5, 0.97, 1.0}) {
        randomFill(mask, oracle, density, rng);
        const auto nextOn = nextTable(oracle, true), nextOff = nextTable(oracle, false);
        for (Index start = 0; start <= MaskT::SIZE; ++start) {
            ASSERT_EQ(mask.findNextOn(start), nextOn[start]) << "start " << start;
            ASSERT_EQ(mask.findNextOff(start), nextOff[start]) << "start " << start;
        }
        EXPECT_EQ(mask.findFirstOn(), nextOn[0]);
        EXPECT_EQ(mask.findFirstOff(), nextOff[0]);
        // Starts past the end find nothing.
        EXPECT_EQ(mask.findNextOn(MaskT::SIZE + 64), MaskT::SIZE);
        EXPECT_EQ(mask.findNextOff(MaskT::SIZE + 1), MaskT::SIZE);
    }
}

TYPED_TEST(BitMaskTyped, IteratorsVisitExactlyTheOracleBitsInOrder) {
    using MaskT = TypeParam;
    std::mt19937 rng(5);
    MaskT mask;
    Oracle oracle;
    for (double density : {0.0, 0.01, 0.3, 0.5, 0.97, 1.0}) {
        randomFill(mask, oracle, density, rng);
        std::vector<Index> on, off;
        for (Index n = 0; n < MaskT::SIZE; ++n)
            (oracle[n] ? on : off).push_back(n);

        std::vector<Index> seen;
        for (auto it = mask.beginOn(); it; ++it)
            seen.push_back(it.pos());
        EXPECT_EQ(seen, on);
        seen.clear();
        for (auto it = mask.beginOff(); it.test(); ++it)
            seen.push_back(*it);
        EXPECT_EQ(seen, off);
        seen.clear();
        for (Index n : mask.onBits())
            seen.push_back(n);
        EXPECT_EQ(seen, on);
        seen.clear();
        for (Index n : mask.offBits())
            seen.push_back(n);
        EXPECT_EQ(seen, off);

        Index expected = 0;
        for (auto it = mask.beginDense(); it; ++it)
            ASSERT_EQ(it.pos(), expected++);
        EXPECT_EQ(expected, MaskT::SIZE);
    }
}

/// The positions a range of bit positions visits, in order.
template <typename RangeT>
std::vector<Index> positions(const RangeT& range) {
    std::vector<Index> out;
    for (Index n : range)
        out.push_back(n);
    return out;
}

TYPED_TEST(BitMaskTyped, IteratorsHandleTheEdgesOfEveryWord) {
    using MaskT = TypeParam;
    // Only the first and last bit of each word, only the last, only the first: the iterators
    // cross every word boundary and stop at the last bit of the mask.
    for (const uint64_t pattern :
         {uint64_t(1) | (uint64_t(1) << 63), uint64_t(1) << 63, uint64_t(1)}) {
        MaskT mask;
        std::vector<Index> on, off;
        for (Index w = 0; w < MaskT::WORD_COUNT; ++w)
            mask.getWord(w) = pattern;
        for (Index n = 0; n < MaskT::SIZE; ++n)
            (mask.isOn(n) ? on : off).push_back(n);
        EXPECT_EQ(positions(mask.onBits()), on);
        EXPECT_EQ(positions(mask.offBits()), off);
        std::vector<Index> seen;
        // An iterator made at any position goes on from there.
        for (Index start : {Index(0), Index(63), Index(64), MaskT::SIZE - 1}) {
            if (start >= MaskT::SIZE)
                continue;
            seen.clear();
            for (typename MaskT::OnIterator it(&mask, start); it; ++it)
                seen.push_back(it.pos());
            std::vector<Index> expected{start};
            for (Index n : on)
                if (n > start)
                    expected.push_back(n);
            EXPECT_EQ(seen, expected) << "start " << start;
        }
    }
}

TYPED_TEST(BitMaskTyped, IteratorsReadEachWordOnceWhenTheyReachIt) {
    using MaskT = TypeParam;
    std::mt19937 rng(11);
    MaskT mask;
    Oracle oracle;
    randomFill(mask, oracle, 0.5, rng);
    // Clearing each bit as it is visited visits every bit that was on.
    std::vector<Index> on, seen;
    for (Index n = 0; n < MaskT::SIZE; ++n)
        if (oracle[n])
            on.push_back(n);
    for (auto it = mask.beginOn(); it; ++it) {
        seen.push_back(it.pos());
        mask.setOff(it.pos());
    }
    EXPECT_EQ(seen, on);
    EXPECT_TRUE(mask.isOff());
    // Bits set ahead in later words are seen; in the current word they are not.
    mask.setOn(0);
    seen.clear();
    for (auto it = mask.beginOn(); it; ++it) {
        seen.push_back(it.pos());
        if (it.pos() == 0) {
            mask.setOn(5);
            if (MaskT::WORD_COUNT > 1)
                mask.setOn(64 + 7);
        }
    }
    std::vector<Index> expected{0};
    if (MaskT::WORD_COUNT > 1)
        expected.push_back(64 + 7);
    EXPECT_EQ(seen, expected);
}

TYPED_TEST(BitMaskTyped, WordwiseOperatorsMatchOracle) {
    using MaskT = TypeParam;
    std::mt19937 rng(99);
    MaskT a, b;
    Oracle oa, ob;
    randomFill(a, oa, 0.4, rng);
    randomFill(b, ob, 0.6, rng);

    Oracle andO(MaskT::SIZE), orO(MaskT::SIZE), xorO(MaskT::SIZE), diffO(MaskT::SIZE),
        notO(MaskT::SIZE);
    for (Index n = 0; n < MaskT::SIZE; ++n) {
        andO[n] = oa[n] && ob[n];
        orO[n] = oa[n] || ob[n];
        xorO[n] = oa[n] != ob[n];
        diffO[n] = oa[n] && !ob[n];
        notO[n] = !oa[n];
    }
    expectMatches(a & b, andO);
    expectMatches(a | b, orO);
    expectMatches(a ^ b, xorO);
    expectMatches(a - b, diffO);
    expectMatches(~a, notO);

    MaskT c = a;
    c &= b;
    EXPECT_EQ(c, a & b);
    c = a;
    c |= b;
    EXPECT_EQ(c, a | b);
    c = a;
    c ^= b;
    EXPECT_EQ(c, a ^ b);
    c = a;
    c -= b;
    EXPECT_EQ(c, a - b);
    EXPECT_NE(a, b);

    // Writing a word through words() sets exactly that word's 64 bits.
    MaskT w;
    w.words()[MaskT::WORD_COUNT - 1] = ~uint64_t(0);
    Oracle wo(MaskT::SIZE, false);
    for (Index n = MaskT::SIZE - 64; n < MaskT::SIZE; ++n)
        wo[n] = true;
    expectMatches(w, wo);
    EXPECT_EQ(w.words(), &w.getWord(0));
}

template <Index N>
void expectSetFromBytesMatchesSettingBits(uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<uint8_t> flags(N);
    for (int pattern = 0; pattern < 4; ++pattern) {
        for (Index n = 0; n < N; ++n)
            flags[n] = pattern == 0 ? 0 : pattern == 1 ? 1 : uint8_t(rng() % (pattern + 1) == 0);
        BitMask<N> expected, mask(true);
        for (Index n = 0; n < N; ++n)
            expected.set(n, flags[n] != 0);
        mask.setFromBytes(flags.data());
        EXPECT_TRUE(mask == expected) << N << " " << pattern;
        EXPECT_EQ(mask.countOn(), Index(std::count(flags.begin(), flags.end(), uint8_t(1))));
    }
}

TEST(BitMask, SetFromBytesSetsEachBitFromItsByte) {
    expectSetFromBytesMatchesSettingBits<64>(1);
    expectSetFromBytesMatchesSettingBits<512>(2);
    expectSetFromBytesMatchesSettingBits<4096>(3);
}

TEST(BitMask, SupportsConstantEvaluation) {
    constexpr auto mask = [] {
        BitMask<128> m;
        m.setOn(3);
        m.setOn(64);
        m.setOn(127);
        m.setOff(3);
        return m;
    }();
    static_assert(mask.countOn() == 2);
    static_assert(mask.findFirstOn() == 64);
    static_assert(mask.findNextOn(65) == 127);
    static_assert(mask.findNextOff(64) == 65);
    EXPECT_TRUE(mask.isOn(127));
}

}  // namespace
}  // namespace vdb::util
