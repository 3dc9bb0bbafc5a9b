#include "io/ply_stream_reader.h"
#include "test_temporary_directory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

using rad::PlyStreamError;
using rad::PlyStreamReader;

std::string tmpPath(const std::string& name) { return std::string(RADIANCE_TEST_TMPDIR) + "/ply_stream_" + name; }

void writeBytes(const std::string& path, const std::string& bytes) {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    std::filesystem::remove(path);
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

// A small mesh written by hand: 5 vertices (a unit square and its centre) with normals and a colour,
// one quad (fanned into 2 triangles) and two triangles, plus an extra "edge" element.
struct Expected {
    std::vector<float> positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 0.25f};
    std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0.6f, 0.8f};
    std::vector<std::uint32_t> triangles = {0, 1, 2, 0, 2, 3, 0, 1, 4, 1, 2, 4};
};

template <typename T>
void put(std::string& out, T value, bool bigEndian) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (bigEndian) std::reverse(bytes, bytes + sizeof(T));
    out.append(bytes, sizeof(T));
}

const char* kHeaderTail =
    "element vertex 5\n"
    "property double x\nproperty double y\nproperty float z\n"
    "property uchar red\nproperty list uchar int ignored\n"
    "property float nx\nproperty float ny\nproperty float nz\n"
    "element face 3\n"
    "property uchar flags\nproperty list uchar uint vertex_indices\nproperty list uchar float texcoord\n"
    "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    "end_header\n";

// The same mesh in binary (LE or BE). Vertex records carry a colour byte and a list to skip.
std::string binaryPly(bool bigEndian) {
    const Expected e;
    std::string out = std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\ncomment hand made\n" + kHeaderTail;
    for (int v = 0; v < 5; ++v) {
        put<double>(out, e.positions[3 * v], bigEndian);
        put<double>(out, e.positions[3 * v + 1], bigEndian);
        put<float>(out, e.positions[3 * v + 2], bigEndian);
        put<std::uint8_t>(out, 200, bigEndian);
        put<std::uint8_t>(out, 2, bigEndian);
        put<std::int32_t>(out, -7, bigEndian);
        put<std::int32_t>(out, 9, bigEndian);
        for (int k = 0; k < 3; ++k) put<float>(out, e.normals[3 * v + k], bigEndian);
    }
    const std::vector<std::vector<std::uint32_t>> faces = {{0, 1, 2, 3}, {0, 1, 4}, {1, 2, 4}};
    for (const auto& f : faces) {
        put<std::uint8_t>(out, 0, bigEndian);
        put<std::uint8_t>(out, std::uint8_t(f.size()), bigEndian);
        for (std::uint32_t i : f) put<std::uint32_t>(out, i, bigEndian);
        put<std::uint8_t>(out, 2, bigEndian);
        put<float>(out, 0.5f, bigEndian);
        put<float>(out, 0.25f, bigEndian);
    }
    put<std::int32_t>(out, 0, bigEndian);
    put<std::int32_t>(out, 1, bigEndian);
    return out;
}

std::string asciiPly() {
    return std::string("ply\r\nformat ascii 1.0\n") + kHeaderTail +
           "0 0 0 200 2 -7 9 0 0 1\n"
           "1 0 0 200 2 -7 9 0 0 1\n"
           "1 1 0 200 0 0 0 1\n"
           "0 1 0 200 1 5 0 0 1\n"
           "0.5 0.5 0.25 200 0 0 0.6 0.8\n"
           "0 4 0 1 2 3 2 0.5 0.25\n"
           "0 3 0 1 4 0\n"
           "0 3 1 2 4 2 1 1\n"
           "0 1\n";
}

struct Loaded {
    std::vector<float> positions, normals;
    std::vector<std::uint32_t> triangles;
    rad::PlyStreamStats stats;
};

Loaded load(const std::string& path, std::size_t chunkVertices = 2, std::size_t chunkTriangles = 1) {
    PlyStreamReader reader(path, chunkVertices, chunkTriangles);
    Loaded out;
    std::uint64_t expectedFirst = 0;
    out.stats = reader.read(
        [&](const rad::PlyVertexChunk& c) {
            EXPECT_EQ(c.firstIndex, expectedFirst);
            expectedFirst += c.count;
            out.positions.insert(out.positions.end(), c.positions, c.positions + 3 * c.count);
            if (c.normals) out.normals.insert(out.normals.end(), c.normals, c.normals + 3 * c.count);
        },
        [&](const rad::PlyTriangleChunk& c) { out.triangles.insert(out.triangles.end(), c.indices, c.indices + 3 * c.count); });
    return out;
}

// The error message of constructing a reader and reading the file; empty when it succeeds.
std::string errorOf(const std::string& bytes, const std::string& name, std::uint64_t* offset = nullptr) {
    const std::string path = tmpPath(name);
    writeBytes(path, bytes);
    try {
        load(path);
    } catch (const PlyStreamError& e) {
        if (offset) *offset = e.byteOffset;
        return e.what();
    }
    return "";
}

TEST(PlyStreamReader, LittleEndianBigEndianAndAsciiGiveTheSameMesh) {
    const Expected e;
    for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"le.ply", binaryPly(false)},
                                      {"be.ply", binaryPly(true)},
                                      {"ascii.ply", asciiPly()}}) {
        SCOPED_TRACE(name);
        writeBytes(tmpPath(name), bytes);
        PlyStreamReader reader(tmpPath(name));
        EXPECT_EQ(reader.info().vertexCount, 5u);
        EXPECT_EQ(reader.info().faceCount, 3u);
        EXPECT_TRUE(reader.info().hasNormals);
        const Loaded got = load(tmpPath(name));
        ASSERT_EQ(got.positions.size(), e.positions.size());
        for (std::size_t i = 0; i < e.positions.size(); ++i) EXPECT_FLOAT_EQ(got.positions[i], e.positions[i]) << i;
        ASSERT_EQ(got.normals.size(), e.normals.size());
        for (std::size_t i = 0; i < e.normals.size(); ++i) EXPECT_FLOAT_EQ(got.normals[i], e.normals[i]) << i;
        EXPECT_EQ(got.triangles, e.triangles);  // the quad fanned from its first vertex
        EXPECT_EQ(got.stats.facesRead, 3u);
        EXPECT_EQ(got.stats.trianglesEmitted, 4u);
        EXPECT_EQ(got.stats.polygonsTriangulated, 1u);
    }
}

TEST(PlyStreamReader, SecondPassAndVerticesOnlyPass) {
    writeBytes(tmpPath("twice.ply"), binaryPly(false));
    PlyStreamReader reader(tmpPath("twice.ply"));
    std::size_t vertices = 0, triangles = 0;
    reader.read([&](const rad::PlyVertexChunk& c) { vertices += c.count; }, [&](const rad::PlyTriangleChunk& c) { triangles += c.count; });
    reader.read([&](const rad::PlyVertexChunk& c) { vertices += c.count; }, [&](const rad::PlyTriangleChunk& c) { triangles += c.count; }, true);
    EXPECT_EQ(vertices, 10u);
    EXPECT_EQ(triangles, 4u);
}

TEST(PlyStreamReader, FileWithoutNormalsAndIntegerCoordinates) {
    const std::string bytes =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty int x\nproperty short y\nproperty uchar z\n"
        "element face 1\nproperty list int int vertex_index\nend_header\n1 -2 3\n4 5 6\n7 8 9\n3 2 1 0\n";
    writeBytes(tmpPath("int.ply"), bytes);
    PlyStreamReader reader(tmpPath("int.ply"));
    EXPECT_FALSE(reader.info().hasNormals);
    const Loaded got = load(tmpPath("int.ply"));
    EXPECT_TRUE(got.normals.empty());
    EXPECT_EQ(got.positions, (std::vector<float>{1, -2, 3, 4, 5, 6, 7, 8, 9}));
    EXPECT_EQ(got.triangles, (std::vector<std::uint32_t>{2, 1, 0}));
}

TEST(PlyStreamReader, TruncatedFilesAreRefusedAtEveryCut) {
    for (bool ascii : {false, true}) {
        const std::string whole = ascii ? asciiPly() : binaryPly(false);
        const std::size_t header = whole.find("end_header\n") + 11;
        // Cuts inside the header, in the vertices, in the faces and in the trailing element.
        for (std::size_t cut : {std::size_t(2), header - 5, header + 3, header + 40, whole.size() - 30, whole.size() - 3}) {
            SCOPED_TRACE(std::to_string(cut) + (ascii ? " ascii" : " binary"));
            std::uint64_t offset = 0;
            const std::string message = errorOf(whole.substr(0, cut), "cut.ply", &offset);
            EXPECT_FALSE(message.empty());
            EXPECT_LE(offset, cut);
            EXPECT_TRUE(message.find("truncated") != std::string::npos || message.find("ends") != std::string::npos ||
                        message.find("not a PLY") != std::string::npos || message.find("need at least") != std::string::npos)
                << message;
        }
    }
}

TEST(PlyStreamReader, CountsBeyondTheFileAreRefusedBeforeReading) {
    std::string bytes = binaryPly(false);
    const std::size_t at = bytes.find("element face 3");
    bytes.replace(at, 14, "element face 3000000000");
    std::uint64_t offset = 0;
    const std::string message = errorOf(bytes, "counts.ply", &offset);
    EXPECT_NE(message.find("3000000000 faces"), std::string::npos) << message;
    EXPECT_NE(message.find("need at least"), std::string::npos) << message;
    EXPECT_EQ(offset, bytes.find("end_header\n") + 11);
}

TEST(PlyStreamReader, BadHeadersAreRefused) {
    EXPECT_NE(errorOf("", "empty.ply").find("not a PLY"), std::string::npos);
    EXPECT_NE(errorOf("solid cube\nfacet normal 0 0 1\n", "stl.ply").find("not a PLY"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat binary_middle_endian 1.0\nend_header\n", "fmt.ply").find("unknown format"),
              std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 2.0\nend_header\n", "ver.ply").find("version"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
                      "noz.ply").find("no x, y and z"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty flot y\nend_header\n",
                      "type.ply").find("unknown property type"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nelement vertex 0\n"
                      "property float x\nproperty float y\nproperty float z\nend_header\n", "order.ply")
                  .find("before the vertex element"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 0\nproperty float vertex_indices\nend_header\n", "facelist.ply")
                  .find("vertex_indices"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement point 1\nproperty float x\nend_header\n1\n", "novertex.ply")
                  .find("no vertex element"), std::string::npos);
}

TEST(PlyStreamReader, IndexOutOfRangeNamesTheFaceAndOffset) {
    for (bool bigEndian : {false, true}) {
        std::string bytes = binaryPly(bigEndian);
        // Third face: flags (1) + count (1) + 3 indices; its first index set to 5 (5 vertices).
        const std::size_t header = bytes.find("end_header\n") + 11;
        const std::size_t vertexBytes = 5 * (8 + 8 + 4 + 1 + 1 + 8 + 12);
        const std::size_t faceStart = header + vertexBytes + (2 + 16 + 9) + (2 + 12 + 9);
        std::string five;
        put<std::uint32_t>(five, 5, bigEndian);
        bytes.replace(faceStart + 2, 4, five);
        std::uint64_t offset = 0;
        const std::string message = errorOf(bytes, "range.ply", &offset);
        EXPECT_NE(message.find("face 2 uses vertex 5, out of range"), std::string::npos) << message;
        EXPECT_EQ(offset, faceStart);
    }
    // Negative index in ASCII.
    std::string ascii = asciiPly();
    ascii.replace(ascii.find("0 3 0 1 4 0\n"), 12, "0 3 0 -1 4 0\n");
    EXPECT_NE(errorOf(ascii, "negative.ply").find("face 1 uses vertex -1"), std::string::npos);
}

TEST(PlyStreamReader, DegenerateFacesNonFiniteAndGarbageAreRefused) {
    std::string two = asciiPly();
    two.replace(two.find("0 3 0 1 4 0\n"), 12, "0 2 0 1 0\n");
    EXPECT_NE(errorOf(two, "two.ply").find("face 1 has 2 vertices"), std::string::npos);

    std::string nan = asciiPly();
    nan.replace(nan.find("1 1 0 200"), 9, "1 nan 0 200");
    EXPECT_NE(errorOf(nan, "nan.ply").find("vertex 2 has a NaN or infinite coordinate"), std::string::npos);

    std::string inf = binaryPly(false);
    const std::size_t header = inf.find("end_header\n") + 11;
    std::string infinity;
    put<double>(infinity, std::numeric_limits<double>::infinity(), false);
    inf.replace(header + 42 + 8, 8, infinity);  // vertex 1's y
    EXPECT_NE(errorOf(inf, "inf.ply").find("vertex 1 has a NaN"), std::string::npos);

    std::string garbage = asciiPly();
    garbage.replace(garbage.find("1 0 0 200"), 9, "1 zero 0 200");
    EXPECT_NE(errorOf(garbage, "garbage.ply").find("'zero' is not a valid number"), std::string::npos);
}

TEST(PlyStreamReader, ManyChunksOfALargerGrid) {
    // A 300 x 200 grid of quads: 60,501 vertices, chunked at 1000 and 777 triangles.
    const int nx = 300, ny = 200;
    std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string((nx + 1) * (ny + 1)) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(nx * ny) +
                      "\nproperty list uchar int vertex_indices\nend_header\n";
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            put<float>(out, float(i), false);
            put<float>(out, float(j), false);
            put<float>(out, 0.0f, false);
        }
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            put<std::uint8_t>(out, 4, false);
            const int a = j * (nx + 1) + i;
            for (int v : {a, a + 1, a + nx + 2, a + nx + 1}) put<std::int32_t>(out, v, false);
        }
    writeBytes(tmpPath("grid.ply"), out);
    const Loaded got = load(tmpPath("grid.ply"), 1000, 777);
    ASSERT_EQ(got.positions.size(), 3u * (nx + 1) * (ny + 1));
    EXPECT_EQ(got.positions[3 * 1000], float(1000 % (nx + 1)));
    EXPECT_EQ(got.positions[3 * 1000 + 1], float(1000 / (nx + 1)));
    ASSERT_EQ(got.triangles.size(), 6u * nx * ny);
    const std::size_t last = 2 * (nx * ny - 1);
    const std::uint32_t a = std::uint32_t((ny - 1) * (nx + 1) + nx - 1);
    EXPECT_EQ(got.triangles[3 * last], a);
    EXPECT_EQ(got.triangles[3 * last + 1], a + 1);
    EXPECT_EQ(got.triangles[3 * last + 2], a + nx + 2);
}

TEST(PlyStreamReader, CancelStopsTheRead) {
    writeBytes(tmpPath("cancel.ply"), binaryPly(false));
    PlyStreamReader reader(tmpPath("cancel.ply"));
    EXPECT_THROW(reader.read({}, {}, false, [](double, const char*) { return false; }), rad::OperationCancelled);
}

// The out-of-core job re-opened the file by path for its second pass: a file replaced or rewritten
// in between gave a layer from one file and a map from the other, reported as success.
TEST(PlyStreamReader, AFileReplacedOrRewrittenBetweenPassesIsRefused) {
    const std::string path = tmpPath("replaced.ply");
    writeBytes(path, binaryPly(false));
    const auto count = [](PlyStreamReader& reader) {
        std::size_t vertices = 0;
        reader.read([&](const rad::PlyVertexChunk& c) { vertices += c.count; }, {});
        return vertices;
    };
    {
        PlyStreamReader reader(path);
        EXPECT_EQ(count(reader), 5u);
        writeBytes(tmpPath("replacement.ply"), binaryPly(true));  // the same mesh, another file
        std::filesystem::rename(tmpPath("replacement.ply"), path);
        try {
            count(reader);
            FAIL() << "a replaced file was read as the same one";
        } catch (const PlyStreamError& e) {
            EXPECT_NE(std::string(e.what()).find("the file changed while it was being read"), std::string::npos)
                << e.what();
        }
    }
    {
        PlyStreamReader reader(path);
        EXPECT_EQ(count(reader), 5u);
        std::ofstream(path, std::ios::binary | std::ios::app) << "appended";  // rewritten in place
        EXPECT_THROW(count(reader), PlyStreamError);
    }
}

// A folder was reported as a file that "does not exist" or "is empty".
TEST(PlyStreamReader, AFolderIsNamedAsAFolder) {
    const std::string path = tmpPath("a_folder.ply");
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
    try {
        PlyStreamReader reader(path);
        FAIL() << "a folder was opened as a PLY file";
    } catch (const PlyStreamError& e) {
        EXPECT_NE(std::string(e.what()).find("is a folder, not a PLY file"), std::string::npos) << e.what();
    }
}

// One polygon with more corners than the file has vertices was fanned until memory ran out, and
// the refusal blamed the target and the texture size.
TEST(PlyStreamReader, APolygonWithMoreCornersThanVerticesIsRefused) {
    std::string bytes =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n200";
    for (int k = 0; k < 200; ++k) bytes += " " + std::to_string(k % 3);
    bytes += "\n";
    const std::string message = errorOf(bytes, "many_corners.ply");
    EXPECT_NE(message.find("face 0 has 200 corners but the file has only 3 vertices"), std::string::npos) << message;
}

}  // namespace
