// SPDX-License-Identifier: Apache-2.0
// Conversions between this library's and OpenVDB's coordinates, boxes and values, shared by the
// compatibility tests (the only tests that include OpenVDB).

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Vec3.h>

#include <openvdb/openvdb.h>

#include <type_traits>

namespace vdb::test {

inline openvdb::Coord toOvdb(const Coord& ijk) {
    return openvdb::Coord(ijk[0], ijk[1], ijk[2]);
}
inline openvdb::CoordBBox toOvdb(const CoordBBox& box) {
    return openvdb::CoordBBox(toOvdb(box.min()), toOvdb(box.max()));
}
inline openvdb::Vec3s toOvdb(const Vec3s& v) {
    return openvdb::Vec3s(v[0], v[1], v[2]);
}
template <typename T>
T toOvdb(const T& v) requires std::is_arithmetic_v<T> {
    return v;
}

inline Coord fromOvdb(const openvdb::Coord& ijk) {
    return Coord(ijk[0], ijk[1], ijk[2]);
}
inline Vec3s fromOvdb(const openvdb::Vec3s& v) {
    return Vec3s(v[0], v[1], v[2]);
}
template <typename T>
T fromOvdb(const T& v) requires std::is_arithmetic_v<T> {
    return v;
}

}  // namespace vdb::test
