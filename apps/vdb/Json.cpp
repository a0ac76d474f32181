// SPDX-License-Identifier: Apache-2.0

#include "Json.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace vdb::app {

std::string jsonQuote(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\b':
                out += "\\b";
                break;
            case '\f':
                out += "\\f";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\r':
                out += "\\r";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

void JsonWriter::newline() {
    mOut += '\n';
    mOut.append(2 * mStack.size(), ' ');
}

void JsonWriter::beforeValue() {
    if (mAfterKey) {
        mAfterKey = false;
        return;
    }
    if (mStack.empty())
        return;
    if (!mStack.back().empty)
        mOut += ',';
    mStack.back().empty = false;
    newline();
}

JsonWriter& JsonWriter::key(std::string_view name) {
    beforeValue();
    mOut += jsonQuote(name) + ": ";
    mAfterKey = true;
    return *this;
}

JsonWriter& JsonWriter::beginObject() {
    beforeValue();
    mOut += '{';
    mStack.push_back({true});
    return *this;
}

JsonWriter& JsonWriter::beginArray() {
    beforeValue();
    mOut += '[';
    mStack.push_back({false});
    return *this;
}

JsonWriter& JsonWriter::endObject() {
    const bool empty = mStack.back().empty;
    mStack.pop_back();
    if (!empty)
        newline();
    mOut += '}';
    return *this;
}

JsonWriter& JsonWriter::endArray() {
    const bool empty = mStack.back().empty;
    mStack.pop_back();
    if (!empty)
        newline();
    mOut += ']';
    return *this;
}

JsonWriter& JsonWriter::value(std::string_view s) {
    beforeValue();
    mOut += jsonQuote(s);
    return *this;
}

std::string JsonWriter::numberText(double d) {
    if (!std::isfinite(d))
        return "null";
    // The shortest of %.6g..%.17g that reads back as the same double.
    char buf[32];
    for (int precision = 6; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, d);
        if (std::strtod(buf, nullptr) == d)
            break;
    }
    return buf;
}

JsonWriter& JsonWriter::value(double d) {
    beforeValue();
    mOut += numberText(d);
    return *this;
}

JsonWriter& JsonWriter::value(int64_t i) {
    beforeValue();
    mOut += std::to_string(i);
    return *this;
}

JsonWriter& JsonWriter::value(uint64_t u) {
    beforeValue();
    mOut += std::to_string(u);
    return *this;
}

JsonWriter& JsonWriter::value(bool b) {
    beforeValue();
    mOut += b ? "true" : "false";
    return *this;
}

JsonWriter& JsonWriter::null() {
    beforeValue();
    mOut += "null";
    return *this;
}

}  // namespace vdb::app
