// SPDX-License-Identifier: Apache-2.0
/// @file
/// Small helpers shared by the node templates (node traits: NodeTraits.h): saturating counts,
/// and the bit test used to skip filling zero-initialized tables. Values are compared with
/// math::isApproxEqual() (math/Math.h, math/Vec3.h), the library's one tolerance comparison.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>
#include <vdb/tree/NodeTraits.h>

#include <cmath>
#include <concepts>
#include <cstring>
#include <type_traits>

namespace vdb::tree {

namespace detail {

/// Voxel counts saturate at 2^64 - 1 instead of wrapping (a bounded [7,6,5,4,3] domain holds
/// 2^75 voxels).
constexpr Index64 saturatingAdd(Index64 a, Index64 b) {
    const Index64 s = a + b;
    return s < a ? ~Index64(0) : s;
}
constexpr Index64 saturatingMul(Index64 a, Index64 b) {
    Index64 p = 0;
    return __builtin_mul_overflow(a, b, &p) ? ~Index64(0) : p;
}

/// True when every byte of `value` is zero, so zero-filled memory already holds it.
template <typename ValueT>
bool isZeroBits(const ValueT& value) {
    static_assert(std::is_trivially_copyable_v<ValueT>);
    unsigned char bytes[sizeof(ValueT)];
    std::memcpy(bytes, &value, sizeof(ValueT));
    for (unsigned char b : bytes)
        if (b != 0)
            return false;
    return true;
}

/// Maps the local child index (i, j, k) of a node of origin `origin` and edge 2^total voxels to
/// the global origin of that child. Components wrap modulo 2^total around the origin, so a
/// node whose origin is not a multiple of its size (the centered top of a bounded tree) maps
/// each table slot to the one coordinate inside its domain with those low bits.
inline Coord localToGlobal(const Coord& origin, Index total, Index i, Index j, Index k,
                           Index childTotal) {
    const uint32_t mask = (total >= 32) ? ~0u : ((uint32_t(1) << total) - 1);
    auto wrap = [&](Int32 o, Index n) {
        return Int32(uint32_t(o) + ((uint32_t(n << childTotal) - uint32_t(o)) & mask));
    };
    return Coord(wrap(origin[0], i), wrap(origin[1], j), wrap(origin[2], k));
}

}  // namespace detail
}  // namespace vdb::tree
