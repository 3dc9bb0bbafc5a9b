// Tests of io/off_reader.h: valid files (comments, blank lines, CRLF, counts on the header line,
// COFF / NOFF), polygon triangulation, and refusal of malformed files with a useful message. When
// samples/fetch_data.sh has filled the data cache, the CGAL meshes are read with their documented
// counts (docs data.md).
#include "io/off_reader.h"
#include "test_temporary_directory.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace {

rad::TriangleMesh parse(const std::string& text) {
    std::istringstream in(text);
    return rad::parseOff(in, "test.off");
}

// The error message of parsing `text`, or "" if it parsed.
std::string errorOf(const std::string& text) {
    try {
        parse(text);
    } catch (const rad::OffReadError& e) {
        return e.what();
    }
    return "";
}

const char* kTetrahedron =
    "OFF\n"
    "4 4 6\n"
    "0 0 0\n"
    "1 0 0\n"
    "0 1 0\n"
    "0 0 1\n"
    "3 0 2 1\n"
    "3 0 1 3\n"
    "3 0 3 2\n"
    "3 1 2 3\n";

TEST(OffReader, ReadsATetrahedron) {
    const rad::TriangleMesh m = parse(kTetrahedron);
    EXPECT_EQ(m.validate(), "");
    ASSERT_EQ(m.vertexCount(), 4u);
    ASSERT_EQ(m.faceCount(), 4u);
    EXPECT_FALSE(m.hasNormals());
    EXPECT_FLOAT_EQ(m.positions[3], 1.0f);
    EXPECT_FLOAT_EQ(m.positions[11], 1.0f);
    EXPECT_EQ(m.faces[0], 0u);
    EXPECT_EQ(m.faces[1], 2u);
    EXPECT_EQ(m.faces[2], 1u);
    EXPECT_EQ(m.faces[11], 3u);
}

TEST(OffReader, AcceptsCommentsBlankLinesCrlfAndCountsOnTheHeaderLine) {
    const rad::TriangleMesh m = parse(
        "# a comment before the header\r\n"
        "OFF 3 1 0   # counts on the header line\r\n"
        "\r\n"
        "  -1.5e0  2.25 +3   # signs and exponents\r\n"
        "# a comment between vertices\n"
        "\t4 5 6\n"
        "7 8 9\n"
        "\n"
        "3 0 1 2\n"
        "\n# trailing comment\n\n");
    ASSERT_EQ(m.vertexCount(), 3u);
    ASSERT_EQ(m.faceCount(), 1u);
    EXPECT_FLOAT_EQ(m.positions[0], -1.5f);
    EXPECT_FLOAT_EQ(m.positions[1], 2.25f);
    EXPECT_FLOAT_EQ(m.positions[2], 3.0f);
    EXPECT_FLOAT_EQ(m.positions[3], 4.0f);
}

TEST(OffReader, AcceptsTwoCountsAndIgnoresTheEdgeCount) {
    EXPECT_EQ(parse("OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").faceCount(), 1u);
    EXPECT_EQ(parse("OFF\n3 1 99\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").faceCount(), 1u);
}

TEST(OffReader, TriangulatesPolygonsAsFans) {
    // A unit cube of six quads -> 12 triangles; and one pentagon -> 3 triangles.
    const rad::TriangleMesh cube = parse(
        "OFF\n8 6 12\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
        "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n");
    EXPECT_EQ(cube.faceCount(), 12u);
    EXPECT_EQ(cube.validate(), "");
    // First quad 0 3 2 1 -> (0 3 2) (0 2 1).
    const std::uint32_t expected[6] = {0, 3, 2, 0, 2, 1};
    for (int i = 0; i < 6; ++i) EXPECT_EQ(cube.faces[i], expected[i]);

    const rad::TriangleMesh penta = parse("OFF\n5 1 0\n1 0 0\n0.3 0.9 0\n-0.8 0.6 0\n-0.8 -0.6 0\n0.3 -0.9 0\n5 0 1 2 3 4\n");
    ASSERT_EQ(penta.faceCount(), 3u);
    const std::uint32_t fan[9] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
    for (int i = 0; i < 9; ++i) EXPECT_EQ(penta.faces[i], fan[i]);
}

TEST(OffReader, ReadsNoffNormalsAndSkipsColours) {
    const rad::TriangleMesh n = parse("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 1 0\n3 0 1 2\n");
    ASSERT_TRUE(n.hasNormals());
    EXPECT_EQ(n.validate(), "");
    EXPECT_FLOAT_EQ(n.normals[2], 1.0f);
    EXPECT_FLOAT_EQ(n.normals[7], 1.0f);

    const rad::TriangleMesh c =
        parse("COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 0 255 0 255\n0 1 0 0 0 255\n3 0 1 2 0.5 0.5 0.5 1\n");
    EXPECT_FALSE(c.hasNormals());
    EXPECT_EQ(c.vertexCount(), 3u);
    EXPECT_EQ(c.faceCount(), 1u);
    EXPECT_FLOAT_EQ(c.positions[3], 1.0f);
}

TEST(OffReader, EmptyMeshIsValid) {
    const rad::TriangleMesh m = parse("OFF\n0 0 0\n");
    EXPECT_EQ(m.vertexCount(), 0u);
    EXPECT_EQ(m.faceCount(), 0u);
}

TEST(OffReader, RefusesABadHeader) {
    EXPECT_NE(errorOf("").find("empty file"), std::string::npos);
    EXPECT_NE(errorOf("PLY\n3 1 0\n").find("not an OFF file"), std::string::npos);
    EXPECT_NE(errorOf("4OFF\n3 1 0\n").find("unsupported OFF variant"), std::string::npos);
    EXPECT_NE(errorOf("OFF BINARY\n").find("binary OFF"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n").find("before the vertex and face counts"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n3\n").find("expected 'nVertices nFaces nEdges'"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n3 x 0\n").find("bad face count"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n-3 1 0\n").find("bad vertex count"), std::string::npos);
}

TEST(OffReader, RefusesTruncatedFiles) {
    const std::string e1 = errorOf("OFF\n3 1 0\n0 0 0\n1 0 0\n");
    EXPECT_NE(e1.find("file ends after 2 of 3 vertices"), std::string::npos) << e1;
    const std::string e2 = errorOf("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_NE(e2.find("file ends after 1 of 2 faces"), std::string::npos) << e2;
    // Truncated in the middle of a line.
    const std::string e3 = errorOf("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1");
    EXPECT_NE(e3.find("vertex 2 has 2 values, expected 3"), std::string::npos) << e3;
    const std::string e4 = errorOf("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1");
    EXPECT_NE(e4.find("announces 3 vertices but lists 2"), std::string::npos) << e4;
}

TEST(OffReader, RefusesBadIndicesAndValues) {
    const std::string head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    const std::string outOfRange = errorOf(head + "3 0 1 3\n");
    EXPECT_NE(outOfRange.find("refers to vertex 3 but the file has 3 vertices"), std::string::npos) << outOfRange;
    EXPECT_NE(outOfRange.find("test.off:6:"), std::string::npos) << "line number: " << outOfRange;
    EXPECT_NE(errorOf(head + "3 0 -1 2\n").find("bad vertex index"), std::string::npos);
    EXPECT_NE(errorOf(head + "3 0 1.5 2\n").find("bad vertex index"), std::string::npos);
    EXPECT_NE(errorOf(head + "3 0 1 1\n").find("uses vertex 1 twice"), std::string::npos);
    EXPECT_NE(errorOf(head + "2 0 1\n").find("at least 3 needed"), std::string::npos);
    EXPECT_NE(errorOf(head + "3 0 1 2 1 1 1 1 1\n").find("values after its indices"), std::string::npos);
    EXPECT_NE(errorOf(head + "3 0 1 2\n3 0 1 2\n").find("unexpected data after the last face"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n3 1 0\n0 0 0\n1 0 0 7\n0 1 0\n3 0 1 2\n").find("vertex 1 has 4 values"),
              std::string::npos);
    EXPECT_NE(errorOf("OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n").find("bad number 'zero'"),
              std::string::npos);
    EXPECT_NE(errorOf("OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n").find("bad number"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n3 1 0\n0 0 0\n1e300 0 0\n0 1 0\n3 0 1 2\n").find("bad number"), std::string::npos);
}

TEST(OffReader, ReadsFilesAndReportsMissingOnes) {
    const std::string path = std::string(RADIANCE_TEST_TMPDIR) + "/off_reader_tetra.off";
    {
        std::ofstream out(path);
        out << kTetrahedron;
    }
    EXPECT_EQ(rad::readOff(path).faceCount(), 4u);
    try {
        rad::readOff(path + ".missing");
        FAIL() << "no exception";
    } catch (const rad::OffReadError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
    }
}

// The real scans of docs data.md, when samples/fetch_data.sh has been run.
TEST(OffReader, ReadsTheCgalMeshesOfTheDataCache) {
    const char* env = std::getenv("RADIANCE_DATA_CACHE");
    const std::string cache = env && *env ? env : std::string(RADIANCE_SOURCE_DIR) + "/data-cache";
    struct Expected {
        const char* name;
        std::size_t vertices, faces;
    };
    const Expected meshes[] = {{"armadillo", 26002, 52000},
                               {"bunny00", 37706, 75408},
                               {"fandisk", 6475, 12946},
                               {"ChineseDragon-10kv", 10000, 19994},
                               {"refined_elephant", 44460, 88928}};
    if (!std::ifstream(cache + "/meshes/armadillo.off")) GTEST_SKIP() << "no data cache (run samples/fetch_data.sh)";
    for (const Expected& e : meshes) {
        const rad::TriangleMesh m = rad::readOff(cache + "/meshes/" + e.name + ".off");
        EXPECT_EQ(m.vertexCount(), e.vertices) << e.name;
        EXPECT_EQ(m.faceCount(), e.faces) << e.name;
        EXPECT_EQ(m.validate(), "") << e.name;
    }
}

}  // namespace
