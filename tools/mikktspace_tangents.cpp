// Prints the MikkTSpace tangents (geometry/mikktspace_tangents.h, Mikkelsen 2008) of a triangle
// mesh given as text, one line "tx ty tz sign" per face corner: what the Blender comparison
// (tests/blender/) and anyone checking another tool's tangents need.
//
// Input (the format tests/blender/export_blender_tangents.py writes):
//   vertices N        then N lines "x y z"
//   faces F           then F lines "a b c" (vertex indices)
//   corners 3F        then 3F lines "nx ny nz u v" (per-corner normal and UV)
// Usage: mikktspace_tangents MESH.txt [--per-vertex-uv]
//   --per-vertex-uv  first checks that every vertex has one UV and one normal, then computes
//                    with per-vertex arrays (the path a PLY with texture_u / texture_v takes)
#include "command_line.h"
#include "geometry/mikktspace_tangents.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

std::size_t readCount(std::istream& in, const std::string& keyword) {
    std::string word;
    std::size_t count = 0;
    if (!(in >> word >> count) || word != keyword)
        throw radtools::UsageError("expected '" + keyword + " <count>' in the mesh file");
    return count;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        std::string path;
        bool perVertexUv = false;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--per-vertex-uv") perVertexUv = true;
            else if (path.empty()) path = a;
            else throw radtools::UsageError("unexpected argument " + a);
        }
        if (path.empty()) throw radtools::UsageError("no mesh file given");
        std::ifstream in(path);
        if (!in) throw std::runtime_error("cannot read " + path);
        const std::size_t n = readCount(in, "vertices");
        std::vector<float> positions(3 * n);
        for (float& x : positions) in >> x;
        const std::size_t f = readCount(in, "faces");
        std::vector<std::uint32_t> faces(3 * f);
        for (std::uint32_t& i : faces) in >> i;
        const std::size_t c = readCount(in, "corners");
        if (c != 3 * f) throw radtools::UsageError("corners must be 3 x faces");
        std::vector<float> normals(3 * c), uv(2 * c);
        for (std::size_t k = 0; k < c; ++k) in >> normals[3 * k] >> normals[3 * k + 1] >> normals[3 * k + 2] >> uv[2 * k] >> uv[2 * k + 1];
        if (!in) throw std::runtime_error(path + ": truncated or not numbers");

        rad::TangentSpaceInput input;
        input.positions = positions.data();
        input.vertexCount = n;
        input.faces = faces.data();
        input.faceCount = f;
        input.normals = normals.data();
        input.normalRate = rad::AttributeRate::PerCorner;
        input.uv = uv.data();
        input.uvRate = rad::AttributeRate::PerCorner;
        std::vector<float> vertexNormals, vertexUv;
        if (perVertexUv) {
            vertexNormals.assign(3 * n, 0.0f);
            vertexUv.assign(2 * n, 0.0f);
            std::vector<char> seen(n, 0);
            for (std::size_t k = 0; k < c; ++k) {
                const std::uint32_t v = faces[k];
                if (v >= n) throw std::runtime_error("vertex index out of range");
                if (seen[v] && (vertexUv[2 * v] != uv[2 * k] || vertexUv[2 * v + 1] != uv[2 * k + 1] ||
                                vertexNormals[3 * v] != normals[3 * k] || vertexNormals[3 * v + 1] != normals[3 * k + 1] ||
                                vertexNormals[3 * v + 2] != normals[3 * k + 2]))
                    throw std::runtime_error("--per-vertex-uv: vertex " + std::to_string(v) +
                                             " has several UVs or normals (a seam): this mesh needs per-corner input");
                seen[v] = 1;
                for (int j = 0; j < 3; ++j) vertexNormals[3 * v + j] = normals[3 * k + j];
                for (int j = 0; j < 2; ++j) vertexUv[2 * v + j] = uv[2 * k + j];
            }
            input.normals = vertexNormals.data();
            input.normalRate = rad::AttributeRate::PerVertex;
            input.uv = vertexUv.data();
            input.uvRate = rad::AttributeRate::PerVertex;
        }
        const rad::CornerTangents result = rad::computeMikkTSpaceTangents(input);
        for (std::size_t k = 0; k < c; ++k) {
            const float* t = result.tangents.data() + 4 * k;
            std::printf("%.9g %.9g %.9g %g\n", t[0], t[1], t[2], t[3]);
        }
        std::fprintf(stderr, "%zu corners, %zu degenerate triangles, %zu triangles without UV derivatives, %zu default frames, %zu zero tangents\n",
                     c, result.degenerateTriangles, result.zeroUvAreaTriangles, result.defaultFrameCorners, result.zeroTangentCorners);
        return 0;
    } catch (const radtools::UsageError& e) {
        std::cerr << "mikktspace_tangents: " << e.what() << "\nusage: mikktspace_tangents MESH.txt [--per-vertex-uv]\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "mikktspace_tangents: " << e.what() << "\n";
        return 1;
    }
}
