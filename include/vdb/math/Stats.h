// SPDX-License-Identifier: Apache-2.0
/// @file
/// Running statistics of a population of values, with OpenVDB's names and meanings: MinMax
/// (smallest and largest of any ordered type), Extrema (min, max and count of doubles), Stats
/// (Extrema plus mean and population variance, by Welford's incremental update in double
/// precision) and Histogram (counts in equal bins over a fixed range).
///
/// Each class merges with another of its kind (add(other)), so parallel passes can reduce
/// partial results; merging is exact for MinMax, Extrema and Histogram, and for Stats it is
/// Chan et al.'s pairwise update, so the result depends on the order of the merges only through
/// rounding (tools/Statistics.h merges in an order fixed by the data, not by the threads).
///
/// @code
/// vdb::math::Stats s;
/// for (double v : {1.0, 2.0, 4.0}) s.add(v);
/// s.mean();      // 7/3
/// s.variance();  // population variance
/// vdb::math::Histogram h(0.0, 4.0, 4);
/// h.add(2.5);    // bin 2
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/math/Math.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace vdb::math {

/// The smallest and largest of the values added, under the order `Less`. A default-constructed
/// MinMax starts from (max, lowest) of the type, so the first value added replaces both.
/// Threads: a plain value; merge per-thread copies with add(other).
template <typename ValueT, typename Less = std::less<ValueT>>
class MinMax {
public:
    MinMax() requires std::numeric_limits<ValueT>::is_specialized
        : mMin(std::numeric_limits<ValueT>::max()),
          mMax(std::numeric_limits<ValueT>::lowest()) {}
    MinMax(const ValueT& min, const ValueT& max) : mMin(min), mMax(max) {}

    void add(const ValueT& value, const Less& less = Less()) {
        if (less(value, mMin))
            mMin = value;
        if (less(mMax, value))
            mMax = value;
    }
    void add(const MinMax& other, const Less& less = Less()) {
        if (less(other.mMin, mMin))
            mMin = other.mMin;
        if (less(mMax, other.mMax))
            mMax = other.mMax;
    }
    const ValueT& min() const { return mMin; }
    const ValueT& max() const { return mMax; }

private:
    ValueT mMin, mMax;
};

/// The count, minimum and maximum of a population of doubles. With no sample, size() is 0 and
/// min() > max().
class Extrema {
public:
    Extrema() = default;

    /// Adds one sample.
    void add(double value) { add(value, 1); }
    /// Adds `n` samples of the same value (a tile of n voxels).
    void add(double value, uint64_t n) {
        if (n == 0)
            return;
        mSize += n;
        mMin = std::min(mMin, value);
        mMax = std::max(mMax, value);
    }
    /// Adds the samples of `other`.
    void add(const Extrema& other) {
        if (other.mSize > 0)
            join(other);
    }

    /// The number of samples.
    uint64_t size() const { return mSize; }
    double min() const { return mMin; }
    double max() const { return mMax; }
    /// max() - min().
    double range() const { return mMax - mMin; }

protected:
    void join(const Extrema& other) {
        mSize += other.mSize;
        mMin = std::min(mMin, other.mMin);
        mMax = std::max(mMax, other.mMax);
    }

    uint64_t mSize = 0;
    double mMin = std::numeric_limits<double>::max();
    double mMax = -std::numeric_limits<double>::max();
};

/// Extrema plus the mean and the population variance, updated incrementally in double precision
/// (variance = mean of (x - mean)^2; 0 for fewer than two samples).
class Stats : public Extrema {
public:
    Stats() = default;

    void add(double value) { add(value, 1); }
    void add(double value, uint64_t n) {
        if (n == 0)
            return;
        const double total = double(mSize + n);
        const double delta = value - mAvg;
        mAvg += delta * double(n) / total;
        mAux += delta * delta * double(mSize) * double(n) / total;
        Extrema::add(value, n);
    }
    /// Adds the samples of `other` (Chan et al.'s pairwise combination).
    void add(const Stats& other) {
        if (other.mSize == 0)
            return;
        const double total = double(mSize + other.mSize);
        const double delta = other.mAvg - mAvg;
        mAvg += delta * double(other.mSize) / total;
        mAux += other.mAux + delta * delta * double(mSize) * double(other.mSize) / total;
        Extrema::join(other);
    }

    double avg() const { return mAvg; }
    double mean() const { return mAvg; }
    /// The population variance (divide by size(), not size() - 1).
    double var() const { return mSize < 2 ? 0.0 : mAux / double(mSize); }
    double variance() const { return var(); }
    /// The square root of the population variance.
    double std() const { return std::sqrt(var()); }
    double stdDev() const { return std(); }

private:
    double mAvg = 0.0;
    double mAux = 0.0;  // sum of squared deviations from the mean
};

/// Counts of samples in `numBins` equal bins over [min, max]. Bin n holds the samples in
/// [min(n), max(n)); the last bin also holds `max` itself. Samples outside the range are not
/// counted (add() returns false).
class Histogram {
public:
    /// @throw ValueError unless min < max (both finite) and numBins >= 1.
    Histogram(double min, double max, size_t numBins = 10) : mMin(min), mMax(max) {
        if (!(min < max) || !std::isfinite(min) || !std::isfinite(max))
            throw ValueError("Histogram: expected finite min < max");
        if (numBins == 0)
            throw ValueError("Histogram: expected at least one bin");
        mDelta = double(numBins) / (max - min);
        mBins.assign(numBins, 0);
    }
    /// The range of `stats` (min to max); see Histogram(double, double, size_t).
    explicit Histogram(const Stats& stats, size_t numBins = 10)
        : Histogram(stats.min(), stats.max(), numBins) {}

    /// Adds `n` samples of `value` when it lies in [min, max]; returns whether it did.
    bool add(double value, uint64_t n = 1) {
        if (!(value >= mMin && value <= mMax))
            return false;
        const size_t bin = std::min(size_t(mDelta * (value - mMin)), mBins.size() - 1);
        mBins[bin] += n;
        mSize += n;
        return true;
    }
    /// Adds the counts of `other` when it has the same range and bins; returns whether it did.
    bool add(const Histogram& other) {
        if (mMin != other.mMin || mMax != other.mMax || mBins.size() != other.mBins.size())
            return false;
        for (size_t i = 0; i < mBins.size(); ++i)
            mBins[i] += other.mBins[i];
        mSize += other.mSize;
        return true;
    }

    size_t numBins() const { return mBins.size(); }
    double min() const { return mMin; }
    double max() const { return mMax; }
    /// The lower and upper bounds of bin `n`.
    double min(int n) const { return mMin + double(n) / mDelta; }
    double max(int n) const { return mMin + double(n + 1) / mDelta; }
    /// The number of samples in bin `n`.
    uint64_t count(int n) const { return mBins[size_t(n)]; }
    /// The number of samples counted.
    uint64_t size() const { return mSize; }

private:
    uint64_t mSize = 0;
    double mMin, mMax, mDelta = 1.0;
    std::vector<uint64_t> mBins;
};

}  // namespace vdb::math
