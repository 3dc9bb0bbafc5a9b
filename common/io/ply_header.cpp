#include "io/ply_header.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace rad {

std::optional<PlyType> parsePlyType(const std::string& name) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& n : names)
        if (name == n.first) return n.second;
    return std::nullopt;
}

const char* plyTypeName(PlyType t) {
    switch (t) {
        case PlyType::Int8: return "char";
        case PlyType::UInt8: return "uchar";
        case PlyType::Int16: return "short";
        case PlyType::UInt16: return "ushort";
        case PlyType::Int32: return "int";
        case PlyType::UInt32: return "uint";
        case PlyType::Float32: return "float";
        case PlyType::Float64: return "double";
    }
    return "?";
}

std::optional<double> parsePlyAsciiNumber(const char* text, std::size_t length, PlyType t) {
    if (isPlyIntegerType(t)) {
        long long value = 0;
        const auto r = std::from_chars(text, text + length, value);
        if (r.ec == std::errc() && r.ptr == text + length) return double(value);
        return std::nullopt;
    }
    double value = 0;
    const auto r = std::from_chars(text, text + length, value);
    if (r.ec == std::errc() && r.ptr == text + length) return value;
    // from_chars does not read "nan" / "inf" spellings with signs everywhere; keep them so that the
    // readers' non-finite checks name them.
    const std::string spelled(text, length);
    if (spelled == "nan" || spelled == "-nan" || spelled == "NaN") return std::nan("");
    if (spelled == "inf" || spelled == "Inf") return INFINITY;
    if (spelled == "-inf" || spelled == "-Inf") return -INFINITY;
    return std::nullopt;
}

std::optional<std::uint64_t> parsePlyUnsigned(const std::string& text) {
    if (text.empty()) return std::nullopt;
    std::uint64_t value = 0;
    for (char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
        const std::uint64_t d = static_cast<std::uint64_t>(c - '0');
        if (value > (std::numeric_limits<std::uint64_t>::max() - d) / 10) return std::nullopt;
        value = value * 10 + d;
    }
    return value;
}

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }
// What std::istream >> std::string skips in the classic locale.
bool isAsciiSpace(char c) { return isBlank(c) || c == '\n' || c == '\v' || c == '\f' || c == '\r'; }

template <typename Separator>
std::vector<std::string> tokenize(const std::string& line, Separator isSeparator) {
    std::vector<std::string> tokens;
    std::size_t pos = 0;
    for (;;) {
        while (pos < line.size() && isSeparator(line[pos])) ++pos;
        if (pos == line.size()) return tokens;
        const std::size_t start = pos;
        while (pos < line.size() && !isSeparator(line[pos])) ++pos;
        tokens.push_back(line.substr(start, pos - start));
    }
}

// One line of the header, without its line break.
struct HeaderLine {
    std::string text;
    std::size_t number = 0;
    std::size_t offset = 0;
};

// The line at pos (pos is advanced past its '\n'); false when no complete line is left.
bool nextLine(const char* data, std::size_t size, std::size_t& pos, HeaderLine& line) {
    const void* nl = pos < size ? std::memchr(data + pos, '\n', size - pos) : nullptr;
    if (!nl) return false;
    const std::size_t end = static_cast<std::size_t>(static_cast<const char*>(nl) - data);
    line.text.assign(data + pos, end - pos);
    line.offset = pos;
    ++line.number;
    pos = end + 1;
    if (!line.text.empty() && line.text.back() == '\r') line.text.pop_back();
    return true;
}

using Fault = std::optional<PlyHeaderFault>;

Fault faultAt(PlyHeaderFaultKind kind, const HeaderLine& line, std::string token = {}, std::string detail = {}) {
    return PlyHeaderFault{kind, line.number, line.offset, std::move(token), std::move(detail)};
}

// A fault of the whole header rather than of one line.
Fault headerFault(PlyHeaderFaultKind kind, std::size_t offset = 0) {
    PlyHeaderFault f;
    f.kind = kind;
    f.lineOffset = offset;
    return f;
}

Fault checkPlyLine(const char* data, std::size_t size, const PlyHeaderRules& rules) {
    if (size == 0) return headerFault(PlyHeaderFaultKind::EmptyFile);
    if (size < 4 || std::memcmp(data, "ply", 3) != 0) return headerFault(PlyHeaderFaultKind::NoPlyLine);
    const bool lineBreak = rules.strict ? data[3] == '\n' || (data[3] == '\r' && size >= 5 && data[4] == '\n')
                                        : data[3] == '\n' || data[3] == '\r';
    if (!lineBreak) return headerFault(PlyHeaderFaultKind::NoPlyLine);
    return std::nullopt;
}

// What the lines read so far have declared.
struct HeaderState {
    PlyHeader& header;
    const PlyHeaderRules& rules;
    bool formatSeen = false;
};

Fault parseFormatLine(const std::vector<std::string>& t, const HeaderLine& line, HeaderState& state) {
    using K = PlyHeaderFaultKind;
    if (state.formatSeen) return faultAt(K::RepeatedFormat, line);
    if (state.rules.strict && !state.header.elements.empty()) return faultAt(K::FormatAfterElements, line);
    if (t.size() != 3) return faultAt(K::MalformedFormat, line);
    PlyEncoding& encoding = state.header.encoding;
    if (t[1] == "ascii") {
        if (!state.rules.acceptAscii) return faultAt(K::EncodingNotAccepted, line, t[1]);
        encoding = PlyEncoding::Ascii;
    } else if (t[1] == "binary_big_endian") {
        if (!state.rules.acceptBigEndian) return faultAt(K::EncodingNotAccepted, line, t[1]);
        encoding = PlyEncoding::BinaryBigEndian;
    } else if (t[1] == "binary_little_endian") {
        encoding = PlyEncoding::BinaryLittleEndian;
    } else {
        return faultAt(K::UnknownFormat, line, t[1]);
    }
    if (t[2] != "1.0") return faultAt(K::UnsupportedVersion, line, t[2]);
    state.formatSeen = true;
    return std::nullopt;
}

Fault parseElementLine(const std::vector<std::string>& t, const HeaderLine& line, HeaderState& state) {
    using K = PlyHeaderFaultKind;
    if (state.rules.strict && !state.formatSeen) return faultAt(K::ElementBeforeFormat, line);
    if (t.size() != 3) return faultAt(K::MalformedElement, line);
    // 20 digits hold every 64-bit count; more are zeros in front, which no writer puts there.
    const auto count = state.rules.strict && t[2].size() > 20 ? std::nullopt : parsePlyUnsigned(t[2]);
    if (!count) return faultAt(K::InvalidElementCount, line, t[1], t[2]);
    for (const auto& e : state.header.elements)
        if (e.name == t[1]) return faultAt(K::DuplicateElement, line, t[1]);
    PlyElement element;
    element.name = t[1];
    element.count = *count;
    state.header.elements.push_back(std::move(element));
    return std::nullopt;
}

// The property of a "property" line; its offset is set by addProperty.
Fault readPropertyDeclaration(const std::vector<std::string>& t, const HeaderLine& line, PlyProperty& p) {
    using K = PlyHeaderFaultKind;
    if (t.size() == 5 && t[1] == "list") {
        const auto countType = parsePlyType(t[2]);
        const auto itemType = parsePlyType(t[3]);
        if (!countType || !itemType) return faultAt(K::UnknownListType, line, t[4]);
        if (!isPlyIntegerType(*countType)) return faultAt(K::NonIntegerListLength, line, t[4]);
        p.isList = true;
        p.countType = *countType;
        p.type = *itemType;
        p.name = t[4];
        return std::nullopt;
    }
    if (t.size() != 3) return faultAt(K::MalformedProperty, line);
    if (t[1] == "list") return faultAt(K::ScalarPropertyOfTypeList, line, t[1]);
    const auto type = parsePlyType(t[1]);
    if (!type) return faultAt(K::UnknownPropertyType, line, t[1]);
    p.type = *type;
    p.name = t[2];
    return std::nullopt;
}

Fault parsePropertyLine(const std::vector<std::string>& t, const HeaderLine& line, HeaderState& state) {
    using K = PlyHeaderFaultKind;
    if (state.header.elements.empty()) return faultAt(K::PropertyBeforeElement, line);
    PlyElement& element = state.header.elements.back();
    PlyProperty p;
    if (Fault f = readPropertyDeclaration(t, line, p)) return f;
    if (element.byName.count(p.name)) return faultAt(K::DuplicateProperty, line, p.name, element.name);
    element.byName.emplace(p.name, element.properties.size());
    if (p.isList) {
        element.hasList = true;
    } else {
        p.offset = element.scalarBytes;
        element.scalarBytes += plyTypeSize(p.type);
    }
    element.properties.push_back(std::move(p));
    return std::nullopt;
}

// One line other than "ply" and "end_header".
Fault parseHeaderLine(std::vector<std::string>& t, HeaderLine& line, HeaderState& state) {
    const std::string& keyword = t[0];
    if (keyword == "comment") {
        state.header.comments.push_back({std::move(t), std::move(line.text), line.number});
        return std::nullopt;
    }
    if (keyword == "obj_info") return std::nullopt;
    if (keyword == "format") return parseFormatLine(t, line, state);
    if (keyword == "element") return parseElementLine(t, line, state);
    if (keyword == "property") return parsePropertyLine(t, line, state);
    return faultAt(PlyHeaderFaultKind::UnknownKeyword, line, keyword);
}

}  // namespace

std::string nextPlyToken(const std::string& line, std::size_t& pos) {
    while (pos < line.size() && isBlank(line[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < line.size() && !isBlank(line[pos])) ++pos;
    return line.substr(start, pos - start);
}

std::uint64_t minimumPlyRecordBytes(const PlyElement& element, int triangleList) {
    std::uint64_t bytes = 0;
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
        const PlyProperty& p = element.properties[i];
        if (!p.isList) bytes += plyTypeSize(p.type);
        else bytes += plyTypeSize(p.countType) + (int(i) == triangleList ? 3 * plyTypeSize(p.type) : 0);
    }
    return bytes;
}

PlyHeaderParse parsePlyHeader(const char* data, std::size_t size, const PlyHeaderRules& rules) {
    PlyHeaderParse result;
    if ((result.fault = checkPlyLine(data, size, rules))) return result;
    HeaderState state{result.header, rules};
    bool ended = false;
    std::size_t pos = 0;
    HeaderLine line;
    while (nextLine(data, size, pos, line)) {
        if (line.number == 1) continue;  // "ply"
        std::vector<std::string> t = rules.strict ? tokenize(line.text, isBlank) : tokenize(line.text, isAsciiSpace);
        if (t.empty()) continue;
        if (t[0] == "end_header") {
            if (rules.strict && t.size() != 1) result.fault = faultAt(PlyHeaderFaultKind::MalformedEndHeader, line);
            ended = true;
            break;
        }
        if ((result.fault = parseHeaderLine(t, line, state))) return result;
    }
    if (!result.fault && !ended) result.fault = headerFault(PlyHeaderFaultKind::NoEndHeader, size);
    if (!result.fault && !state.formatSeen) result.fault = headerFault(PlyHeaderFaultKind::NoFormatLine);
    result.header.dataOffset = pos;
    return result;
}

}  // namespace rad
