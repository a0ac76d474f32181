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

/// How the vectors of a vector-valued grid transform when the grid's transform changes; stored
/// in the file as the `vector_type` metadata (OpenVDB's names and order).
enum VecType {
    VEC_INVARIANT = 0,           ///< not transformed (a colour, an index)
    VEC_COVARIANT,               ///< transformed by the inverse transpose (a gradient, a normal)
    VEC_COVARIANT_NORMALIZE,     ///< covariant, then normalised (unit normals)
    VEC_CONTRAVARIANT_RELATIVE,  ///< transformed by the linear part (a velocity, a direction)
    VEC_CONTRAVARIANT_ABSOLUTE   ///< transformed as a point, translation included (a position)
};
inline constexpr int NUM_VEC_TYPES = VEC_CONTRAVARIANT_ABSOLUTE + 1;

/// Which values a tree or node iterator, or a tree walk (tree/NodeEdit.h), visits.
enum class ValueFilter { On, Off, All };

/// What an operation of tools::combineExtended() sees at one place (OpenVDB's CombineArgs): a
/// value of each tree with its active state, and the result it sets. The result is active
/// where either input is, unless the operation calls setResultIsActive().
template <typename AValueT, typename BValueT = AValueT>
class CombineArgs {
public:
    CombineArgs(const AValueT& a, const BValueT& b, bool aIsActive, bool bIsActive)
        : mA(&a),
          mB(&b),
          mResult(a),
          mAOn(aIsActive),
          mBOn(bIsActive),
          mResultOn(aIsActive || bIsActive) {}
    const AValueT& a() const { return *mA; }
    const BValueT& b() const { return *mB; }
    bool aIsActive() const { return mAOn; }
    bool bIsActive() const { return mBOn; }
    const AValueT& result() const { return mResult; }
    AValueT& result() { return mResult; }
    bool resultIsActive() const { return mResultOn; }
    CombineArgs& setResult(const AValueT& value) {
        mResult = value;
        return *this;
    }
    CombineArgs& setResultIsActive(bool on) {
        mResultOn = on;
        return *this;
    }

private:
    const AValueT* mA;
    const BValueT* mB;
    AValueT mResult;
    bool mAOn, mBOn, mResultOn;
};

}  // namespace vdb
