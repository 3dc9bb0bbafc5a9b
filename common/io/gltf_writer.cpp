// glTF 2.0 binary writer (gltf_writer.h). Layout of the binary chunk: the vertex attributes and
// the indices (each view 4-byte aligned, as accessors of 4-byte components require), then the
// PNG images; the JSON refers to them by byte offset.
#include "io/gltf_writer.h"

#include "io/glb_container.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace rad {

namespace {

struct SplitVertex {
    std::uint32_t vertex;
    std::uint32_t bits[6];  // u, v, tangent x, y, z, w (bit patterns)
    bool operator==(const SplitVertex& o) const {
        return vertex == o.vertex && std::memcmp(bits, o.bits, sizeof bits) == 0;
    }
};
struct SplitVertexHash {
    std::size_t operator()(const SplitVertex& k) const {
        std::uint64_t h = 1469598103934665603ull ^ k.vertex;
        for (std::uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
        return std::size_t(h ^ (h >> 31));
    }
};

std::uint32_t bitsOf(float f) {
    std::uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
}

void check(const GltfMesh& m) {
    if (!m.positions || !m.normals || !m.faces || !m.wedgeUv || m.vertexCount == 0 || m.faceCount == 0)
        throw GltfInputError("A glTF file needs a mesh with vertices, vertex normals, faces and texture coordinates.");
    if (!m.normalTexturePng.empty() && !m.cornerTangents)
        throw GltfInputError("A glTF normal texture needs tangents (MikkTSpace) for every face corner.");
    for (std::size_t i = 0; i < 3 * m.faceCount; ++i)
        if (m.faces[i] >= m.vertexCount)
            throw GltfInputError("Face " + std::to_string(i / 3) + " refers to vertex " + std::to_string(m.faces[i]) +
                                 ", beyond the " + std::to_string(m.vertexCount) + " vertices.");
    for (std::size_t i = 0; i < 3 * m.vertexCount; ++i)
        if (!std::isfinite(m.positions[i]) || !std::isfinite(m.normals[i]))
            throw GltfInputError("Vertex " + std::to_string(i / 3) +
                                 " has a coordinate or normal that is not a finite number; glTF forbids them.");
    for (std::size_t i = 0; i < 6 * m.faceCount; ++i)
        if (!std::isfinite(m.wedgeUv[i]))
            throw GltfInputError("Face " + std::to_string(i / 6) + " has a texture coordinate that is not a number.");
}

// The split: per corner, the index of its glTF vertex; `first` gets one corner per glTF vertex.
std::vector<std::uint32_t> splitCorners(const GltfMesh& m, std::vector<std::size_t>& first) {
    const std::size_t corners = 3 * m.faceCount;
    std::vector<std::uint32_t> index(corners);
    std::unordered_map<SplitVertex, std::uint32_t, SplitVertexHash> seen;
    seen.reserve(corners);
    for (std::size_t c = 0; c < corners; ++c) {
        SplitVertex key{m.faces[c], {bitsOf(m.wedgeUv[2 * c]), bitsOf(m.wedgeUv[2 * c + 1]), 0, 0, 0, 0}};
        if (m.cornerTangents)
            for (int k = 0; k < 4; ++k) key.bits[2 + k] = bitsOf(m.cornerTangents[4 * c + k]);
        const auto inserted = seen.emplace(key, std::uint32_t(first.size()));
        if (inserted.second) first.push_back(c);
        index[c] = inserted.first->second;
    }
    return index;
}

}  // namespace

std::size_t gltfVertexCount(const GltfMesh& mesh) {
    check(mesh);
    std::vector<std::size_t> first;
    splitCorners(mesh, first);
    return first.size();
}

std::vector<unsigned char> buildGlb(const GltfMesh& m) {
    check(m);
    std::vector<std::size_t> first;
    const std::vector<std::uint32_t> indices = splitCorners(m, first);
    const std::size_t n = first.size();
    const bool withTangents = m.cornerTangents != nullptr;

    std::vector<float> position(3 * n), normal(3 * n), uv(2 * n), tangent(withTangents ? 4 * n : 0);
    float lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::numeric_limits<float>::max();
        hi[k] = -lo[k];
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t c = first[i];
        const std::uint32_t v = m.faces[c];
        const float* p = m.positions + 3 * std::size_t(v);
        const float* q = m.normals + 3 * std::size_t(v);
        const float length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        for (int k = 0; k < 3; ++k) {
            position[3 * i + k] = p[k];
            lo[k] = std::min(lo[k], p[k]);
            hi[k] = std::max(hi[k], p[k]);
            // A zero normal (which glTF forbids) becomes +z rather than NaN.
            normal[3 * i + k] = length > 0 ? q[k] / length : (k == 2 ? 1.0f : 0.0f);
        }
        uv[2 * i] = m.wedgeUv[2 * c];
        uv[2 * i + 1] = 1.0f - m.wedgeUv[2 * c + 1];
        if (withTangents) {
            const float* t = m.cornerTangents + 4 * c;
            for (int k = 0; k < 4; ++k) tangent[4 * i + k] = t[k];
            tangent[4 * i + 3] = t[3] < 0 ? -1.0f : 1.0f;
        }
    }

    GlbBinary bin;
    const std::size_t positionView = bin.addView(position.data(), position.size() * 4, 34962);
    const std::size_t normalView = bin.addView(normal.data(), normal.size() * 4, 34962);
    const std::size_t uvView = bin.addView(uv.data(), uv.size() * 4, 34962);
    const std::size_t tangentView = withTangents ? bin.addView(tangent.data(), tangent.size() * 4, 34962) : 0;
    const std::size_t indexView = bin.addView(indices.data(), indices.size() * 4, 34963);
    struct Texture {
        const char* role;
        std::size_t view;
    };
    std::vector<Texture> textures;
    for (const auto& [role, png] : {std::pair<const char*, const std::vector<unsigned char>*>{"normal", &m.normalTexturePng},
                                    {"baseColor", &m.baseColorTexturePng},
                                    {"metallicRoughness", &m.metallicRoughnessTexturePng}})
        if (!png->empty()) textures.push_back({role, bin.addView(png->data(), png->size(), 0)});

    // JSON.
    std::ostringstream j;
    j << "{\"asset\":{\"version\":\"2.0\",\"generator\":" << jsonString(m.generator) << "},";
    j << "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,\"name\":" << jsonString(m.name) << "}],";
    j << "\"meshes\":[{\"name\":" << jsonString(m.name) << ",\"primitives\":[{\"attributes\":{\"POSITION\":0,"
      << "\"NORMAL\":1,\"TEXCOORD_0\":2" << (withTangents ? ",\"TANGENT\":3" : "") << "},\"indices\":"
      << (withTangents ? 4 : 3) << ",\"material\":0,\"mode\":4}]}],";
    j << "\"accessors\":[";
    j << "{\"bufferView\":" << positionView << ",\"componentType\":5126,\"count\":" << n << ",\"type\":\"VEC3\",\"min\":["
      << jsonNumber(lo[0]) << "," << jsonNumber(lo[1]) << "," << jsonNumber(lo[2]) << "],\"max\":[" << jsonNumber(hi[0]) << ","
      << jsonNumber(hi[1]) << "," << jsonNumber(hi[2]) << "]},";
    j << "{\"bufferView\":" << normalView << ",\"componentType\":5126,\"count\":" << n << ",\"type\":\"VEC3\"},";
    j << "{\"bufferView\":" << uvView << ",\"componentType\":5126,\"count\":" << n << ",\"type\":\"VEC2\"},";
    if (withTangents)
        j << "{\"bufferView\":" << tangentView << ",\"componentType\":5126,\"count\":" << n << ",\"type\":\"VEC4\"},";
    j << "{\"bufferView\":" << indexView << ",\"componentType\":5125,\"count\":" << indices.size()
      << ",\"type\":\"SCALAR\"}],";
    j << bin.viewsJson();
    int normalIndex = -1, baseColorIndex = -1, metallicRoughnessIndex = -1;
    if (!textures.empty()) {
        j << ",\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":33071,\"wrapT\":33071}],\"images\":[";
        for (std::size_t i = 0; i < textures.size(); ++i)
            j << (i ? "," : "") << "{\"bufferView\":" << textures[i].view << ",\"mimeType\":\"image/png\",\"name\":\""
              << textures[i].role << "\"}";
        j << "],\"textures\":[";
        for (std::size_t i = 0; i < textures.size(); ++i) {
            j << (i ? "," : "") << "{\"sampler\":0,\"source\":" << i << "}";
            const std::string role = textures[i].role;
            (role == "normal" ? normalIndex : role == "baseColor" ? baseColorIndex : metallicRoughnessIndex) = int(i);
        }
        j << "]";
    }
    j << ",\"materials\":[{\"name\":" << jsonString(m.name + " material") << ",\"pbrMetallicRoughness\":{";
    if (baseColorIndex >= 0) j << "\"baseColorTexture\":{\"index\":" << baseColorIndex << "},";
    if (metallicRoughnessIndex >= 0) j << "\"metallicRoughnessTexture\":{\"index\":" << metallicRoughnessIndex << "},";
    j << "\"metallicFactor\":" << jsonNumber(m.metallicFactor) << ",\"roughnessFactor\":" << jsonNumber(m.roughnessFactor) << "}";
    if (normalIndex >= 0) j << ",\"normalTexture\":{\"index\":" << normalIndex << "}";
    j << "}]}";
    try {
        return assembleGlb(j.str(), bin.bytes(), "bake smaller maps or simplify the mesh further.");
    } catch (const std::length_error& e) {
        throw GltfInputError(e.what());
    }
}

}  // namespace rad
