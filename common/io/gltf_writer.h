// A triangle mesh with its baked maps as one glTF 2.0 binary file (.glb), the container Blender,
// three.js, Unity and Unreal import, so that a bake made in MeshLab is used elsewhere as it is:
// positions, normals, UVs, MikkTSpace tangents (Mikkelsen 2008, what glTF's normalTexture assumes)
// and one metallic-roughness material with embedded PNG textures. Written by us, without a JSON
// library. v is written as 1 - v (glTF's v goes down); vertices are split where a corner's UV or
// tangent differs.
// Details: docs/gltf-export.md, "`common/io/gltf_writer.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct GltfMesh {
    const float* positions = nullptr;      // 3 per vertex
    const float* normals = nullptr;        // 3 per vertex (normalised when written)
    std::size_t vertexCount = 0;
    const std::uint32_t* faces = nullptr;  // 3 per triangle
    std::size_t faceCount = 0;
    const float* wedgeUv = nullptr;        // 6 per face, v upwards (MeshLab)
    const float* cornerTangents = nullptr;  // 4 per corner (x, y, z, sign); required with a normal texture
    std::vector<unsigned char> normalTexturePng;             // tangent space, +Y up; empty: none
    std::vector<unsigned char> baseColorTexturePng;          // sRGB colour; empty: none
    std::vector<unsigned char> metallicRoughnessTexturePng;  // G = roughness, B = metallic; empty: none
    float metallicFactor = 0.0f, roughnessFactor = 1.0f;     // multiply the texture (glTF 2.0 sec. 3.9.2)
    std::string name = "mesh";
    std::string generator = "radiance-tools";
};

struct GltfInputError : InputError {
    using InputError::InputError;
};

// The whole .glb file. Throws GltfInputError for missing arrays, an index out of range, a
// non-finite value, a normal texture without tangents, or a file beyond glTF's 4 GiB limit.
std::vector<unsigned char> buildGlb(const GltfMesh& mesh);

// How many vertices the .glb holds after splitting (for logs and tests).
std::size_t gltfVertexCount(const GltfMesh& mesh);

}  // namespace rad
