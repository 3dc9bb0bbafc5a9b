// The PLY header and scalar types, shared by the project's PLY readers: the strict radiance PLY
// reader (radiance_ply.cpp, binary little endian only), the streaming reader of large scans
// (ply_stream_reader.cpp, every encoding) and the Gaussian splat reader (splats/gaussian_splat_ply.cpp,
// every encoding). One parser reads the header for all; it reports a fault as a PlyHeaderFault (what
// is wrong, where, with the offending token) rather than as a sentence, so that each reader keeps the
// refusal messages its users and tests know.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace rad {

// ---------------------------------------------------------------------------------------------------
// Scalar types

enum class PlyType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

// Both spellings of the PLY 1.0 specification ("uchar" and "uint8", ...); nullopt for anything else.
std::optional<PlyType> parsePlyType(const std::string& name);
// Bytes of one binary value. Inline: the readers call it once per value of the file.
inline std::size_t plyTypeSize(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8: return 1;
        case PlyType::Int16:
        case PlyType::UInt16: return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 0;
}
// The classic spelling ("uchar", "float", ...), as the readers' messages name types.
const char* plyTypeName(PlyType t);
inline bool isPlyIntegerType(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

namespace ply_detail {
template <typename T>
T loadScalar(const unsigned char* p, bool swapBytes) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if (swapBytes)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}
// Whether values of this byte order must be reversed on this host.
inline bool needsSwap(bool bigEndianData) {
#if defined(__BYTE_ORDER__) && defined(__ORDER_BIG_ENDIAN__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    return !bigEndianData;
#else
    return bigEndianData;
#endif
}
}  // namespace ply_detail

namespace ply_detail {
// The readers call this once per value of the file, from loops the compiler would otherwise not
// inline it into (a call per value costs them several percent).
#if defined(__GNUC__)
#define RAD_PLY_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define RAD_PLY_ALWAYS_INLINE inline
#endif
// The value of type t at p converted to Out; integer Out reads the float types as 0.
template <typename Out>
RAD_PLY_ALWAYS_INLINE Out readScalarAs(const unsigned char* p, PlyType t, bool bigEndian) {
    const bool swap = needsSwap(bigEndian);
    switch (t) {
        case PlyType::Int8: return static_cast<Out>(static_cast<std::int8_t>(p[0]));
        case PlyType::UInt8: return static_cast<Out>(p[0]);
        case PlyType::Int16: return static_cast<Out>(loadScalar<std::int16_t>(p, swap));
        case PlyType::UInt16: return static_cast<Out>(loadScalar<std::uint16_t>(p, swap));
        case PlyType::Int32: return static_cast<Out>(loadScalar<std::int32_t>(p, swap));
        case PlyType::UInt32: return static_cast<Out>(loadScalar<std::uint32_t>(p, swap));
        case PlyType::Float32: return std::is_integral_v<Out> ? Out(0) : static_cast<Out>(loadScalar<float>(p, swap));
        case PlyType::Float64: return std::is_integral_v<Out> ? Out(0) : static_cast<Out>(loadScalar<double>(p, swap));
    }
    return Out(0);
}
}  // namespace ply_detail

// A binary value of type t at p (unaligned; big endian when bigEndian), as a double. Inline: the
// readers call these once per value of the file.
inline double readPlyNumber(const unsigned char* p, PlyType t, bool bigEndian) {
    return ply_detail::readScalarAs<double>(p, t, bigEndian);
}

// A binary integer of type t at p; 0 for the float types (list lengths and indices are integers,
// which the header parser checks for lengths and the readers check for indices).
inline std::int64_t readPlyInteger(const unsigned char* p, PlyType t, bool bigEndian) {
    return ply_detail::readScalarAs<std::int64_t>(p, t, bigEndian);
}

// An ASCII value of type t (the whole of text[0, length)): integers as a 64-bit integer, floats with
// std::from_chars (independent of the C locale) plus the spellings nan, -nan, NaN, inf, Inf, -inf,
// -Inf that some writers use. nullopt when the text is not such a value.
std::optional<double> parsePlyAsciiNumber(const char* text, std::size_t length, PlyType t);

// Decimal digits only (no sign, no blanks, no length limit); nullopt on anything else or overflow.
std::optional<std::uint64_t> parsePlyUnsigned(const std::string& text);

// The next token of a header line separated by blanks (space, tab) from pos, which is advanced past
// it; empty at the end of the line.
std::string nextPlyToken(const std::string& line, std::size_t& pos);

// ---------------------------------------------------------------------------------------------------
// Header

struct PlyProperty {
    std::string name;
    bool isList = false;
    PlyType type = PlyType::Float32;     // scalar type, or list item type
    PlyType countType = PlyType::UInt8;  // list length type
    std::size_t offset = 0;              // byte offset in a binary record (scalars before any list)
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
    std::unordered_map<std::string, std::size_t> byName;
    bool hasList = false;
    std::size_t scalarBytes = 0;  // binary record size when !hasList

    const PlyProperty* find(const std::string& n) const {
        const auto it = byName.find(n);
        return it == byName.end() ? nullptr : &properties[it->second];
    }
    // Index of the property, or -1.
    int indexOf(const std::string& n) const {
        const auto it = byName.find(n);
        return it == byName.end() ? -1 : static_cast<int>(it->second);
    }
};

// The smallest binary record of the element: lists empty, except the list at index triangleList
// (when >= 0), which holds at least 3 items (a face's vertex indices).
std::uint64_t minimumPlyRecordBytes(const PlyElement& element, int triangleList = -1);

struct PlyComment {
    std::vector<std::string> tokens;  // tokens[0] == "comment"
    std::string line;
    std::size_t lineNumber = 0;
};

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::BinaryLittleEndian;
    std::vector<PlyElement> elements;
    std::vector<PlyComment> comments;
    std::size_t dataOffset = 0;  // bytes of the header, end_header line included

    const PlyElement* find(const std::string& n) const {
        for (const auto& e : elements)
            if (e.name == n) return &e;
        return nullptr;
    }
};

// What the parser accepts. The radiance reader is strict (it must refuse anything it cannot read
// exactly and save again); the streaming reader takes the headers that scanners and other tools write.
struct PlyHeaderRules {
    // Strict: the first line is exactly "ply" (LF or CRLF); tokens are separated by blanks (space,
    // tab) only; "end_header" stands alone; the format line comes before every element; an element
    // count has at most 20 digits. Lenient: "ply" then CR or LF; tokens separated by any ASCII white
    // space; anything after "end_header" ignored; format and element lines in any order.
    bool strict = true;
    bool acceptAscii = true;
    bool acceptBigEndian = true;
};

enum class PlyHeaderFaultKind {
    EmptyFile,
    NoPlyLine,               // does not start with the line "ply"
    MalformedEndHeader,      // strict: tokens after end_header
    RepeatedFormat,
    FormatAfterElements,     // strict
    MalformedFormat,         // not "format <encoding> <version>"
    EncodingNotAccepted,     // token: "ascii" or "binary_big_endian", refused by the rules
    UnknownFormat,           // token: the encoding
    UnsupportedVersion,      // token: the version
    ElementBeforeFormat,     // strict
    MalformedElement,
    InvalidElementCount,     // token: the element name, detail: the count
    DuplicateElement,        // token: the element name
    PropertyBeforeElement,
    UnknownListType,         // token: the property name (a length or item type is not a type)
    NonIntegerListLength,    // token: the property name
    ScalarPropertyOfTypeList,  // "property list <name>": token "list"
    UnknownPropertyType,     // token: the type
    MalformedProperty,
    DuplicateProperty,       // token: the property name, detail: the element name
    UnknownKeyword,          // token: the keyword
    NoEndHeader,             // the text ends (or the bytes given end) before end_header
    NoFormatLine,
};

struct PlyHeaderFault {
    PlyHeaderFaultKind kind = PlyHeaderFaultKind::NoPlyLine;
    std::size_t lineNumber = 0;  // 1 for the "ply" line; 0 when the fault has no line
    std::size_t lineOffset = 0;  // byte offset of that line in the file
    std::string token;           // the offending token (see the kinds)
    std::string detail;          // a second token (see the kinds)
};

struct PlyHeaderParse {
    PlyHeader header;
    std::optional<PlyHeaderFault> fault;  // set when the header is refused; header is then partial
};

// Parses the header from the first `size` bytes of a file (`data`). The caller gives at least as
// many bytes as it accepts headers of; a header that does not end within them is NoEndHeader.
PlyHeaderParse parsePlyHeader(const char* data, std::size_t size, const PlyHeaderRules& rules);

}  // namespace rad
