// make_scene: writes one of the generated scenes of geometry/primitive_meshes.h (exact per-vertex
// normals) as a binary little-endian PLY or an ASCII NOFF file, for MeshLab and the tests.
//
//   make_scene sphere  [--level 4] [--radius 1] -o sphere.ply          icosphere (Vanhoey et al. 2015 Fig. 8)
//   make_scene uvsphere [--stacks 32] [--slices 64] [--radius 1] -o uv.ply
//   make_scene quad    [--tilt 30] [--size 1] -o quad.ply              Vanhoey et al. 2015 Fig. 6 (tilt in degrees)
//   make_scene column  [--segments 16] [--rings 4] [--radius 0.15] [--height 1]
//                      [--ground 8] [--ground-size 1] -o column.ply    Křivánek et al. 2004 Fig. 1
//   make_scene torus   [--major 1] [--minor 0.35] [--major-segments 48] [--minor-segments 24] -o torus.off
//
// The format follows the output's extension: .ply -> binary_little_endian PLY with
// "x y z nx ny nz" floats per vertex and "list uchar int vertex_indices" faces; .off -> NOFF
// (positions and normals, one vertex per line), which MeshLab's OFF importer reads too.
#include "geometry/primitive_meshes.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

void usage(std::ostream& out) {
    out << "usage: make_scene SCENE [options] -o OUTPUT.{ply,off}\n"
           "scenes and their options (defaults in brackets):\n"
           "  sphere    --level [4] --radius [1]                  icosphere, 10*4^level+2 vertices\n"
           "  uvsphere  --stacks [32] --slices [64] --radius [1]  latitude/longitude sphere\n"
           "  quad      --tilt [30] --size [1]                    4-vertex quad, normals tilted outwards\n"
           "                                                      by --tilt degrees (Vanhoey et al. 2015 Fig. 6)\n"
           "  column    --segments [16] --rings [4] --radius [0.15] --height [1]\n"
           "            --ground [8] --ground-size [1]            column on a ground plane (Křivánek et al. 2004 Fig. 1)\n"
           "  torus     --major [1] --minor [0.35] --major-segments [48] --minor-segments [24]\n"
           "output: .ply = binary little-endian PLY (x y z nx ny nz, faces as uchar/int lists),\n"
           "        .off = ASCII NOFF (positions and normals)\n";
}

using radtools::UsageError;

void putU32(std::ostream& out, std::uint32_t v) {
    const unsigned char b[4] = {static_cast<unsigned char>(v), static_cast<unsigned char>(v >> 8),
                                static_cast<unsigned char>(v >> 16), static_cast<unsigned char>(v >> 24)};
    out.write(reinterpret_cast<const char*>(b), 4);
}

void putF32(std::ostream& out, float f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, 4);
    putU32(out, bits);
}

void writePly(const rad::TriangleMesh& m, const std::string& path, const std::string& comment) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error("cannot write " + path);
    out << "ply\nformat binary_little_endian 1.0\ncomment " << comment << "\n"
        << "element vertex " << m.vertexCount() << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property float nx\nproperty float ny\nproperty float nz\n"
        << "element face " << m.faceCount() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        for (int k = 0; k < 3; ++k) putF32(out, m.positions[3 * v + k]);
        for (int k = 0; k < 3; ++k) putF32(out, m.normals[3 * v + k]);
    }
    for (std::size_t f = 0; f < m.faceCount(); ++f) {
        out.put(3);
        for (int k = 0; k < 3; ++k) putU32(out, m.faces[3 * f + k]);  // int32: indices < 2^31
    }
    if (!out.flush()) throw std::runtime_error("error while writing " + path);
}

void writeNoff(const rad::TriangleMesh& m, const std::string& path, const std::string& comment) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + path);
    std::fprintf(f, "NOFF\n# %s\n%zu %zu 0\n", comment.c_str(), m.vertexCount(), m.faceCount());
    // %.9g round-trips a float exactly; "C" locale in a plain program.
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        const float* p = &m.positions[3 * v];
        const float* n = &m.normals[3 * v];
        std::fprintf(f, "%.9g %.9g %.9g %.9g %.9g %.9g\n", p[0], p[1], p[2], n[0], n[1], n[2]);
    }
    for (std::size_t i = 0; i < m.faceCount(); ++i)
        std::fprintf(f, "3 %u %u %u\n", static_cast<unsigned>(m.faces[3 * i]), static_cast<unsigned>(m.faces[3 * i + 1]),
                     static_cast<unsigned>(m.faces[3 * i + 2]));
    const bool ok = std::ferror(f) == 0;
    if (std::fclose(f) != 0 || !ok) throw std::runtime_error("error while writing " + path);
}

bool endsWith(const std::string& s, const std::string& suffix) {
    if (s.size() < suffix.size()) return false;
    std::string tail = s.substr(s.size() - suffix.size());
    for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return tail == suffix;
}

int run(int argc, char** argv) {
    if (argc < 2) throw UsageError("no scene given");
    const std::string scene = argv[1];
    if (scene == "-h" || scene == "--help") {
        usage(std::cout);
        return 0;
    }
    static const std::map<std::string, std::set<std::string>> allowed = {
        {"sphere", {"level", "radius"}},
        {"uvsphere", {"stacks", "slices", "radius"}},
        {"quad", {"tilt", "size"}},
        {"column", {"segments", "rings", "radius", "height", "ground", "ground-size"}},
        {"torus", {"major", "minor", "major-segments", "minor-segments"}},
    };
    const auto keys = allowed.find(scene);
    if (keys == allowed.end()) throw UsageError("unknown scene '" + scene + "'");

    std::map<std::string, std::string> opt;
    std::string output;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string value = argv[++i];
        if (a == "-o" || a == "--output") {
            output = value;
        } else if (a.rfind("--", 0) == 0 && keys->second.count(a.substr(2))) {
            opt[a.substr(2)] = value;
        } else {
            throw UsageError("unknown option '" + a + "' for scene " + scene);
        }
    }
    if (output.empty()) throw UsageError("no output file (-o FILE.ply or FILE.off)");
    const bool ply = endsWith(output, ".ply");
    if (!ply && !endsWith(output, ".off")) throw UsageError("output must end in .ply or .off: " + output);

    auto num = [&](const std::string& k, double def) { return opt.count(k) ? radtools::toNumber("--" + k, opt[k]) : def; };
    auto integer = [&](const std::string& k, int def) { return opt.count(k) ? radtools::toInt("--" + k, opt[k]) : def; };

    rad::TriangleMesh mesh;
    std::string comment = "make_scene " + scene;
    for (const auto& [k, v] : opt) comment += " --" + k + " " + v;
    if (scene == "sphere") {
        mesh = rad::makeIcosphere(integer("level", 4), static_cast<float>(num("radius", 1.0)));
    } else if (scene == "uvsphere") {
        mesh = rad::makeUvSphere(integer("stacks", 32), integer("slices", 64), static_cast<float>(num("radius", 1.0)));
    } else if (scene == "quad") {
        mesh = rad::makeDivergingQuad(static_cast<float>(num("tilt", 30.0) * kPi / 180.0),
                                      static_cast<float>(num("size", 1.0)));
    } else if (scene == "column") {
        rad::ColumnSceneOptions o;
        o.segments = integer("segments", o.segments);
        o.heightRings = integer("rings", o.heightRings);
        o.radius = static_cast<float>(num("radius", o.radius));
        o.height = static_cast<float>(num("height", o.height));
        o.groundResolution = integer("ground", o.groundResolution);
        o.groundHalfSize = static_cast<float>(num("ground-size", o.groundHalfSize));
        mesh = rad::makeColumnOnPlane(o);
    } else {
        mesh = rad::makeTorus(static_cast<float>(num("major", 1.0)), static_cast<float>(num("minor", 0.35)),
                              integer("major-segments", 48), integer("minor-segments", 24));
    }
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw std::runtime_error("generated mesh is invalid: " + problem);

    if (ply)
        writePly(mesh, output, comment);
    else
        writeNoff(mesh, output, comment);
    std::cout << "wrote " << output << ": " << scene << ", " << mesh.vertexCount() << " vertices, " << mesh.faceCount()
              << " faces\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    // Parameters refused by the generators (std::invalid_argument) exit with 2, as usage errors.
    return radtools::runTool("make_scene", argc, argv, run, usage, /*invalidArgumentIsUsage=*/true);
}
