// SPDX-License-Identifier: Apache-2.0
/// @file
/// The names the `.vdb` format uses for value types ("float", "vec3s", "mask", ...), and the
/// tree type string built from them ("Tree_float_5_4_3").

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Vec3.h>

#include <string>
#include <string_view>

namespace vdb {

/// `typeName<T>()` is the file name of value type T; unlisted types do not compile.
template <typename T>
constexpr std::string_view typeName() = delete;
template <>
constexpr std::string_view typeName<float>() {
    return "float";
}
template <>
constexpr std::string_view typeName<double>() {
    return "double";
}
template <>
constexpr std::string_view typeName<Int32>() {
    return "int32";
}
template <>
constexpr std::string_view typeName<Int64>() {
    return "int64";
}
template <>
constexpr std::string_view typeName<bool>() {
    return "bool";
}
template <>
constexpr std::string_view typeName<ValueMask>() {
    return "mask";
}
template <>
constexpr std::string_view typeName<Vec3s>() {
    return "vec3s";
}
template <>
constexpr std::string_view typeName<Vec3d>() {
    return "vec3d";
}
template <>
constexpr std::string_view typeName<Vec3i>() {
    return "vec3i";
}

namespace tree::detail {
template <typename NodeT>
void appendLog2Dims(std::string& s) {
    if constexpr (NodeT::LEVEL > 0) {
        s += '_';
        s += std::to_string(NodeT::LOG2DIM);
        appendLog2Dims<typename NodeT::ChildNodeType>(s);
    } else {
        s += '_';
        s += std::to_string(NodeT::LOG2DIM);
    }
}
}  // namespace tree::detail

/// The tree type string of `TreeT`: "Tree_" + value type + the log2 dimensions from the top
/// internal level down, as OpenVDB writes it ("Tree_float_5_4_3"). Trees with a fixed internal
/// node on top are named "FixedTree_..." (a type that OpenVDB files cannot hold).
template <typename TreeT>
std::string treeTypeName() {
    std::string s = TreeT::BOUNDED ? "FixedTree_" : "Tree_";
    s += typeName<typename TreeT::BuildType>();
    using TopT = typename TreeT::TopNodeType;
    if constexpr (TreeT::BOUNDED) {
        tree::detail::appendLog2Dims<TopT>(s);
    } else {
        tree::detail::appendLog2Dims<typename TopT::ChildNodeType>(s);
    }
    return s;
}

}  // namespace vdb
