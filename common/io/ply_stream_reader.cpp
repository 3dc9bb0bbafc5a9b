#include "io/ply_stream_reader.h"

#include <algorithm>
#include <cctype>
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
    std::vector<PlyElement> elements;
    int vertexElement = -1, faceElement = -1;
    int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, faceList = -1;

    // The byte source of one pass.
    std::FILE* file = nullptr;
    std::vector<unsigned char> buffer;
    std::size_t begin = 0, end = 0;   // valid bytes buffer[begin, end)
    std::uint64_t bufferOffset = 0;   // file offset of buffer[0]
    bool eof = false;
    std::string path;
    bool bigEndian = false;
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
    double asciiNumber(PlyType t, const char* what, std::uint64_t index) {
        const std::uint64_t at = offset();
        const auto [p, n] = token();
        if (!p) {
            std::ostringstream s;
            s << "the file is truncated: it ends inside " << what << ' ' << index
              << " (the header announces more data than the file holds; write or copy the file again)";
            fail(s.str(), at);
        }
        if (const auto value = parsePlyAsciiNumber(p, n, t)) return *value;
        std::ostringstream s;
        s << what << ' ' << index << ": " << shown(std::string(p, n)) << " is not a valid "
          << (isPlyIntegerType(t) ? "integer" : "number") << " (the ASCII data does not match the header)";
        fail(s.str(), at);
    }

    double number(PlyType t, const char* what, std::uint64_t index) {
        if (ascii) return asciiNumber(t, what, index);
        return readPlyNumber(take(plyTypeSize(t), what, index), t, bigEndian);
    }
    std::int64_t integer(PlyType t, const char* what, std::uint64_t index) {
        if (ascii) return static_cast<std::int64_t>(asciiNumber(t, what, index));
        return readPlyInteger(take(plyTypeSize(t), what, index), t, bigEndian);
    }
};

namespace {

using Impl = PlyStreamReader::Impl;

// The shared header parser's fault, in this reader's words.
[[noreturn]] void refuseHeader(const Impl& m, const PlyHeaderFault& f, bool wholeFile) {
    using K = PlyHeaderFaultKind;
    std::string what;
    switch (f.kind) {
        case K::EmptyFile:
        case K::NoPlyLine: m.fail("not a PLY file: it does not start with the line 'ply' (choose a .ply mesh file)", 0);
        case K::NoEndHeader:
            m.fail(wholeFile ? "the file ends inside its header (no end_header line): it was not completely written; "
                               "write it again"
                             : "no end_header line in the first MiB: not a PLY header",
                   f.lineOffset);
        case K::NoFormatLine: m.fail("the PLY header has no format line", 0);
        case K::RepeatedFormat:
        case K::MalformedFormat: what = "malformed or repeated format line"; break;
        case K::UnknownFormat:
            what = "unknown format " + shown(f.token) + " (ascii, binary_little_endian or binary_big_endian)";
            break;
        case K::UnsupportedVersion: what = "unsupported PLY version " + shown(f.token) + " (1.0 expected)"; break;
        case K::MalformedElement: what = "malformed element line"; break;
        case K::InvalidElementCount: what = "element " + shown(f.token) + " has an invalid count"; break;
        case K::DuplicateElement: what = "element " + shown(f.token) + " declared twice"; break;
        case K::PropertyBeforeElement: what = "property before any element"; break;
        case K::UnknownListType:
        case K::NonIntegerListLength:
            what = "list property " + shown(f.token) + " has an unknown or non-integer length type";
            break;
        case K::ScalarPropertyOfTypeList:
        case K::UnknownPropertyType: what = "unknown property type " + shown(f.token); break;
        case K::MalformedProperty: what = "malformed property line"; break;
        case K::DuplicateProperty: what = "property " + shown(f.token) + " declared twice"; break;
        case K::UnknownKeyword: what = "unknown keyword " + shown(f.token); break;
        // Only strict rules or a refused encoding give these; this reader's rules give none of them.
        case K::MalformedEndHeader:
        case K::FormatAfterElements:
        case K::EncodingNotAccepted:
        case K::ElementBeforeFormat: what = "malformed header line"; break;
    }
    m.fail("header line " + std::to_string(f.lineNumber) + ": " + what + " (not a valid PLY header)", f.lineOffset);
}

// The file's first MiB (or all of it), and its size and identity.
std::vector<char> readHead(Impl& m, PlyStreamInfo& info) {
    std::error_code folderError;
    if (std::filesystem::is_directory(m.path, folderError))
        m.fail("this is a folder, not a PLY file: choose the scan's .ply file inside it", 0);
    std::FILE* f = std::fopen(m.path.c_str(), "rb");
    if (!f) m.fail("cannot open the file (check that it exists and is readable)", 0);
    if (!identityOf(f, m.path, m.identity)) {
        std::fclose(f);
        m.fail("cannot read the file's size and time (check that it is a regular file)", 0);
    }
    std::fseek(f, 0, SEEK_END);
    const long size = std::ftell(f);
    std::fseek(f, 0, SEEK_SET);
    info.fileBytes = size > 0 ? std::uint64_t(size) : 0;
    std::vector<char> head(std::min<std::uint64_t>(info.fileBytes, 1 << 20));
    const std::size_t got = std::fread(head.data(), 1, head.size(), f);
    std::fclose(f);
    head.resize(got);
    return head;
}

// Every encoding, and the headers that scanners and other tools write (lenient rules).
void parseHeader(Impl& m, const std::vector<char>& head, PlyStreamInfo& info) {
    PlyHeaderRules rules;
    rules.strict = false;
    PlyHeaderParse parse = parsePlyHeader(head.data(), head.size(), rules);
    if (parse.fault) refuseHeader(m, *parse.fault, head.size() == info.fileBytes);
    m.elements = std::move(parse.header.elements);
    info.encoding = parse.header.encoding;
    info.headerBytes = parse.header.dataOffset;
    m.ascii = info.encoding == PlyEncoding::Ascii;
    m.bigEndian = info.encoding == PlyEncoding::BinaryBigEndian;
}

// The vertex element's positions and normals, and the face element's vertex list.
void findMeshProperties(Impl& m, PlyStreamInfo& info) {
    for (std::size_t i = 0; i < m.elements.size(); ++i) {
        if (m.elements[i].name == "vertex") m.vertexElement = int(i);
        if (m.elements[i].name == "face") m.faceElement = int(i);
    }
    if (m.vertexElement < 0) m.fail("the PLY file has no vertex element: it is not a mesh or a point cloud", 0);
    const PlyElement& v = m.elements[std::size_t(m.vertexElement)];
    m.x = v.indexOf("x"), m.y = v.indexOf("y"), m.z = v.indexOf("z");
    if (m.x < 0 || m.y < 0 || m.z < 0)
        m.fail("the vertex element has no x, y and z properties: the file holds no positions", 0);
    for (int p : {m.x, m.y, m.z})
        if (v.properties[std::size_t(p)].isList) m.fail("the vertex position x, y or z is declared as a list", 0);
    m.nx = v.indexOf("nx"), m.ny = v.indexOf("ny"), m.nz = v.indexOf("nz");
    info.hasNormals = m.nx >= 0 && m.ny >= 0 && m.nz >= 0 && !v.properties[std::size_t(m.nx)].isList &&
                      !v.properties[std::size_t(m.ny)].isList && !v.properties[std::size_t(m.nz)].isList;
    info.vertexCount = v.count;
    if (v.count > 0xffffffffull)
        m.fail("the file has " + std::to_string(v.count) + " vertices, more than 32-bit indices can address", 0);
    if (m.faceElement >= 0) {
        const PlyElement& f = m.elements[std::size_t(m.faceElement)];
        if (m.faceElement < m.vertexElement)
            m.fail("the face element comes before the vertex element: a streaming reader needs the positions first; "
                   "save the file again with MeshLab (vertices first)", 0);
        m.faceList = f.indexOf("vertex_indices");
        if (m.faceList < 0) m.faceList = f.indexOf("vertex_index");
        if (m.faceList < 0 || !f.properties[std::size_t(m.faceList)].isList ||
            !isPlyIntegerType(f.properties[std::size_t(m.faceList)].type))
            m.fail("the face element has no integer list property vertex_indices", 0);
        info.faceCount = f.count;
    }
}

// Counts the file cannot hold: refused before anything is read.
void checkCountsFitFile(const Impl& m, const PlyStreamInfo& info) {
    std::uint64_t needed = 0;
    for (std::size_t i = 0; i < m.elements.size(); ++i) {
        const PlyElement& e = m.elements[i];
        const std::uint64_t perRecord = m.ascii ? std::max<std::size_t>(e.properties.size(), 1) * 2 - 1
                                                : minimumPlyRecordBytes(e, int(i) == m.faceElement ? m.faceList : -1);
        if (perRecord > 0 && e.count > (~std::uint64_t(0) - needed) / perRecord) needed = ~std::uint64_t(0);
        else needed += e.count * perRecord;
    }
    if (needed > info.fileBytes - info.headerBytes)
        m.fail("the header announces " + std::to_string(info.vertexCount) + " vertices and " +
                   std::to_string(info.faceCount) + " faces, which need at least " + std::to_string(needed) +
                   " bytes, but only " + std::to_string(info.fileBytes - info.headerBytes) +
                   " follow the header: the file is truncated or its counts are wrong",
               info.headerBytes);
}

}  // namespace

PlyStreamReader::PlyStreamReader(std::string path, std::size_t chunkVertices, std::size_t chunkTriangles)
    : path_(std::move(path)), chunkVertices_(std::max<std::size_t>(chunkVertices, 1)),
      chunkTriangles_(std::max<std::size_t>(chunkTriangles, 1)), impl_(new Impl) {
    Impl& m = *impl_;
    m.path = path_;
    const std::vector<char> head = readHead(m, info_);
    parseHeader(m, head, info_);
    findMeshProperties(m, info_);
    checkCountsFitFile(m, info_);
}

PlyStreamReader::~PlyStreamReader() {
    if (impl_ && impl_->file) std::fclose(impl_->file);
}

namespace {

// Passes over another file (replaced or rewritten since the header was read) would mix two meshes
// and report success: refused at the start and at the end of every pass.
void checkSameFile(const Impl& m, std::uint64_t at) {
    FileIdentity now;
    if (!identityOf(m.file, m.path, now) || !(now == m.identity))
        m.fail("the file changed while it was being read (replaced, or its size or time differ from the first "
               "pass): let the program writing it finish, then run the filter again",
               at);
}

// Opens the file again and positions the byte source after the header.
void startPass(Impl& m, std::uint64_t headerBytes) {
    if (m.file) std::fclose(m.file);
    m.file = std::fopen(m.path.c_str(), "rb");
    if (!m.file) m.fail("cannot open the file again (was it moved or deleted?)", 0);
    checkSameFile(m, 0);
    m.buffer.assign(std::size_t(4) << 20, 0);
    m.begin = m.end = 0;
    m.bufferOffset = 0;
    m.eof = false;
    std::fseek(m.file, long(headerBytes), SEEK_SET);
    m.bufferOffset = headerBytes;
}

void endPass(Impl& m) {
    checkSameFile(m, m.offset());
    std::fclose(m.file);
    m.file = nullptr;
    m.buffer.clear();
    m.buffer.shrink_to_fit();
}

// One pass's chunks on their way to the callbacks, its statistics and its progress.
struct PassOutput {
    const Impl& m;
    const PlyStreamInfo& info;
    const std::function<void(const PlyVertexChunk&)>& onVertices;
    const std::function<void(const PlyTriangleChunk&)>& onTriangles;
    const ProgressCallback& progress;
    std::size_t chunkVertices, chunkTriangles;
    PlyStreamStats stats;
    std::vector<float> positions, normals;
    std::vector<std::uint32_t> triangles;
    std::uint64_t chunkFirst = 0;  // index of the first vertex in positions
    std::uint64_t lastReport = 0;

    PassOutput(const Impl& m, const PlyStreamInfo& info, const std::function<void(const PlyVertexChunk&)>& onVertices,
               const std::function<void(const PlyTriangleChunk&)>& onTriangles, const ProgressCallback& progress,
               std::size_t chunkVertices, std::size_t chunkTriangles)
        : m(m), info(info), onVertices(onVertices), onTriangles(onTriangles), progress(progress),
          chunkVertices(chunkVertices), chunkTriangles(chunkTriangles) {}

    void report(bool force) {
        if (!progress) return;
        const std::uint64_t at = m.offset();
        if (!force && at - lastReport < (std::uint64_t(16) << 20)) return;
        lastReport = at;
        reportProgress(progress, info.fileBytes ? double(at) / double(info.fileBytes) : 1.0, "reading the PLY file");
    }
    void flushVertices(std::uint64_t next) {
        if (onVertices && !positions.empty()) {
            PlyVertexChunk chunk;
            chunk.firstIndex = chunkFirst;
            chunk.count = positions.size() / 3;
            chunk.positions = positions.data();
            chunk.normals = info.hasNormals ? normals.data() : nullptr;
            onVertices(chunk);
        }
        positions.clear();
        normals.clear();
        chunkFirst = next;
        report(false);
    }
    void flushTriangles() {
        if (onTriangles && !triangles.empty()) {
            PlyTriangleChunk chunk;
            chunk.count = triangles.size() / 3;
            chunk.indices = triangles.data();
            onTriangles(chunk);
        }
        triangles.clear();
        report(false);
    }
};

// What one record holds of what a pass keeps.
struct RecordValues {
    float xyz[3] = {0, 0, 0}, n[3] = {0, 0, 0};
    std::vector<std::int64_t> polygon;  // the face's vertex indices

    void clear() {
        std::fill(xyz, xyz + 3, 0.0f);
        std::fill(n, n + 3, 0.0f);
        polygon.clear();
    }
};

// What an element is to a pass: a constant of readRecord, so that each role gets its own loop.
enum class ElementRole { Vertex, Face, Other };

constexpr const char* recordName(ElementRole role) {
    return role == ElementRole::Vertex ? "vertex" : role == ElementRole::Face ? "face" : "element record";
}

// The face's vertex list of record r, whose length is count.
void readPolygon(Impl& m, const PlyProperty& p, std::int64_t count, std::uint64_t r, std::uint64_t recordOffset,
                 std::uint64_t vertexCount, std::vector<std::int64_t>& polygon) {
    if (count < 3)
        m.fail("face " + std::to_string(r) + " has " + std::to_string(count) +
                   " vertices; a face needs at least 3 (remove it, e.g. with MeshLab's \"Remove "
                   "Zero Area Faces\")", recordOffset);
    // More corners than vertices repeats some: a damaged count, not a polygon (it was read as one and
    // fanned until memory ran out).
    if (std::uint64_t(count) > std::max<std::uint64_t>(vertexCount, 3))
        m.fail("face " + std::to_string(r) + " has " + std::to_string(count) + " corners but the file has only " +
                   std::to_string(vertexCount) + " vertices: the face list is damaged; export the mesh again (as triangles)",
               recordOffset);
    for (std::int64_t k = 0; k < count; ++k) {
        const std::int64_t index = m.integer(p.type, "face", r);
        if (index < 0 || std::uint64_t(index) >= vertexCount)
            m.fail("face " + std::to_string(r) + " uses vertex " + std::to_string(index) + ", out of range (the file has " +
                       std::to_string(vertexCount) + " vertices): the file is damaged; export it again",
                   recordOffset);
        polygon.push_back(index);
    }
}

// Record r of the element: every property read (or skipped), the values the pass keeps in values.
template <ElementRole role>
void readRecord(Impl& m, const PlyElement& e, std::uint64_t r, std::uint64_t recordOffset, std::uint64_t vertexCount,
                RecordValues& values) {
    constexpr const char* what = recordName(role);
    for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        const PlyProperty& p = e.properties[pi];
        if (p.isList) {
            const std::int64_t count = m.integer(p.countType, what, r);
            if (role == ElementRole::Face && int(pi) == m.faceList) {
                readPolygon(m, p, count, r, recordOffset, vertexCount, values.polygon);
            } else {
                if (count < 0) m.fail(std::string(what) + " " + std::to_string(r) + " has a list of negative length", recordOffset);
                for (std::int64_t k = 0; k < count; ++k) m.number(p.type, what, r);
            }
            continue;
        }
        const double value = m.number(p.type, what, r);
        if constexpr (role == ElementRole::Vertex) {
            const int i = int(pi);
            if (i == m.x) values.xyz[0] = float(value);
            else if (i == m.y) values.xyz[1] = float(value);
            else if (i == m.z) values.xyz[2] = float(value);
            else if (i == m.nx) values.n[0] = float(value);
            else if (i == m.ny) values.n[1] = float(value);
            else if (i == m.nz) values.n[2] = float(value);
        }
    }
}

void readVertices(Impl& m, const PlyElement& e, PassOutput& out) {
    out.positions.reserve(3 * out.chunkVertices);
    if (out.info.hasNormals) out.normals.reserve(3 * out.chunkVertices);
    RecordValues values;
    for (std::uint64_t r = 0; r < e.count; ++r) {
        const std::uint64_t recordOffset = m.offset();
        values.clear();
        readRecord<ElementRole::Vertex>(m, e, r, recordOffset, out.info.vertexCount, values);
        const float* xyz = values.xyz;
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
            m.fail("vertex " + std::to_string(r) + " has a NaN or infinite coordinate: the scan is damaged; "
                       "delete that vertex and its faces (MeshLab: \"Remove Unreferenced Vertices\" after "
                       "deleting them) and export it again",
                   recordOffset);
        out.positions.insert(out.positions.end(), xyz, xyz + 3);
        if (out.info.hasNormals) out.normals.insert(out.normals.end(), values.n, values.n + 3);
        ++out.stats.verticesRead;
        if (out.positions.size() >= 3 * out.chunkVertices) out.flushVertices(r + 1);
    }
    out.flushVertices(e.count);
}

// Polygons with k > 3 corners become a fan of k - 2 triangles from their first corner.
void readFaces(Impl& m, const PlyElement& e, PassOutput& out) {
    out.triangles.reserve(3 * out.chunkTriangles + 3);
    RecordValues values;
    for (std::uint64_t r = 0; r < e.count; ++r) {
        const std::uint64_t recordOffset = m.offset();
        values.clear();
        readRecord<ElementRole::Face>(m, e, r, recordOffset, out.info.vertexCount, values);
        const std::vector<std::int64_t>& polygon = values.polygon;
        ++out.stats.facesRead;
        if (polygon.size() > 3) ++out.stats.polygonsTriangulated;
        for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
            out.triangles.push_back(std::uint32_t(polygon[0]));
            out.triangles.push_back(std::uint32_t(polygon[k]));
            out.triangles.push_back(std::uint32_t(polygon[k + 1]));
            ++out.stats.trianglesEmitted;
            // A huge polygon's fan goes out in chunks like any triangles.
            if (out.triangles.size() >= 3 * out.chunkTriangles) out.flushTriangles();
        }
        if (out.triangles.size() >= 3 * out.chunkTriangles) out.flushTriangles();
    }
    out.flushTriangles();
}

// Elements other than vertices and faces: fixed-size binary records are skipped by size, the others
// read value by value.
void skipElement(Impl& m, const PlyElement& e, std::uint64_t vertexCount) {
    if (!m.ascii && !e.hasList) {
        const std::uint64_t record = minimumPlyRecordBytes(e);
        for (std::uint64_t r = 0; r < e.count; ++r) m.take(record, recordName(ElementRole::Other), r);
        return;
    }
    RecordValues values;
    for (std::uint64_t r = 0; r < e.count; ++r) {
        values.clear();
        readRecord<ElementRole::Other>(m, e, r, m.offset(), vertexCount, values);
    }
}

}  // namespace

PlyStreamStats PlyStreamReader::read(const std::function<void(const PlyVertexChunk&)>& onVertices,
                                     const std::function<void(const PlyTriangleChunk&)>& onTriangles, bool verticesOnly,
                                     const ProgressCallback& progress) {
    Impl& m = *impl_;
    startPass(m, info_.headerBytes);
    PassOutput out(m, info_, onVertices, onTriangles, progress, chunkVertices_, chunkTriangles_);
    for (std::size_t ei = 0; ei < m.elements.size(); ++ei) {
        if (verticesOnly && ei > std::size_t(m.vertexElement)) break;
        const PlyElement& e = m.elements[ei];
        if (int(ei) == m.vertexElement) readVertices(m, e, out);
        else if (int(ei) == m.faceElement) readFaces(m, e, out);
        else skipElement(m, e, info_.vertexCount);
    }
    out.report(true);
    endPass(m);
    return out.stats;
}

}  // namespace rad
