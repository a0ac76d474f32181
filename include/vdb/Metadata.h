// SPDX-License-Identifier: Apache-2.0
/// @file
/// Typed metadata: name-value pairs attached to grids and files, with the value types of the
/// `.vdb` format. Values of types this library does not interpret are kept as opaque bytes so
/// that they survive a read-write round trip.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Vec3.h>

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace vdb {

/// A metadata value of a type the library does not interpret: its type name and its bytes as
/// stored in a file.
struct OpaqueMetadata {
    std::string typeName;
    std::vector<uint8_t> bytes;
    bool operator==(const OpaqueMetadata&) const = default;
};

/// Any metadata value. The alternatives' type names in files are, in order: "string", "bool",
/// "int32", "int64", "float", "double", "vec3i", "vec3s", "vec3d"; OpaqueMetadata keeps its own.
using MetaValue = std::variant<std::string, bool, Int32, Int64, float, double, Vec3i, Vec3s, Vec3d,
                               OpaqueMetadata>;

/// Returns the file type name of `value`.
inline std::string_view metaTypeName(const MetaValue& value) {
    static constexpr std::string_view kNames[] = {"string", "bool",  "int32", "int64", "float",
                                                  "double", "vec3i", "vec3s", "vec3d"};
    if (const auto* opaque = std::get_if<OpaqueMetadata>(&value))
        return opaque->typeName;
    return kNames[value.index()];
}

/// Name-value metadata, ordered by name (the order files store it in).
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
class MetaMap {
public:
    using Map = std::map<std::string, MetaValue, std::less<>>;

    /// Adds or replaces the entry `name`. A `const char*` is stored as a string.
    void insertMeta(std::string_view name, const MetaValue& value) {
        mMeta.insert_or_assign(std::string(name), value);
    }
    void insertMeta(std::string_view name, const char* value) {
        insertMeta(name, MetaValue(std::string(value)));
    }
    void removeMeta(std::string_view name) {
        if (auto it = mMeta.find(name); it != mMeta.end())
            mMeta.erase(it);
    }
    void clearMetadata() { mMeta.clear(); }
    size_t metaCount() const { return mMeta.size(); }
    bool hasMeta(std::string_view name) const { return mMeta.find(name) != mMeta.end(); }

    /// Returns the value of `name`, or null when absent.
    const MetaValue* findMeta(std::string_view name) const {
        auto it = mMeta.find(name);
        return it == mMeta.end() ? nullptr : &it->second;
    }
    /// Returns the value of `name` if it has type T, else null.
    template <typename T>
    const T* getMeta(std::string_view name) const {
        const MetaValue* v = findMeta(name);
        return v ? std::get_if<T>(v) : nullptr;
    }
    /// Returns the value of `name`; throws ValueError when absent, TypeError when not a T.
    template <typename T>
    T metaValue(std::string_view name) const {
        const MetaValue* v = findMeta(name);
        if (!v)
            throw ValueError("no metadata named \"" + std::string(name) + "\"");
        if (const T* t = std::get_if<T>(v))
            return *t;
        throw TypeError("metadata \"" + std::string(name) + "\" has type " +
                        std::string(metaTypeName(*v)));
    }

    const Map& metadata() const { return mMeta; }
    Map::const_iterator beginMeta() const { return mMeta.begin(); }
    Map::const_iterator endMeta() const { return mMeta.end(); }
    bool operator==(const MetaMap&) const = default;

private:
    Map mMeta;
};

}  // namespace vdb
