#include "io/radiance_ply.h"
#include "test_temporary_directory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using rad::BasisKind;
using rad::BasisSpec;
using rad::NamedVertexBlock;
using rad::RadianceField;
using rad::RadianceFileError;
using rad::RadianceMesh;

std::string tmpPath(const std::string& name) { return std::string(RADIANCE_TEST_TMPDIR) + "/radiance_ply_" + name; }

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::string& bytes) {
    std::filesystem::remove(path);  // not truncate: ext4 flushes files truncated then rewritten, which is slow
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Unit normal n and a unit tangent orthogonal to it, from a random generator.
void randomFrame(std::mt19937& rng, float* t, float* n) {
    std::normal_distribution<double> g(0.0, 1.0);
    double a[3], b[3];
    double len = 0;
    do {
        for (double& x : a) x = g(rng);
        len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    } while (len < 1e-3);
    for (double& x : a) x /= len;
    do {
        for (double& x : b) x = g(rng);
        const double d = b[0] * a[0] + b[1] * a[1] + b[2] * a[2];
        for (int i = 0; i < 3; ++i) b[i] -= d * a[i];
        len = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    } while (len < 1e-3);
    for (int i = 0; i < 3; ++i) {
        n[i] = static_cast<float>(a[i]);
        t[i] = static_cast<float>(b[i] / len);
    }
}

struct MeshOptions {
    std::size_t vertices = 23;
    bool normals = true;
    bool colors = true;
    bool quality = true;
    std::optional<BasisSpec> basis = BasisSpec{BasisKind::HemisphericalPolynomial, 4};
    bool reflected = false;
    bool block = false;
    unsigned seed = 1;
};

RadianceMesh makeMesh(const MeshOptions& o) {
    std::mt19937 rng(o.seed);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f);
    RadianceMesh m;
    const std::size_t n = o.vertices;
    for (std::size_t i = 0; i < 3 * n; ++i) m.positions.push_back(u(rng));
    if (n > 2) {
        m.positions[0] = -0.0f;                                   // sign of zero must survive
        m.positions[1] = std::numeric_limits<float>::denorm_min();  // so must denormals
        m.positions[2] = std::numeric_limits<float>::max();
    }
    std::vector<float> frames(6 * n);
    for (std::size_t v = 0; v < n; ++v) randomFrame(rng, frames.data() + 6 * v, frames.data() + 6 * v + 3);
    if (o.normals)
        for (std::size_t v = 0; v < n; ++v)
            for (int i = 0; i < 3; ++i) m.normals.push_back(frames[6 * v + 3 + static_cast<std::size_t>(i)]);
    if (o.colors)
        for (std::size_t i = 0; i < 4 * n; ++i) m.colors.push_back(static_cast<std::uint8_t>(rng() & 255));
    if (o.quality) {
        for (std::size_t i = 0; i < n; ++i) m.quality.push_back(u(rng));
        // Quality is passed through untouched, NaN payloads included.
        std::uint32_t bits = 0x7fc01234u;
        if (n > 1) std::memcpy(&m.quality[1], &bits, 4);
    }
    for (std::size_t f = 0; f + 2 < n; ++f) {
        m.faces.push_back(static_cast<std::uint32_t>(f));
        m.faces.push_back(static_cast<std::uint32_t>(f + 1));
        m.faces.push_back(static_cast<std::uint32_t>((f * 7 + 2) % n));
    }
    if (o.basis) {
        RadianceField rf(*o.basis, n, o.reflected);
        rf.frames = frames;
        std::normal_distribution<float> g(0.0f, 3.0f);
        for (float& c : rf.coefficients) c = g(rng);
        if (!rf.coefficients.empty()) rf.coefficients[0] = -0.0f;
        m.radiance = std::move(rf);
    }
    if (o.block) {
        NamedVertexBlock b;
        b.prefix = "prt";
        b.width = 5;
        for (std::size_t i = 0; i < 5 * n; ++i) b.values.push_back(u(rng));
        b.values[3] = std::numeric_limits<float>::infinity();  // blocks are user data: not checked
        b.metadata["kind"] = "transfer";
        b.metadata["basis"] = "SH2 band-limited";
        b.metadata["note"] = "  leading spaces and trailing one ";
        b.metadata["empty"] = "";
        m.extraBlocks.push_back(std::move(b));
        NamedVertexBlock c;
        c.prefix = "prt_1";
        c.width = 2;
        for (std::size_t i = 0; i < 2 * n; ++i) c.values.push_back(u(rng));
        m.extraBlocks.push_back(std::move(c));
    }
    return m;
}

void expectSameMesh(const RadianceMesh& written, const RadianceMesh& read) {
    EXPECT_TRUE(sameBits(written.positions, read.positions));
    EXPECT_TRUE(sameBits(written.colors, read.colors));
    EXPECT_TRUE(sameBits(written.quality, read.quality));
    EXPECT_TRUE(sameBits(written.faces, read.faces));
    ASSERT_EQ(written.radiance.has_value(), read.radiance.has_value());
    if (written.radiance) {
        const RadianceField& a = *written.radiance;
        const RadianceField& b = *read.radiance;
        EXPECT_EQ(a.basis, b.basis);
        EXPECT_EQ(a.reflected, b.reflected);
        EXPECT_TRUE(sameBits(a.coefficients, b.coefficients));
        EXPECT_TRUE(sameBits(a.frames, b.frames));
        // The file's normals are the frame normals.
        ASSERT_EQ(read.normals.size(), 3 * read.vertexCount());
        for (std::size_t v = 0; v < read.vertexCount(); ++v)
            EXPECT_EQ(0, std::memcmp(read.normals.data() + 3 * v, b.frame(v) + 3, 12));
    } else {
        EXPECT_TRUE(sameBits(written.normals, read.normals));
    }
    ASSERT_EQ(written.extraBlocks.size(), read.extraBlocks.size());
    for (std::size_t i = 0; i < written.extraBlocks.size(); ++i) {
        EXPECT_EQ(written.extraBlocks[i].prefix, read.extraBlocks[i].prefix);
        EXPECT_EQ(written.extraBlocks[i].width, read.extraBlocks[i].width);
        EXPECT_TRUE(sameBits(written.extraBlocks[i].values, read.extraBlocks[i].values));
        EXPECT_EQ(written.extraBlocks[i].metadata, read.extraBlocks[i].metadata);
    }
}

// The message of the RadianceFileError thrown by f (fails the test if none or another exception).
template <typename F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const RadianceFileError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "unexpected exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << "no RadianceFileError thrown";
    return {};
}

// ---------------------------------------------------------------------------------------------------
// Hand-written PLY files (bytes built here, not by the writer)

void put(std::string& out, const std::string& type, double value) {
    auto raw = [&](auto v) { out.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
    if (type == "float") raw(static_cast<float>(value));
    else if (type == "double") raw(value);
    else if (type == "uchar") raw(static_cast<std::uint8_t>(value));
    else if (type == "char") raw(static_cast<std::int8_t>(value));
    else if (type == "short") raw(static_cast<std::int16_t>(value));
    else if (type == "ushort") raw(static_cast<std::uint16_t>(value));
    else if (type == "int") raw(static_cast<std::int32_t>(value));
    else if (type == "uint") raw(static_cast<std::uint32_t>(value));
    else if (type.rfind("list uchar ", 0) == 0) raw(static_cast<std::uint8_t>(0));  // an empty list
    else ADD_FAILURE() << "bad type " << type;
}

struct PlyBuilder {
    std::string format = "binary_little_endian 1.0";
    std::vector<std::string> comments;
    struct Prop {
        std::string type, name;
    };
    std::vector<Prop> vertexProps;
    std::vector<std::map<std::string, double>> vertices;  // values by property name
    std::vector<std::vector<std::int64_t>> faces;
    std::string faceCountType = "uchar", faceIndexType = "int";
    bool faceFlagsAndTexcoords = false;  // adds "uchar flags" and "list uchar float texcoord"
    std::string extraHeader;             // appended after the face element
    std::string extraData;

    void remove(const std::string& name) {
        vertexProps.erase(std::remove_if(vertexProps.begin(), vertexProps.end(), [&](const Prop& p) { return p.name == name; }),
                          vertexProps.end());
    }
    Prop& prop(const std::string& name) {
        for (auto& p : vertexProps)
            if (p.name == name) return p;
        ADD_FAILURE() << "no property " << name;
        return vertexProps.front();
    }
    void removeComment(const std::string& prefix) {
        comments.erase(std::remove_if(comments.begin(), comments.end(),
                                      [&](const std::string& c) { return c.rfind(prefix, 0) == 0; }),
                       comments.end());
    }

    std::string build() const {
        std::ostringstream h;
        h << "ply\nformat " << format << "\n";
        for (const auto& c : comments) h << "comment " << c << "\n";
        h << "element vertex " << vertices.size() << "\n";
        for (const auto& p : vertexProps) h << "property " << p.type << " " << p.name << "\n";
        h << "element face " << faces.size() << "\n";
        if (faceFlagsAndTexcoords) h << "property uchar flags\n";
        h << "property list " << faceCountType << " " << faceIndexType << " vertex_indices\n";
        if (faceFlagsAndTexcoords) h << "property list uchar float texcoord\n";
        h << extraHeader << "end_header\n";
        std::string out = h.str();
        for (const auto& v : vertices)
            for (const auto& p : vertexProps) {
                const auto it = v.find(p.name);
                put(out, p.type, it == v.end() ? 0.0 : it->second);
            }
        for (std::size_t f = 0; f < faces.size(); ++f) {
            if (faceFlagsAndTexcoords) put(out, "uchar", 7);
            put(out, faceCountType, static_cast<double>(faces[f].size()));
            for (auto i : faces[f]) put(out, faceIndexType, static_cast<double>(i));
            if (faceFlagsAndTexcoords) {
                put(out, "uchar", 6);
                for (int k = 0; k < 6; ++k) put(out, "float", 0.25 * k + static_cast<double>(f));
            }
        }
        return out + extraData;
    }
};

// A valid PB1 file: 4 vertices, 2 triangles, normals, colors (with alpha), quality, an unknown
// short property, properties in a scrambled order.
PlyBuilder baseBuilder(unsigned shuffleSeed = 0) {
    PlyBuilder b;
    b.comments = {"written by hand", "radiance_format_version 1", "radiance_basis PB1", "radiance_reflected 1",
                  "radiance_channels rgb", "radiance_color_space linear", "radiance_frame tangent_normal",
                  "some_other_tool says hello"};
    std::vector<std::string> floats = {"x", "y", "z", "nx", "ny", "nz", "quality", "rf_tx", "rf_ty", "rf_tz"};
    for (const char* c : {"r", "g", "b"})
        for (int k = 0; k < 3; ++k) floats.push_back(std::string("rf_") + c + "_" + std::to_string(k));
    for (const auto& f : floats) b.vertexProps.push_back({"float", f});
    for (const char* c : {"red", "green", "blue", "alpha"}) b.vertexProps.push_back({"uchar", c});
    b.vertexProps.push_back({"short", "unknown_short"});
    b.vertexProps.push_back({"double", "unknown_double"});
    if (shuffleSeed) {
        std::mt19937 rng(shuffleSeed);
        std::shuffle(b.vertexProps.begin(), b.vertexProps.end(), rng);
    } else {
        // A fixed scramble: coefficients before positions, colors in the middle, unknowns between.
        std::reverse(b.vertexProps.begin(), b.vertexProps.end());
    }
    const float normals[4][3] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0.6f, 0.8f, 0}};
    const float tangents[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.8f, -0.6f, 0}};
    for (int v = 0; v < 4; ++v) {
        std::map<std::string, double> values;
        values["x"] = v + 0.5;
        values["y"] = -v * 2.25;
        values["z"] = 100 + v;
        values["nx"] = normals[v][0];
        values["ny"] = normals[v][1];
        values["nz"] = normals[v][2];
        values["rf_tx"] = tangents[v][0];
        values["rf_ty"] = tangents[v][1];
        values["rf_tz"] = tangents[v][2];
        values["quality"] = v * 0.125;
        values["red"] = 10 * v;
        values["green"] = 10 * v + 1;
        values["blue"] = 10 * v + 2;
        values["alpha"] = 200 + v;
        values["unknown_short"] = -1234;
        values["unknown_double"] = 3.5;
        const char* channels[3] = {"r", "g", "b"};
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                values[std::string("rf_") + channels[c] + "_" + std::to_string(k)] = v * 100 + c * 10 + k + 0.5;
        b.vertices.push_back(values);
    }
    b.faces = {{0, 1, 2}, {0, 2, 3}};
    return b;
}

void checkBaseMesh(const RadianceMesh& m, bool alpha = true) {
    ASSERT_EQ(m.vertexCount(), 4u);
    ASSERT_TRUE(m.radiance);
    EXPECT_EQ(m.radiance->basis.name(), "PB1");
    EXPECT_TRUE(m.radiance->reflected);
    ASSERT_EQ(m.faces, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
    for (int v = 0; v < 4; ++v) {
        EXPECT_EQ(m.positions[3 * v + 0], v + 0.5f);
        EXPECT_EQ(m.positions[3 * v + 1], -v * 2.25f);
        EXPECT_EQ(m.positions[3 * v + 2], 100.0f + v);
        EXPECT_EQ(m.quality[v], v * 0.125f);
        EXPECT_EQ(m.colors[4 * v + 0], 10 * v);
        EXPECT_EQ(m.colors[4 * v + 1], 10 * v + 1);
        EXPECT_EQ(m.colors[4 * v + 2], 10 * v + 2);
        EXPECT_EQ(m.colors[4 * v + 3], alpha ? 200 + v : 255);
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                EXPECT_EQ(m.radiance->channelCoefficients(static_cast<std::size_t>(v), c)[k], v * 100 + c * 10 + k + 0.5f);
        for (int i = 0; i < 3; ++i) EXPECT_EQ(m.normals[3 * v + i], m.radiance->frame(static_cast<std::size_t>(v))[3 + i]);
    }
    EXPECT_EQ(m.normals[3 * 3 + 0], 0.6f);
    EXPECT_EQ(m.radiance->frame(3)[1], -0.6f);
}

std::string refusal(const std::string& bytes, const std::string& name) {
    std::string safe = name;
    for (char& c : safe)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    const std::string path = tmpPath("refuse_" + safe.substr(0, 60) + ".ply");
    writeBytes(path, bytes);
    return errorOf([&] { rad::readRadiancePly(path); });
}

#define EXPECT_REFUSED(bytes, phrase)                                       \
    do {                                                                    \
        const std::string message_ = refusal((bytes), #phrase);             \
        EXPECT_NE(message_.find(phrase), std::string::npos) << message_;    \
    } while (0)

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Round trips

TEST(RadiancePlyRoundTrip, BitExactForPbAndShWithAndWithoutAttributes) {
    int variant = 0;
    for (const auto basis : {std::optional<BasisSpec>{BasisSpec{BasisKind::HemisphericalPolynomial, 4}},
                             std::optional<BasisSpec>{BasisSpec{BasisKind::SphericalHarmonics, 3}},
                             std::optional<BasisSpec>{BasisSpec{BasisKind::HemisphericalPolynomial, 0}},
                             std::optional<BasisSpec>{}})
        for (int attributes = 0; attributes < 8; ++attributes) {
            MeshOptions o;
            o.basis = basis;
            o.normals = attributes & 1;
            o.colors = attributes & 2;
            o.quality = attributes & 4;
            o.reflected = attributes & 1;
            o.block = (attributes % 3) == 0;
            o.seed = static_cast<unsigned>(++variant);
            const RadianceMesh mesh = makeMesh(o);
            ASSERT_EQ(rad::validateRadianceMesh(mesh), "");
            const std::string path = tmpPath("roundtrip.ply");
            rad::writeRadiancePly(path, mesh);
            const RadianceMesh back = rad::readRadiancePly(path);
            SCOPED_TRACE("variant " + std::to_string(variant));
            expectSameMesh(mesh, back);
            // Writing what was read gives the same bytes.
            rad::writeRadiancePly(tmpPath("roundtrip2.ply"), back);
            EXPECT_EQ(readBytes(path), readBytes(tmpPath("roundtrip2.ply")));
        }
}

TEST(RadiancePlyRoundTrip, EmptyMeshAndPointCloud) {
    RadianceMesh empty;
    rad::writeRadiancePly(tmpPath("empty.ply"), empty);
    const RadianceMesh back = rad::readRadiancePly(tmpPath("empty.ply"));
    EXPECT_EQ(back.vertexCount(), 0u);
    EXPECT_TRUE(back.faces.empty());

    MeshOptions o;
    o.vertices = 1;
    RadianceMesh one = makeMesh(o);
    EXPECT_TRUE(one.faces.empty());
    rad::writeRadiancePly(tmpPath("one.ply"), one);
    expectSameMesh(one, rad::readRadiancePly(tmpPath("one.ply")));
}

TEST(RadiancePlyRoundTrip, HeaderIsAsDocumented) {
    MeshOptions o;
    o.vertices = 3;
    o.block = true;
    const RadianceMesh mesh = makeMesh(o);
    rad::writeRadiancePly(tmpPath("header.ply"), mesh);
    const std::string bytes = readBytes(tmpPath("header.ply"));
    const std::string header = bytes.substr(0, bytes.find("end_header\n") + 11);
    const std::string expectedStart =
        "ply\nformat binary_little_endian 1.0\ncomment radiance_format_version 1\ncomment radiance_basis PB4\n"
        "comment radiance_reflected 0\ncomment radiance_channels rgb\ncomment radiance_color_space linear\n"
        "comment radiance_frame tangent_normal\ncomment block prt width 5\ncomment block_meta prt basis SH2 band-limited\n"
        "comment block_meta prt empty\ncomment block_meta prt kind transfer\n"
        "comment block_meta prt note   leading spaces and trailing one \ncomment block prt_1 width 2\n"
        "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
        "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
        "property float quality\nproperty float rf_tx\nproperty float rf_ty\nproperty float rf_tz\n"
        "property float rf_r_0\n";
    EXPECT_EQ(header.substr(0, expectedStart.size()), expectedStart);
    EXPECT_NE(header.find("property float rf_b_14\nproperty float prt_0\n"), std::string::npos);
    EXPECT_NE(header.find("property float prt_1_1\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"),
              std::string::npos);
    const std::size_t record = 4 * (3 + 3 + 1 + 3 + 45 + 5 + 2) + 4;
    EXPECT_EQ(bytes.size(), header.size() + 3 * record + 13);
}

// ---------------------------------------------------------------------------------------------------
// Hand-written files

TEST(RadiancePlyHandWritten, ReorderedPropertiesAndUnknownPropertiesLoad) {
    const std::string path = tmpPath("hand.ply");
    writeBytes(path, baseBuilder().build());
    checkBaseMesh(rad::readRadiancePly(path));
    for (unsigned seed = 1; seed <= 20; ++seed) {
        writeBytes(path, baseBuilder(seed).build());
        SCOPED_TRACE(seed);
        checkBaseMesh(rad::readRadiancePly(path));
    }
}

TEST(RadiancePlyHandWritten, FaceExtrasUnknownElementsAndNoAlpha) {
    PlyBuilder b = baseBuilder(7);
    b.faceFlagsAndTexcoords = true;       // variable-size face records
    b.remove("alpha");                    // alpha defaults to 255
    b.faceCountType = "int";
    b.faceIndexType = "uint";
    b.extraHeader = "element material 2\nproperty float shininess\nproperty uchar id\n";
    b.extraData = std::string(10, '\x01');
    const std::string path = tmpPath("hand_extras.ply");
    writeBytes(path, b.build());
    checkBaseMesh(rad::readRadiancePly(path), false);

    // The same with fixed-size faces (fast path), and an unknown element before the vertices.
    PlyBuilder c = baseBuilder(9);
    c.extraHeader = "element material 2\nproperty float shininess\nproperty uchar id\n";
    c.extraData = std::string(10, '\x01');
    std::string bytes = c.build();
    const std::string before = "element camera 1\nproperty double focal\n";
    bytes.insert(bytes.find("element vertex"), before);
    bytes.insert(bytes.find("end_header\n") + 11, std::string(8, '\0'));
    writeBytes(path, bytes);
    checkBaseMesh(rad::readRadiancePly(path));
}

TEST(RadiancePlyHandWritten, CrLfHeaderAndPlainPly) {
    std::string bytes = baseBuilder().build();
    const std::size_t end = bytes.find("end_header\n") + 11;
    std::string header = bytes.substr(0, end), crlf;
    for (char c : header) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    writeBytes(tmpPath("crlf.ply"), crlf + bytes.substr(end));
    checkBaseMesh(rad::readRadiancePly(tmpPath("crlf.ply")));

    // A plain MeshLab-style PLY without any radiance comment.
    PlyBuilder b;
    b.vertexProps = {{"float", "x"}, {"float", "y"}, {"float", "z"}, {"uchar", "red"}, {"uchar", "green"}, {"uchar", "blue"}};
    b.vertices = {{{"x", 1}, {"red", 9}}, {{"y", 1}}, {{"z", 1}}};
    b.faces = {{0, 1, 2}};
    writeBytes(tmpPath("plain.ply"), b.build());
    const RadianceMesh m = rad::readRadiancePly(tmpPath("plain.ply"));
    EXPECT_FALSE(m.radiance);
    EXPECT_EQ(m.vertexCount(), 3u);
    EXPECT_TRUE(m.normals.empty());
    EXPECT_EQ(m.colors[0], 9);
    EXPECT_EQ(m.colors[3], 255);
}

TEST(RadiancePlyHandWritten, BlocksByHand) {
    PlyBuilder b = baseBuilder();
    b.comments.push_back("block tv width 2");
    b.comments.push_back("block_meta tv kind transfer vector");
    b.vertexProps.insert(b.vertexProps.begin() + 3, {"float", "tv_1"});
    b.vertexProps.push_back({"float", "tv_0"});
    for (std::size_t v = 0; v < b.vertices.size(); ++v) {
        b.vertices[v]["tv_0"] = static_cast<double>(v);
        b.vertices[v]["tv_1"] = -static_cast<double>(v);
    }
    writeBytes(tmpPath("blocks.ply"), b.build());
    const RadianceMesh m = rad::readRadiancePly(tmpPath("blocks.ply"));
    checkBaseMesh(m);
    ASSERT_EQ(m.extraBlocks.size(), 1u);
    EXPECT_EQ(m.extraBlocks[0].prefix, "tv");
    EXPECT_EQ(m.extraBlocks[0].values, (std::vector<float>{0, -0.0f, 1, -1, 2, -2, 3, -3}));
    EXPECT_EQ(m.extraBlocks[0].metadata.at("kind"), "transfer vector");

    // Without radiance_format_version, "block" comments are foreign comments and tv_* unknown properties.
    b.removeComment("radiance_");
    for (const char* name : {"rf_tx", "rf_ty", "rf_tz"}) b.remove(name);
    for (const char* c : {"r", "g", "b"})
        for (int k = 0; k < 3; ++k) b.remove(std::string("rf_") + c + "_" + std::to_string(k));
    writeBytes(tmpPath("blocks.ply"), b.build());
    const RadianceMesh plain = rad::readRadiancePly(tmpPath("blocks.ply"));
    EXPECT_FALSE(plain.radiance);
    EXPECT_TRUE(plain.extraBlocks.empty());
    EXPECT_EQ(plain.vertexCount(), 4u);
}

// ---------------------------------------------------------------------------------------------------
// Refusals

TEST(RadiancePlyRefuses, NotPlyAsciiBigEndian) {
    EXPECT_REFUSED(std::string("hello world\n"), "not a PLY file");
    EXPECT_REFUSED(std::string(), "not a PLY file");
    EXPECT_REFUSED(std::string("plywood\n"), "not a PLY file");
    PlyBuilder b = baseBuilder();
    b.format = "ascii 1.0";
    EXPECT_REFUSED(b.build(), "ASCII format");
    EXPECT_REFUSED(b.build(), "binary little endian");
    b.format = "binary_big_endian 1.0";
    EXPECT_REFUSED(b.build(), "binary big endian");
    EXPECT_REFUSED(b.build(), "MeshLab");
    b.format = "binary_little_endian 2.0";
    EXPECT_REFUSED(b.build(), "unsupported PLY version");
    const std::string path = tmpPath("does_not_exist.ply");
    std::filesystem::remove(path);
    EXPECT_NE(errorOf([&] { rad::readRadiancePly(path); }).find("cannot open"), std::string::npos);
    EXPECT_NE(errorOf([&] { rad::readRadiancePly(RADIANCE_TEST_TMPDIR); }).find("folder"), std::string::npos);
}

TEST(RadiancePlyRefuses, HeaderProblems) {
    const std::string good = baseBuilder().build();
    EXPECT_REFUSED(good.substr(0, good.find("end_header")), "file truncated inside its header");
    std::string unknownKeyword = good;
    unknownKeyword.insert(unknownKeyword.find("element vertex"), "elephant 3\n");
    EXPECT_REFUSED(unknownKeyword, "unknown header keyword");
    PlyBuilder b = baseBuilder();
    b.vertexProps.push_back({"float", "x"});
    EXPECT_REFUSED(b.build(), "declared twice");
    std::string badType = good;
    badType.replace(badType.find("property float x\n"), 17, "property float128 x\n");
    EXPECT_REFUSED(badType, "unknown property type");
    std::string noEnd = good.substr(0, good.find("end_header")) + std::string(2 << 20, 'a');
    EXPECT_REFUSED(noEnd, "no end_header line in the first 1 MiB");
}

TEST(RadiancePlyRefuses, MissingOrMistypedProperties) {
    PlyBuilder b = baseBuilder();
    b.remove("x");
    EXPECT_REFUSED(b.build(), "missing vertex property 'x'");
    b = baseBuilder();
    b.remove("ny");
    EXPECT_REFUSED(b.build(), "missing vertex property 'ny'");
    b = baseBuilder();
    b.remove("nx");
    b.remove("ny");
    b.remove("nz");
    EXPECT_REFUSED(b.build(), "radiance data needs the per-vertex normals");
    b = baseBuilder();
    b.remove("green");
    EXPECT_REFUSED(b.build(), "missing vertex property 'green'");
    b = baseBuilder();
    b.prop("red").type = "float";
    EXPECT_REFUSED(b.build(), "'red' is float but must be uchar");
    b = baseBuilder();
    b.prop("y").type = "double";
    EXPECT_REFUSED(b.build(), "'y' is double but must be float");
    b = baseBuilder();
    b.remove("rf_g_1");
    EXPECT_REFUSED(b.build(), "missing radiance coefficient property 'rf_g_1'");
    b = baseBuilder();
    b.prop("rf_b_2").name = "rf_b_3";
    EXPECT_REFUSED(b.build(), "does not belong to basis PB1");
    b = baseBuilder();
    b.prop("rf_r_0").type = "double";
    EXPECT_REFUSED(b.build(), "'rf_r_0' is double but must be float");
    b = baseBuilder();
    b.remove("rf_ty");
    EXPECT_REFUSED(b.build(), "missing radiance frame tangent property 'rf_ty'");
    b = baseBuilder();
    b.comments.push_back("radiance_basis PB2");
    b.removeComment("radiance_basis PB1");
    EXPECT_REFUSED(b.build(), "missing radiance coefficient property 'rf_r_3'");
    b = baseBuilder();
    b.vertexProps.push_back({"list uchar float", "weights"});
    EXPECT_REFUSED(b.build(), "variable-size vertex records are not supported");
}

TEST(RadiancePlyRefuses, RadianceComments) {
    PlyBuilder b = baseBuilder();
    b.removeComment("radiance_basis");
    b.comments.push_back("radiance_basis XY2");
    EXPECT_REFUSED(b.build(), "unknown radiance basis 'XY2'");
    b.removeComment("radiance_basis");
    b.comments.push_back("radiance_basis PB9");
    EXPECT_REFUSED(b.build(), "degree out of range");
    b.removeComment("radiance_basis");
    b.comments.push_back("radiance_basis SH11");
    EXPECT_REFUSED(b.build(), "degree out of range");
    b = baseBuilder();
    b.removeComment("radiance_format_version");
    EXPECT_REFUSED(b.build(), "without comment radiance_format_version");
    b = baseBuilder();
    b.removeComment("radiance_format_version");
    b.comments.push_back("radiance_format_version 2");
    EXPECT_REFUSED(b.build(), "newer version");
    b = baseBuilder();
    b.removeComment("radiance_basis");
    b.removeComment("radiance_reflected");
    b.removeComment("radiance_c");
    b.removeComment("radiance_frame");
    EXPECT_REFUSED(b.build(), "no radiance_basis comment");
    b = baseBuilder();
    b.removeComment("radiance_reflected");
    EXPECT_REFUSED(b.build(), "without comment radiance_reflected");
    b = baseBuilder();
    b.removeComment("radiance_reflected");
    b.comments.push_back("radiance_reflected yes");
    EXPECT_REFUSED(b.build(), "radiance_reflected must be 0 or 1");
    b = baseBuilder();
    b.removeComment("radiance_channels");
    b.comments.push_back("radiance_channels rgba");
    EXPECT_REFUSED(b.build(), "unsupported radiance_channels");
    b = baseBuilder();
    b.removeComment("radiance_color_space");
    b.comments.push_back("radiance_color_space srgb");
    EXPECT_REFUSED(b.build(), "unsupported radiance_color_space");
    b = baseBuilder();
    b.comments.push_back("radiance_basis PB1");
    EXPECT_REFUSED(b.build(), "appears twice");
}

TEST(RadiancePlyRefuses, Blocks) {
    PlyBuilder b = baseBuilder();
    b.comments.push_back("block tv width 3");
    b.vertexProps.push_back({"float", "tv_0"});
    b.vertexProps.push_back({"float", "tv_1"});
    EXPECT_REFUSED(b.build(), "missing vertex property 'tv_2' of block 'tv'");
    b.vertexProps.push_back({"float", "tv_3"});
    EXPECT_REFUSED(b.build(), "'tv_3' does not belong to block 'tv'");
    b = baseBuilder();
    b.comments.push_back("block tv width 1");
    b.vertexProps.push_back({"double", "tv_0"});
    EXPECT_REFUSED(b.build(), "'tv_0' is double but must be float");
    b = baseBuilder();
    b.comments.push_back("block tv width 1");
    b.comments.push_back("block_meta other key value");
    b.vertexProps.push_back({"float", "tv_0"});
    EXPECT_REFUSED(b.build(), "block_meta for undeclared block");
    b = baseBuilder();
    b.comments.push_back("block tv width 1000000");
    EXPECT_REFUSED(b.build(), "invalid width");
    b = baseBuilder();
    b.comments.push_back("block tv width 60000");
    EXPECT_REFUSED(b.build(), "block properties are missing");
    b = baseBuilder();
    b.comments.push_back("block rf_extra width 1");
    EXPECT_REFUSED(b.build(), "invalid block prefix");
    b = baseBuilder();
    b.comments.push_back("block tv wide 1");
    EXPECT_REFUSED(b.build(), "malformed block comment");
}

TEST(RadiancePlyRefuses, FacesAndElements) {
    PlyBuilder b = baseBuilder();
    b.faces[1] = {0, 2, 4};
    EXPECT_REFUSED(b.build(), "references vertex 4 but the file has only 4 vertices");
    b.faces[1] = {0, -1, 2};
    EXPECT_REFUSED(b.build(), "negative vertex index");
    b.faces[1] = {0, 1, 2, 3};
    EXPECT_REFUSED(b.build(), "triangulate");
    b.faceFlagsAndTexcoords = true;
    EXPECT_REFUSED(b.build(), "triangulate");
    b = baseBuilder();
    b.faces = {{0, 1, 2, 3}};
    EXPECT_REFUSED(b.build(), "triangulate");
    b = baseBuilder();
    b.faceIndexType = "short";
    EXPECT_REFUSED(b.build(), "must be int or uint");
    b = baseBuilder();
    b.extraHeader = "element edge 1\nproperty list uchar int vertex_indices\n";
    b.extraData = std::string("\x02\0\0\0\0\x01\0\0\0", 9);
    EXPECT_REFUSED(b.build(), "has list properties");
    std::string noVertex = "ply\nformat binary_little_endian 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
    EXPECT_REFUSED(noVertex, "no vertex element");
    b = baseBuilder();
    std::string noIndices = b.build();
    noIndices.replace(noIndices.find("vertex_indices"), 14, "vertex_indexes");
    EXPECT_REFUSED(noIndices, "no 'vertex_indices' list property");
}

TEST(RadiancePlyRefuses, NonFiniteValuesAndBadNormals) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    PlyBuilder b = baseBuilder();
    b.vertices[2]["y"] = nan;
    EXPECT_REFUSED(b.build(), "vertex 2 has a position that is not a finite number");
    b = baseBuilder();
    b.vertices[1]["nz"] = inf;
    EXPECT_REFUSED(b.build(), "vertex 1 has a normal that is not a finite number");
    b = baseBuilder();
    b.vertices[3]["rf_g_2"] = -inf;
    EXPECT_REFUSED(b.build(), "vertex 3 has a radiance coefficient that is not a finite number");
    b = baseBuilder();
    b.vertices[0]["rf_tx"] = nan;
    EXPECT_REFUSED(b.build(), "vertex 0 has a radiance frame tangent that is not a finite number");
    b = baseBuilder();
    b.vertices[0]["nx"] = 0.5;
    EXPECT_REFUSED(b.build(), "not unit length");
    // Without radiance, normals need not be unit, but must be finite.
    b = baseBuilder();
    b.vertices[0]["quality"] = nan;  // quality is user data: accepted
    writeBytes(tmpPath("nan_quality.ply"), b.build());
    EXPECT_TRUE(std::isnan(rad::readRadiancePly(tmpPath("nan_quality.ply")).quality[0]));
}

TEST(RadiancePlyRefuses, TruncatedAndTrailingData) {
    const std::string good = baseBuilder().build();
    EXPECT_REFUSED(good.substr(0, good.size() - 1), "file truncated");
    EXPECT_REFUSED(good.substr(0, good.find("end_header\n") + 11 + 30), "expected 360 bytes of vertex data, found 30");
    EXPECT_REFUSED(good.substr(0, good.find("end_header\n") + 11 + 30), "not completely written");
    EXPECT_REFUSED(good + "x", "1 byte of unexpected data after the last element");
    EXPECT_REFUSED(good + std::string(100, '\0'), "unexpected data after the last element");
    PlyBuilder b = baseBuilder();
    b.faceFlagsAndTexcoords = true;
    const std::string variable = b.build();
    EXPECT_REFUSED(variable.substr(0, variable.size() - 3), "file truncated");
    EXPECT_REFUSED(variable + "zz", "unexpected data after the last element");
}

TEST(RadiancePlyRefuses, AbsurdCountsWithoutAllocating) {
    struct rusage before{};
    getrusage(RUSAGE_SELF, &before);
    std::string bytes = baseBuilder().build();
    bytes.replace(bytes.find("element vertex 4"), 16, "element vertex 2147483648");
    EXPECT_REFUSED(bytes, "file truncated: expected 193273528320 bytes of vertex data");
    bytes = baseBuilder().build();
    bytes.replace(bytes.find("element face 2"), 14, "element face 2147483648");
    EXPECT_REFUSED(bytes, "bytes of face data");
    bytes = baseBuilder().build();
    bytes.replace(bytes.find("element vertex 4"), 16, "element vertex 99999999999");
    EXPECT_REFUSED(bytes, "more than this format supports");
    bytes = baseBuilder().build();
    bytes.replace(bytes.find("element vertex 4"), 16, "element vertex 999999999999999999999999");
    EXPECT_REFUSED(bytes, "invalid count");
    bytes = baseBuilder().build();
    bytes.insert(bytes.find("end_header"), "element nothing 18446744073709551615\nproperty double v\n");
    EXPECT_REFUSED(bytes, "file truncated");
    struct rusage after{};
    getrusage(RUSAGE_SELF, &after);
    EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 64 * 1024);  // kilobytes
}

// ---------------------------------------------------------------------------------------------------
// Robustness

namespace {
// Reads path; returns true when it loaded. Fails the test on any exception but RadianceFileError.
bool loadsOrRefuses(const std::string& path) {
    try {
        const RadianceMesh m = rad::readRadiancePly(path);
        const std::size_t n = m.vertexCount();
        for (auto i : m.faces) EXPECT_LT(i, n);
        if (m.radiance) {
            EXPECT_EQ(m.radiance->validate(), "");
        }
        // What loads can be saved again (the fuzzer's oracle, bench/fuzz/radiance_ply_fuzzer.cpp).
        EXPECT_EQ(rad::validateRadianceMesh(m), "") << path;
        return true;
    } catch (const RadianceFileError&) {
        return false;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "unexpected exception: " << e.what();
        return false;
    }
}
}  // namespace

TEST(RadiancePlyRobustness, TruncationAtEveryOffsetThrows) {
    MeshOptions o;
    o.vertices = 7;
    o.basis = BasisSpec{BasisKind::SphericalHarmonics, 2};
    o.block = true;
    const std::string path = tmpPath("full.ply");
    rad::writeRadiancePly(path, makeMesh(o));
    PlyBuilder b = baseBuilder(3);
    b.faceFlagsAndTexcoords = true;
    for (const std::string& good : {readBytes(path), b.build()}) {
        const std::string cut = tmpPath("cut.ply");
        for (std::size_t size = 0; size < good.size(); ++size) {
            writeBytes(cut, good.substr(0, size));
            EXPECT_FALSE(loadsOrRefuses(cut)) << "loaded a file truncated at " << size << " of " << good.size();
        }
        writeBytes(cut, good);
        EXPECT_TRUE(loadsOrRefuses(cut));
    }
}

TEST(RadiancePlyRobustness, MutationsNeverCrash) {
    MeshOptions o;
    o.vertices = 9;
    o.basis = BasisSpec{BasisKind::HemisphericalPolynomial, 2};
    o.block = true;
    const std::string path = tmpPath("mutate_src.ply");
    rad::writeRadiancePly(path, makeMesh(o));
    const std::string written = readBytes(path);
    PlyBuilder b = baseBuilder(5);
    b.faceFlagsAndTexcoords = true;
    b.extraHeader = "element material 2\nproperty float shininess\n";
    b.extraData = std::string(8, '\x02');
    const std::string hand = b.build();
    const std::string mutated = tmpPath("mutated.ply");
    std::mt19937 rng(1234);
    int loaded = 0, refused = 0;
    for (const std::string& good : {written, hand}) {
        const std::size_t headerSize = good.find("end_header\n") + 11;
        // Bit flips in the header.
        for (int i = 0; i < 300; ++i) {
            std::string bytes = good;
            const int flips = 1 + static_cast<int>(rng() % 3);
            for (int f = 0; f < flips; ++f) bytes[rng() % headerSize] ^= static_cast<char>(1u << (rng() % 8));
            writeBytes(mutated, bytes);
            (loadsOrRefuses(mutated) ? loaded : refused)++;
        }
        // Random bytes anywhere.
        for (int i = 0; i < 200; ++i) {
            std::string bytes = good;
            const int changes = 1 + static_cast<int>(rng() % 8);
            for (int f = 0; f < changes; ++f) bytes[rng() % bytes.size()] = static_cast<char>(rng() & 255);
            writeBytes(mutated, bytes);
            (loadsOrRefuses(mutated) ? loaded : refused)++;
        }
        // Header digits replaced (counts, widths, degrees).
        for (int i = 0; i < 100; ++i) {
            std::string bytes = good;
            std::vector<std::size_t> digits;
            for (std::size_t k = 0; k < headerSize; ++k)
                if (bytes[k] >= '0' && bytes[k] <= '9') digits.push_back(k);
            bytes[digits[rng() % digits.size()]] = static_cast<char>('0' + rng() % 10);
            writeBytes(mutated, bytes);
            (loadsOrRefuses(mutated) ? loaded : refused)++;
        }
    }
    // Pure garbage, with and without a plausible first line.
    for (int i = 0; i < 100; ++i) {
        std::string bytes = (i % 2) ? "ply\nformat binary_little_endian 1.0\n" : "";
        const std::size_t size = rng() % 2000;
        for (std::size_t k = 0; k < size; ++k) bytes += static_cast<char>(rng() & 255);
        writeBytes(mutated, bytes);
        (loadsOrRefuses(mutated) ? loaded : refused)++;
    }
    EXPECT_GT(refused, 100);
    EXPECT_EQ(loaded + refused, 2 * 600 + 100);
}

// ---------------------------------------------------------------------------------------------------
// Writer

TEST(RadiancePlyWriter, RefusesInconsistentInputAndKeepsTheOldFile) {
    MeshOptions o;
    o.vertices = 5;
    o.block = true;
    const RadianceMesh good = makeMesh(o);
    const std::string path = tmpPath("keep.ply");
    rad::writeRadiancePly(path, good);
    const std::string before = readBytes(path);

    auto expectRefusedMesh = [&](const RadianceMesh& m, const std::string& phrase) {
        const std::string message = errorOf([&] { rad::writeRadiancePly(path, m); });
        EXPECT_NE(message.find(phrase), std::string::npos) << message;
        EXPECT_EQ(message.find("cannot save"), 0u) << message;
        EXPECT_EQ(readBytes(path), before);
    };
    RadianceMesh m = good;
    m.normals.pop_back();
    expectRefusedMesh(m, "normals has 14 floats");
    m = good;
    m.positions.pop_back();
    expectRefusedMesh(m, "not a multiple of 3");
    m = good;
    m.colors.resize(3);
    expectRefusedMesh(m, "colors has 3 bytes");
    m = good;
    m.quality.push_back(1);
    expectRefusedMesh(m, "quality has 6 values");
    m = good;
    m.faces[4] = 5;
    expectRefusedMesh(m, "face 1 references vertex 5");
    m = good;
    m.positions[7] = std::numeric_limits<float>::quiet_NaN();
    expectRefusedMesh(m, "vertex 2 has a position that is not a finite number");
    m = good;
    m.radiance->coefficients[50] = std::numeric_limits<float>::infinity();
    expectRefusedMesh(m, "invalid radiance field");
    m = good;
    m.radiance->frames.resize(24);
    expectRefusedMesh(m, "invalid radiance field");
    m = good;
    m.normals[4] += 0.25f;
    expectRefusedMesh(m, "differs from its radiance frame normal");
    m = good;
    m.extraBlocks[0].prefix = "rf_prt";
    expectRefusedMesh(m, "is reserved");
    m = good;
    m.extraBlocks[0].prefix = "has space";
    expectRefusedMesh(m, "not an identifier");
    m = good;
    m.extraBlocks[1].prefix = "prt";
    expectRefusedMesh(m, "two extra blocks");
    m = good;
    m.extraBlocks[0].values.pop_back();
    expectRefusedMesh(m, "values, expected");
    m = good;
    m.extraBlocks[0].metadata["two words"] = "x";
    expectRefusedMesh(m, "contains whitespace");
    m = good;
    m.extraBlocks[0].metadata["k"] = "line\nbreak";
    expectRefusedMesh(m, "control character");

    // Mesh normals may be absent when radiance is present: the frame normals are written.
    m = good;
    m.normals.clear();
    rad::writeRadiancePly(path, m);
    expectSameMesh(m, rad::readRadiancePly(path));

    // No temporary file is left behind.
    for (const auto& entry : std::filesystem::directory_iterator(RADIANCE_TEST_TMPDIR))
        EXPECT_EQ(entry.path().filename().string().find("radiance_ply_keep.ply.part"), std::string::npos)
            << entry.path();
}

TEST(RadiancePlyWriter, IoFailures) {
    const RadianceMesh mesh = makeMesh(MeshOptions{});
    std::string message = errorOf([&] { rad::writeRadiancePly(tmpPath("no_such_dir/x.ply"), mesh); });
    EXPECT_NE(message.find("cannot create the temporary file"), std::string::npos) << message;
    // Target is an existing folder: rename fails, the temporary file is removed.
    const std::string dir = tmpPath("a_folder.ply");
    std::filesystem::create_directories(dir);
    message = errorOf([&] { rad::writeRadiancePly(dir, mesh); });
    EXPECT_NE(message.find("cannot replace the file"), std::string::npos) << message;
    for (const auto& entry : std::filesystem::directory_iterator(RADIANCE_TEST_TMPDIR))
        EXPECT_EQ(entry.path().filename().string().find("radiance_ply_a_folder.ply.part"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------------
// Hostile input (nothing crashes, nothing lies, nothing is lost)

TEST(RadiancePlyHostile, BlockMetadataWithControlCharactersIsRefusedLikeTheWriterDoes) {
    for (const std::string& value : {std::string("a\tb"), std::string("bell\x07"), std::string("cr\rinside"),
                                     std::string("del\x7f")}) {
        PlyBuilder b = baseBuilder();
        b.comments.push_back("block tv width 1");
        b.comments.push_back("block_meta tv note " + value);
        b.vertexProps.push_back({"float", "tv_0"});
        const std::string message = refusal(b.build(), "meta_value");
        SCOPED_TRACE(message);
        // Line 12: ply, format, the eight base comments, the block line, then this one.
        EXPECT_NE(message.find("header line 12: the value of block_meta 'note' of block 'tv' contains a control "
                               "character"),
                  std::string::npos);
        EXPECT_NE(message.find("replace the control characters"), std::string::npos);
        // The writer refuses the same value, so the reader must not hand it out.
        RadianceMesh m = makeMesh(MeshOptions{});
        NamedVertexBlock block;
        block.prefix = "tv";
        block.width = 1;
        block.values.assign(m.vertexCount(), 0.0f);
        block.metadata["note"] = value;
        m.extraBlocks.push_back(block);
        EXPECT_NE(rad::validateRadianceMesh(m).find("control character"), std::string::npos);
    }
    PlyBuilder b = baseBuilder();
    b.comments.push_back("block tv width 1");
    b.comments.push_back("block_meta tv ke\x01y value");
    b.vertexProps.push_back({"float", "tv_0"});
    EXPECT_REFUSED(b.build(), "block_meta key 'ke\\x01y' of block 'tv' contains a control character");
    // Printable UTF-8 and spaces stay accepted.
    b = baseBuilder();
    b.comments.push_back("block tv width 1");
    b.comments.push_back("block_meta tv note caf\xc3\xa9 with  spaces ");
    b.vertexProps.push_back({"float", "tv_0"});
    writeBytes(tmpPath("meta_ok.ply"), b.build());
    EXPECT_EQ(rad::readRadiancePly(tmpPath("meta_ok.ply")).extraBlocks.at(0).metadata.at("note"),
              "caf\xc3\xa9 with  spaces ");
}

TEST(RadiancePlyHostile, UnknownListElementsAreRefusedEvenWhenEmpty) {
    PlyBuilder b = baseBuilder();
    b.extraHeader = "element edge 0\nproperty list uchar int vertex_indices\n";
    EXPECT_REFUSED(b.build(), "element 'edge' has list properties");
    EXPECT_REFUSED(b.build(), "remove the element and its property lines");
}

TEST(RadiancePlyHostile, TruncatedElementAfterFacesWithListsSaysTruncated) {
    PlyBuilder b = baseBuilder();
    b.faceFlagsAndTexcoords = true;
    b.extraHeader = "element edge 1\nproperty int a\n";
    b.extraData = std::string("\x01\x00\x00\x00", 4);
    const std::string good = b.build();
    writeBytes(tmpPath("edge_after_faces.ply"), good);
    checkBaseMesh(rad::readRadiancePly(tmpPath("edge_after_faces.ply")));
    // Three bytes short: the size check (smallest face records) passes, the element does not fit.
    const std::string message = refusal(good.substr(0, good.size() - 3), "edge_cut");
    EXPECT_NE(message.find("file truncated: expected 4 bytes of data for element 'edge', found 1"), std::string::npos)
        << message;
    EXPECT_EQ(message.find("unexpected data"), std::string::npos) << message;
}

TEST(RadiancePlyHostile, SizeRefusalGivesTheFigures) {
    std::string bytes = baseBuilder().build();
    bytes.replace(bytes.find("element vertex 4"), 16, "element vertex 1000000");
    // 90 bytes per vertex: x..rf_b_2 (19 floats), 4 colours, a short and a double.
    const std::string message = refusal(bytes, "figures");
    EXPECT_NE(message.find("expected 90000000 bytes of vertex data, found 386: the header declares 1000000 vertices "
                           "of 90 bytes each"),
              std::string::npos)
        << message;
}

namespace {
long maxRssKilobytes() {
    struct rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
}

// A header for n PB1 vertices (radiance: 3 + 3 + 3 + 9 floats = 72 bytes each) and `faces` faces,
// followed by a hole: the file has the declared size but is all zeros (sparse, no disk used).
std::string sparseFile(const std::string& name, std::size_t n, std::size_t faces) {
    std::ostringstream h;
    h << "ply\nformat binary_little_endian 1.0\ncomment radiance_format_version 1\ncomment radiance_basis PB1\n"
         "comment radiance_reflected 0\nelement vertex "
      << n << "\n";
    for (const char* p : {"x", "y", "z", "nx", "ny", "nz", "rf_tx", "rf_ty", "rf_tz"}) h << "property float " << p << "\n";
    for (const char* c : {"r", "g", "b"})
        for (int k = 0; k < 3; ++k) h << "property float rf_" << c << "_" << k << "\n";
    h << "element face " << faces << "\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string path = tmpPath(name);
    writeBytes(path, h.str());
    std::filesystem::resize_file(path, h.str().size() + 72 * n + 13 * faces);
    return path;
}
}  // namespace

// Reading the 512 MiB file whole would raise the peak by more than 512 MiB. Under AddressSanitizer the
// reserved (never filled) output arrays cost 1/8 of their size in shadow memory when they are freed
// (about 70 MiB here, measured 88 MiB in all), so the sanitizer build gets a looser bound that still
// lies far below the file's size.
#if defined(__SANITIZE_ADDRESS__)
constexpr long kSparseReadRssLimitKilobytes = 192 * 1024;
#else
constexpr long kSparseReadRssLimitKilobytes = 64 * 1024;
#endif

TEST(RadiancePlyHostile, SparseFileIsRefusedWithoutAllocatingItsSize) {
    // 512 MiB of zeros behind a plausible header: reading it whole would cost 512 MiB of buffer plus
    // as much again in arrays; refused after one chunk it costs a few MiB.
    const std::size_t n = (std::size_t(512) << 20) / 72;
    const long before = maxRssKilobytes();
    const std::string withFaces = sparseFile("sparse_faces.ply", n, 1000000);
    std::string message = errorOf([&] { rad::readRadiancePly(withFaces); });
    EXPECT_NE(message.find("face 0 has 0 vertices"), std::string::npos) << message;
    const std::string noFaces = sparseFile("sparse_vertices.ply", n, 0);
    message = errorOf([&] { rad::readRadiancePly(noFaces); });
    EXPECT_NE(message.find("normal of vertex 0 is not unit length"), std::string::npos) << message;
    EXPECT_LT(maxRssKilobytes() - before, kSparseReadRssLimitKilobytes);
    std::filesystem::remove(withFaces);
    std::filesystem::remove(noFaces);
}

TEST(RadiancePlyHostile, ManyChunksRoundTripBitExact) {
    // More than 8 MiB of vertex records (PB4 with normals, colours, quality and blocks of widths 5 and 2:
    // 252 bytes each, three chunks), and a problem in the last chunk is still found.
    MeshOptions o;
    o.vertices = 70000;
    o.block = true;
    const RadianceMesh mesh = makeMesh(o);
    const std::string path = tmpPath("chunks.ply");
    rad::writeRadiancePly(path, mesh);
    expectSameMesh(mesh, rad::readRadiancePly(path));
    std::string bytes = readBytes(path);
    // Last coefficient of the last vertex (rf_b_14, just before the blocks' 7 floats and the faces).
    const std::size_t at = bytes.size() - 13 * mesh.faceCount() - 4 * 7 - 4;
    const float inf = std::numeric_limits<float>::infinity();
    std::memcpy(&bytes[at], &inf, 4);
    EXPECT_REFUSED(bytes, "vertex 69999 has a radiance coefficient that is not a finite number");
}

TEST(RadiancePlyHostile, SkippedDataIsReported) {
    PlyBuilder b = baseBuilder();
    b.faceFlagsAndTexcoords = true;
    b.extraHeader = "element material 2\nproperty float shininess\n";
    b.extraData = std::string(8, '\x01');
    writeBytes(tmpPath("skipped.ply"), b.build());
    const RadianceMesh m = rad::readRadiancePly(tmpPath("skipped.ply"));
    ASSERT_EQ(m.skippedOnRead.size(), 3u);
    EXPECT_NE(m.skippedOnRead[0].find("vertex properties 'unknown_double', 'unknown_short'"), std::string::npos)
        << m.skippedOnRead[0];
    EXPECT_NE(m.skippedOnRead[0].find("declare it as a block"), std::string::npos);
    EXPECT_NE(m.skippedOnRead[1].find("face properties 'flags', 'texcoord'"), std::string::npos) << m.skippedOnRead[1];
    EXPECT_NE(m.skippedOnRead[2].find("element 'material' (2 records)"), std::string::npos) << m.skippedOnRead[2];
    // Our own files skip nothing.
    MeshOptions o;
    o.block = true;
    rad::writeRadiancePly(tmpPath("skipped_none.ply"), makeMesh(o));
    EXPECT_TRUE(rad::readRadiancePly(tmpPath("skipped_none.ply")).skippedOnRead.empty());
}

TEST(RadiancePlyHostile, ExtraBlocksOtherThanPrtSurviveARoundTrip) {
    MeshOptions o;
    o.basis.reset();
    o.block = true;  // blocks "prt" and "prt_1"
    RadianceMesh mesh = makeMesh(o);
    NamedVertexBlock c;
    c.prefix = "curvature";
    c.width = 3;
    for (std::size_t i = 0; i < 3 * mesh.vertexCount(); ++i) c.values.push_back(0.125f * static_cast<float>(i));
    c.metadata["unit"] = "1/m";
    mesh.extraBlocks.push_back(c);
    rad::writeRadiancePly(tmpPath("blocks_a.ply"), mesh);
    const RadianceMesh back = rad::readRadiancePly(tmpPath("blocks_a.ply"));
    expectSameMesh(mesh, back);
    ASSERT_EQ(back.extraBlocks.size(), 3u);
    EXPECT_EQ(back.extraBlocks[2].values[5], 0.625f);
}

namespace {
// A process id that is certainly not running: a child that has exited and been reaped.
pid_t deadPid() {
    const pid_t child = fork();
    if (child == 0) _exit(0);
    int status = 0;
    waitpid(child, &status, 0);
    return child;
}
}  // namespace

TEST(RadiancePlyWriter, RemovesStaleTemporariesOfDeadWritersOnly) {
    const std::string path = tmpPath("stale.ply");
    const RadianceMesh old = makeMesh(MeshOptions{});
    rad::writeRadiancePly(path, old);
    const pid_t dead = deadPid();
    const std::string stale = path + ".part-" + std::to_string(dead) + "-0-4242";
    const std::string live = path + ".part-" + std::to_string(getppid()) + "-3-17";  // a running process
    const std::string notOurs = path + ".part-notes";
    const std::string otherTarget = tmpPath("stale_other.ply") + ".part-" + std::to_string(dead) + "-0-1";
    for (const auto& p : {stale, live, notOurs, otherTarget}) writeBytes(p, std::string(1000, 'x'));
    MeshOptions o;
    o.seed = 99;
    const RadianceMesh next = makeMesh(o);
    rad::writeRadiancePly(path, next);
    EXPECT_FALSE(std::filesystem::exists(stale));
    EXPECT_TRUE(std::filesystem::exists(live));
    EXPECT_TRUE(std::filesystem::exists(notOurs));
    EXPECT_TRUE(std::filesystem::exists(otherTarget));
    expectSameMesh(next, rad::readRadiancePly(path));
    for (const auto& p : {live, notOurs, otherTarget}) std::filesystem::remove(p);
}

// Inputs found by bench/fuzz_radiance_ply.sh (the harness run on the reader before issue 16): the
// reader accepted block metadata with control characters (NUL, SOH, BEL...) that the writer refuses,
// so a file that loaded could not be saved. Each must now be refused with the header line named.
TEST(RadiancePlyFuzzRegressions, ControlCharactersInBlockMetadata) {
    const std::filesystem::path folder = std::filesystem::path(RADIANCE_SOURCE_DIR) / "tests/unit/data/rply_fuzz_regressions";
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        ++files;
        const std::string message = errorOf([&] { rad::readRadiancePly(entry.path().string()); });
        SCOPED_TRACE(entry.path().filename().string());
        EXPECT_NE(message.find("contains a control character"), std::string::npos) << message;
        EXPECT_NE(message.find(": header line "), std::string::npos) << message;
        EXPECT_FALSE(loadsOrRefuses(entry.path().string()));
    }
    EXPECT_EQ(files, 6);
}

// Found by comparing the two readers on the fuzzer's corpus (bench/fuzz/compare_readers.py): names
// taken from the file went raw into some messages; a NUL byte would cut the sentence short in the log.
TEST(RadiancePlyHostile, NamesFromTheFileAreEscapedInEveryMessage) {
    PlyBuilder b = baseBuilder();
    b.comments.push_back(std::string("block_meta bl\0ck key value", 26));
    std::string message = refusal(b.build(), "raw_prefix");
    EXPECT_EQ(message.find('\0'), std::string::npos);
    EXPECT_NE(message.find("block_meta for undeclared block 'bl\\x00ck' (add 'comment block <prefix> width <n>')"),
              std::string::npos)
        << message;
    b = baseBuilder();
    b.faceFlagsAndTexcoords = true;
    b.extraHeader = std::string("element m\xe3t 1\nproperty int a\n");
    b.extraData = std::string("\x01", 1);
    message = refusal(b.build(), "raw_element");
    EXPECT_NE(message.find("expected 4 bytes of data for element 'm\\xe3t', found 1"), std::string::npos) << message;
}
