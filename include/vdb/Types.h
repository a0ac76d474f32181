// SPDX-License-Identifier: Apache-2.0
/// @file
/// Basic scalar types, tags and enums shared by every layer of the library.

#pragma once

#include <cstdint>

namespace vdb {

using Index = uint32_t;
using Index32 = uint32_t;
using Index64 = uint64_t;
using Int32 = int32_t;
using Int64 = int64_t;

/// Tag value type of topology-only trees: a mask leaf stores activity bits and no values.
/// Trees built on it report `bool` as their ValueType (a voxel's value is its active state).
struct ValueMask {};

/// What a grid's values mean; stored in the file as the `class` metadata.
enum GridClass { GRID_UNKNOWN = 0, GRID_LEVEL_SET, GRID_FOG_VOLUME, GRID_STAGGERED };

/// Which values a tree or node iterator visits.
enum class ValueFilter { On, Off, All };

}  // namespace vdb
