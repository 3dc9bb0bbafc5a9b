// Tests of io/obj_mesh.h: the corner forms (v, v/vt, v/vt/vn, v//vn), negative indices, fan
// triangulation, texture from mtllib/map_Kd, per-vertex normals from vn, exact write-read round
// trips (with and without texture and normals), and refusals naming the file and the line.
#include "io/obj_mesh.h"
#include "test_temporary_directory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

namespace {

std::string tmpPath(const std::string& name) { return std::string(RADIANCE_TEST_TMPDIR) + "/obj_mesh_" + name; }

std::string writeText(const std::string& name, const std::string& text) {
    const std::string path = tmpPath(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string readError(const std::string& path) {
    try {
        rad::readObj(path);
    } catch (const rad::ObjReadError& e) {
        return e.what();
    }
    return "";
}

TEST(ObjMesh, ReadsCornerFormsNegativeIndicesAndTriangulatesPolygonsAsFans) {
    writeText("quad.mtl", "newmtl other\nmap_Kd other map.png\nnewmtl skin\nmap_Kd -s 1 1 1 tex/skin.png\n");
    const std::string path = writeText("quad.obj",
                                       "# a quad and a triangle\r\n"
                                       "mtllib obj_mesh_quad.mtl\n"
                                       "v 0 0 0\nv 1 0 0 0.5 0.5 0.5\nv 1 1 0\nv 0 1 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1 0\n"
                                       "usemtl skin\n"
                                       "o thing\ng part\ns 1\n"
                                       "f 1/1 2/2 3/3 4/4\n"
                                       "f -4/-4 -2/-2 \\\n -1/-1\n");
    const rad::ObjMesh obj = rad::readObj(path);
    ASSERT_EQ(obj.mesh.vertexCount(), 4u);
    ASSERT_EQ(obj.mesh.faceCount(), 3u);
    const std::vector<std::uint32_t> faces = {0, 1, 2, 0, 2, 3, 0, 2, 3};
    EXPECT_EQ(obj.mesh.faces, faces);
    const std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1, 0, 0, 1, 1, 0, 1};
    EXPECT_EQ(obj.wedgeUv, uv);
    EXPECT_FALSE(obj.mesh.hasNormals());
    EXPECT_EQ(obj.textureName, "tex/skin.png");  // the material used, not the first; option skipped
    EXPECT_EQ(obj.texturePath, std::string(RADIANCE_TEST_TMPDIR) + "/tex/skin.png");
    EXPECT_TRUE(obj.warnings.empty());
    // Without usemtl: the first map_Kd, spaces in the name kept.
    const rad::ObjMesh plain = rad::readObj(writeText("plain.obj", "mtllib obj_mesh_quad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_EQ(plain.textureName, "other map.png");
}

TEST(ObjMesh, NormalsFromVnAndNoUvsForVDoubleSlashVn) {
    const std::string path = writeText("normals.obj",
                                       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                       "vn 0 0 2\nvn 0 1 0\nvn 1 0 0\n"
                                       "f 1//1 2//1 3//1\nf 1//2 4//3 2//2\n");
    const rad::ObjMesh obj = rad::readObj(path);
    EXPECT_TRUE(obj.wedgeUv.empty());
    ASSERT_TRUE(obj.mesh.hasNormals());
    // Vertex 0 (1-based 1): corners with vn (0,0,2) and (0,1,0): normalised mean.
    EXPECT_NEAR(obj.mesh.normals[1], 1 / std::sqrt(5.0f), 1e-6f);
    EXPECT_NEAR(obj.mesh.normals[2], 2 / std::sqrt(5.0f), 1e-6f);
    EXPECT_FLOAT_EQ(obj.mesh.normals[3 * 2 + 2], 1.0f);   // vertex 2: (0,0,2) normalised
    EXPECT_FLOAT_EQ(obj.mesh.normals[3 * 3 + 0], 1.0f);   // vertex 3: (1,0,0)
    // v/vt/vn with mixed vn: normals dropped with a warning, uvs kept.
    const rad::ObjMesh mixed = rad::readObj(writeText("mixed_vn.obj",
                                                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
                                                      "f 1/1/1 2/1/1 3/1\n"));
    EXPECT_FALSE(mixed.mesh.hasNormals());
    EXPECT_EQ(mixed.wedgeUv.size(), 6u);
    EXPECT_EQ(mixed.warnings.size(), 1u);
    // A missing .mtl is a warning, not an error.
    const rad::ObjMesh noMtl = rad::readObj(writeText("no_mtl.obj", "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_TRUE(noMtl.textureName.empty());
    ASSERT_EQ(noMtl.warnings.size(), 1u);
    EXPECT_NE(noMtl.warnings[0].find("nowhere.mtl"), std::string::npos);
}

rad::TriangleMesh randomMesh(std::size_t vertices, std::size_t faces, bool normals, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-100, 100);
    rad::TriangleMesh m;
    for (std::size_t i = 0; i < 3 * vertices; ++i) m.positions.push_back(u(rng) * 1e-3f * float(i % 7 + 1));
    if (normals)
        for (std::size_t i = 0; i < vertices; ++i) {
            float n[3] = {u(rng), u(rng), u(rng)};
            const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (float c : n) m.normals.push_back(c / len);
        }
    for (std::size_t f = 0; f < faces; ++f)
        for (int k = 0; k < 3; ++k) m.faces.push_back(std::uint32_t((f + std::size_t(k) * 7) % vertices));
    return m;
}

TEST(ObjMesh, WriteReadRoundTripIsExact) {
    for (const bool normals : {false, true})
        for (const bool uvs : {false, true}) {
            const rad::TriangleMesh mesh = randomMesh(50, 80, normals, 7);
            std::vector<float> wedgeUv;
            std::mt19937 rng(9);
            std::uniform_real_distribution<float> u(0, 1);
            if (uvs)
                for (int i = 0; i < 6 * 80; ++i) wedgeUv.push_back(u(rng));
            const std::string name = std::string("round_") + (normals ? "n" : "") + (uvs ? "t" : "");
            const std::string path = tmpPath(name + ".obj");
            rad::writeObj(path, mesh, wedgeUv, uvs ? "maps/" + name + ".png" : "");
            const rad::ObjMesh back = rad::readObj(path);
            EXPECT_EQ(back.mesh.positions, mesh.positions);
            EXPECT_EQ(back.mesh.faces, mesh.faces);
            EXPECT_EQ(back.wedgeUv, wedgeUv);
            if (normals) {
                // Normalising a written unit normal may move it by an ulp.
                ASSERT_EQ(back.mesh.normals.size(), mesh.normals.size());
                for (std::size_t i = 0; i < mesh.normals.size(); ++i) EXPECT_NEAR(back.mesh.normals[i], mesh.normals[i], 2e-7f);
            } else {
                EXPECT_FALSE(back.mesh.hasNormals());
            }
            EXPECT_EQ(back.textureName, uvs ? "maps/" + name + ".png" : "");
            EXPECT_TRUE(back.warnings.empty());
        }
}

TEST(ObjMesh, MalformedFilesAreRefusedWithFileAndLine) {
    const struct {
        const char* name;
        const char* text;
        const char* where;
        const char* what;
    } cases[] = {
        {"bad_number.obj", "v 0 0 0\nv 1 x 0\n", ":2:", "malformed vertex coordinate 'x'"},
        {"short_vertex.obj", "v 0 0\n", ":1:", "a vertex needs x y z"},
        {"index_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", ":5:", "vertex index 4 out of range"},
        {"index_negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", ":4:", "vertex index -4 out of range"},
        {"index_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ":4:", "index 0"},
        {"two_corners.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", ":3:", "at least 3 corners"},
        {"vt_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", ":5:", "texture coordinate index 2 out of range"},
        {"mixed_vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 2 3\n", ":6:", "all or none"},
        {"bad_corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", ":4:", "malformed face corner"},
        {"bad_vn.obj", "vn 0 1\n", ":1:", "a normal needs x y z"},
    };
    for (const auto& c : cases) {
        const std::string path = writeText(c.name, c.text);
        const std::string why = readError(path);
        EXPECT_NE(why.find(path + c.where), std::string::npos) << c.name << ": " << why;
        EXPECT_NE(why.find(c.what), std::string::npos) << c.name << ": " << why;
    }
    const std::string missing = tmpPath("missing.obj");
    std::remove(missing.c_str());
    EXPECT_NE(readError(missing).find(missing), std::string::npos);
}

TEST(ObjMesh, WriterRefusesInconsistentInput) {
    rad::TriangleMesh mesh = randomMesh(4, 2, false, 1);
    EXPECT_THROW(rad::writeObj(tmpPath("bad_uv.obj"), mesh, std::vector<float>(5, 0.5f)), rad::ObjWriteError);
    mesh.faces[0] = 99;
    EXPECT_THROW(rad::writeObj(tmpPath("bad_face.obj"), mesh, {}), rad::ObjWriteError);
    EXPECT_THROW(rad::writeObj(tmpPath("no_dir/x.obj"), randomMesh(4, 2, false, 1), {}), rad::ObjWriteError);
}

// The OBJ and its MTL replace older files whole, and no temporary is left beside them.
TEST(ObjMesh, WriterReplacesFilesWholeAndLeavesNoTemporary) {
    const std::filesystem::path folder = std::filesystem::path(RADIANCE_TEST_TMPDIR) / "obj_mesh_atomic";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const std::string path = (folder / "mesh.obj").string();
    { std::ofstream(path) << "an older, longer file that must not leave a tail behind\n" << std::string(100000, 'x'); }
    const rad::TriangleMesh mesh = randomMesh(6, 4, false, 3);
    rad::writeObj(path, mesh, std::vector<float>(6 * mesh.faceCount(), 0.25f), "mesh_normal.png");
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"mesh.mtl", "mesh.obj"}));
    EXPECT_EQ(readError(path), "");
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text.find("older"), std::string::npos);
    EXPECT_EQ(text.find("xxxx"), std::string::npos);
    std::filesystem::remove_all(folder);
}

}  // namespace
