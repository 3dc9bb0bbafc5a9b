#include "io/ply_stream_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>
#include <vector>

#ifndef _WIN32
#include <sys/stat.h>
#endif

namespace rad {

namespace {

enum class PType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<PType> parseType(const std::string& s) {
    static const std::pair<const char*, PType> names[] = {
        {"char", PType::Int8},     {"int8", PType::Int8},       {"uchar", PType::UInt8},   {"uint8", PType::UInt8},
        {"short", PType::Int16},   {"int16", PType::Int16},     {"ushort", PType::UInt16}, {"uint16", PType::UInt16},
        {"int", PType::Int32},     {"int32", PType::Int32},     {"uint", PType::UInt32},   {"uint32", PType::UInt32},
        {"float", PType::Float32}, {"float32", PType::Float32}, {"double", PType::Float64}, {"float64", PType::Float64}};
    for (const auto& n : names)
        if (s == n.first) return n.second;
    return std::nullopt;
}

std::size_t typeSize(PType t) {
    switch (t) {
        case PType::Int8:
        case PType::UInt8: return 1;
        case PType::Int16:
        case PType::UInt16: return 2;
        case PType::Int32:
        case PType::UInt32:
        case PType::Float32: return 4;
        case PType::Float64: return 8;
    }
    return 0;
}

bool isInteger(PType t) { return t != PType::Float32 && t != PType::Float64; }

struct Property {
    std::string name;
    bool isList = false;
    PType type = PType::Float32;
    PType countType = PType::UInt8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
    int find(const std::string& n) const {
        for (std::size_t i = 0; i < properties.size(); ++i)
            if (properties[i].name == n) return int(i);
        return -1;
    }
    bool hasList() const {
        return std::any_of(properties.begin(), properties.end(), [](const Property& p) { return p.isList; });
    }
    // Smallest binary record (lists empty; the face list at least 3 items when `faceList` >= 0).
    std::uint64_t minimumBytes(int faceList) const {
        std::uint64_t bytes = 0;
        for (std::size_t i = 0; i < properties.size(); ++i) {
            const Property& p = properties[i];
            bytes += p.isList ? typeSize(p.countType) + (int(i) == faceList ? 3 * typeSize(p.type) : 0) : typeSize(p.type);
        }
        return bytes;
    }
};

std::string shown(const std::string& s) { return "'" + s.substr(0, 40) + "'"; }

}  // namespace

namespace {

// What tells a file from another one put at the same path, or the same one rewritten: the device and
// inode (POSIX), the size and the modification time (nanoseconds where the system keeps them).
struct FileIdentity {
    unsigned long long device = 0, inode = 0, size = 0;
    long long modifiedSeconds = 0, modifiedNanoseconds = 0;
    bool operator==(const FileIdentity& o) const {
        return device == o.device && inode == o.inode && size == o.size && modifiedSeconds == o.modifiedSeconds &&
               modifiedNanoseconds == o.modifiedNanoseconds;
    }
};

bool identityOf(std::FILE* file, const std::string& path, FileIdentity& out) {
#ifndef _WIN32
    (void)path;
    struct stat st;
    if (fstat(fileno(file), &st) != 0) return false;
    out.device = st.st_dev;
    out.inode = st.st_ino;
    out.size = static_cast<unsigned long long>(st.st_size);
    out.modifiedSeconds = st.st_mtim.tv_sec;
    out.modifiedNanoseconds = st.st_mtim.tv_nsec;
#else
    (void)file;
    std::error_code ec;
    out.size = std::filesystem::file_size(path, ec);
    out.modifiedSeconds = std::filesystem::last_write_time(path, ec).time_since_epoch().count();
    if (ec) return false;
#endif
    return true;
}

}  // namespace

struct PlyStreamReader::Impl {
    FileIdentity identity;  // of the file whose header was parsed; every pass checks it
    std::vector<Element> elements;
    int vertexElement = -1, faceElement = -1;
    int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, faceList = -1;

    // The byte source of one pass.
    std::FILE* file = nullptr;
    std::vector<unsigned char> buffer;
    std::size_t begin = 0, end = 0;   // valid bytes buffer[begin, end)
    std::uint64_t bufferOffset = 0;   // file offset of buffer[0]
    bool eof = false;
    std::string path;
    bool swap = false;
    bool ascii = false;

    [[noreturn]] void fail(const std::string& what, std::uint64_t offset) const {
        std::ostringstream message;
        message << "The PLY file cannot be read: " << path << ": " << what << " (byte offset " << offset << ")";
        throw PlyStreamError(message.str(), offset);
    }
    std::uint64_t offset() const { return bufferOffset + begin; }

    // Makes at least n bytes available at buffer[begin]; false at the end of the file.
    bool fill(std::size_t n) {
        if (end - begin >= n) return true;
        if (begin > 0) {
            std::memmove(buffer.data(), buffer.data() + begin, end - begin);
            bufferOffset += begin;
            end -= begin;
            begin = 0;
        }
        while (end < n && !eof) {
            if (buffer.size() < n) buffer.resize(n);
            const std::size_t got = std::fread(buffer.data() + end, 1, buffer.size() - end, file);
            if (got == 0) eof = true;
            end += got;
        }
        return end - begin >= n;
    }

    // --- binary values
    const unsigned char* take(std::size_t n, const char* what, std::uint64_t index) {
        if (!fill(n)) {
            std::ostringstream s;
            s << "the file is truncated: it ends inside " << what << ' ' << index
              << " (the header announces more data than the file holds; the file was probably not completely "
                 "written or copied: write or copy it again)";
            fail(s.str(), offset());
        }
        const unsigned char* p = buffer.data() + begin;
        begin += n;
        return p;
    }
    template <typename T>
    T load(const unsigned char* p) const {
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, p, sizeof(T));
        if (swap) std::reverse(bytes, bytes + sizeof(T));
        T value;
        std::memcpy(&value, bytes, sizeof(T));
        return value;
    }
    double binaryNumber(const unsigned char* p, PType t) const {
        switch (t) {
            case PType::Int8: return static_cast<std::int8_t>(p[0]);
            case PType::UInt8: return p[0];
            case PType::Int16: return load<std::int16_t>(p);
            case PType::UInt16: return load<std::uint16_t>(p);
            case PType::Int32: return load<std::int32_t>(p);
            case PType::UInt32: return load<std::uint32_t>(p);
            case PType::Float32: return load<float>(p);
            case PType::Float64: return load<double>(p);
        }
        return 0;
    }
    std::int64_t binaryInteger(const unsigned char* p, PType t) const {
        switch (t) {
            case PType::Int8: return static_cast<std::int8_t>(p[0]);
            case PType::UInt8: return p[0];
            case PType::Int16: return load<std::int16_t>(p);
            case PType::UInt16: return load<std::uint16_t>(p);
            case PType::Int32: return load<std::int32_t>(p);
            case PType::UInt32: return load<std::uint32_t>(p);
            default: return 0;
        }
    }

    // --- ASCII tokens
    // The next whitespace-separated token; empty at the end of the file.
    std::pair<const char*, std::size_t> token() {
        for (;;) {
            while (begin < end && std::isspace(buffer[begin])) ++begin;
            if (begin < end) break;
            if (!fill(1)) return {nullptr, 0};
        }
        std::size_t length = 0;
        for (;;) {
            while (begin + length < end && !std::isspace(buffer[begin + length])) ++length;
            if (begin + length < end || eof) break;
            if (!fill(length + 1)) break;
        }
        const char* p = reinterpret_cast<const char*>(buffer.data() + begin);
        begin += length;
        return {p, length};
    }
    double asciiNumber(PType t, const char* what, std::uint64_t index) {
        const std::uint64_t at = offset();
        const auto [p, n] = token();
        if (!p) {
            std::ostringstream s;
            s << "the file is truncated: it ends inside " << what << ' ' << index
              << " (the header announces more data than the file holds; write or copy the file again)";
            fail(s.str(), at);
        }
        if (isInteger(t)) {
            long long value = 0;
            const auto r = std::from_chars(p, p + n, value);
            if (r.ec == std::errc() && r.ptr == p + n) return double(value);
        } else {
            double value = 0;
            const auto r = std::from_chars(p, p + n, value);
            if (r.ec == std::errc() && r.ptr == p + n) return value;
            // from_chars does not read "nan" / "inf" spellings with signs everywhere; keep them so
            // that the non-finite check below names them.
            const std::string text(p, n);
            if (text == "nan" || text == "-nan" || text == "NaN") return std::nan("");
            if (text == "inf" || text == "Inf") return INFINITY;
            if (text == "-inf" || text == "-Inf") return -INFINITY;
        }
        std::ostringstream s;
        s << what << ' ' << index << ": " << shown(std::string(p, n)) << " is not a valid "
          << (isInteger(t) ? "integer" : "number") << " (the ASCII data does not match the header)";
        fail(s.str(), at);
    }

    double number(PType t, const char* what, std::uint64_t index) {
        if (ascii) return asciiNumber(t, what, index);
        return binaryNumber(take(typeSize(t), what, index), t);
    }
    std::int64_t integer(PType t, const char* what, std::uint64_t index) {
        if (ascii) return static_cast<std::int64_t>(asciiNumber(t, what, index));
        return binaryInteger(take(typeSize(t), what, index), t);
    }
};

PlyStreamReader::PlyStreamReader(std::string path, std::size_t chunkVertices, std::size_t chunkTriangles)
    : path_(std::move(path)), chunkVertices_(std::max<std::size_t>(chunkVertices, 1)),
      chunkTriangles_(std::max<std::size_t>(chunkTriangles, 1)), impl_(new Impl) {
    Impl& m = *impl_;
    m.path = path_;
    std::error_code folderError;
    if (std::filesystem::is_directory(path_, folderError))
        m.fail("this is a folder, not a PLY file: choose the scan's .ply file inside it", 0);
    std::FILE* f = std::fopen(path_.c_str(), "rb");
    if (!f) m.fail("cannot open the file (check that it exists and is readable)", 0);
    if (!identityOf(f, path_, m.identity)) {
        std::fclose(f);
        m.fail("cannot read the file's size and time (check that it is a regular file)", 0);
    }
    std::fseek(f, 0, SEEK_END);
    const long size = std::ftell(f);
    std::fseek(f, 0, SEEK_SET);
    info_.fileBytes = size > 0 ? std::uint64_t(size) : 0;
    std::vector<char> head(std::min<std::uint64_t>(info_.fileBytes, 1 << 20));
    const std::size_t got = std::fread(head.data(), 1, head.size(), f);
    std::fclose(f);
    head.resize(got);

    if (head.size() < 4 || std::memcmp(head.data(), "ply", 3) != 0 || (head[3] != '\n' && head[3] != '\r'))
        m.fail("not a PLY file: it does not start with the line 'ply' (choose a .ply mesh file)", 0);
    std::size_t pos = 0, line = 0;
    bool formatSeen = false, ended = false;
    while (pos < head.size()) {
        const std::size_t lineStart = pos;
        const auto nl = std::find(head.begin() + std::ptrdiff_t(pos), head.end(), '\n');
        if (nl == head.end()) break;
        std::string text(head.begin() + std::ptrdiff_t(pos), nl);
        pos = std::size_t(nl - head.begin()) + 1;
        ++line;
        if (!text.empty() && text.back() == '\r') text.pop_back();
        if (line == 1) continue;
        std::istringstream in(text);
        std::vector<std::string> t;
        for (std::string w; in >> w;) t.push_back(w);
        if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
        auto bad = [&](const std::string& what) {
            m.fail("header line " + std::to_string(line) + ": " + what + " (not a valid PLY header)", lineStart);
        };
        if (t[0] == "end_header") {
            ended = true;
            break;
        }
        if (t[0] == "format") {
            if (t.size() != 3 || formatSeen) bad("malformed or repeated format line");
            if (t[1] == "ascii") info_.encoding = PlyEncoding::Ascii;
            else if (t[1] == "binary_little_endian") info_.encoding = PlyEncoding::BinaryLittleEndian;
            else if (t[1] == "binary_big_endian") info_.encoding = PlyEncoding::BinaryBigEndian;
            else bad("unknown format " + shown(t[1]) + " (ascii, binary_little_endian or binary_big_endian)");
            if (t[2] != "1.0") bad("unsupported PLY version " + shown(t[2]) + " (1.0 expected)");
            formatSeen = true;
        } else if (t[0] == "element") {
            if (t.size() != 3) bad("malformed element line");
            Element e;
            e.name = t[1];
            const auto r = std::from_chars(t[2].data(), t[2].data() + t[2].size(), e.count);
            if (r.ec != std::errc() || r.ptr != t[2].data() + t[2].size()) bad("element " + shown(t[1]) + " has an invalid count");
            for (const Element& other : m.elements)
                if (other.name == e.name) bad("element " + shown(e.name) + " declared twice");
            m.elements.push_back(std::move(e));
        } else if (t[0] == "property") {
            if (m.elements.empty()) bad("property before any element");
            Property p;
            if (t.size() == 5 && t[1] == "list") {
                const auto c = parseType(t[2]), i = parseType(t[3]);
                if (!c || !i || !isInteger(*c)) bad("list property " + shown(t[4]) + " has an unknown or non-integer length type");
                p.isList = true;
                p.countType = *c;
                p.type = *i;
                p.name = t[4];
            } else if (t.size() == 3) {
                const auto ty = parseType(t[1]);
                if (!ty) bad("unknown property type " + shown(t[1]));
                p.type = *ty;
                p.name = t[2];
            } else {
                bad("malformed property line");
            }
            if (m.elements.back().find(p.name) >= 0) bad("property " + shown(p.name) + " declared twice");
            m.elements.back().properties.push_back(std::move(p));
        } else {
            bad("unknown keyword " + shown(t[0]));
        }
    }
    if (!ended)
        m.fail(head.size() == info_.fileBytes ? "the file ends inside its header (no end_header line): it was not "
                                                "completely written; write it again"
                                              : "no end_header line in the first MiB: not a PLY header",
               head.size());
    if (!formatSeen) m.fail("the PLY header has no format line", 0);
    info_.headerBytes = pos;
    m.ascii = info_.encoding == PlyEncoding::Ascii;
    m.swap = info_.encoding == PlyEncoding::BinaryBigEndian;

    for (std::size_t i = 0; i < m.elements.size(); ++i) {
        if (m.elements[i].name == "vertex") m.vertexElement = int(i);
        if (m.elements[i].name == "face") m.faceElement = int(i);
    }
    if (m.vertexElement < 0) m.fail("the PLY file has no vertex element: it is not a mesh or a point cloud", 0);
    const Element& v = m.elements[std::size_t(m.vertexElement)];
    m.x = v.find("x"), m.y = v.find("y"), m.z = v.find("z");
    if (m.x < 0 || m.y < 0 || m.z < 0)
        m.fail("the vertex element has no x, y and z properties: the file holds no positions", 0);
    for (int p : {m.x, m.y, m.z})
        if (v.properties[std::size_t(p)].isList) m.fail("the vertex position x, y or z is declared as a list", 0);
    m.nx = v.find("nx"), m.ny = v.find("ny"), m.nz = v.find("nz");
    info_.hasNormals = m.nx >= 0 && m.ny >= 0 && m.nz >= 0 && !v.properties[std::size_t(m.nx)].isList &&
                       !v.properties[std::size_t(m.ny)].isList && !v.properties[std::size_t(m.nz)].isList;
    info_.vertexCount = v.count;
    if (v.count > 0xffffffffull)
        m.fail("the file has " + std::to_string(v.count) + " vertices, more than 32-bit indices can address", 0);
    if (m.faceElement >= 0) {
        const Element& f = m.elements[std::size_t(m.faceElement)];
        if (m.faceElement < m.vertexElement)
            m.fail("the face element comes before the vertex element: a streaming reader needs the positions first; "
                   "save the file again with MeshLab (vertices first)", 0);
        m.faceList = f.find("vertex_indices");
        if (m.faceList < 0) m.faceList = f.find("vertex_index");
        if (m.faceList < 0 || !f.properties[std::size_t(m.faceList)].isList ||
            !isInteger(f.properties[std::size_t(m.faceList)].type))
            m.fail("the face element has no integer list property vertex_indices", 0);
        info_.faceCount = f.count;
    }
    // Counts the file cannot hold: refused before anything is read.
    std::uint64_t needed = 0;
    for (std::size_t i = 0; i < m.elements.size(); ++i) {
        const Element& e = m.elements[i];
        const std::uint64_t perRecord = m.ascii ? std::max<std::size_t>(e.properties.size(), 1) * 2 - 1
                                                : e.minimumBytes(int(i) == m.faceElement ? m.faceList : -1);
        if (perRecord > 0 && e.count > (~std::uint64_t(0) - needed) / perRecord) needed = ~std::uint64_t(0);
        else needed += e.count * perRecord;
    }
    if (needed > info_.fileBytes - info_.headerBytes)
        m.fail("the header announces " + std::to_string(info_.vertexCount) + " vertices and " +
                   std::to_string(info_.faceCount) + " faces, which need at least " + std::to_string(needed) +
                   " bytes, but only " + std::to_string(info_.fileBytes - info_.headerBytes) +
                   " follow the header: the file is truncated or its counts are wrong",
               info_.headerBytes);
}

PlyStreamReader::~PlyStreamReader() {
    if (impl_ && impl_->file) std::fclose(impl_->file);
}

PlyStreamStats PlyStreamReader::read(const std::function<void(const PlyVertexChunk&)>& onVertices,
                                     const std::function<void(const PlyTriangleChunk&)>& onTriangles, bool verticesOnly,
                                     const ProgressCallback& progress) {
    Impl& m = *impl_;
    if (m.file) std::fclose(m.file);
    m.file = std::fopen(path_.c_str(), "rb");
    if (!m.file) m.fail("cannot open the file again (was it moved or deleted?)", 0);
    // Passes over another file (replaced or rewritten since the header was read) would mix two
    // meshes and report success: refused at the start and at the end of every pass.
    const auto checkSameFile = [&](std::uint64_t at) {
        FileIdentity now;
        if (!identityOf(m.file, path_, now) || !(now == m.identity))
            m.fail("the file changed while it was being read (replaced, or its size or time differ from the first "
                   "pass): let the program writing it finish, then run the filter again",
                   at);
    };
    checkSameFile(0);
    m.buffer.assign(std::size_t(4) << 20, 0);
    m.begin = m.end = 0;
    m.bufferOffset = 0;
    m.eof = false;
    std::fseek(m.file, long(info_.headerBytes), SEEK_SET);
    m.bufferOffset = info_.headerBytes;

    PlyStreamStats stats;
    std::vector<float> positions, normals;
    std::vector<std::uint32_t> triangles;
    std::uint64_t lastReport = 0;
    auto report = [&](bool force) {
        if (!progress) return;
        const std::uint64_t at = m.offset();
        if (!force && at - lastReport < (std::uint64_t(16) << 20)) return;
        lastReport = at;
        reportProgress(progress, info_.fileBytes ? double(at) / double(info_.fileBytes) : 1.0, "reading the PLY file");
    };

    for (std::size_t ei = 0; ei < m.elements.size(); ++ei) {
        const Element& e = m.elements[ei];
        const bool isVertex = int(ei) == m.vertexElement, isFace = int(ei) == m.faceElement;
        if (verticesOnly && ei > std::size_t(m.vertexElement)) break;
        const char* what = isVertex ? "vertex" : isFace ? "face" : "element record";
        // Fixed-size binary records whose fields we ignore: skipped by size.
        if (!isVertex && !isFace && !m.ascii && !e.hasList()) {
            const std::uint64_t record = e.minimumBytes(-1);
            for (std::uint64_t r = 0; r < e.count; ++r) m.take(record, what, r);
            continue;
        }
        if (isVertex) {
            positions.reserve(3 * chunkVertices_);
            if (info_.hasNormals) normals.reserve(3 * chunkVertices_);
        }
        if (isFace) triangles.reserve(3 * chunkTriangles_ + 3);
        std::uint64_t chunkFirst = 0;
        std::vector<std::int64_t> polygon;
        auto flushVertices = [&](std::uint64_t next) {
            if (onVertices && !positions.empty()) {
                PlyVertexChunk chunk;
                chunk.firstIndex = chunkFirst;
                chunk.count = positions.size() / 3;
                chunk.positions = positions.data();
                chunk.normals = info_.hasNormals ? normals.data() : nullptr;
                onVertices(chunk);
            }
            positions.clear();
            normals.clear();
            chunkFirst = next;
            report(false);
        };
        auto flushTriangles = [&]() {
            if (onTriangles && !triangles.empty()) {
                PlyTriangleChunk chunk;
                chunk.count = triangles.size() / 3;
                chunk.indices = triangles.data();
                onTriangles(chunk);
            }
            triangles.clear();
            report(false);
        };
        for (std::uint64_t r = 0; r < e.count; ++r) {
            const std::uint64_t recordOffset = m.offset();
            float xyz[3] = {0, 0, 0}, n[3] = {0, 0, 0};
            polygon.clear();
            for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
                const Property& p = e.properties[pi];
                if (p.isList) {
                    const std::int64_t count = m.integer(p.countType, what, r);
                    if (isFace && int(pi) == m.faceList) {
                        if (count < 3)
                            m.fail("face " + std::to_string(r) + " has " + std::to_string(count) +
                                       " vertices; a face needs at least 3 (remove it, e.g. with MeshLab's \"Remove "
                                       "Zero Area Faces\")", recordOffset);
                        // More corners than vertices repeats some: a damaged count, not a polygon
                        // (it was read as one and fanned until memory ran out).
                        if (std::uint64_t(count) > std::max<std::uint64_t>(info_.vertexCount, 3))
                            m.fail("face " + std::to_string(r) + " has " + std::to_string(count) +
                                       " corners but the file has only " + std::to_string(info_.vertexCount) +
                                       " vertices: the face list is damaged; export the mesh again (as triangles)",
                                   recordOffset);
                        for (std::int64_t k = 0; k < count; ++k) {
                            const std::int64_t index = m.integer(p.type, what, r);
                            if (index < 0 || std::uint64_t(index) >= info_.vertexCount)
                                m.fail("face " + std::to_string(r) + " uses vertex " + std::to_string(index) +
                                           ", out of range (the file has " + std::to_string(info_.vertexCount) +
                                           " vertices): the file is damaged; export it again",
                                       recordOffset);
                            polygon.push_back(index);
                        }
                    } else {
                        if (count < 0) m.fail(std::string(what) + " " + std::to_string(r) + " has a list of negative length", recordOffset);
                        for (std::int64_t k = 0; k < count; ++k) m.number(p.type, what, r);
                    }
                    continue;
                }
                const double value = m.number(p.type, what, r);
                if (isVertex) {
                    const int i = int(pi);
                    if (i == m.x) xyz[0] = float(value);
                    else if (i == m.y) xyz[1] = float(value);
                    else if (i == m.z) xyz[2] = float(value);
                    else if (i == m.nx) n[0] = float(value);
                    else if (i == m.ny) n[1] = float(value);
                    else if (i == m.nz) n[2] = float(value);
                }
            }
            if (isVertex) {
                if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
                    m.fail("vertex " + std::to_string(r) + " has a NaN or infinite coordinate: the scan is damaged; "
                               "delete that vertex and its faces (MeshLab: \"Remove Unreferenced Vertices\" after "
                               "deleting them) and export it again",
                           recordOffset);
                positions.insert(positions.end(), xyz, xyz + 3);
                if (info_.hasNormals) normals.insert(normals.end(), n, n + 3);
                ++stats.verticesRead;
                if (positions.size() >= 3 * chunkVertices_) flushVertices(r + 1);
            } else if (isFace) {
                ++stats.facesRead;
                if (polygon.size() > 3) ++stats.polygonsTriangulated;
                for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
                    triangles.push_back(std::uint32_t(polygon[0]));
                    triangles.push_back(std::uint32_t(polygon[k]));
                    triangles.push_back(std::uint32_t(polygon[k + 1]));
                    ++stats.trianglesEmitted;
                    // A huge polygon's fan goes out in chunks like any triangles.
                    if (triangles.size() >= 3 * chunkTriangles_) flushTriangles();
                }
                if (triangles.size() >= 3 * chunkTriangles_) flushTriangles();
            }
        }
        if (isVertex) flushVertices(e.count);
        if (isFace) flushTriangles();
    }
    report(true);
    checkSameFile(m.offset());
    std::fclose(m.file);
    m.file = nullptr;
    m.buffer.clear();
    m.buffer.shrink_to_fit();
    return stats;
}

}  // namespace rad
