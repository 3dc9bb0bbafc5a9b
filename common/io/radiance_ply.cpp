#include "io/radiance_ply.h"

#include "io/atomic_file.h"
#include "io/ply_header.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <new>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

// The file is little endian and values are copied bytewise.
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__)
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "radiance_ply.cpp assumes a little-endian host");
#endif
static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559, "float must be IEEE 754 binary32");

namespace rad {
namespace {

// Limits (documented in docs/radiance-ply-format.md).
constexpr std::size_t kMaxHeaderBytes = std::size_t(1) << 20;  // 1 MiB
constexpr int kMaxBlockWidth = 65536;
constexpr std::uint64_t kMaxElementCount = 0xFFFFFFFFull;       // vertex and face counts (uint32 indices)
constexpr std::uint64_t kMaxWrittenVertexCount = 0x80000000ull;  // indices are written as int

[[noreturn]] void fail(const std::string& message) { throw RadianceFileError(message); }

template <typename... Args>
std::string cat(const Args&... args) {
    std::ostringstream s;
    (s << ... << args);
    return s.str();
}

// A header token as it may appear in a message: quoted, non-printable bytes escaped, length bounded.
std::string shown(const std::string& text) {
    std::string out = "'";
    const std::size_t limit = 48;
    for (std::size_t i = 0; i < text.size() && i < limit; ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            static const char* hex = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (text.size() > limit) out += "...";
    return out + "'";
}

bool allDigits(const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Decimal digits only (no sign, no spaces, at most 20); nullopt on anything else or overflow.
std::optional<std::uint64_t> parseUnsigned(const std::string& s) {
    if (s.size() > 20) return std::nullopt;
    return parsePlyUnsigned(s);
}

// a * b, saturating at the maximum (sizes compared against the file size, never allocated).
std::uint64_t mulSat(std::uint64_t a, std::uint64_t b) {
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::numeric_limits<std::uint64_t>::max();
    return a * b;
}
std::uint64_t addSat(std::uint64_t a, std::uint64_t b) {
    return a > std::numeric_limits<std::uint64_t>::max() - b ? std::numeric_limits<std::uint64_t>::max() : a + b;
}

bool isIdentifier(const std::string& s) {
    if (s.empty() || s.size() > 64) return false;
    auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
    if (!alpha(s[0])) return false;
    return std::all_of(s.begin(), s.end(), [&](char c) { return alpha(c) || (c >= '0' && c <= '9'); });
}
bool isReservedPrefix(const std::string& s) { return s == "rf" || s.rfind("rf_", 0) == 0; }

// Metadata keys: visible ASCII or UTF-8 bytes, no whitespace. Values: no control characters.
bool isMetadataKey(const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
        const unsigned char u = static_cast<unsigned char>(c);
        return u > 0x20 && u != 0x7f;
    });
}
bool isMetadataValue(const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char c) {
        const unsigned char u = static_cast<unsigned char>(c);
        return u >= 0x20 && u != 0x7f;
    });
}

const char* kConvertHint =
    "our writer produces binary little endian PLY; convert the file, e.g. open it in MeshLab and export it "
    "again as PLY with the 'Binary encoding' box checked";

// The refusal of the shared header parser's fault, in this reader's words.
[[noreturn]] void refuseHeader(const PlyHeaderFault& f, bool wholeFile) {
    using K = PlyHeaderFaultKind;
    const std::string line = cat("header line ", f.lineNumber, ": ");
    switch (f.kind) {
        case K::EmptyFile: fail("not a PLY file: the file is empty");
        case K::NoPlyLine: fail("not a PLY file: it does not start with the line 'ply'");
        case K::MalformedEndHeader: fail(line + "malformed end_header line");
        case K::RepeatedFormat: fail(line + "second format line");
        case K::FormatAfterElements: fail(line + "the format line must come before the elements");
        case K::MalformedFormat: fail(line + "malformed format line");
        case K::EncodingNotAccepted:
            if (f.token == "ascii") fail(cat("the PLY file is in ASCII format, which is not supported: ", kConvertHint));
            fail(cat("the PLY file is binary big endian, which is not supported: ", kConvertHint));
        case K::UnknownFormat: fail(cat(line, "unknown PLY format ", shown(f.token), "; ", kConvertHint));
        case K::UnsupportedVersion: fail(cat(line, "unsupported PLY version ", shown(f.token), " (expected 1.0)"));
        case K::ElementBeforeFormat: fail(line + "element before the format line");
        case K::MalformedElement: fail(line + "malformed element line");
        case K::InvalidElementCount:
            fail(cat(line, "element ", shown(f.token), " has an invalid count ", shown(f.detail)));
        case K::DuplicateElement: fail(cat(line, "element ", shown(f.token), " declared twice"));
        case K::PropertyBeforeElement: fail(line + "property before any element");
        case K::UnknownListType: fail(cat(line, "unknown type in list property ", shown(f.token)));
        case K::NonIntegerListLength: fail(cat(line, "list property ", shown(f.token), " has a non-integer length type"));
        case K::ScalarPropertyOfTypeList:
        case K::MalformedProperty: fail(line + "malformed property line");
        case K::UnknownPropertyType: fail(cat(line, "unknown property type ", shown(f.token)));
        case K::DuplicateProperty:
            fail(cat(line, "property ", shown(f.token), " of element ", shown(f.detail), " declared twice"));
        case K::UnknownKeyword: fail(cat(line, "unknown header keyword ", shown(f.token), "; not a valid PLY header"));
        case K::NoEndHeader:
            if (wholeFile)
                fail("file truncated inside its header (no end_header line); the file was probably not completely written");
            fail("no end_header line in the first 1 MiB: not a PLY header this reader accepts");
        case K::NoFormatLine: fail("the PLY header has no format line");
    }
    fail("the PLY header is not valid");
}

// `data` holds the first `size` bytes of the file; `wholeFile` when that is all of it. Strict, and
// binary little endian only: the file must read back exactly what the writer wrote.
PlyHeader parseHeader(const char* data, std::size_t size, bool wholeFile) {
    PlyHeaderRules rules;
    rules.strict = true;
    rules.acceptAscii = false;
    rules.acceptBigEndian = false;
    PlyHeaderParse parse = parsePlyHeader(data, size, rules);
    if (parse.fault) refuseHeader(*parse.fault, wholeFile);
    return std::move(parse.header);
}

// ---------------------------------------------------------------------------------------------------
// The radiance comments

struct BlockDeclaration {
    std::string prefix;
    int width = 0;
    std::map<std::string, std::string> metadata;
};

struct RadianceHeader {
    bool ourFormat = false;  // radiance_format_version present
    std::optional<BasisSpec> basis;
    bool reflected = false;
    std::vector<BlockDeclaration> blocks;
};

BasisSpec parseBasisOrFail(const std::string& text) {
    if (const auto basis = BasisSpec::parse(text)) return *basis;
    std::string prefix = text.substr(0, 2);
    for (char& c : prefix) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if ((prefix == "PB" || prefix == "SH") && allDigits(text.substr(std::min<std::size_t>(2, text.size()))))
        fail(cat("radiance basis ", shown(text), " has a degree out of range (PB degrees 0..", kMaxPolynomialDegree,
                 ", SH degrees 0..", kMaxHarmonicDegree, ")"));
    fail(cat("unknown radiance basis ", shown(text), " in comment radiance_basis (supported: PB0..PB",
             kMaxPolynomialDegree, ", SH0..SH", kMaxHarmonicDegree, ")"));
}

// Version first, so that a newer file gets the "newer version" message whatever else it contains.
// Returns whether the file declares the format (radiance_format_version).
bool checkFormatVersion(const PlyHeader& header) {
    bool ourFormat = false;
    for (const auto& c : header.comments) {
        if (c.tokens.size() < 2 || c.tokens[1] != "radiance_format_version") continue;
        if (ourFormat) fail("comment radiance_format_version appears twice");
        const auto version = c.tokens.size() == 3 ? parseUnsigned(c.tokens[2]) : std::nullopt;
        if (!version || *version == 0) fail(cat("header line ", c.lineNumber, ": malformed radiance_format_version comment"));
        if (*version > static_cast<std::uint64_t>(kRadiancePlyFormatVersion))
            fail(cat("the file was written by a newer version of the radiance PLY format (version ", c.tokens[2],
                     "); this reader supports version ", kRadiancePlyFormatVersion, ": update the plugin"));
        ourFormat = true;
    }
    return ourFormat;
}

// The radiance_* comments (basis, reflected, channels, colour space, frame), each at most once and
// only with the format version.
void parseRadianceKeys(const PlyHeader& header, RadianceHeader& r) {
    std::unordered_set<std::string> seen;
    std::string firstRadianceKey;
    for (const auto& c : header.comments) {
        if (c.tokens.size() < 2) continue;
        const std::string& key = c.tokens[1];
        const bool known = key == "radiance_basis" || key == "radiance_reflected" || key == "radiance_channels" ||
                           key == "radiance_color_space" || key == "radiance_frame";
        if (!known) continue;  // unknown comments (including block ones, handled below) are ignored here
        if (!seen.insert(key).second) fail(cat("comment ", key, " appears twice"));
        if (firstRadianceKey.empty()) firstRadianceKey = key;
        if (c.tokens.size() != 3) fail(cat("header line ", c.lineNumber, ": malformed ", key, " comment"));
        const std::string& value = c.tokens[2];
        if (key == "radiance_basis") {
            r.basis = parseBasisOrFail(value);
        } else if (key == "radiance_reflected") {
            if (value != "0" && value != "1") fail(cat("comment radiance_reflected must be 0 or 1, not ", shown(value)));
            r.reflected = value == "1";
        } else if (key == "radiance_channels") {
            if (value != "rgb") fail(cat("unsupported radiance_channels ", shown(value), " (only rgb)"));
        } else if (key == "radiance_color_space") {
            if (value != "linear") fail(cat("unsupported radiance_color_space ", shown(value), " (only linear)"));
        } else if (key == "radiance_frame") {
            if (value != "tangent_normal") fail(cat("unsupported radiance_frame ", shown(value), " (only tangent_normal)"));
        }
    }
    if (!firstRadianceKey.empty() && !r.ourFormat)
        fail(cat("comment ", firstRadianceKey, " without comment radiance_format_version; add the line "
                 "'comment radiance_format_version 1' to the header"));
    if (r.basis && !seen.count("radiance_reflected"))
        fail("comment radiance_basis without comment radiance_reflected; add 'comment radiance_reflected 0' "
             "(or 1 when the coefficients encode the reflected function)");
    if (!r.basis && !seen.empty())
        fail(cat("comment ", firstRadianceKey, " without comment radiance_basis"));
}

// The "comment block <prefix> width <n>" declarations.
void parseBlockDeclarations(const PlyHeader& header, RadianceHeader& r) {
    for (const auto& c : header.comments) {
        if (c.tokens.size() < 2 || c.tokens[1] != "block") continue;
        const auto& t = c.tokens;
        if (t.size() != 5 || t[3] != "width")
            fail(cat("header line ", c.lineNumber, ": malformed block comment (expected 'comment block <prefix> width <n>')"));
        if (!isIdentifier(t[2]) || isReservedPrefix(t[2]))
            fail(cat("header line ", c.lineNumber, ": invalid block prefix ", shown(t[2])));
        const auto width = parseUnsigned(t[4]);
        if (!width || *width == 0 || *width > static_cast<std::uint64_t>(kMaxBlockWidth))
            fail(cat("header line ", c.lineNumber, ": block ", shown(t[2]), " has an invalid width ", shown(t[4]),
                     " (1..", kMaxBlockWidth, ")"));
        for (const auto& b : r.blocks)
            if (b.prefix == t[2]) fail(cat("block ", shown(t[2]), " declared twice"));
        r.blocks.push_back({t[2], static_cast<int>(*width), {}});
    }
}

// The "comment block_meta <prefix> <key> <value>" lines of the declared blocks.
void parseBlockMetadata(const PlyHeader& header, RadianceHeader& r) {
    for (const auto& c : header.comments) {
        if (c.tokens.size() < 2 || c.tokens[1] != "block_meta") continue;
        std::size_t pos = 0;
        nextPlyToken(c.line, pos);  // comment
        nextPlyToken(c.line, pos);  // block_meta
        const std::string prefix = nextPlyToken(c.line, pos);
        const std::string key = nextPlyToken(c.line, pos);
        if (key.empty())
            fail(cat("header line ", c.lineNumber, ": malformed block_meta comment (expected 'comment block_meta <prefix> <key> <value>')"));
        // The value is everything after the one blank that follows the key.
        const std::string value = pos < c.line.size() ? c.line.substr(pos + 1) : std::string();
        auto block = std::find_if(r.blocks.begin(), r.blocks.end(), [&](const BlockDeclaration& b) { return b.prefix == prefix; });
        if (block == r.blocks.end())
            fail(cat("header line ", c.lineNumber, ": block_meta for undeclared block ", shown(prefix),
                     " (add 'comment block ", isIdentifier(prefix) ? prefix : std::string("<prefix>"), " width <n>')"));
        // The writer refuses these, so accepting them would load a file that cannot be saved again.
        if (!isMetadataKey(key))
            fail(cat("header line ", c.lineNumber, ": block_meta key ", shown(key), " of block ", shown(prefix),
                     " contains a control character; metadata keys are visible characters without blanks: "
                     "rename the key in that header line"));
        if (!isMetadataValue(value))
            fail(cat("header line ", c.lineNumber, ": the value of block_meta ", shown(key), " of block ", shown(prefix),
                     " contains a control character (", shown(value), "); metadata values are one line of "
                     "printable text: replace the control characters (tabs, line breaks...) in that header line by spaces"));
        if (!block->metadata.emplace(key, value).second)
            fail(cat("block_meta ", shown(key), " of block ", shown(prefix), " appears twice"));
    }
}

RadianceHeader parseRadianceComments(const PlyHeader& header) {
    RadianceHeader r;
    r.ourFormat = checkFormatVersion(header);
    parseRadianceKeys(header, r);
    if (!r.ourFormat) return r;  // "block" comments of foreign files are just comments
    parseBlockDeclarations(header, r);
    parseBlockMetadata(header, r);
    return r;
}

// ---------------------------------------------------------------------------------------------------
// Copying between file records and per-vertex arrays

// One contiguous run of bytes per vertex: record[recordOffset, +bytes) <-> array[v * arrayStride, +bytes).
template <typename Byte>
struct CopyRun {
    std::size_t recordOffset;
    Byte* array;
    std::size_t arrayStride;
    std::size_t bytes;
};

// Sorts by record offset and merges runs adjacent both in the record and in the same array
// (e.g. x y z, or the 3K coefficients written in order), so the per-vertex loop is a few memcpy.
template <typename Byte>
std::vector<CopyRun<Byte>> mergeRuns(std::vector<CopyRun<Byte>> runs) {
    std::sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.recordOffset < b.recordOffset; });
    std::vector<CopyRun<Byte>> merged;
    for (const auto& r : runs) {
        if (!merged.empty()) {
            auto& last = merged.back();
            if (last.recordOffset + last.bytes == r.recordOffset && last.arrayStride == r.arrayStride &&
                last.array + last.bytes == r.array) {
                last.bytes += r.bytes;
                continue;
            }
        }
        merged.push_back(r);
    }
    return merged;
}

// Vertex properties understood by the reader, by name.
enum class Slot : std::uint8_t { Position, Normal, Color, Quality, Tangent, Coefficient, Block };
struct SlotRef {
    Slot slot;
    int index;  // component / coefficient index (c * K + k) / property index within the block
    int block = 0;
};

const char* kChannelNames[kColorChannels] = {"r", "g", "b"};

std::string coefficientName(int c, int k) { return cat("rf_", kChannelNames[c], "_", k); }

// Whether name is "<prefix>_<digits>" for one of the declared blocks (a misnumbered block property).
const BlockDeclaration* looksLikeBlockProperty(const std::string& name, const std::vector<BlockDeclaration>& blocks) {
    const std::size_t us = name.rfind('_');
    if (us == std::string::npos || !allDigits(name.substr(us + 1))) return nullptr;
    const std::string prefix = name.substr(0, us);
    for (const auto& b : blocks)
        if (b.prefix == prefix) return &b;
    return nullptr;
}

std::string nonFinite(const char* what, std::size_t v) {
    return cat("vertex ", v, " has a ", what, " that is not a finite number (NaN or infinity); fix or remove "
               "that vertex before saving");
}

// Which file offsets hold what, for the vertex element.
struct VertexLayout {
    std::size_t recordBytes = 0;
    long position[3] = {-1, -1, -1};
    long normal[3] = {-1, -1, -1};
    long color[4] = {-1, -1, -1, -1};
    long quality = -1;
    long tangent[3] = {-1, -1, -1};
    std::vector<long> coefficients;            // c * K + k
    std::vector<std::vector<long>> blocks;     // per declared block, per index
    std::vector<std::string> unknown;          // names of the skipped properties
};

// The vertex properties the format knows for this header, by name.
std::unordered_map<std::string, SlotRef> expectedVertexProperties(const RadianceHeader& rh) {
    const int K = rh.basis ? rh.basis->coefficientCount() : 0;
    std::unordered_map<std::string, SlotRef> expected;
    expected.emplace("x", SlotRef{Slot::Position, 0});
    expected.emplace("y", SlotRef{Slot::Position, 1});
    expected.emplace("z", SlotRef{Slot::Position, 2});
    expected.emplace("nx", SlotRef{Slot::Normal, 0});
    expected.emplace("ny", SlotRef{Slot::Normal, 1});
    expected.emplace("nz", SlotRef{Slot::Normal, 2});
    expected.emplace("red", SlotRef{Slot::Color, 0});
    expected.emplace("green", SlotRef{Slot::Color, 1});
    expected.emplace("blue", SlotRef{Slot::Color, 2});
    expected.emplace("alpha", SlotRef{Slot::Color, 3});
    expected.emplace("quality", SlotRef{Slot::Quality, 0});
    if (rh.basis) {
        expected.emplace("rf_tx", SlotRef{Slot::Tangent, 0});
        expected.emplace("rf_ty", SlotRef{Slot::Tangent, 1});
        expected.emplace("rf_tz", SlotRef{Slot::Tangent, 2});
        for (int c = 0; c < kColorChannels; ++c)
            for (int k = 0; k < K; ++k) expected.emplace(coefficientName(c, k), SlotRef{Slot::Coefficient, c * K + k});
    }
    for (std::size_t b = 0; b < rh.blocks.size(); ++b)
        for (int i = 0; i < rh.blocks[b].width; ++i)
            expected.emplace(cat(rh.blocks[b].prefix, "_", i), SlotRef{Slot::Block, i, static_cast<int>(b)});
    return expected;
}

// A property the format does not know: refused when it looks like radiance or block data that does
// not fit the header, otherwise listed in layout.unknown.
void noteUnknownProperty(const PlyProperty& p, const RadianceHeader& rh, VertexLayout& layout) {
    if (p.name.rfind("rf_", 0) == 0) {
        if (!rh.basis)
            fail(cat("vertex property ", shown(p.name), " looks like radiance data but the header has no "
                     "radiance_basis comment; the comments were probably removed by another tool: add "
                     "'comment radiance_format_version 1', 'comment radiance_basis <basis>' and "
                     "'comment radiance_reflected 0|1'"));
        const int K = rh.basis->coefficientCount();
        fail(cat("vertex property ", shown(p.name), " does not belong to basis ", rh.basis->name(),
                 " (expected rf_tx rf_ty rf_tz and rf_r_0..rf_r_", K - 1, ", rf_g_0..rf_g_", K - 1,
                 ", rf_b_0..rf_b_", K - 1, "); the radiance_basis comment does not match the properties"));
    }
    if (const BlockDeclaration* b = looksLikeBlockProperty(p.name, rh.blocks))
        fail(cat("vertex property ", shown(p.name), " does not belong to block ", shown(b->prefix),
                 " of width ", b->width, " (expected ", b->prefix, "_0..", b->prefix, "_", b->width - 1, ")"));
    layout.unknown.push_back(p.name);  // skipped, and reported (it is data a save would not write)
}

void placeVertexProperty(const PlyProperty& p, const SlotRef& ref, VertexLayout& layout) {
    const PlyType want = ref.slot == Slot::Color ? PlyType::UInt8 : PlyType::Float32;
    if (p.type != want)
        fail(cat("vertex property ", shown(p.name), " is ", plyTypeName(p.type), " but must be ", plyTypeName(want)));
    const long offset = static_cast<long>(p.offset);
    switch (ref.slot) {
        case Slot::Position: layout.position[ref.index] = offset; break;
        case Slot::Normal: layout.normal[ref.index] = offset; break;
        case Slot::Color: layout.color[ref.index] = offset; break;
        case Slot::Quality: layout.quality = offset; break;
        case Slot::Tangent: layout.tangent[ref.index] = offset; break;
        case Slot::Coefficient: layout.coefficients[static_cast<std::size_t>(ref.index)] = offset; break;
        case Slot::Block:
            layout.blocks[static_cast<std::size_t>(ref.block)][static_cast<std::size_t>(ref.index)] = offset;
            break;
    }
}

// Every property the header's data needs is there: positions always, all of a group or none of it
// (normals, colours), and with radiance the normals, tangents and coefficients; every block complete.
void checkVertexPropertiesComplete(const VertexLayout& layout, const RadianceHeader& rh) {
    static const char* xyz[3] = {"x", "y", "z"};
    static const char* nxyz[3] = {"nx", "ny", "nz"};
    static const char* rgba[4] = {"red", "green", "blue", "alpha"};
    static const char* txyz[3] = {"rf_tx", "rf_ty", "rf_tz"};
    for (int i = 0; i < 3; ++i)
        if (layout.position[i] < 0)
            fail(cat("missing vertex property '", xyz[i], "'; every vertex needs float x, y, z"));
    const int normals = (layout.normal[0] >= 0) + (layout.normal[1] >= 0) + (layout.normal[2] >= 0);
    if (normals != 0 && normals != 3)
        for (int i = 0; i < 3; ++i)
            if (layout.normal[i] < 0) fail(cat("missing vertex property '", nxyz[i], "'; normals need nx, ny and nz"));
    const int colors = (layout.color[0] >= 0) + (layout.color[1] >= 0) + (layout.color[2] >= 0);
    if ((colors != 0 && colors != 3) || (colors == 0 && layout.color[3] >= 0))
        for (int i = 0; i < 3; ++i)
            if (layout.color[i] < 0)
                fail(cat("missing vertex property '", rgba[i], "'; colors need red, green, blue (and optionally alpha)"));
    if (rh.basis) {
        const int K = rh.basis->coefficientCount();
        if (normals == 0)
            fail("missing vertex property 'nx': radiance data needs the per-vertex normals (the frame normal nx ny nz)");
        for (int i = 0; i < 3; ++i)
            if (layout.tangent[i] < 0) fail(cat("missing radiance frame tangent property '", txyz[i], "'"));
        for (int c = 0; c < kColorChannels; ++c)
            for (int k = 0; k < K; ++k)
                if (layout.coefficients[static_cast<std::size_t>(c * K + k)] < 0)
                    fail(cat("missing radiance coefficient property '", coefficientName(c, k), "' (basis ", rh.basis->name(),
                             " needs rf_r_0..rf_r_", K - 1, ", rf_g_0..rf_g_", K - 1, ", rf_b_0..rf_b_", K - 1, ")"));
    }
    for (std::size_t b = 0; b < rh.blocks.size(); ++b)
        for (int i = 0; i < rh.blocks[b].width; ++i)
            if (layout.blocks[b][static_cast<std::size_t>(i)] < 0)
                fail(cat("missing vertex property '", rh.blocks[b].prefix, "_", i, "' of block ", shown(rh.blocks[b].prefix),
                         " (width ", rh.blocks[b].width, ")"));
}

VertexLayout planVertices(const PlyElement& vertex, const RadianceHeader& rh) {
    VertexLayout layout;
    layout.recordBytes = vertex.scalarBytes;
    std::uint64_t blockTotal = 0;
    for (const auto& b : rh.blocks) blockTotal += static_cast<std::uint64_t>(b.width);
    if (blockTotal > vertex.properties.size())
        fail(cat("the block comments declare ", blockTotal, " vertex properties but the vertex element has only ",
                 vertex.properties.size(), " properties; block properties are missing"));

    const std::unordered_map<std::string, SlotRef> expected = expectedVertexProperties(rh);
    if (rh.basis) layout.coefficients.assign(static_cast<std::size_t>(kColorChannels * rh.basis->coefficientCount()), -1);
    layout.blocks.resize(rh.blocks.size());
    for (std::size_t b = 0; b < rh.blocks.size(); ++b) layout.blocks[b].assign(static_cast<std::size_t>(rh.blocks[b].width), -1);

    for (const auto& p : vertex.properties) {
        if (p.isList)
            fail(cat("vertex property ", shown(p.name), " is a list: variable-size vertex records are not supported; "
                     "remove that property (or re-save the mesh from MeshLab)"));
        const auto it = expected.find(p.name);
        if (it == expected.end()) noteUnknownProperty(p, rh, layout);
        else placeVertexProperty(p, it->second, layout);
    }
    checkVertexPropertiesComplete(layout, rh);
    return layout;
}

struct FaceLayout {
    std::size_t indexProperty = 0;
    std::uint64_t minRecordBytes = 0;
};

FaceLayout planFaces(const PlyElement& face) {
    FaceLayout layout;
    const PlyProperty* indices = face.find("vertex_indices");
    if (!indices) indices = face.find("vertex_index");
    if (!indices || !indices->isList)
        fail("the face element has no 'vertex_indices' list property");
    if (indices->type != PlyType::Int32 && indices->type != PlyType::UInt32)
        fail(cat("face property ", shown(indices->name), " has items of type ", plyTypeName(indices->type),
                 " but they must be int or uint"));
    layout.indexProperty = static_cast<std::size_t>(indices - face.properties.data());
    layout.minRecordBytes = minimumPlyRecordBytes(face, static_cast<int>(layout.indexProperty));
    return layout;
}

std::string trailing(std::uint64_t bytes) {
    return cat(bytes, bytes == 1 ? " byte" : " bytes", " of unexpected data after the last element: the header does not "
               "describe the data (wrong element count or property type?); this reader refuses trailing data");
}

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f) std::fclose(f);
    }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

bool seekTo(std::FILE* f, std::uint64_t offset) {
#ifdef _WIN32
    return _fseeki64(f, static_cast<__int64>(offset), SEEK_SET) == 0;
#else
    return fseeko(f, static_cast<off_t>(offset), SEEK_SET) == 0;
#endif
}

// The open file and its size, read chunk by chunk through one reused buffer.
struct ChunkedFile {
    FilePtr file;
    std::uint64_t size = 0;
    std::vector<unsigned char> buffer;

    // bytes bytes at offset, valid until the next call.
    const unsigned char* readAt(std::uint64_t offset, std::size_t bytes) {
        if (!seekTo(file.get(), offset)) fail("cannot seek in the file");
        buffer.resize(std::max<std::size_t>(bytes, 1));
        if (bytes && std::fread(buffer.data(), 1, bytes, file.get()) != bytes)
            fail("read error (the file changed while it was read, or the disk failed)");
        return buffer.data();
    }
    void releaseBuffer() {
        buffer.clear();
        buffer.shrink_to_fit();
    }
};

ChunkedFile openForReading(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail("it is a folder, not a file");
    ChunkedFile in;
    in.file.reset(std::fopen(path.c_str(), "rb"));
    if (!in.file) fail(cat("cannot open the file: ", std::strerror(errno)));
    const std::uintmax_t fileSizeRaw = std::filesystem::file_size(path, ec);
    if (ec) fail(cat("cannot get the file size: ", ec.message()));
    in.size = static_cast<std::uint64_t>(fileSizeRaw);
    return in;
}

PlyHeader readHeader(ChunkedFile& in) {
    const std::size_t headBytes = static_cast<std::size_t>(std::min<std::uint64_t>(in.size, kMaxHeaderBytes));
    std::string head(headBytes, '\0');
    if (headBytes && std::fread(head.data(), 1, headBytes, in.file.get()) != headBytes)
        fail("read error in the header (the file changed or the disk failed)");
    return parseHeader(head.data(), head.size(), headBytes == in.size);
}

// The elements the reader decodes and how, checked before any data is read.
struct ReadPlan {
    const PlyElement* vertex = nullptr;
    const PlyElement* face = nullptr;  // none when the file has no face element
    VertexLayout vertexLayout;
    FaceLayout faceLayout;
};

ReadPlan planElements(const PlyHeader& header, const RadianceHeader& rh) {
    ReadPlan plan;
    plan.vertex = header.find("vertex");
    if (!plan.vertex) fail("the PLY file has no vertex element");
    plan.face = header.find("face");
    if (plan.vertex->count > kMaxElementCount)
        fail(cat("the header declares ", plan.vertex->count, " vertices, more than this format supports (",
                 kMaxElementCount, "); the header is probably damaged"));
    if (plan.face && plan.face->count > kMaxElementCount)
        fail(cat("the header declares ", plan.face->count, " faces, more than this format supports (",
                 kMaxElementCount, "); the header is probably damaged"));
    plan.vertexLayout = planVertices(*plan.vertex, rh);
    if (plan.face) plan.faceLayout = planFaces(*plan.face);
    // Refused even when empty: the rule is the same for every count (the specification says so), and
    // an empty one is still a declaration that a save would drop.
    for (const auto& e : header.elements)
        if (&e != plan.vertex && &e != plan.face && e.hasList)
            fail(cat("element ", shown(e.name), " has list properties (variable-size records) and is not a face element; "
                     "this reader cannot skip such elements safely, even empty ones: remove the element and its "
                     "property lines from the header (e.g. re-save the mesh from MeshLab)"));
    return plan;
}

// Where the data lies, from the sizes the header declares.
struct DataExtent {
    std::uint64_t dataBytes = 0;   // bytes after the header
    std::uint64_t needed = 0;      // bytes the elements need at least
    std::uint64_t faceOffset = 0;  // file offset of the face element when faceSizeKnown
    bool faceSizeKnown = false;
};

// Sizes against the file size, before allocating anything. Face records have a known size when the
// only list is vertex_indices (and every face is a triangle, which the decoder checks).
DataExtent checkSizesAgainstFile(const PlyHeader& header, const ReadPlan& plan, std::uint64_t fileSize) {
    const PlyElement* faceElement = plan.face;
    DataExtent extent;
    extent.dataBytes = fileSize - header.dataOffset;
    extent.faceSizeKnown = !faceElement || faceElement->properties.size() == 1 ||
                           std::count_if(faceElement->properties.begin(), faceElement->properties.end(),
                                         [](const PlyProperty& p) { return p.isList; }) == 1;
    const std::uint64_t dataBytes = extent.dataBytes;
    std::uint64_t& needed = extent.needed;
    for (const auto& e : header.elements) {
        const std::uint64_t record = &e == faceElement ? plan.faceLayout.minRecordBytes : e.scalarBytes;
        const std::uint64_t bytes = mulSat(e.count, record);
        if (addSat(needed, bytes) > dataBytes) {
            const std::uint64_t found = dataBytes - std::min(needed, dataBytes);
            // The figures, so that a user can tell a cut file from a damaged count.
            const auto refuse = [&](const char* data, const char* records, const char* countName) {
                const bool atLeast = &e == faceElement && !extent.faceSizeKnown;
                fail(cat("file truncated: expected ", atLeast ? "at least " : "", bytes, " bytes of ", data, ", found ",
                         found, ": the header declares ", e.count, " ", records, " of ", atLeast ? "at least " : "",
                         record, " bytes each; the file was probably not completely written, or its header declares a "
                         "wrong ", countName));
            };
            if (&e == plan.vertex) refuse("vertex data", "vertices", "vertex count");
            if (&e == faceElement) refuse("face data", "faces", "face count");
            refuse(("data for element " + shown(e.name)).c_str(), "records", "element count");
        }
        if (&e == faceElement) extent.faceOffset = header.dataOffset + needed;
        needed += bytes;
    }
    // With triangles only, the data size is exact; a quad mesh is larger, so leave the trailing-data
    // verdict to the face decoder then (it says "triangulate").
    if (extent.faceSizeKnown && dataBytes > needed && (!faceElement || faceElement->count == 0))
        fail(trailing(dataBytes - needed));
    return extent;
}

// What the file holds that the mesh does not keep, in mesh.skippedOnRead.
void listSkippedData(const PlyHeader& header, const ReadPlan& plan, RadianceMesh& mesh) {
    const std::vector<std::string>& unknown = plan.vertexLayout.unknown;
    if (!unknown.empty() && plan.vertex->count > 0) {
        std::string names;
        for (const auto& u : unknown) names += (names.empty() ? "" : ", ") + shown(u);
        const bool one = unknown.size() == 1;
        mesh.skippedOnRead.push_back(cat("vertex ", one ? "property " : "properties ", names, " of the file ",
                                         one ? "is" : "are", " not part of the radiance PLY format and ",
                                         one ? "was" : "were", " not loaded (saving the mesh will not write ",
                                         one ? "it" : "them",
                                         "; to keep such data, declare it as a block: 'comment block <prefix> width <n>' "
                                         "with properties <prefix>_0..<prefix>_<n-1>)"));
    }
    for (const auto& e : header.elements) {
        if (&e == plan.vertex || e.count == 0) continue;
        if (&e == plan.face) {
            std::string names;
            for (std::size_t i = 0; i < e.properties.size(); ++i)
                if (i != plan.faceLayout.indexProperty) names += (names.empty() ? "" : ", ") + shown(e.properties[i].name);
            if (!names.empty())
                mesh.skippedOnRead.push_back(cat("face properties ", names, " were not loaded (the radiance PLY format "
                                                 "stores only the vertex indices of a face)"));
            continue;
        }
        mesh.skippedOnRead.push_back(cat("element ", shown(e.name), " (", e.count, " records) is not part of the radiance "
                                         "PLY format and was not loaded (saving the mesh will not write it)"));
    }
}

// Decodes face records into triangles, checking each one.
struct FaceDecoder {
    const PlyElement& element;
    const FaceLayout& layout;
    std::size_t vertexCount;
    std::vector<std::uint32_t>& faces;
    bool signedIndex;  // int indices (uint otherwise)

    FaceDecoder(const ReadPlan& plan, std::vector<std::uint32_t>& faces)
        : element(*plan.face), layout(plan.faceLayout), vertexCount(static_cast<std::size_t>(plan.vertex->count)),
          faces(faces), signedIndex(element.properties[layout.indexProperty].type == PlyType::Int32) {}

    [[noreturn]] void truncatedFace(std::size_t f) const {
        fail(cat("file truncated: the face data ends inside face ", f, " of ", static_cast<std::size_t>(element.count),
                 "; the file was probably not completely written"));
    }

    // The vertex_indices list of face f after its length: 3 indices of 4 bytes.
    const unsigned char* decodeTriangle(std::size_t f, std::int64_t count, const unsigned char* cursor,
                                        const unsigned char* end) const {
        if (count != 3)
            fail(cat("face ", f, " has ", count, " vertices but only triangle meshes are supported: "
                     "triangulate the mesh first (e.g. {{Turn into a Pure-Triangular mesh}}) and save it again"));
        if (static_cast<std::size_t>(end - cursor) < 12) truncatedFace(f);
        for (std::size_t k = 0; k < 3; ++k) {
            std::uint32_t raw;
            std::memcpy(&raw, cursor + 4 * k, 4);
            if (signedIndex && raw > 0x7fffffffu)
                fail(cat("face ", f, " has a negative vertex index ", static_cast<std::int32_t>(raw)));
            if (raw >= vertexCount)
                fail(cat("face ", f, " references vertex ", raw, " but the file has only ", vertexCount,
                         " vertices: vertex index out of range"));
            faces.push_back(raw);
        }
        return cursor + 12;
    }

    // Records [f0, f1) from cursor; returns the end of the last one.
    const unsigned char* decode(const unsigned char* cursor, const unsigned char* end, std::size_t f0,
                                std::size_t f1) const {
        for (std::size_t f = f0; f < f1; ++f) {
            for (std::size_t pi = 0; pi < element.properties.size(); ++pi) {
                const PlyProperty& p = element.properties[pi];
                if (!p.isList) {
                    const std::size_t s = plyTypeSize(p.type);
                    if (static_cast<std::size_t>(end - cursor) < s) truncatedFace(f);
                    cursor += s;
                    continue;
                }
                const std::size_t cs = plyTypeSize(p.countType);
                if (static_cast<std::size_t>(end - cursor) < cs) truncatedFace(f);
                const std::int64_t count = readPlyInteger(cursor, p.countType, false);
                cursor += cs;
                if (pi == layout.indexProperty) {
                    cursor = decodeTriangle(f, count, cursor, end);
                    continue;
                }
                if (count < 0) fail(cat("face ", f, " has a negative length in list property ", shown(p.name)));
                const std::uint64_t listBytes = static_cast<std::uint64_t>(count) * plyTypeSize(p.type);
                if (static_cast<std::uint64_t>(end - cursor) < listBytes) truncatedFace(f);
                cursor += listBytes;
            }
        }
        return cursor;
    }
};

// Data is decoded in chunks of about this size through one reused buffer, and every chunk is checked
// as soon as it is decoded: a damaged or hostile file (e.g. a sparse file of zeros with a plausible
// header) is refused after one chunk instead of after allocating and filling the whole mesh. The
// output arrays are only reserved up front (address space, not memory) and grow chunk by chunk.
constexpr std::size_t kChunkBytes = std::size_t(8) << 20;

// Faces first when their size is known: they are small, and a damaged face block is then refused
// before the (usually much larger) vertex data is read and allocated. Returns whether it read them.
bool readTriangleFacesFirst(ChunkedFile& in, const ReadPlan& plan, const DataExtent& extent, RadianceMesh& mesh) {
    if (!plan.face || !extent.faceSizeKnown) return false;
    const FaceDecoder decoder(plan, mesh.faces);
    const std::size_t faceCount = static_cast<std::size_t>(plan.face->count);
    const std::size_t rec = static_cast<std::size_t>(plan.faceLayout.minRecordBytes);
    mesh.faces.reserve(faceCount * 3);
    const std::size_t perChunk = std::max<std::size_t>(1, kChunkBytes / rec);
    for (std::size_t f0 = 0; f0 < faceCount; f0 += perChunk) {
        const std::size_t f1 = std::min(faceCount, f0 + perChunk);
        const unsigned char* data = in.readAt(extent.faceOffset + std::uint64_t(f0) * rec, (f1 - f0) * rec);
        decoder.decode(data, data + (f1 - f0) * rec, f0, f1);
    }
    // Every face was a triangle of exactly `rec` bytes, so the sizes are exact now.
    if (extent.dataBytes > extent.needed) fail(trailing(extent.dataBytes - extent.needed));
    return true;
}

// Faces with lists other than vertex_indices: records of unknown size, read in one block (everything
// left, which the file size bounds). Returns the bytes they took.
std::uint64_t readFacesOfUnknownSize(ChunkedFile& in, std::uint64_t position, const ReadPlan& plan, RadianceMesh& mesh) {
    const FaceDecoder decoder(plan, mesh.faces);
    const std::size_t faceCount = static_cast<std::size_t>(plan.face->count);
    const std::size_t bytes = static_cast<std::size_t>(position > in.size ? 0 : in.size - position);
    const unsigned char* data = in.readAt(position, bytes);
    mesh.faces.reserve(faceCount * 3);
    const unsigned char* used = decoder.decode(data, data + bytes, 0, faceCount);
    const std::uint64_t taken = static_cast<std::uint64_t>(used - data);
    in.releaseBuffer();
    return taken;
}

// Reserves every per-vertex array of the mesh (and creates its radiance field and blocks); returns
// the coefficients per vertex.
std::size_t reserveVertexArrays(const VertexLayout& layout, const RadianceHeader& rh, std::size_t n, RadianceMesh& mesh) {
    mesh.positions.reserve(n * 3);
    if (layout.normal[0] >= 0) mesh.normals.reserve(n * 3);
    if (layout.color[0] >= 0) mesh.colors.reserve(n * 4);
    if (layout.quality >= 0) mesh.quality.reserve(n);
    std::size_t perVertex = 0;
    if (rh.basis) {
        mesh.radiance.emplace();
        mesh.radiance->basis = *rh.basis;
        mesh.radiance->reflected = rh.reflected;
        perVertex = static_cast<std::size_t>(mesh.radiance->coefficientsPerVertex());
        mesh.radiance->frames.reserve(n * 6);
        mesh.radiance->coefficients.reserve(n * perVertex);
    }
    for (const auto& b : rh.blocks) {
        NamedVertexBlock block;
        block.prefix = b.prefix;
        block.width = b.width;
        block.metadata = b.metadata;
        block.values.reserve(n * static_cast<std::size_t>(b.width));
        mesh.extraBlocks.push_back(std::move(block));
    }
    return perVertex;
}

// Grows every per-vertex array to v1 vertices (within what was reserved).
void growVertexArrays(const VertexLayout& layout, std::size_t v1, std::size_t perVertex, RadianceMesh& mesh) {
    mesh.positions.resize(v1 * 3);
    if (layout.normal[0] >= 0) mesh.normals.resize(v1 * 3);
    if (layout.color[0] >= 0) mesh.colors.resize(v1 * 4, 255);  // alpha stays 255 when the file has none
    if (layout.quality >= 0) mesh.quality.resize(v1);
    if (mesh.radiance) {
        mesh.radiance->frames.resize(v1 * 6);
        mesh.radiance->coefficients.resize(v1 * perVertex);
    }
    for (auto& block : mesh.extraBlocks) block.values.resize(v1 * static_cast<std::size_t>(block.width));
}

// Record bytes to array bytes, merged into a few memcpy per vertex. The arrays must not move while
// the plan is used.
std::vector<CopyRun<unsigned char>> vertexCopyPlan(const VertexLayout& layout, std::size_t perVertex, RadianceMesh& mesh) {
    using Run = CopyRun<unsigned char>;
    std::vector<Run> runs;
    auto add = [&](long offset, void* array, std::size_t stride, std::size_t size) {
        runs.push_back({static_cast<std::size_t>(offset), static_cast<unsigned char*>(array), stride, size});
    };
    for (int i = 0; i < 3; ++i) add(layout.position[i], mesh.positions.data() + i, 12, 4);
    if (layout.normal[0] >= 0)
        for (int i = 0; i < 3; ++i) add(layout.normal[i], mesh.normals.data() + i, 12, 4);
    for (int i = 0; i < 4; ++i)
        if (layout.color[i] >= 0) add(layout.color[i], mesh.colors.data() + i, 4, 1);
    if (layout.quality >= 0) add(layout.quality, mesh.quality.data(), 4, 4);
    if (mesh.radiance) {
        RadianceField& rf = *mesh.radiance;
        for (int i = 0; i < 3; ++i) add(layout.tangent[i], rf.frames.data() + i, 24, 4);
        for (std::size_t j = 0; j < perVertex; ++j)
            add(layout.coefficients[j], rf.coefficients.data() + j, perVertex * 4, 4);
    }
    for (std::size_t b = 0; b < mesh.extraBlocks.size(); ++b) {
        auto& block = mesh.extraBlocks[b];
        const std::size_t w = static_cast<std::size_t>(block.width);
        for (std::size_t i = 0; i < w; ++i) add(layout.blocks[b][i], block.values.data() + i, w * 4, 4);
    }
    return mergeRuns(std::move(runs));
}

// Copies the frame normals of vertices [v0, v1) from the normals and checks the chunk, in the order
// positions, normals, tangents, coefficients, unit normals.
void completeAndCheckVertexChunk(std::size_t v0, std::size_t v1, std::size_t perVertex, RadianceMesh& mesh) {
    for (std::size_t i = v0 * 3; i < v1 * 3; ++i)
        if (!std::isfinite(mesh.positions[i])) fail(nonFinite("position", i / 3));
    if (!mesh.normals.empty())
        for (std::size_t i = v0 * 3; i < v1 * 3; ++i)
            if (!std::isfinite(mesh.normals[i])) fail(nonFinite("normal", i / 3));
    if (!mesh.radiance) return;
    RadianceField& rf = *mesh.radiance;
    for (std::size_t v = v0; v < v1; ++v) {
        float* frame = rf.frame(v);
        std::memcpy(frame + 3, mesh.normals.data() + v * 3, 12);
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(frame[i])) fail(nonFinite("radiance frame tangent", v));
    }
    for (std::size_t i = v0 * perVertex; i < v1 * perVertex; ++i)
        if (!std::isfinite(rf.coefficients[i])) fail(nonFinite("radiance coefficient", i / perVertex));
    for (std::size_t v = v0; v < v1; ++v) {
        const float* f = rf.frame(v);
        const float nn = f[3] * f[3] + f[4] * f[4] + f[5] * f[5];
        if (std::fabs(nn - 1.0f) > 1e-3f) {
            std::ostringstream why;  // RadianceField::validate's sentence
            why << "invalid radiance data: normal of vertex " << v << " is not unit length (|n|^2 = " << nn << ")";
            fail(why.str());
        }
    }
}

// The vertex records at file offset start, chunk by chunk.
void readVertexData(ChunkedFile& in, std::uint64_t start, const ReadPlan& plan, const RadianceHeader& rh,
                    RadianceMesh& mesh) {
    const std::size_t n = static_cast<std::size_t>(plan.vertex->count);
    const VertexLayout& layout = plan.vertexLayout;
    const std::size_t rec = layout.recordBytes;
    const std::size_t perVertex = reserveVertexArrays(layout, rh, n, mesh);
    if (n == 0) return;
    const std::size_t perChunk = std::max<std::size_t>(1, kChunkBytes / std::max<std::size_t>(rec, 1));
    for (std::size_t v0 = 0; v0 < n; v0 += perChunk) {
        const std::size_t v1 = std::min(n, v0 + perChunk);
        const unsigned char* records = in.readAt(start + std::uint64_t(v0) * rec, (v1 - v0) * rec);
        growVertexArrays(layout, v1, perVertex, mesh);
        const std::vector<CopyRun<unsigned char>> runs = vertexCopyPlan(layout, perVertex, mesh);
        for (std::size_t v = v0; v < v1; ++v) {
            const unsigned char* record = records + (v - v0) * rec;
            for (const auto& r : runs) std::memcpy(r.array + v * r.arrayStride, record + r.recordOffset, r.bytes);
        }
        completeAndCheckVertexChunk(v0, v1, perVertex, mesh);
    }
}

// Every element in file order: vertices decoded, faces decoded unless already read, the others
// skipped. Returns the file offset after the last element.
std::uint64_t readElements(ChunkedFile& in, const PlyHeader& header, const ReadPlan& plan, const RadianceHeader& rh,
                           bool facesDone, RadianceMesh& mesh) {
    std::uint64_t position = header.dataOffset;  // file offset of the next element
    const auto needBytes = [&](std::uint64_t bytes, const std::string& what) {
        if (position > in.size || in.size - position < bytes)
            fail(cat("file truncated: expected ", bytes, " bytes of ", what, ", found ",
                     position > in.size ? 0 : in.size - position, "; the file was probably not completely written "
                     "(or the header declares a wrong count)"));
    };
    for (const auto& e : header.elements) {
        if (&e == plan.vertex) {
            const std::uint64_t bytes = e.count * plan.vertexLayout.recordBytes;
            needBytes(bytes, "vertex data");
            readVertexData(in, position, plan, rh, mesh);
            position += bytes;
        } else if (&e == plan.face) {
            position += facesDone ? e.count * plan.faceLayout.minRecordBytes : readFacesOfUnknownSize(in, position, plan, mesh);
        } else {
            // Fixed size; checked above only with the smallest face records, so check again here.
            const std::uint64_t bytes = e.count * e.scalarBytes;
            needBytes(bytes, "data for element " + shown(e.name));
            position += bytes;
        }
    }
    return position;
}

RadianceMesh readImpl(const std::string& path) {
    ChunkedFile in = openForReading(path);
    const PlyHeader header = readHeader(in);
    const RadianceHeader rh = parseRadianceComments(header);
    const ReadPlan plan = planElements(header, rh);
    const DataExtent extent = checkSizesAgainstFile(header, plan, in.size);
    RadianceMesh mesh;
    listSkippedData(header, plan, mesh);
    const bool facesDone = readTriangleFacesFirst(in, plan, extent, mesh);
    const std::uint64_t position = readElements(in, header, plan, rh, facesDone, mesh);
    if (position != in.size) fail(trailing(in.size - position));
    in.file.reset();
    if (mesh.radiance) {
        const std::string problem = mesh.radiance->validate();  // a last guard; the chunks were checked
        if (!problem.empty()) fail("invalid radiance data: " + problem);
    }
    return mesh;
}

// ---------------------------------------------------------------------------------------------------
// Writing

bool sameBits(const float* a, const float* b, std::size_t count) { return std::memcmp(a, b, count * sizeof(float)) == 0; }

std::string makeHeader(const RadianceMesh& mesh) {
    std::string h;
    auto line = [&](const std::string& s) { h += s; h += '\n'; };
    line("ply");
    line("format binary_little_endian 1.0");
    line(cat("comment radiance_format_version ", kRadiancePlyFormatVersion));
    if (mesh.radiance) {
        line("comment radiance_basis " + mesh.radiance->basis.name());
        line(cat("comment radiance_reflected ", mesh.radiance->reflected ? 1 : 0));
        line("comment radiance_channels rgb");
        line("comment radiance_color_space linear");
        line("comment radiance_frame tangent_normal");
    }
    for (const auto& b : mesh.extraBlocks) {
        line(cat("comment block ", b.prefix, " width ", b.width));
        for (const auto& kv : b.metadata)
            line("comment block_meta " + b.prefix + " " + kv.first + (kv.second.empty() ? "" : " " + kv.second));
    }
    line(cat("element vertex ", mesh.vertexCount()));
    line("property float x");
    line("property float y");
    line("property float z");
    if (!mesh.normals.empty() || mesh.radiance) {
        line("property float nx");
        line("property float ny");
        line("property float nz");
    }
    if (!mesh.colors.empty()) {
        line("property uchar red");
        line("property uchar green");
        line("property uchar blue");
        line("property uchar alpha");
    }
    if (!mesh.quality.empty()) line("property float quality");
    if (mesh.radiance) {
        line("property float rf_tx");
        line("property float rf_ty");
        line("property float rf_tz");
        const int K = mesh.radiance->coefficientsPerChannel();
        for (int c = 0; c < kColorChannels; ++c)
            for (int k = 0; k < K; ++k) line("property float " + coefficientName(c, k));
    }
    for (const auto& b : mesh.extraBlocks)
        for (int i = 0; i < b.width; ++i) line(cat("property float ", b.prefix, "_", i));
    line(cat("element face ", mesh.faceCount()));
    line("property list uchar int vertex_indices");
    line("end_header");
    return h;
}

}  // namespace

std::string validateRadianceMesh(const RadianceMesh& mesh) {
    if (mesh.positions.size() % 3 != 0) return cat("positions has ", mesh.positions.size(), " floats, not a multiple of 3");
    const std::size_t n = mesh.vertexCount();
    if (n > kMaxWrittenVertexCount) return cat("the mesh has ", n, " vertices; the format supports at most 2^31");
    if (!mesh.normals.empty() && mesh.normals.size() != 3 * n)
        return cat("normals has ", mesh.normals.size(), " floats, expected ", 3 * n, " (3 per vertex) or none");
    if (!mesh.colors.empty() && mesh.colors.size() != 4 * n)
        return cat("colors has ", mesh.colors.size(), " bytes, expected ", 4 * n, " (RGBA per vertex) or none");
    if (!mesh.quality.empty() && mesh.quality.size() != n)
        return cat("quality has ", mesh.quality.size(), " values, expected ", n, " (1 per vertex) or none");
    if (mesh.faces.size() % 3 != 0) return cat("faces has ", mesh.faces.size(), " indices, not a multiple of 3");
    if (mesh.faceCount() > kMaxElementCount) return "too many faces (at most 2^32-1)";
    for (std::size_t i = 0; i < mesh.faces.size(); ++i)
        if (mesh.faces[i] >= n)
            return cat("face ", i / 3, " references vertex ", mesh.faces[i], " but the mesh has ", n, " vertices");
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (!std::isfinite(mesh.positions[i])) return cat("vertex ", i / 3, " has a position that is not a finite number");
    for (std::size_t i = 0; i < mesh.normals.size(); ++i)
        if (!std::isfinite(mesh.normals[i])) return cat("vertex ", i / 3, " has a normal that is not a finite number");
    if (mesh.radiance) {
        const RadianceField& rf = *mesh.radiance;
        const std::string problem = rf.validate();
        if (!problem.empty()) return "invalid radiance field: " + problem;
        if (rf.vertexCount() != n)
            return cat("the radiance field has ", rf.vertexCount(), " vertices but the mesh has ", n);
        if (!mesh.normals.empty())
            for (std::size_t v = 0; v < n; ++v)
                if (!sameBits(mesh.normals.data() + 3 * v, rf.frame(v) + 3, 3))
                    return cat("the normal of vertex ", v, " differs from its radiance frame normal; the file stores one "
                               "normal per vertex (the frame normal): copy the frame normals into the mesh normals or "
                               "leave the mesh normals empty");
    }
    std::unordered_set<std::string> prefixes;
    for (const auto& b : mesh.extraBlocks) {
        if (!isIdentifier(b.prefix))
            return cat("extra block prefix ", shown(b.prefix), " is not an identifier ([A-Za-z_][A-Za-z0-9_]*, at most 64 characters)");
        if (isReservedPrefix(b.prefix)) return cat("extra block prefix ", shown(b.prefix), " is reserved (rf, rf_*)");
        if (!prefixes.insert(b.prefix).second) return cat("two extra blocks have the prefix ", shown(b.prefix));
        if (b.width < 1 || b.width > kMaxBlockWidth)
            return cat("extra block ", shown(b.prefix), " has width ", b.width, " (1..", kMaxBlockWidth, ")");
        if (b.values.size() != n * static_cast<std::size_t>(b.width))
            return cat("extra block ", shown(b.prefix), " has ", b.values.size(), " values, expected ",
                       n * static_cast<std::size_t>(b.width), " (width x vertices)");
        for (const auto& kv : b.metadata) {
            if (!isMetadataKey(kv.first))
                return cat("metadata key ", shown(kv.first), " of block ", shown(b.prefix), " is empty or contains whitespace");
            if (!isMetadataValue(kv.second))
                return cat("metadata value of key ", shown(kv.first), " of block ", shown(b.prefix),
                           " contains a control character (e.g. a line break)");
        }
    }
    return {};
}

void writeRadiancePly(const std::string& path, const RadianceMesh& mesh) {
    const std::string problem = validateRadianceMesh(mesh);
    if (!problem.empty()) throw RadianceFileError("cannot save '" + path + "': " + problem);

    const std::size_t n = mesh.vertexCount();
    const std::string header = makeHeader(mesh);

    // Vertex records.
    std::size_t rec = 12;
    using Run = CopyRun<const unsigned char>;
    std::vector<Run> runs;
    auto add = [&](const void* array, std::size_t stride, std::size_t bytes) {
        runs.push_back({rec, static_cast<const unsigned char*>(array), stride, bytes});
        rec += bytes;
    };
    std::unique_ptr<unsigned char[]> vertexData;
    std::unique_ptr<unsigned char[]> faceData;
    try {
        if (n > 0) {
            rec = 0;
            add(mesh.positions.data(), 12, 12);
            if (mesh.radiance) {
                add(mesh.radiance->frames.data() + 3, 24, 12);
            } else if (!mesh.normals.empty()) {
                add(mesh.normals.data(), 12, 12);
            }
            if (!mesh.colors.empty()) add(mesh.colors.data(), 4, 4);
            if (!mesh.quality.empty()) add(mesh.quality.data(), 4, 4);
            if (mesh.radiance) {
                const RadianceField& rf = *mesh.radiance;
                const std::size_t perVertex = static_cast<std::size_t>(rf.coefficientsPerVertex());
                add(rf.frames.data(), 24, 12);
                add(rf.coefficients.data(), perVertex * 4, perVertex * 4);
            }
            for (const auto& b : mesh.extraBlocks) {
                const std::size_t w = static_cast<std::size_t>(b.width);
                add(b.values.data(), w * 4, w * 4);
            }
            vertexData.reset(new unsigned char[n * rec]);
            for (std::size_t v = 0; v < n; ++v) {
                unsigned char* record = vertexData.get() + v * rec;
                for (const Run& r : runs) std::memcpy(record + r.recordOffset, r.array + v * r.arrayStride, r.bytes);
            }
        }
        const std::size_t faceCount = mesh.faceCount();
        if (faceCount > 0) {
            faceData.reset(new unsigned char[faceCount * 13]);
            for (std::size_t f = 0; f < faceCount; ++f) {
                unsigned char* record = faceData.get() + f * 13;
                record[0] = 3;
                std::memcpy(record + 1, mesh.faces.data() + 3 * f, 12);  // < 2^31: same bytes as int
            }
        }
    } catch (const std::bad_alloc&) {
        throw RadianceFileError("cannot save '" + path + "': not enough memory");
    }

    // Temporary file, then rename.
    try {
        writeFileAtomically(path, {{header.data(), header.size()},
                                   {vertexData.get(), n * rec},
                                   {faceData.get(), mesh.faceCount() * 13}});
    } catch (const AtomicFileError& error) {
        throw RadianceFileError(error.what());
    }
}

RadianceMesh readRadiancePly(const std::string& path) {
    try {
        return readImpl(path);
    } catch (const RadianceFileError& e) {
        throw RadianceFileError("cannot load '" + path + "': " + e.what());
    } catch (const std::bad_alloc&) {
        throw RadianceFileError("cannot load '" + path + "': not enough memory");
    } catch (const std::length_error&) {
        throw RadianceFileError("cannot load '" + path + "': the mesh is too large for this computer");
    } catch (const std::filesystem::filesystem_error& e) {
        throw RadianceFileError("cannot load '" + path + "': " + e.what());
    }
}

}  // namespace rad
