#include "simplify/progressive_mesh.h"

#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"
#include "radiance/material_radiance.h"
#include "io/radiance_ply.h"
#include "simplify/radiance_simplification.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

namespace {

using rad::CollapseKind;

rad::RadianceMesh sphereWithRadiance(int level, rad::BasisSpec basis) {
    rad::TriangleMesh sphere = rad::makeIcosphere(level);
    rad::computeAreaWeightedNormals(sphere);
    rad::AnalyticMaterial material;
    material.exponent = 20.0;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.3, 0.5, 1.0), rad::Rgb(1.0, 0.9, 0.8)});
    rad::MaterialRadianceOptions options;
    options.basis = basis;
    rad::RadianceMesh mesh;
    mesh.positions = sphere.positions;
    mesh.faces = sphere.faces;
    mesh.radiance = rad::makeMaterialRadiance(sphere.positions.data(), sphere.normals.data(), sphere.vertexCount(),
                                              material, lighting, options);
    mesh.normals = std::vector<float>();
    mesh.quality.resize(mesh.vertexCount());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) mesh.quality[v] = static_cast<float>(v);
    return mesh;
}

// Faces as a set of position triples (rotated so the smallest vertex comes first, orientation kept),
// independent of vertex numbering.
std::set<std::vector<float>> faceSet(const std::vector<float>& p, const std::vector<std::uint32_t>& f) {
    std::set<std::vector<float>> out;
    for (std::size_t i = 0; i < f.size() / 3; ++i) {
        std::vector<std::vector<float>> corners;
        for (int k = 0; k < 3; ++k) corners.push_back({p[3 * f[3 * i + k]], p[3 * f[3 * i + k] + 1], p[3 * f[3 * i + k] + 2]});
        const auto smallest = std::min_element(corners.begin(), corners.end()) - corners.begin();
        std::vector<float> key;
        for (int k = 0; k < 3; ++k) {
            const auto& c = corners[(smallest + k) % 3];
            key.insert(key.end(), c.begin(), c.end());
        }
        out.insert(key);
    }
    return out;
}

TEST(ProgressiveMesh, ReplayReproducesEveryIntermediateMesh) {
    for (CollapseKind kind : {CollapseKind::HalfEdge, CollapseKind::Full}) {
        const rad::RadianceMesh original = sphereWithRadiance(3, {rad::BasisKind::SphericalHarmonics, 3});
        rad::CollapseMesh mesh(original.positions.data(), original.vertexCount(), original.faces.data(),
                               original.faceCount());
        rad::ProgressiveRadianceMesh progressive;
        progressive.base = original;
        progressive.kind = kind;
        rad::RadianceField field = *original.radiance;  // geometry-only: rows stay v1's
        rad::ProgressiveRecorder recorder(progressive, mesh, &field);
        const std::size_t checkpoints[] = {1, 37, 200};
        std::vector<std::set<std::vector<float>>> snapshots;
        rad::EdgeCollapseOptions options;
        options.kind = kind;
        options.targetFaceCount = 300;
        rad::simplifyByEdgeCollapse(mesh, nullptr, options, [&](const rad::CollapseStep& s) {
            recorder(s);
            if (std::find(std::begin(checkpoints), std::end(checkpoints), progressive.steps.size()) != std::end(checkpoints)) {
                std::vector<float> p;
                std::vector<std::uint32_t> f, map;
                mesh.compact(p, f, map);
                snapshots.push_back(faceSet(p, f));
            }
        });
        ASSERT_EQ(snapshots.size(), 3u);
        for (int i = 0; i < 3; ++i) {
            const rad::RadianceMesh lod = progressive.extract(checkpoints[i]);
            EXPECT_EQ(faceSet(lod.positions, lod.faces), snapshots[i]) << "kind " << int(kind) << " step " << checkpoints[i];
            EXPECT_EQ(lod.faceCount(), progressive.faceCountAfter[checkpoints[i] - 1]);
            EXPECT_TRUE(rad::validateRadianceMesh(lod).empty()) << rad::validateRadianceMesh(lod);
        }
        // Per-vertex data follows the vertices: quality was the original index.
        const rad::RadianceMesh last = progressive.extract(progressive.steps.size());
        std::set<float> removed;
        for (const rad::CollapseStep& s : progressive.steps) removed.insert(static_cast<float>(s.removed));
        for (float q : last.quality) EXPECT_EQ(removed.count(q), 0u);
        EXPECT_EQ(last.vertexCount() + progressive.steps.size(), original.vertexCount());
        // Zero steps is the original.
        EXPECT_EQ(progressive.extract(0).faces, original.faces);
    }
}

TEST(ProgressiveMesh, StepsForFaceCount) {
    rad::ProgressiveRadianceMesh p;
    p.base.faces.resize(3 * 10);
    p.steps.resize(4);
    p.faceCountAfter = {8, 6, 4, 2};
    EXPECT_EQ(p.stepsForFaceCount(10), 0u);
    EXPECT_EQ(p.stepsForFaceCount(9), 1u);
    EXPECT_EQ(p.stepsForFaceCount(6), 2u);
    EXPECT_EQ(p.stepsForFaceCount(5), 3u);
    EXPECT_EQ(p.stepsForFaceCount(0), 4u);
}

class ProgressiveFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir = std::filesystem::temp_directory_path() /
              ("progressive_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    std::filesystem::path dir;
};

TEST_F(ProgressiveFile, RoundTripReplaysTheSameLevels) {
    for (CollapseKind kind : {CollapseKind::HalfEdge, CollapseKind::Full}) {
        rad::RadianceSimplificationOptions options;
        options.metric = rad::SimplificationMetric::GeometryOnly;
        options.collapse.kind = kind;
        options.collapse.targetFaceCount = 100;
        const rad::RadianceSimplificationResult r =
            rad::simplifyRadianceMesh(sphereWithRadiance(2, {rad::BasisKind::SphericalHarmonics, 2}), options);
        const std::string path = (dir / "sphere.rpm").string(), base = (dir / "sphere_base.rply").string();
        rad::writeProgressiveMesh(path, base, r.progressive);
        const rad::ProgressiveRadianceMesh back = rad::readProgressiveMesh(path);
        ASSERT_EQ(back.steps.size(), r.progressive.steps.size());
        EXPECT_EQ(back.kind, kind);
        EXPECT_EQ(back.faceCountAfter, r.progressive.faceCountAfter);
        EXPECT_EQ(back.survivorRows, r.progressive.survivorRows);
        for (std::size_t k : {std::size_t(0), back.steps.size() / 2, back.steps.size()}) {
            const rad::RadianceMesh a = r.progressive.extract(k), b = back.extract(k);
            EXPECT_EQ(a.faces, b.faces);
            EXPECT_EQ(a.positions, b.positions);
            EXPECT_EQ(a.radiance->coefficients, b.radiance->coefficients);
        }
    }
}

TEST_F(ProgressiveFile, RefusesTruncatedAndMismatchedFiles) {
    rad::RadianceSimplificationOptions options;
    options.metric = rad::SimplificationMetric::GeometryOnly;
    options.collapse.targetFaceCount = 100;
    const rad::RadianceSimplificationResult r =
        rad::simplifyRadianceMesh(sphereWithRadiance(2, {rad::BasisKind::HemisphericalPolynomial, 2}), options);
    const std::string path = (dir / "a.rpm").string(), base = (dir / "a.rply").string();
    rad::writeProgressiveMesh(path, base, r.progressive);
    std::vector<char> bytes = radtest::readBytes(path);
    bytes.resize(bytes.size() - 5);
    radtest::writeBytes(path, bytes);
    try {
        rad::readProgressiveMesh(path);
        FAIL() << "truncated file accepted";
    } catch (const rad::ProgressiveMeshError& e) {
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
    // A base with another vertex count.
    rad::writeProgressiveMesh(path, base, r.progressive);
    rad::RadianceMesh other = sphereWithRadiance(1, {rad::BasisKind::HemisphericalPolynomial, 2});
    rad::writeRadiancePly(base, other);
    EXPECT_THROW(rad::readProgressiveMesh(path), rad::ProgressiveMeshError);
    const std::string garbage = "not a progressive mesh\n";
    radtest::writeBytes(path, std::vector<char>(garbage.begin(), garbage.end()));
    EXPECT_THROW(rad::readProgressiveMesh(path), rad::ProgressiveMeshError);
}

}  // namespace
