// SPDX-License-Identifier: Apache-2.0
/// @file
/// BitMask: the fixed-size bit set of every VDB node (value masks, child masks), stored as
/// 64-bit words, with hardware popcount and count-trailing-zeros searches.

#pragma once

#include <vdb/Types.h>
#include <vdb/util/Assert.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <iterator>

namespace vdb::util {

/// A set of `NumBits` flags, numbered 0 to NumBits-1, packed into 64-bit words.
///
/// Bit n lives in word n / 64 at position n % 64. find* searches scan whole words with
/// std::countr_zero, so visiting the on bits of a sparse mask costs one instruction per bit
/// plus one per empty word.
///
/// Invariant: NumBits is a positive multiple of 64, so every word is fully used.
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
template <Index NumBits>
class BitMask {
    static_assert(NumBits > 0 && NumBits % 64 == 0,
                  "a BitMask holds a whole number of 64-bit words");

public:
    using Word = uint64_t;
    static constexpr Index SIZE = NumBits;
    static constexpr Index WORD_COUNT = NumBits / 64;

    /// Creates a mask with every bit off (or every bit on, with `on` true).
    constexpr BitMask() = default;
    constexpr explicit BitMask(bool on) { set(on); }

    // ---- Single bits
    constexpr bool isOn(Index n) const {
        VDB_ASSERT(n < SIZE);
        return (mWords[n >> 6] >> (n & 63)) & 1u;
    }
    constexpr bool isOff(Index n) const { return !isOn(n); }
    constexpr void setOn(Index n) {
        VDB_ASSERT(n < SIZE);
        mWords[n >> 6] |= Word(1) << (n & 63);
    }
    constexpr void setOff(Index n) {
        VDB_ASSERT(n < SIZE);
        mWords[n >> 6] &= ~(Word(1) << (n & 63));
    }
    constexpr void set(Index n, bool on) { on ? setOn(n) : setOff(n); }
    constexpr void toggle(Index n) {
        VDB_ASSERT(n < SIZE);
        mWords[n >> 6] ^= Word(1) << (n & 63);
    }

    /// Sets bit n to `flags[n]` for every n: the bridge from loops that compute one byte, 0 or
    /// 1, per bit (which compilers vectorise, where setting bits one by one does not).
    /// @pre every flags[n] is 0 or 1
    void setFromBytes(const uint8_t* flags) {
        for (Index w = 0; w < WORD_COUNT; ++w) {
            Word bits = 0;
            for (Index g = 0; g < 8; ++g) {
                const uint8_t* b = flags + w * 64 + g * 8;
                uint64_t x;
                if constexpr (std::endian::native == std::endian::little) {
                    std::memcpy(&x, b, 8);
                    // Byte k lands on bit 56 + k; the other partial products stay below bit 56
                    // (their exponents are distinct, so nothing carries).
                    x = (x * 0x0102040810204080ull) >> 56;
                } else {
                    x = 0;
                    for (Index k = 0; k < 8; ++k)
                        x |= uint64_t(b[k] & 1u) << k;
                }
                bits |= Word(x) << (g * 8);
            }
            mWords[w] = bits;
        }
    }

    // ---- Whole mask
    constexpr void set(bool on) { mWords.fill(on ? ~Word(0) : Word(0)); }
    constexpr void setOn() { set(true); }
    constexpr void setOff() { set(false); }
    constexpr void toggle() {
        for (Word& w : mWords)
            w = ~w;
    }
    /// True when every bit is on.
    constexpr bool isOn() const {
        for (Word w : mWords)
            if (w != ~Word(0))
                return false;
        return true;
    }
    /// True when every bit is off.
    constexpr bool isOff() const {
        for (Word w : mWords)
            if (w != 0)
                return false;
        return true;
    }
    /// Number of on bits, WORD_COUNT popcounts.
    constexpr Index countOn() const {
        Index n = 0;
        for (Word w : mWords)
            n += Index(std::popcount(w));
        return n;
    }
    constexpr Index countOff() const { return SIZE - countOn(); }

    // ---- Searches; each returns SIZE when there is no such bit
    constexpr Index findFirstOn() const { return findNextOn(0); }
    constexpr Index findFirstOff() const { return findNextOff(0); }
    /// Returns the first on bit at or after `start`.
    constexpr Index findNextOn(Index start) const {
        Index w = start >> 6;
        if (w >= WORD_COUNT)
            return SIZE;
        Word bits = mWords[w] & (~Word(0) << (start & 63));
        while (bits == 0) {
            if (++w == WORD_COUNT)
                return SIZE;
            bits = mWords[w];
        }
        return (w << 6) + Index(std::countr_zero(bits));
    }
    /// Returns the first off bit at or after `start`.
    constexpr Index findNextOff(Index start) const {
        Index w = start >> 6;
        if (w >= WORD_COUNT)
            return SIZE;
        Word bits = ~mWords[w] & (~Word(0) << (start & 63));
        while (bits == 0) {
            if (++w == WORD_COUNT)
                return SIZE;
            bits = ~mWords[w];
        }
        return (w << 6) + Index(std::countr_zero(bits));
    }

    // ---- Word access (bit n of the mask is bit n % 64 of word n / 64)
    constexpr Word getWord(Index w) const { return mWords[w]; }
    constexpr Word& getWord(Index w) { return mWords[w]; }
    constexpr const Word* words() const { return mWords.data(); }
    constexpr Word* words() { return mWords.data(); }

    // ---- Word-wise boolean operators
    constexpr BitMask& operator&=(const BitMask& o) {
        for (Index i = 0; i < WORD_COUNT; ++i)
            mWords[i] &= o.mWords[i];
        return *this;
    }
    constexpr BitMask& operator|=(const BitMask& o) {
        for (Index i = 0; i < WORD_COUNT; ++i)
            mWords[i] |= o.mWords[i];
        return *this;
    }
    constexpr BitMask& operator^=(const BitMask& o) {
        for (Index i = 0; i < WORD_COUNT; ++i)
            mWords[i] ^= o.mWords[i];
        return *this;
    }
    /// Set difference: clears every bit that is on in `o`.
    constexpr BitMask& operator-=(const BitMask& o) {
        for (Index i = 0; i < WORD_COUNT; ++i)
            mWords[i] &= ~o.mWords[i];
        return *this;
    }
    constexpr BitMask operator~() const {
        BitMask m(*this);
        m.toggle();
        return m;
    }
    friend constexpr BitMask operator&(BitMask a, const BitMask& b) { return a &= b; }
    friend constexpr BitMask operator|(BitMask a, const BitMask& b) { return a |= b; }
    friend constexpr BitMask operator^(BitMask a, const BitMask& b) { return a ^= b; }
    friend constexpr BitMask operator-(BitMask a, const BitMask& b) { return a -= b; }
    constexpr bool operator==(const BitMask&) const = default;

    // ---- Iterators over bit positions
    /// Visits the on bits (On), the off bits (Off) or every bit (Dense) in increasing order.
    /// `pos()` is the current bit; the iterator converts to false past the end.
    ///
    /// The On and Off iterators read each 64-bit word once, when they reach it, and keep the
    /// bits still to visit in a register: a step is a count-trailing-zeros and a clear-lowest-
    /// bit, with no load. So changing the current bit while iterating is safe, changes to later
    /// words are seen, and changes to the rest of the current word are not.
    template <ValueFilter Filter>
    class Iterator {
    public:
        constexpr Iterator() = default;
        constexpr Iterator(const BitMask* mask, Index pos) : mMask(mask), mPos(pos) {
            if constexpr (Filter != ValueFilter::All) {
                if (pos < SIZE)
                    mBits = wordAt(pos >> 6) & (~Word(1) << (pos & 63));
            }
        }

        constexpr Index pos() const { return mPos; }
        constexpr Index operator*() const { return mPos; }
        constexpr explicit operator bool() const { return mPos < SIZE; }
        constexpr bool test() const { return mPos < SIZE; }
        constexpr Iterator& operator++() {
            if constexpr (Filter == ValueFilter::All) {
                ++mPos;
            } else if (mBits != 0) {
                mPos = (mPos & ~Index(63)) + Index(std::countr_zero(mBits));
                mBits &= mBits - 1;
            } else {
                nextWord();
            }
            return *this;
        }
        constexpr bool operator==(const Iterator& o) const { return mPos == o.mPos; }
        // Range-for support: an iterator equals the end sentinel once exhausted.
        constexpr bool operator==(std::default_sentinel_t) const { return mPos >= SIZE; }

    private:
        constexpr Word wordAt(Index w) const {
            return Filter == ValueFilter::On ? mMask->mWords[w] : ~mMask->mWords[w];
        }
        constexpr void nextWord() {
            for (Index w = (mPos >> 6) + 1; w < WORD_COUNT; ++w) {
                const Word bits = wordAt(w);
                if (bits != 0) {
                    mPos = (w << 6) + Index(std::countr_zero(bits));
                    mBits = bits & (bits - 1);
                    return;
                }
            }
            mPos = SIZE;
        }

        const BitMask* mMask = nullptr;
        Index mPos = SIZE;
        Word mBits = 0;  // the bits of the current word after mPos still to visit
    };
    using OnIterator = Iterator<ValueFilter::On>;
    using OffIterator = Iterator<ValueFilter::Off>;
    using DenseIterator = Iterator<ValueFilter::All>;

    constexpr OnIterator beginOn() const { return OnIterator(this, findFirstOn()); }
    constexpr OffIterator beginOff() const { return OffIterator(this, findFirstOff()); }
    constexpr DenseIterator beginDense() const { return DenseIterator(this, 0); }

    /// A range over the positions of the on bits: `for (Index n : mask.onBits())`.
    struct OnRange {
        const BitMask* mask;
        constexpr OnIterator begin() const { return mask->beginOn(); }
        constexpr std::default_sentinel_t end() const { return {}; }
    };
    struct OffRange {
        const BitMask* mask;
        constexpr OffIterator begin() const { return mask->beginOff(); }
        constexpr std::default_sentinel_t end() const { return {}; }
    };
    constexpr OnRange onBits() const { return {this}; }
    constexpr OffRange offBits() const { return {this}; }

    /// Bytes of memory the mask occupies.
    static constexpr Index64 memUsage() { return sizeof(BitMask); }

private:
    std::array<Word, WORD_COUNT> mWords{};
};

}  // namespace vdb::util
