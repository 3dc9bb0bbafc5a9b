// normal_map_error SCAN TARGET.obj MAP.png [--max-distance D] [--histogram] [--code-offset C]
//
// The quality metric of a baked object-space normal map (issue 7): how well the simplified target
// mesh, shaded with its map, reproduces the normals of the original scan.
//
// For every scan vertex s with normal n_s: the closest point of the target (RayScene::
// closestPoint) gives a face and barycentrics, hence a UV through the target's wedge coordinates;
// the map is sampled bilinearly there (texel centres as in bake/texture_atlas.h: texel (c, r) of
// a W x H map has its centre at u = (c + 0.5) / W, v = 1 - (r + 0.5) / H; clamped at the border),
// decoded with n = 2 * code / max - 1 (the encoding (x + 1) / 2 * 255 or 65535 of
// bake/normal_baker.h) and renormalised; the error is the angle between that normal and n_s.
// Prints the count, mean, median, 95th percentile and maximum in degrees (and a histogram).
//
// Why this correspondence: our baker fills a texel by casting a ray from the target along the
// target's normal to the scan; MeshLab's "Transfer: Vertex Attributes to Texture" takes, for a
// texel, the nearest scan point to the target point. Going the other way round (each scan vertex
// to its nearest target point) is neither of the two, so the metric favours neither; and it
// weights the scan uniformly per vertex, i.e. by the detail the scan actually has.
//
// Inputs:
//   SCAN    OFF (NOFF for normals), binary little-endian PLY, or OBJ. Its vertex normals are used
//           when the file has them; otherwise area-weighted face normals are computed (MeshLab's
//           default weighting, geometry/mesh_normals.h) and the tool says so. Faces are needed only
//           for that.
//   TARGET  OBJ with per-wedge texture coordinates (io/obj_mesh.h).
//   MAP     PNG, 8 or 16 bit, RGB (or RGBA: alpha ignored), object space.
// Options:
//   --max-distance D  skip scan vertices farther than D from the target (reported); default: none
//   --histogram       also print how many errors fall in [0,1), [1,2), [2,5), [5,10), [10,20),
//                     [20,45), [45,90), [90,180] degrees
//   --code-offset C   add C codes before decoding. MeshLab's transfer truncates (n + 1) / 2 * 255 to
//                     an integer (vcg::Color4b from float), i.e. a code stands for [k, k + 1):
//                     --code-offset 0.5 decodes its codes at their centre. Default 0 (our baker
//                     rounds).
// Exit status: 0, 1 on an input error, 2 on a usage error.
#include "command_line.h"
#include "geometry/mesh_normals.h"
#include "image/image_io.h"
#include "io/obj_mesh.h"
#include "io/off_reader.h"
#include "io/radiance_ply.h"
#include "raycast/ray_scene.h"

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace {

void usage(std::ostream& out) {
    out << "usage: normal_map_error SCAN(.off|.ply|.obj) TARGET.obj MAP.png [--max-distance D] [--histogram]\n"
           "                        [--code-offset C]\n";
}

std::string lowerExtension(const std::string& path) {
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return "";
    std::string e = path.substr(dot + 1);
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

rad::TriangleMesh readScan(const std::string& path) {
    const std::string ext = lowerExtension(path);
    if (ext == "off") return rad::readOff(path);
    if (ext == "obj") return rad::readObj(path).mesh;
    if (ext == "ply" || ext == "rply") {
        rad::RadianceMesh m = rad::readRadiancePly(path);
        rad::TriangleMesh t;
        t.positions = std::move(m.positions);
        t.normals = std::move(m.normals);
        t.faces = std::move(m.faces);
        return t;
    }
    throw radtools::UsageError("the scan '" + path + "' is not .off, .ply or .obj");
}

struct NormalMap {
    int width = 0, height = 0, channels = 0;
    std::vector<std::uint16_t> codes;
    float offset = 0.0f;

    Eigen::Vector3f texel(int c, int r) const {
        const std::uint16_t* p = codes.data() + (std::size_t(r) * width + c) * channels;
        Eigen::Vector3f n;
        for (int k = 0; k < 3; ++k) n[k] = (float(p[k]) + offset * 257.0f) / 65535.0f * 2.0f - 1.0f;
        return n;
    }
    // Bilinear at (u, v), v up, clamped to the border texels; renormalised (zero if degenerate).
    Eigen::Vector3f sample(float u, float v) const {
        const float x = std::min(std::max(u * width - 0.5f, 0.0f), float(width - 1));
        const float y = std::min(std::max((1.0f - v) * height - 0.5f, 0.0f), float(height - 1));
        const int x0 = std::min(int(x), width - 1), y0 = std::min(int(y), height - 1);
        const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
        const float fx = x - x0, fy = y - y0;
        const Eigen::Vector3f n = (1 - fx) * (1 - fy) * texel(x0, y0) + fx * (1 - fy) * texel(x1, y0) +
                                  (1 - fx) * fy * texel(x0, y1) + fx * fy * texel(x1, y1);
        const float len = n.norm();
        return len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero();
    }
};

int run(int argc, char** argv) {
    std::vector<std::string> positional;
    float maxDistance = std::numeric_limits<float>::infinity();
    bool histogram = false;
    float codeOffset = 0.0f;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw radtools::UsageError(a + " needs a value");
            return argv[++i];
        };
        if (a == "--max-distance") {
            maxDistance = float(radtools::toNumber(a, value()));
            if (!(maxDistance > 0)) throw radtools::UsageError("--max-distance must be positive");
        } else if (a == "--histogram") {
            histogram = true;
        } else if (a == "--code-offset") {
            codeOffset = float(radtools::toNumber(a, value()));
        } else if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        } else if (!a.empty() && a[0] == '-') {
            throw radtools::UsageError("unknown option " + a);
        } else {
            positional.push_back(a);
        }
    }
    if (positional.size() != 3) throw radtools::UsageError("expected SCAN TARGET.obj MAP.png");

    rad::TriangleMesh scan = readScan(positional[0]);
    std::string problem = scan.validate();
    if (!problem.empty()) throw std::runtime_error(positional[0] + ": " + problem);
    if (scan.vertexCount() == 0) throw std::runtime_error(positional[0] + ": no vertices");
    if (scan.hasNormals()) {
        std::printf("scan %s: %zu vertices, its own vertex normals\n", positional[0].c_str(), scan.vertexCount());
    } else {
        if (scan.faceCount() == 0)
            throw std::runtime_error(positional[0] + ": a point set without normals (nothing to compare with)");
        const std::size_t bad = rad::computeAreaWeightedNormals(scan);
        std::printf("scan %s: %zu vertices, no normals in the file: area-weighted face normals computed (%zu "
                    "vertices without one are skipped)\n",
                    positional[0].c_str(), scan.vertexCount(), bad);
    }

    const rad::ObjMesh target = rad::readObj(positional[1]);
    problem = target.mesh.validate();
    if (!problem.empty()) throw std::runtime_error(positional[1] + ": " + problem);
    if (target.mesh.faceCount() == 0) throw std::runtime_error(positional[1] + ": no faces");
    if (target.wedgeUv.empty())
        throw std::runtime_error(positional[1] + ": no texture coordinates (the map cannot be looked up)");
    std::printf("target %s: %zu vertices, %zu faces\n", positional[1].c_str(), target.mesh.vertexCount(),
                target.mesh.faceCount());

    NormalMap map;
    map.codes = rad::readPng16(positional[2], map.width, map.height, map.channels);
    map.offset = codeOffset;
    if (map.channels < 3) throw std::runtime_error(positional[2] + ": a normal map needs RGB, the file has " +
                                                   std::to_string(map.channels) + " channel(s)");
    std::printf("map %s: %d x %d\n", positional[2].c_str(), map.width, map.height);

    const rad::RayScene scene(target.mesh.positions.data(), target.mesh.vertexCount(), target.mesh.faces.data(),
                              target.mesh.faceCount());
    const std::ptrdiff_t n = std::ptrdiff_t(scan.vertexCount());
    std::vector<float> angle(std::size_t(n), -1.0f);  // -1: skipped (too far), -2: no normal
    const double radToDeg = 180.0 / 3.14159265358979323846;
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        const Eigen::Vector3f p = Eigen::Map<const Eigen::Vector3f>(scan.positions.data() + 3 * i);
        Eigen::Vector3f ns = Eigen::Map<const Eigen::Vector3f>(scan.normals.data() + 3 * i);
        const float len = ns.norm();
        if (!(len > 0)) {
            angle[std::size_t(i)] = -2.0f;
            continue;
        }
        ns /= len;
        const rad::ClosestPoint cp = scene.closestPoint(p, maxDistance);
        if (!cp.found) continue;
        const float* w = target.wedgeUv.data() + 6 * std::size_t(cp.face);
        const float b0 = 1 - cp.u - cp.v;
        const float u = b0 * w[0] + cp.u * w[2] + cp.v * w[4];
        const float v = b0 * w[1] + cp.u * w[3] + cp.v * w[5];
        const Eigen::Vector3f nm = map.sample(u, v);
        const double c = std::min(1.0, std::max(-1.0, double(nm.dot(ns))));
        angle[std::size_t(i)] = nm.squaredNorm() > 0 ? float(std::acos(c) * radToDeg) : 180.0f;
    }

    std::vector<float> errors;
    errors.reserve(angle.size());
    std::size_t skippedFar = 0, noNormal = 0;
    for (const float a : angle) {
        if (a == -1.0f) ++skippedFar;
        else if (a == -2.0f) ++noNormal;
        else errors.push_back(a);
    }
    std::printf("skipped: %zu scan vertices farther than --max-distance from the target, %zu without a normal\n",
                skippedFar, noNormal);
    if (errors.empty()) throw std::runtime_error("no scan vertex to compare");
    double sum = 0;
    for (const float e : errors) sum += e;
    std::sort(errors.begin(), errors.end());
    auto quantile = [&](double q) {
        const double pos = q * double(errors.size() - 1);
        const std::size_t lo = std::size_t(pos);
        const std::size_t hi = std::min(lo + 1, errors.size() - 1);
        return errors[lo] + (pos - double(lo)) * (errors[hi] - errors[lo]);
    };
    std::printf("normal error (degrees) over %zu scan vertices: mean %.4f  median %.4f  p95 %.4f  max %.4f\n",
                errors.size(), sum / double(errors.size()), quantile(0.5), quantile(0.95), double(errors.back()));
    if (histogram) {
        const float edges[] = {0, 1, 2, 5, 10, 20, 45, 90, 180.0001f};
        for (int b = 0; b + 1 < int(sizeof edges / sizeof edges[0]); ++b) {
            const auto count = std::lower_bound(errors.begin(), errors.end(), edges[b + 1]) -
                               std::lower_bound(errors.begin(), errors.end(), edges[b]);
            std::printf("  [%5.0f, %5.0f%c %10zu  %6.2f %%\n", double(edges[b]), std::floor(double(edges[b + 1])),
                        b + 2 == int(sizeof edges / sizeof edges[0]) ? ']' : ')', std::size_t(count),
                        100.0 * double(count) / double(errors.size()));
        }
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("normal_map_error", argc, argv, run, usage); }
