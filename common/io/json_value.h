// A small JSON reader (RFC 8259): a whole text into a tree of values. Camera files
// (nerfstudio's transforms.json) are small; no JSON library is among the project's dependencies,
// and this much is easier to check than to add one.
#pragma once

#include "errors/error_categories.h"

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct JsonError : FileError {
    using FileError::FileError;
};

struct JsonValue {
    enum class Type { Null, Bool, Number, String, Array, Object };
    Type type = Type::Null;
    bool boolean = false;
    double number = 0.0;
    std::string string;
    std::vector<JsonValue> array;
    std::map<std::string, JsonValue> object;

    bool isNumber() const { return type == Type::Number; }
    // The member `key` of an object, or null when absent (or when this is not an object).
    const JsonValue* find(const std::string& key) const;
};

// Parses `text`; throws JsonError with the line and what was expected. `what` names the text.
// Besides standard JSON, NaN / Infinity / -Infinity are read as numbers (Python's json module
// writes them): the caller's validation then names the value that is not finite.
JsonValue parseJson(const std::string& text, const std::string& what);

}  // namespace rad
