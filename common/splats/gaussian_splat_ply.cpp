#include "splats/gaussian_splat_ply.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace rad {
namespace {

enum class Encoding { Ascii, Little, Big };

struct Property {
    std::string name;
    std::string type;
    int bytes = 0;      // scalar size; 0 for a list
    bool list = false;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
    // Bytes of one record in a binary file; 0 when a list property makes records variable.
    std::size_t recordBytes() const {
        std::size_t sum = 0;
        for (const Property& p : properties) {
            if (p.list) return 0;
            sum += p.bytes;
        }
        return sum;
    }
};

struct Header {
    Encoding encoding = Encoding::Ascii;
    std::vector<Element> elements;
};

int scalarBytes(const std::string& type) {
    static const std::map<std::string, int> sizes = {
        {"char", 1},  {"int8", 1},  {"uchar", 1}, {"uint8", 1},  {"short", 2},   {"int16", 2},
        {"ushort", 2}, {"uint16", 2}, {"int", 4},   {"int32", 4},  {"uint", 4},    {"uint32", 4},
        {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

std::string fileLabel(const std::string& path) { return "'" + path + "'"; }

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
    throw SplatFileError("Gaussian splat file " + fileLabel(path) + ": " + what);
}

// Step 1: the header, up to and including "end_header".
Header readHeader(std::istream& in, const std::string& path) {
    Header header;
    std::string line;
    if (!std::getline(in, line)) refuse(path, "the file is empty; give the .ply a 3D Gaussian Splatting trainer or SuperSplat wrote.");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line != "ply") refuse(path, "not a PLY file (it does not start with 'ply'); give the .ply a 3D Gaussian Splatting trainer or SuperSplat wrote.");
    bool formatSeen = false;
    while (true) {
        if (!std::getline(in, line))
            refuse(path, "the file ends inside its PLY header (no 'end_header'); the file is truncated, write it again.");
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "end_header") break;
        if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "format") {
            std::string format, version;
            words >> format >> version;
            if (format == "ascii") header.encoding = Encoding::Ascii;
            else if (format == "binary_little_endian") header.encoding = Encoding::Little;
            else if (format == "binary_big_endian") header.encoding = Encoding::Big;
            else refuse(path, "unknown PLY format '" + format + "'.");
            formatSeen = true;
        } else if (keyword == "element") {
            Element element;
            long long count = -1;
            words >> element.name >> count;
            if (element.name.empty() || count < 0) refuse(path, "malformed PLY header line '" + line + "'.");
            element.count = static_cast<std::uint64_t>(count);
            header.elements.push_back(element);
        } else if (keyword == "property") {
            if (header.elements.empty()) refuse(path, "PLY header has a property before any element.");
            Property p;
            words >> p.type;
            if (p.type == "list") {
                std::string countType, itemType;
                words >> countType >> itemType >> p.name;
                p.list = true;
                if (!scalarBytes(countType) || !scalarBytes(itemType)) refuse(path, "malformed PLY header line '" + line + "'.");
                p.type = countType + " " + itemType;
            } else {
                words >> p.name;
                p.bytes = scalarBytes(p.type);
                if (!p.bytes) refuse(path, "unknown PLY property type '" + p.type + "' in '" + line + "'.");
            }
            if (p.name.empty()) refuse(path, "malformed PLY header line '" + line + "'.");
            header.elements.back().properties.push_back(p);
        } else {
            refuse(path, "malformed PLY header line '" + line + "'.");
        }
    }
    if (!formatSeen) refuse(path, "the PLY header has no 'format' line.");
    return header;
}

// Where each splat quantity sits in a vertex record (property indices), and the SH degree.
struct Layout {
    int x = -1, y = -1, z = -1, opacity = -1;
    int dc[3] = {-1, -1, -1}, scale[3] = {-1, -1, -1}, rot[4] = {-1, -1, -1, -1};
    std::vector<int> rest;  // f_rest_0.. in order
    int degree = 0;
};

// Step 2: the vertex element must be a splat set.
Layout findLayout(const Header& header, std::size_t& vertexElement, const std::string& path) {
    const char* const remedy =
        " Give the .ply a 3D Gaussian Splatting trainer (point_cloud/iteration_*/point_cloud.ply) or SuperSplat "
        "(File > Export > PLY) wrote.";
    vertexElement = header.elements.size();
    for (std::size_t e = 0; e < header.elements.size(); ++e)
        if (header.elements[e].name == "vertex") vertexElement = e;
    bool compressed = false;
    for (const Element& element : header.elements)
        for (const Property& p : element.properties)
            if (p.name == "packed_position") compressed = true;
    if (compressed)
        refuse(path, std::string("this is a compressed splat PLY (PlayCanvas / SuperSplat 'compressed.ply': packed "
                                 "chunks), which is not read; export the scene from SuperSplat as an uncompressed .ply "
                                 "(File > Export > PLY) and give that file."));
    if (vertexElement == header.elements.size()) refuse(path, std::string("a PLY file without vertices, not a splat file.") + remedy);
    const Element& vertex = header.elements[vertexElement];
    std::map<std::string, int> index;
    for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
        if (vertex.properties[i].list) continue;
        index[vertex.properties[i].name] = static_cast<int>(i);
    }
    Layout layout;
    std::vector<std::string> missing;
    auto need = [&](const std::string& name, int& slot) {
        const auto it = index.find(name);
        if (it == index.end()) missing.push_back(name);
        else slot = it->second;
    };
    need("x", layout.x);
    need("y", layout.y);
    need("z", layout.z);
    for (int c = 0; c < 3; ++c) need("f_dc_" + std::to_string(c), layout.dc[c]);
    need("opacity", layout.opacity);
    for (int c = 0; c < 3; ++c) need("scale_" + std::to_string(c), layout.scale[c]);
    for (int c = 0; c < 4; ++c) need("rot_" + std::to_string(c), layout.rot[c]);
    if (!missing.empty()) {
        std::string have, lack;
        for (const Property& p : vertex.properties) have += (have.empty() ? "" : " ") + p.name;
        for (const std::string& m : missing) lack += (lack.empty() ? "" : " ") + m;
        refuse(path, "a PLY file but not a 3D Gaussian splat file: its vertices lack " + lack + " (they have: " +
                         (have.empty() ? std::string("no properties") : have) + ")." + remedy);
    }
    std::size_t restCount = 0;
    while (index.count("f_rest_" + std::to_string(restCount))) {
        layout.rest.push_back(index["f_rest_" + std::to_string(restCount)]);
        ++restCount;
    }
    std::size_t restNamed = 0;
    for (const auto& entry : index)
        if (entry.first.rfind("f_rest_", 0) == 0) ++restNamed;
    if (restNamed != restCount)
        refuse(path, "its f_rest_* properties are not numbered 0, 1, 2, ... without gaps (" + std::to_string(restNamed) +
                         " of them, f_rest_0 .. f_rest_" + std::to_string(restCount) +
                         " consecutive); the file is damaged, export it again.");
    int degree = 0;
    while (3 * ((degree + 1) * (degree + 1) - 1) < static_cast<int>(restCount)) ++degree;
    if (3 * ((degree + 1) * (degree + 1) - 1) != static_cast<int>(restCount))
        refuse(path, "it has " + std::to_string(restCount) +
                         " f_rest_* properties, which is not 3 ((d+1)^2 - 1) for any spherical-harmonic degree d (0, 9, "
                         "24 and 45 are degrees 0 to 3); the file is damaged, export it again.");
    if (degree > kMaxSplatShDegree)
        refuse(path, "its spherical harmonics are of degree " + std::to_string(degree) + " (" + std::to_string(restCount) +
                         " f_rest_* properties); degrees 0 to 3 are read, as 3D Gaussian Splatting trains them. Retrain "
                         "with sh_degree 3 or less, or drop the bands above 3 (f_rest of each channel keeps its first "
                         "15 coefficients).");
    layout.degree = degree;
    return layout;
}

enum class Scalar { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

Scalar scalarKind(const std::string& type) {
    if (type == "float" || type == "float32") return Scalar::Float32;
    if (type == "double" || type == "float64") return Scalar::Float64;
    if (type == "char" || type == "int8") return Scalar::Int8;
    if (type == "uchar" || type == "uint8") return Scalar::Uint8;
    if (type == "short" || type == "int16") return Scalar::Int16;
    if (type == "ushort" || type == "uint16") return Scalar::Uint16;
    if (type == "int" || type == "int32") return Scalar::Int32;
    return Scalar::Uint32;
}

double decodeBinary(const unsigned char* p, Scalar kind, int bytes, bool swap) {
    unsigned char b[8];
    for (int i = 0; i < bytes; ++i) b[i] = swap ? p[bytes - 1 - i] : p[i];
    switch (kind) {
    case Scalar::Float32: { float v; std::memcpy(&v, b, 4); return v; }
    case Scalar::Float64: { double v; std::memcpy(&v, b, 8); return v; }
    case Scalar::Int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
    case Scalar::Uint8: return b[0];
    case Scalar::Int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
    case Scalar::Uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
    case Scalar::Int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
    case Scalar::Uint32: break;
    }
    std::uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
}

// Step 3 helpers: skipping the elements stored before the vertices.
void skipElement(std::istream& in, const Element& element, Encoding encoding, const std::string& path) {
    if (encoding == Encoding::Ascii) {
        std::string line;
        for (std::uint64_t i = 0; i < element.count; ++i)
            if (!std::getline(in, line)) refuse(path, "the file ends inside element '" + element.name + "'; it is truncated, write it again.");
        return;
    }
    const std::size_t record = element.recordBytes();
    if (record == 0)
        refuse(path, "element '" + element.name + "' with list properties comes before the splats; save the splats "
                     "as the file's first element (as 3D Gaussian Splatting and SuperSplat do).");
    in.seekg(static_cast<std::streamoff>(record * element.count), std::ios::cur);
    if (!in) refuse(path, "the file ends inside element '" + element.name + "'; it is truncated, write it again.");
}

// One splat's values by property index, from its record.
struct RecordReader {
    const Element& vertex;
    Encoding encoding;
    std::vector<std::size_t> offsets;  // binary: byte offset of each property in a record
    std::vector<Scalar> kinds;
    std::size_t recordBytes = 0;

    RecordReader(const Element& v, Encoding e) : vertex(v), encoding(e) {
        std::size_t offset = 0;
        for (const Property& p : vertex.properties) {
            offsets.push_back(offset);
            kinds.push_back(scalarKind(p.type));
            offset += p.bytes;
        }
        recordBytes = offset;
    }
};

}  // namespace

GaussianSplats readGaussianSplatPly(const std::string& path, const ProgressCallback& progress) {
    std::ifstream in(path, std::ios::binary);
    if (!in) refuse(path, "cannot be opened (missing or unreadable); check the path.");
    const Header header = readHeader(in, path);
    std::size_t vertexIndex = 0;
    const Layout layout = findLayout(header, vertexIndex, path);
    const Element& vertex = header.elements[vertexIndex];
    if (vertex.count == 0) refuse(path, "it holds no splats (element vertex 0); give a trained scene.");
    if (header.encoding != Encoding::Ascii && vertex.recordBytes() == 0)
        refuse(path, "its splats have list properties, which a splat file does not have; export it again.");
    for (std::size_t e = 0; e < vertexIndex; ++e) skipElement(in, header.elements[e], header.encoding, path);

    GaussianSplats splats;
    splats.shDegree = layout.degree;
    const std::size_t n = vertex.count;
    const int k = splats.coefficientsPerChannel();
    splats.positions.resize(3 * n);
    splats.sh.resize(3 * k * n);
    splats.opacityLogit.resize(n);
    splats.logScale.resize(3 * n);
    splats.rotation.resize(4 * n);

    const RecordReader reader(vertex, header.encoding);
    const bool swap = header.encoding == Encoding::Big;
    const std::size_t propertyCount = vertex.properties.size();
    std::vector<double> values(propertyCount);
    const std::size_t chunk = 4096;
    std::vector<unsigned char> bytes;
    std::string line;
    for (std::size_t first = 0; first < n; first += chunk) {
        reportProgress(progress, double(first) / n, "Reading splats");
        const std::size_t last = std::min(n, first + chunk);
        if (header.encoding != Encoding::Ascii) {
            bytes.resize((last - first) * reader.recordBytes);
            in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
            if (static_cast<std::size_t>(in.gcount()) != bytes.size())
                refuse(path, "the file ends at splat " + std::to_string(first + in.gcount() / reader.recordBytes) + " of " +
                                 std::to_string(n) + " its header announces; it is truncated, write it again.");
        }
        for (std::size_t s = first; s < last; ++s) {
            // 3a. The record's values, by property index.
            if (header.encoding == Encoding::Ascii) {
                if (!std::getline(in, line))
                    refuse(path, "the file ends at splat " + std::to_string(s) + " of " + std::to_string(n) +
                                     " its header announces; it is truncated, write it again.");
                const char* p = line.data();
                const char* end = line.data() + line.size();
                for (std::size_t i = 0; i < propertyCount; ++i) {
                    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
                    if (vertex.properties[i].list) refuse(path, "its splats have list properties, which a splat file does not have; export it again.");
                    const auto result = std::from_chars(p, end, values[i]);
                    if (result.ec != std::errc()) {
                        // from_chars reads "nan" and "inf"; anything else here is not a number.
                        refuse(path, "splat " + std::to_string(s) + ": value " + std::to_string(i + 1) + " of its line ('" +
                                         vertex.properties[i].name + "') is missing or not a number; the file is damaged, "
                                         "export it again.");
                    }
                    p = result.ptr;
                }
            } else {
                const unsigned char* record = bytes.data() + (s - first) * reader.recordBytes;
                for (std::size_t i = 0; i < propertyCount; ++i)
                    values[i] = decodeBinary(record + reader.offsets[i], reader.kinds[i], vertex.properties[i].bytes, swap);
            }
            // 3b. Every value the transfer uses must be finite (a diverged training leaves NaN).
            auto take = [&](int property) {
                const double v = values[property];
                if (!std::isfinite(v))
                    refuse(path, "splat " + std::to_string(s) + " has a value that is not a finite number (NaN or "
                                     "infinity) in '" + vertex.properties[property].name +
                                     "'; the training diverged or the file is damaged. Remove such splats (e.g. "
                                     "SuperSplat's selection tools) or retrain.");
                return static_cast<float>(v);
            };
            splats.positions[3 * s] = take(layout.x);
            splats.positions[3 * s + 1] = take(layout.y);
            splats.positions[3 * s + 2] = take(layout.z);
            float* sh = splats.sh.data() + 3 * k * s;
            for (int c = 0; c < 3; ++c) {
                sh[c * k] = take(layout.dc[c]);
                for (int j = 1; j < k; ++j) sh[c * k + j] = take(layout.rest[c * (k - 1) + (j - 1)]);
            }
            splats.opacityLogit[s] = take(layout.opacity);
            for (int c = 0; c < 3; ++c) splats.logScale[3 * s + c] = take(layout.scale[c]);
            double norm2 = 0.0;
            for (int c = 0; c < 4; ++c) {
                splats.rotation[4 * s + c] = take(layout.rot[c]);
                norm2 += double(splats.rotation[4 * s + c]) * splats.rotation[4 * s + c];
            }
            if (!(norm2 > 1e-30))
                refuse(path, "splat " + std::to_string(s) + " has a zero rotation quaternion (rot_0..rot_3), which "
                                 "orients nothing; the file is damaged, export it again.");
        }
    }
    reportProgress(progress, 1.0, "Reading splats");
    return splats;
}

}  // namespace rad
