// SPDX-License-Identifier: Apache-2.0
/// @file
/// Thin wrappers over oneTBB for the loops the library runs: a parallel for over an index
/// range and a deterministic parallel reduction. Both run serially when `threaded` is false.

#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <cstddef>

namespace vdb::util {

/// Calls `op(begin, end)` on disjoint sub-ranges covering [0, n), in parallel when `threaded`.
/// `grain` is the smallest sub-range worth a task.
template <typename OpT>
void parallelForRange(size_t n, const OpT& op, bool threaded = true, size_t grain = 64) {
    if (n == 0)
        return;
    if (!threaded) {
        op(size_t(0), n);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                      [&](const tbb::blocked_range<size_t>& r) { op(r.begin(), r.end()); });
}

/// Calls `op(i)` for every i in [0, n), in parallel when `threaded`.
template <typename OpT>
void parallelFor(size_t n, const OpT& op, bool threaded = true, size_t grain = 64) {
    parallelForRange(
        n,
        [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i)
                op(i);
        },
        threaded, grain);
}

/// Reduces `map(begin, end)` over sub-ranges of [0, n) with `join(a, b)`. The sub-ranges and
/// the order of joins depend only on n and `grain`, never on the number of threads, so
/// floating-point results are reproducible.
template <typename T, typename MapT, typename JoinT>
T parallelReduce(size_t n, const T& identity, const MapT& map, const JoinT& join,
                 bool threaded = true, size_t grain = 256) {
    if (n == 0)
        return identity;
    if (!threaded) {
        // The threaded path's blocking and order of joins: halves split while longer than
        // `grain` (as tbb::blocked_range splits), each leaf mapped from `identity`, siblings
        // joined left to right; so both give identical results.
        const auto reduce = [&](const auto& self, size_t b, size_t e) -> T {
            if (e - b > grain) {
                const size_t m = b + (e - b) / 2;
                return join(self(self, b, m), self(self, m, e));
            }
            return join(identity, map(b, e));
        };
        return reduce(reduce, size_t(0), n);
    }
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<size_t>(0, n, grain), identity,
        [&](const tbb::blocked_range<size_t>& r, T acc) {
            return join(acc, map(r.begin(), r.end()));
        },
        join);
}

}  // namespace vdb::util
