// SPDX-License-Identifier: Apache-2.0
/// @file
/// A small streaming JSON writer for the tool's --json output: objects, arrays, strings with
/// the escapes of RFC 8259, and numbers (non-finite numbers become null).

#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace vdb::app {

/// Builds one JSON document, indented by two spaces. Keys and values are written in call
/// order; commas are placed automatically.
class JsonWriter {
public:
    JsonWriter& beginObject();
    JsonWriter& endObject();
    JsonWriter& beginArray();
    JsonWriter& endArray();
    /// The key of the next value inside an object.
    JsonWriter& key(std::string_view name);

    JsonWriter& value(std::string_view s);
    JsonWriter& value(const char* s) { return value(std::string_view(s)); }
    JsonWriter& value(const std::string& s) { return value(std::string_view(s)); }
    JsonWriter& value(double d);
    JsonWriter& value(int64_t i);
    JsonWriter& value(uint64_t u);
    JsonWriter& value(int i) { return value(static_cast<int64_t>(i)); }
    JsonWriter& value(unsigned u) { return value(static_cast<uint64_t>(u)); }
    JsonWriter& value(bool b);
    JsonWriter& null();
    /// An array of three numbers.
    template <typename Vec3T>
    JsonWriter& triple(const Vec3T& v) {
        beforeValue();
        mOut += '[';
        for (int i = 0; i < 3; ++i) {
            mOut += i ? ", " : "";
            mOut += numberText(static_cast<double>(v[i]));
        }
        mOut += ']';
        return *this;
    }

    /// The document so far, with a final newline once every object and array is closed.
    std::string str() const { return mStack.empty() ? mOut + "\n" : mOut; }

private:
    static std::string numberText(double d);
    void beforeValue();
    void newline();

    struct Level {
        bool isObject;
        bool empty = true;
    };
    std::string mOut;
    std::vector<Level> mStack;
    bool mAfterKey = false;
};

/// `s` as a quoted JSON string.
std::string jsonQuote(std::string_view s);

}  // namespace vdb::app
