// Writes the seed corpus of the radiance PLY fuzzer (bench/fuzz_radiance_ply.sh) into the folder
// given as argument: small valid files written by rad::writeRadiancePly (with and without radiance,
// PB and SH, colours, quality, the prt block and other blocks with metadata), variants that exercise
// the reader's tolerance (foreign properties and elements, face lists), and ASCII renderings of the
// same meshes (refused, but they reach the header parser's other branches).
#include "io/radiance_ply.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace {

rad::RadianceMesh makeMesh(std::size_t n, bool normals, bool colors, bool quality, int basis, bool blocks) {
    rad::RadianceMesh m;
    for (std::size_t v = 0; v < n; ++v) {
        m.positions.insert(m.positions.end(), {float(v), float(v % 2), float(v % 3) * 0.5f});
        if (colors) m.colors.insert(m.colors.end(), {std::uint8_t(v * 40), 20, 30, 255});
        if (quality) m.quality.push_back(0.25f * float(v));
    }
    for (std::size_t f = 0; f + 2 < n; ++f)
        m.faces.insert(m.faces.end(), {std::uint32_t(f), std::uint32_t(f + 1), std::uint32_t(f + 2)});
    if (normals || basis)
        for (std::size_t v = 0; v < n; ++v) m.normals.insert(m.normals.end(), {0.0f, 0.0f, 1.0f});
    if (basis) {
        const rad::BasisSpec spec{basis == 1 ? rad::BasisKind::HemisphericalPolynomial : rad::BasisKind::SphericalHarmonics, 1};
        rad::RadianceField rf(spec, n, basis == 2);
        for (std::size_t v = 0; v < n; ++v) {
            float* frame = rf.frame(v);
            frame[0] = 1; frame[1] = 0; frame[2] = 0; frame[3] = 0; frame[4] = 0; frame[5] = 1;
        }
        for (std::size_t i = 0; i < rf.coefficients.size(); ++i) rf.coefficients[i] = 0.01f * float(i);
        m.radiance = std::move(rf);
    }
    if (blocks) {
        rad::NamedVertexBlock prt;
        prt.prefix = "prt";
        prt.width = 4;
        prt.values.assign(4 * n, 0.5f);
        prt.metadata = {{"kind", "sh_transfer_shadowed_diffuse"}, {"sh_degree", "1"}, {"channels", "1"},
                        {"rays", "64"}, {"ray_offset", "0.0001"}, {"occluders", "mesh"}};
        m.extraBlocks.push_back(prt);
        rad::NamedVertexBlock other;
        other.prefix = "curvature";
        other.width = 2;
        other.values.assign(2 * n, -1.5f);
        other.metadata = {{"note", "two principal curvatures"}, {"empty", ""}};
        m.extraBlocks.push_back(other);
    }
    return m;
}

std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeAll(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

// The same file as ASCII PLY: the header with "format ascii 1.0", then one line per record.
std::string toAscii(const rad::RadianceMesh& m, const std::string& binary) {
    std::string header = binary.substr(0, binary.find("end_header\n") + 11);
    header.replace(header.find("binary_little_endian"), 20, "ascii");
    std::ostringstream out;
    out << header;
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        out << m.positions[3 * v] << ' ' << m.positions[3 * v + 1] << ' ' << m.positions[3 * v + 2] << '\n';
    }
    for (std::size_t f = 0; f < m.faceCount(); ++f)
        out << "3 " << m.faces[3 * f] << ' ' << m.faces[3 * f + 1] << ' ' << m.faces[3 * f + 2] << '\n';
    return out.str();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s SEED_FOLDER\n", argv[0]);
        return 2;
    }
    const std::string dir = argv[1];
    int count = 0;
    for (int basis = 0; basis < 3; ++basis)
        for (int variant = 0; variant < 4; ++variant) {
            const rad::RadianceMesh m = makeMesh(variant == 3 ? 1 : 4, variant & 1, variant & 2, variant != 0, basis, variant >= 1);
            const std::string path = dir + "/seed_" + std::to_string(count++) + ".rply";
            rad::writeRadiancePly(path, m);
            const std::string bytes = readAll(path);
            writeAll(dir + "/seed_" + std::to_string(count++) + "_ascii.ply", toAscii(m, bytes));
            if (variant == 2) {
                // Tolerated foreign content: an unknown property, a scalar element, face flags and a list.
                std::string h = bytes.substr(0, bytes.find("end_header\n"));
                std::string tail = bytes.substr(h.size() + 11);
                std::string foreign = h;
                foreign.insert(foreign.find("element face"), "property short foreign_short\n");
                std::string data;
                const std::size_t n = m.vertexCount();
                const std::size_t record = tail.size() - 13 * m.faceCount();
                const std::size_t rec = record / n;
                for (std::size_t v = 0; v < n; ++v) data += tail.substr(v * rec, rec) + std::string("\x07\x00", 2);
                foreign.replace(foreign.find("property list uchar int vertex_indices"), 38,
                                "property uchar flags\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord");
                for (std::size_t f = 0; f < m.faceCount(); ++f) {
                    data += '\x01';
                    data += tail.substr(record + 13 * f, 13);
                    data += std::string("\x02\x00\x00\x80\x3f\x00\x00\x00\x00", 9);
                }
                foreign += "\nelement material 1\nproperty float shininess\nend_header\n";
                data += std::string("\x00\x00\x80\x3f", 4);
                writeAll(dir + "/seed_" + std::to_string(count++) + "_foreign.rply", foreign + data);
            }
        }
    std::printf("%d seed files in %s\n", count, dir.c_str());
    return 0;
}
