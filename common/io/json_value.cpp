#include "io/json_value.h"

#include <cmath>
#include <cstdlib>

namespace rad {

namespace {

class Parser {
public:
    Parser(const std::string& text, const std::string& what) : s_(text), what_(what) {}

    JsonValue document() {
        JsonValue v = value(0);
        skipSpace();
        if (at_ != s_.size()) fail("text after the JSON value");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& expected) const {
        int line = 1;
        for (std::size_t i = 0; i < at_ && i < s_.size(); ++i) line += s_[i] == '\n';
        throw JsonError("'" + what_ + "' is not valid JSON (line " + std::to_string(line) + ": " + expected + ")");
    }
    void skipSpace() {
        while (at_ < s_.size() && (s_[at_] == ' ' || s_[at_] == '\t' || s_[at_] == '\n' || s_[at_] == '\r')) ++at_;
    }
    bool consume(const char* word) {
        std::size_t n = 0;
        while (word[n] != 0) ++n;
        if (s_.compare(at_, n, word) != 0) return false;
        at_ += n;
        return true;
    }
    JsonValue value(int depth) {
        if (depth > 64) fail("nesting deeper than 64 levels");
        skipSpace();
        if (at_ >= s_.size()) fail("a value, found the end of the text");
        JsonValue v;
        const char c = s_[at_];
        if (c == '{') {
            v.type = JsonValue::Type::Object;
            ++at_;
            skipSpace();
            if (at_ < s_.size() && s_[at_] == '}') { ++at_; return v; }
            for (;;) {
                skipSpace();
                if (at_ >= s_.size() || s_[at_] != '"') fail("a member name in quotes");
                const std::string key = stringLiteral();
                skipSpace();
                if (at_ >= s_.size() || s_[at_] != ':') fail("':' after a member name");
                ++at_;
                v.object[key] = value(depth + 1);
                skipSpace();
                if (at_ < s_.size() && s_[at_] == ',') { ++at_; continue; }
                if (at_ < s_.size() && s_[at_] == '}') { ++at_; return v; }
                fail("',' or '}' in an object");
            }
        }
        if (c == '[') {
            v.type = JsonValue::Type::Array;
            ++at_;
            skipSpace();
            if (at_ < s_.size() && s_[at_] == ']') { ++at_; return v; }
            for (;;) {
                v.array.push_back(value(depth + 1));
                skipSpace();
                if (at_ < s_.size() && s_[at_] == ',') { ++at_; continue; }
                if (at_ < s_.size() && s_[at_] == ']') { ++at_; return v; }
                fail("',' or ']' in an array");
            }
        }
        if (c == '"') {
            v.type = JsonValue::Type::String;
            v.string = stringLiteral();
            return v;
        }
        if (consume("true")) { v.type = JsonValue::Type::Bool; v.boolean = true; return v; }
        if (consume("false")) { v.type = JsonValue::Type::Bool; return v; }
        if (consume("null")) return v;
        v.type = JsonValue::Type::Number;
        if (consume("NaN")) { v.number = std::nan(""); return v; }
        if (consume("Infinity")) { v.number = HUGE_VAL; return v; }
        if (consume("-Infinity")) { v.number = -HUGE_VAL; return v; }
        const char* begin = s_.c_str() + at_;
        char* end = nullptr;
        v.number = std::strtod(begin, &end);
        if (end == begin || !(c == '-' || (c >= '0' && c <= '9'))) fail("a value");
        at_ += std::size_t(end - begin);
        return v;
    }
    std::string stringLiteral() {
        ++at_;  // the opening quote
        std::string out;
        while (at_ < s_.size() && s_[at_] != '"') {
            char c = s_[at_++];
            if (c != '\\') { out += c; continue; }
            if (at_ >= s_.size()) break;
            c = s_[at_++];
            switch (c) {
                case 'n': out += '\n'; break;
                case 't': out += '\t'; break;
                case 'r': out += '\r'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'u': {
                    if (at_ + 4 > s_.size()) fail("four hex digits after \\u");
                    const unsigned code = unsigned(std::strtoul(s_.substr(at_, 4).c_str(), nullptr, 16));
                    at_ += 4;
                    // UTF-8 of a code point of the Basic Multilingual Plane (file names).
                    if (code < 0x80) out += char(code);
                    else if (code < 0x800) { out += char(0xC0 | (code >> 6)); out += char(0x80 | (code & 0x3F)); }
                    else { out += char(0xE0 | (code >> 12)); out += char(0x80 | ((code >> 6) & 0x3F)); out += char(0x80 | (code & 0x3F)); }
                    break;
                }
                default: out += c;  // \" \\ \/
            }
        }
        if (at_ >= s_.size()) fail("the closing quote of a string");
        ++at_;
        return out;
    }

    const std::string& s_;
    std::string what_;
    std::size_t at_ = 0;
};

}  // namespace

const JsonValue* JsonValue::find(const std::string& key) const {
    if (type != Type::Object) return nullptr;
    const auto found = object.find(key);
    return found == object.end() ? nullptr : &found->second;
}

JsonValue parseJson(const std::string& text, const std::string& what) { return Parser(text, what).document(); }

}  // namespace rad
