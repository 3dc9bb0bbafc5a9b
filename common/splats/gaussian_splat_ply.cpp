#include "splats/gaussian_splat_ply.h"

#include "io/ply_header.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>

namespace rad {
namespace {

// The header is read from the file's first MiB (a splat header of degree 3 is about 2 KB).
constexpr std::size_t kMaxHeaderBytes = std::size_t(1) << 20;

std::string fileLabel(const std::string& path) { return "'" + path + "'"; }

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
    throw SplatFileError("Gaussian splat file " + fileLabel(path) + ": " + what);
}

// The header line a fault names, without its line break.
std::string faultLine(const std::string& head, const PlyHeaderFault& f) {
    const std::size_t start = std::min(f.lineOffset, head.size());
    std::string line = head.substr(start, head.find('\n', start) - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
}

// The shared header parser's fault, in this reader's words. `head` holds the bytes parsed,
// `wholeFile` when that is all of the file.
[[noreturn]] void refuseHeader(const std::string& path, const std::string& head, bool wholeFile,
                               const PlyHeaderFault& f) {
    using K = PlyHeaderFaultKind;
    const char* const remedy = "give the .ply a 3D Gaussian Splatting trainer or SuperSplat wrote.";
    const std::string malformed = "malformed PLY header line '" + faultLine(head, f) + "'.";
    const std::string truncated =
        "the file ends inside its PLY header (no 'end_header'); the file is truncated, write it again.";
    switch (f.kind) {
        case K::EmptyFile: refuse(path, std::string("the file is empty; ") + remedy);
        case K::NoPlyLine:
            // "ply" and nothing else: the start of a PLY file that was cut short.
            if (wholeFile && head == "ply") refuse(path, truncated);
            refuse(path, std::string("not a PLY file (it does not start with 'ply'); ") + remedy);
        case K::NoEndHeader:
            if (wholeFile) refuse(path, truncated);
            refuse(path, "no 'end_header' in the first MiB of the file: not a PLY header; " + std::string(remedy));
        case K::NoFormatLine: refuse(path, "the PLY header has no 'format' line.");
        case K::UnknownFormat: refuse(path, "unknown PLY format '" + f.token + "'.");
        case K::UnsupportedVersion:
            refuse(path, "unsupported PLY version '" + f.token + "' in '" + faultLine(head, f) + "' (1.0 is read).");
        case K::RepeatedFormat: refuse(path, "the PLY header has a second 'format' line '" + faultLine(head, f) + "'.");
        case K::DuplicateElement: refuse(path, "the PLY header declares element '" + f.token + "' twice.");
        case K::DuplicateProperty:
            refuse(path, "the PLY header declares property '" + f.token + "' of element '" + f.detail + "' twice.");
        case K::PropertyBeforeElement: refuse(path, "PLY header has a property before any element.");
        case K::UnknownPropertyType:
            refuse(path, "unknown PLY property type '" + f.token + "' in '" + faultLine(head, f) + "'.");
        case K::MalformedFormat:
        case K::MalformedElement:
        case K::InvalidElementCount:
        case K::UnknownListType:
        case K::NonIntegerListLength:
        case K::ScalarPropertyOfTypeList:
        case K::MalformedProperty:
        case K::UnknownKeyword:
        // Only strict rules or a refused encoding give these; this reader's rules give none of them.
        case K::MalformedEndHeader:
        case K::FormatAfterElements:
        case K::ElementBeforeFormat:
        case K::EncodingNotAccepted: refuse(path, malformed);
    }
    refuse(path, malformed);
}

// Step 1: the header (any encoding, the headers tools write: lenient rules); `in` is left at the
// first byte of data.
PlyHeader readHeader(std::istream& in, const std::string& path) {
    std::string head(kMaxHeaderBytes, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    const bool wholeFile = head.size() < kMaxHeaderBytes || in.peek() == std::char_traits<char>::eof();
    PlyHeaderRules rules;
    rules.strict = false;
    PlyHeaderParse parse = parsePlyHeader(head.data(), head.size(), rules);
    if (parse.fault) refuseHeader(path, head, wholeFile, *parse.fault);
    in.clear();
    in.seekg(static_cast<std::streamoff>(parse.header.dataOffset));
    if (!in) refuse(path, "cannot be read after its PLY header (the file changed or the disk failed); check the file.");
    return std::move(parse.header);
}

// Where each splat quantity sits in a vertex record (property indices), and the SH degree.
struct Layout {
    int x = -1, y = -1, z = -1, opacity = -1;
    int dc[3] = {-1, -1, -1}, scale[3] = {-1, -1, -1}, rot[4] = {-1, -1, -1, -1};
    std::vector<int> rest;  // f_rest_0.. in order
    int degree = 0;
};

// Step 2: the vertex element must be a splat set.
Layout findLayout(const PlyHeader& header, std::size_t& vertexElement, const std::string& path) {
    const char* const remedy =
        " Give the .ply a 3D Gaussian Splatting trainer (point_cloud/iteration_*/point_cloud.ply) or SuperSplat "
        "(File > Export > PLY) wrote.";
    vertexElement = header.elements.size();
    for (std::size_t e = 0; e < header.elements.size(); ++e)
        if (header.elements[e].name == "vertex") vertexElement = e;
    bool compressed = false;
    for (const PlyElement& element : header.elements)
        for (const PlyProperty& p : element.properties)
            if (p.name == "packed_position") compressed = true;
    if (compressed)
        refuse(path, std::string("this is a compressed splat PLY (PlayCanvas / SuperSplat 'compressed.ply': packed "
                                 "chunks), which is not read; export the scene from SuperSplat as an uncompressed .ply "
                                 "(File > Export > PLY) and give that file."));
    if (vertexElement == header.elements.size()) refuse(path, std::string("a PLY file without vertices, not a splat file.") + remedy);
    const PlyElement& vertex = header.elements[vertexElement];
    std::map<std::string, int> index;
    for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
        if (vertex.properties[i].isList) continue;
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
        for (const PlyProperty& p : vertex.properties) have += (have.empty() ? "" : " ") + p.name;
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

// Step 3 helpers: skipping the elements stored before the vertices.
void skipElement(std::istream& in, const PlyElement& element, PlyEncoding encoding, const std::string& path) {
    if (encoding == PlyEncoding::Ascii) {
        std::string line;
        for (std::uint64_t i = 0; i < element.count; ++i)
            if (!std::getline(in, line)) refuse(path, "the file ends inside element '" + element.name + "'; it is truncated, write it again.");
        return;
    }
    if (element.hasList)
        refuse(path, "element '" + element.name + "' with list properties comes before the splats; save the splats "
                     "as the file's first element (as 3D Gaussian Splatting and SuperSplat do).");
    in.seekg(static_cast<std::streamoff>(element.scalarBytes * element.count), std::ios::cur);
    if (!in) refuse(path, "the file ends inside element '" + element.name + "'; it is truncated, write it again.");
}

}  // namespace

GaussianSplats readGaussianSplatPly(const std::string& path, const ProgressCallback& progress) {
    std::ifstream in(path, std::ios::binary);
    if (!in) refuse(path, "cannot be opened (missing or unreadable); check the path.");
    const PlyHeader header = readHeader(in, path);
    std::size_t vertexIndex = 0;
    const Layout layout = findLayout(header, vertexIndex, path);
    const PlyElement& vertex = header.elements[vertexIndex];
    if (vertex.count == 0) refuse(path, "it holds no splats (element vertex 0); give a trained scene.");
    const bool ascii = header.encoding == PlyEncoding::Ascii;
    if (!ascii && vertex.hasList)
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

    const bool bigEndian = header.encoding == PlyEncoding::BinaryBigEndian;
    const std::size_t recordBytes = vertex.scalarBytes;
    const std::size_t propertyCount = vertex.properties.size();
    std::vector<double> values(propertyCount);
    const std::size_t chunk = 4096;
    std::vector<unsigned char> bytes;
    std::string line;
    for (std::size_t first = 0; first < n; first += chunk) {
        reportProgress(progress, double(first) / n, "Reading splats");
        const std::size_t last = std::min(n, first + chunk);
        if (!ascii) {
            bytes.resize((last - first) * recordBytes);
            in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
            if (static_cast<std::size_t>(in.gcount()) != bytes.size())
                refuse(path, "the file ends at splat " + std::to_string(first + in.gcount() / recordBytes) + " of " +
                                 std::to_string(n) + " its header announces; it is truncated, write it again.");
        }
        for (std::size_t s = first; s < last; ++s) {
            // 3a. The record's values, by property index.
            if (ascii) {
                if (!std::getline(in, line))
                    refuse(path, "the file ends at splat " + std::to_string(s) + " of " + std::to_string(n) +
                                     " its header announces; it is truncated, write it again.");
                const char* p = line.data();
                const char* end = line.data() + line.size();
                for (std::size_t i = 0; i < propertyCount; ++i) {
                    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
                    if (vertex.properties[i].isList) refuse(path, "its splats have list properties, which a splat file does not have; export it again.");
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
                const unsigned char* record = bytes.data() + (s - first) * recordBytes;
                for (std::size_t i = 0; i < propertyCount; ++i) {
                    const PlyProperty& p = vertex.properties[i];
                    values[i] = readPlyNumber(record + p.offset, p.type, bigEndian);
                }
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
