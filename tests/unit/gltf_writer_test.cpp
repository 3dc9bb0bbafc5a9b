// io/gltf_writer.h: the GLB container read back here byte by byte (header, chunk types, lengths,
// 4-byte alignment: glTF 2.0 sec. 4.4), the vertex split at UV seams, v flipped, tangents and
// their signs, min / max of POSITION, refusals. A full parse by a glTF reader and an import by
// Blender are in tests/python/test_pymeshlab_gltf.py.
#include "io/gltf_writer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

std::uint32_t u32(const std::vector<unsigned char>& b, std::size_t at) {
    return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
           std::uint32_t(b[at + 3]) << 24;
}

struct Glb {
    std::string json;
    std::vector<unsigned char> bin;
};

Glb parse(const std::vector<unsigned char>& b) {
    Glb g;
    EXPECT_GE(b.size(), 28u);
    EXPECT_EQ(u32(b, 0), 0x46546C67u) << "magic glTF";
    EXPECT_EQ(u32(b, 4), 2u) << "version";
    EXPECT_EQ(u32(b, 8), b.size()) << "total length";
    const std::uint32_t jsonLength = u32(b, 12);
    EXPECT_EQ(u32(b, 16), 0x4E4F534Au) << "JSON chunk";
    EXPECT_EQ(jsonLength % 4, 0u);
    g.json.assign(reinterpret_cast<const char*>(b.data() + 20), jsonLength);
    const std::size_t binAt = 20 + jsonLength;
    const std::uint32_t binLength = u32(b, binAt);
    EXPECT_EQ(u32(b, binAt + 4), 0x004E4942u) << "BIN chunk";
    EXPECT_EQ(binLength % 4, 0u);
    EXPECT_EQ(binAt + 8 + binLength, b.size());
    g.bin.assign(b.begin() + binAt + 8, b.end());
    return g;
}

// A square [0, 2] x [0, 1] as two triangles, normal +z; corner UVs (u = x / 2, v = y) given per face.
struct Quad {
    std::vector<float> positions = {0, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0};
    std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    std::vector<std::uint32_t> faces = {0, 1, 2, 0, 2, 3};
    std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
    std::vector<float> tangents = std::vector<float>(24, 0.0f);
    Quad() {
        for (int c = 0; c < 6; ++c) {
            tangents[4 * c] = 1.0f;
            tangents[4 * c + 3] = 1.0f;
        }
    }
    rad::GltfMesh mesh() const {
        rad::GltfMesh m;
        m.positions = positions.data();
        m.normals = normals.data();
        m.vertexCount = 4;
        m.faces = faces.data();
        m.faceCount = 2;
        m.wedgeUv = uv.data();
        m.cornerTangents = tangents.data();
        return m;
    }
};

TEST(GltfWriter, ContainerHeaderChunksAndJsonAreWellFormed) {
    Quad q;
    rad::GltfMesh m = q.mesh();
    m.normalTexturePng = {0x89, 'P', 'N', 'G', 1, 2, 3};  // opaque bytes: the writer only embeds them
    m.name = "quad \"one\"";
    const Glb g = parse(rad::buildGlb(m));
    EXPECT_NE(g.json.find("\"version\":\"2.0\""), std::string::npos);
    EXPECT_NE(g.json.find("\"TANGENT\":3"), std::string::npos);
    EXPECT_NE(g.json.find("\"normalTexture\":{\"index\":0}"), std::string::npos);
    EXPECT_NE(g.json.find("\"mimeType\":\"image/png\""), std::string::npos);
    EXPECT_NE(g.json.find("\"name\":\"quad \\\"one\\\"\""), std::string::npos) << "name not escaped: " << g.json;
    EXPECT_NE(g.json.find("\"min\":[0,0,0],\"max\":[2,1,0]"), std::string::npos) << g.json;
    EXPECT_NE(g.json.find("\"byteLength\":" + std::to_string(g.bin.size()) + "}"), std::string::npos);
    // Four vertices (no seam), six indices.
    EXPECT_NE(g.json.find("\"count\":4,\"type\":\"VEC3\",\"min\""), std::string::npos);
    EXPECT_NE(g.json.find("\"count\":6,\"type\":\"SCALAR\""), std::string::npos);
    // The JSON is padded with spaces only.
    EXPECT_EQ(g.json.find('\0'), std::string::npos);
    // The PNG bytes are in the binary chunk.
    const unsigned char png[] = {0x89, 'P', 'N', 'G', 1, 2, 3};
    EXPECT_NE(std::search(g.bin.begin(), g.bin.end(), png, png + 7), g.bin.end());
}

TEST(GltfWriter, AttributesAreWrittenInCornerOrderWithVFlipped) {
    // Layout (gltf_writer.cpp): positions at 0, then normals, UVs, tangents, indices; glTF vertex
    // i is the first corner that needed it: corners 0, 1, 2 (vertices 0, 1, 2), corner 5 (vertex 3).
    Quad q;
    const Glb g = parse(rad::buildGlb(q.mesh()));
    const auto f = [&](std::size_t at) {
        float v;
        std::memcpy(&v, g.bin.data() + at, 4);
        return v;
    };
    const std::size_t n = 4;
    const std::uint32_t vertexOrder[4] = {0, 1, 2, 3};
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(f(12 * i + 4 * k), q.positions[3 * vertexOrder[i] + k]) << i;
    const std::size_t uvAt = 24 * n;  // after positions and normals
    // Vertex 3 = (0, 1) has UV (0, 1) -> glTF (0, 0); vertex 1 = (2, 0) has (1, 0) -> (1, 1).
    EXPECT_EQ(f(uvAt + 8 * 3), 0.0f);
    EXPECT_EQ(f(uvAt + 8 * 3 + 4), 0.0f);
    EXPECT_EQ(f(uvAt + 8 * 1), 1.0f);
    EXPECT_EQ(f(uvAt + 8 * 1 + 4), 1.0f);
    const std::size_t tangentAt = uvAt + 8 * n;
    for (std::size_t i = 0; i < n; ++i) {
        EXPECT_EQ(f(tangentAt + 16 * i), 1.0f);
        EXPECT_EQ(f(tangentAt + 16 * i + 12), 1.0f);
    }
    const std::size_t indexAt = tangentAt + 16 * n;
    const std::uint32_t expected[6] = {0, 1, 2, 0, 2, 3};
    for (int c = 0; c < 6; ++c) EXPECT_EQ(u32(g.bin, indexAt + 4 * c), expected[c]) << c;
}

TEST(GltfWriter, VerticesAreSplitAtUvSeamsAndTangentSignChanges) {
    Quad q;
    q.uv[6] = 0.5f;  // corner 3 (vertex 0 in face 1) gets another UV: a seam
    EXPECT_EQ(rad::gltfVertexCount(q.mesh()), 5u);
    Quad mirrored;
    for (int c = 3; c < 6; ++c) mirrored.tangents[4 * c + 3] = -1.0f;  // face 1 mirrored: its shared corners split
    EXPECT_EQ(rad::gltfVertexCount(mirrored.mesh()), 6u);
    const Glb g = parse(rad::buildGlb(mirrored.mesh()));
    std::size_t negative = 0;
    const std::size_t tangentAt = 6 * (12 + 12 + 8);
    for (std::size_t i = 0; i < 6; ++i) {
        float w;
        std::memcpy(&w, g.bin.data() + tangentAt + 16 * i + 12, 4);
        EXPECT_TRUE(w == 1.0f || w == -1.0f);
        negative += w < 0;
    }
    EXPECT_EQ(negative, 3u);
}

TEST(GltfWriter, RefusesWhatGltfCannotHold) {
    Quad q;
    rad::GltfMesh m = q.mesh();
    m.cornerTangents = nullptr;
    m.normalTexturePng = {1, 2, 3};
    EXPECT_THROW(rad::buildGlb(m), rad::GltfInputError);
    Quad bad;
    bad.positions[4] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(rad::buildGlb(bad.mesh()), rad::GltfInputError);
    Quad outOfRange;
    outOfRange.faces[5] = 9;
    EXPECT_THROW(rad::buildGlb(outOfRange.mesh()), rad::GltfInputError);
    // Without a normal texture the tangents may be left out: no TANGENT attribute then.
    Quad plain;
    rad::GltfMesh noTangents = plain.mesh();
    noTangents.cornerTangents = nullptr;
    const Glb g = parse(rad::buildGlb(noTangents));
    EXPECT_EQ(g.json.find("TANGENT"), std::string::npos);
}

}  // namespace
