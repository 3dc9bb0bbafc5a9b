// The whole out-of-core job (outofcore/out_of_core_simplification.h): a PLY file in, the simplified
// mesh, its atlas and the files of a bake out; refusals leave no file.
#include "outofcore/out_of_core_simplification.h"

#include "bake/bake_description.h"
#include "bake/texture_atlas.h"
#include "geometry/primitive_meshes.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using Folder = radtest::TemporaryFolder;

// Binary little-endian PLY of the mesh, without normals (the job computes area-weighted ones).
std::string writePly(const fs::path& path, const rad::TriangleMesh& mesh) {
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << mesh.vertexCount()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.faceCount()
        << "\nproperty list uchar uint vertex_indices\nend_header\n";
    out.write(reinterpret_cast<const char*>(mesh.positions.data()), std::streamsize(4 * mesh.positions.size()));
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
        const char three = 3;
        out.write(&three, 1);
        out.write(reinterpret_cast<const char*>(&mesh.faces[3 * f]), 12);
    }
    return path.string();
}

// A request over `mesh` written as <folder>/<name>.ply, with outputs at <folder>/<name>_*.
rad::OutOfCoreRequest requestFor(const Folder& folder, const std::string& name, const rad::TriangleMesh& mesh,
                                 std::size_t targetTriangles, int textureSize) {
    rad::OutOfCoreRequest request;
    request.plyPath = writePly(folder.path / (name + ".ply"), mesh);
    request.targetTriangles = targetTriangles;
    request.textureSize = textureSize;
    request.outputBase = (folder.path / name).string();
    return request;
}

// Mean angle, in degrees, between the written map at each face's UV centroid and the unit sphere's
// normal at the face's centroid (the direction from the centre); infinite when the map's size is
// not `size`.
double meanDegreesFromTheSphereAtUvCentroids(const rad::OutOfCoreReport& report, int size) {
    int width = 0, height = 0;
    const std::vector<float> map = rad::readNormalMap(report.normalMapFile, width, height);
    if (width != size || height != size) return std::numeric_limits<double>::infinity();
    double sum = 0;
    for (std::size_t f = 0; f < report.mesh.faceCount(); ++f) {
        float u = 0, v = 0, p[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            u += report.wedgeUv[6 * f + 2 * k] / 3;
            v += report.wedgeUv[6 * f + 2 * k + 1] / 3;
            for (int a = 0; a < 3; ++a) p[a] += report.mesh.positions[3 * report.mesh.faces[3 * f + k] + a] / 3;
        }
        const int column = std::min(width - 1, int(u * width)), row = std::min(height - 1, int((1 - v) * height));
        const float* n = &map[3 * (std::size_t(row) * width + column)];
        const float length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        sum += std::acos(std::min(1.0f, (n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / length)) * 180.0 / 3.14159265;
    }
    return sum / double(report.mesh.faceCount());
}

TEST(OutOfCoreSimplification, SphereFileGivesASimplifiedMeshAndAMap) {
    const Folder folder("radiance_ooc_sphere");
    // A level-5 icosphere: 20,480 triangles.
    const rad::OutOfCoreRequest request = requestFor(folder, "sphere", rad::makeIcosphere(5), 500, 256);
    const rad::OutOfCoreReport report = rad::simplifyOutOfCore(request);
    EXPECT_FALSE(report.normalsFromFile);
    EXPECT_EQ(report.read.trianglesEmitted, 20480u);
    EXPECT_GT(report.mesh.faceCount(), 350u);
    EXPECT_LT(report.mesh.faceCount(), 650u);
    EXPECT_EQ(report.wedgeUv.size(), 6 * report.mesh.faceCount());
    EXPECT_EQ(report.pointsSplatted, rad::icosphereVertexCount(5));
    const rad::BakeDescription description = rad::readBakeDescription(report.descriptionFile);
    EXPECT_EQ(description.space, rad::NormalSpace::Object);
    EXPECT_EQ(description.size, 256);
    // The map at each face's UV centroid is the sphere's normal at the face's centroid (within the
    // faceting of the points' normals: area-weighted normals of a level-5 icosphere).
    EXPECT_LT(meanDegreesFromTheSphereAtUvCentroids(report, 256), 2.0);
    EXPECT_EQ(folder.files(), 3u);  // sphere.ply, sphere_normal.png, sphere_bake.txt: no temporary left
}

// Gutter 0 packs the atlas's triangles edge to edge: 64^2 texels hold 288 triangles (cells of 5
// texels) where a 1-texel gutter holds 162 (cells of 7), so a target of 200 is refused with 1 and
// baked with 0; no texel is covered by two triangles, and the map still gives the sphere's normals.
TEST(OutOfCoreSimplification, GutterZeroFitsTwiceAsManyTrianglesWithoutSharedTexels) {
    const Folder folder("radiance_ooc_gutter0");
    rad::OutOfCoreRequest request = requestFor(folder, "sphere", rad::makeIcosphere(5), 200, 64);
    request.gutterTexels = 1;
    EXPECT_THROW(rad::simplifyOutOfCore(request), rad::BakeInputError);
    request.gutterTexels = -1;
    EXPECT_THROW(rad::simplifyOutOfCore(request), rad::BakeInputError);
    request.gutterTexels = 0;
    const rad::OutOfCoreReport report = rad::simplifyOutOfCore(request);
    ASSERT_GT(report.mesh.faceCount(), 162u);
    // Texel centres covered by each triangle (corners on texel centres: centres on an edge count);
    // no centre is covered by two triangles.
    std::vector<int> owner(64 * 64, -1);
    std::size_t shared = 0;
    for (std::size_t f = 0; f < report.mesh.faceCount(); ++f) {
        const float* uv = &report.wedgeUv[6 * f];
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const double px = (x + 0.5) / 64, py = (y + 0.5) / 64;
                double d[3];
                for (int k = 0; k < 3; ++k) {
                    const float* a = uv + 2 * k;
                    const float* b = uv + 2 * ((k + 1) % 3);
                    d[k] = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
                }
                const double eps = 1e-9;
                const bool inside = (d[0] >= -eps && d[1] >= -eps && d[2] >= -eps) || (d[0] <= eps && d[1] <= eps && d[2] <= eps);
                if (!inside) continue;
                if (owner[y * 64 + x] >= 0) ++shared;
                owner[y * 64 + x] = int(f);
            }
    }
    EXPECT_EQ(shared, 0u);
    EXPECT_LT(meanDegreesFromTheSphereAtUvCentroids(report, 64), 3.0);
}

TEST(OutOfCoreSimplification, RefusalsAndCancelLeaveNoFile) {
    const Folder folder("radiance_ooc_refusals");
    const rad::OutOfCoreRequest request = requestFor(folder, "sphere", rad::makeIcosphere(3), 100, 128);

    rad::OutOfCoreRequest badSize = request;
    badSize.textureSize = 100;
    EXPECT_THROW(rad::simplifyOutOfCore(badSize), rad::BakeInputError);
    rad::OutOfCoreRequest badFolder = request;
    badFolder.outputBase = (folder.path / "missing" / "out").string();
    EXPECT_THROW(rad::simplifyOutOfCore(badFolder), rad::BakeInputError);
    rad::OutOfCoreRequest missing = request;
    missing.plyPath = (folder.path / "nothing.ply").string();
    EXPECT_THROW(rad::simplifyOutOfCore(missing), rad::PlyStreamError);
    rad::OutOfCoreRequest tooBig = request;
    tooBig.targetTriangles = 1000000;  // a million triangles do not fit a 128^2 atlas
    EXPECT_THROW(rad::simplifyOutOfCore(tooBig), rad::BakeInputError);
    rad::OutOfCoreRequest cancelled = request;
    cancelled.progress = [](double fraction, const char*) { return fraction < 0.7; };
    EXPECT_THROW(rad::simplifyOutOfCore(cancelled), rad::OperationCancelled);
    EXPECT_EQ(folder.files(), 1u);  // only the input
}

// One stray vertex that no triangle uses, 1e6 away, stretched the clustering grid: a target of
// 400 triangles gave 36. The grid is now placed on the vertices the triangles use.
TEST(OutOfCoreSimplification, AnUnreferencedFarVertexChangesNothing) {
    const Folder folder("radiance_ooc_stray");
    rad::TriangleMesh sphere = rad::makeIcosphere(4);
    const rad::OutOfCoreReport clean = rad::simplifyOutOfCore(requestFor(folder, "clean", sphere, 400, 256));
    sphere.positions.insert(sphere.positions.end(), {1e6f, 0.0f, 0.0f});
    const rad::OutOfCoreReport stray = rad::simplifyOutOfCore(requestFor(folder, "stray", sphere, 400, 256));
    EXPECT_EQ(stray.mesh.faceCount(), clean.mesh.faceCount());
    EXPECT_GT(stray.mesh.faceCount(), 300u);
    EXPECT_EQ(stray.pointsSplatted, clean.pointsSplatted);  // the stray point is not in the map
    EXPECT_LT(meanDegreesFromTheSphereAtUvCentroids(stray, 256), 2.0);
}

// At 1e-30 every point landed in one texel, at 1e20 none was used, and at 1e-12 or 1e15 the map
// drifted from the in-core bake without a word: refused before any file is written, with the fix.
TEST(OutOfCoreSimplification, ScalesTheCoresCannotComputeWithAreRefused) {
    const Folder folder("radiance_ooc_scale");
    for (float scale : {1e-30f, 1e-12f, 1e15f, 1e20f}) {
        rad::TriangleMesh sphere = rad::makeIcosphere(3);
        for (float& x : sphere.positions) x *= scale;
        const rad::OutOfCoreRequest request = requestFor(folder, "scaled", sphere, 100, 128);
        try {
            rad::simplifyOutOfCore(request);
            ADD_FAILURE() << "a sphere of radius " << scale << " was accepted";
        } catch (const rad::BakeInputError& e) {
            const std::string text = e.what();
            EXPECT_TRUE(text.find("scale it up") != std::string::npos ||
                        text.find("scale the mesh down") != std::string::npos) << text;
        }
        EXPECT_EQ(folder.files(), 1u) << scale;  // only the input
    }
}

// Two runs to the same output base shared the fixed temporaries <base>_normal.png.part and
// <base>_bake.txt.part (run A could report success with run B's files). Each run has its own: a
// leftover at the old fixed name (a folder here, which no write can go through) is never used.
TEST(OutOfCoreSimplification, TemporariesAreUniquePerRun) {
    const Folder folder("radiance_ooc_temporaries");
    rad::OutOfCoreRequest request = requestFor(folder, "out", rad::makeIcosphere(3), 100, 128);
    request.bits = 8;
    fs::create_directory(folder.path / "out_normal.png.part");
    fs::create_directory(folder.path / "out_bake.txt.part");
    const rad::OutOfCoreReport report = rad::simplifyOutOfCore(request);
    EXPECT_TRUE(fs::is_regular_file(report.normalMapFile));
    EXPECT_TRUE(fs::is_regular_file(report.descriptionFile));
    EXPECT_EQ(folder.files(), 5u);  // the input, the two files, the two folders: no temporary left
}

}  // namespace
