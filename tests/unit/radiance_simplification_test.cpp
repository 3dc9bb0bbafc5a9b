// simplifyRadianceMesh (simplify/radiance_simplification.h) on the defects of real scans.
#include "simplify/radiance_simplification.h"

#include "geometry/primitive_meshes.h"
#include "radiance/material_radiance.h"
#include "radiance/radiance_frame.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace {

// An 8 x 8 flat grid (98 faces) with glossy radiance, plus the two defects scans carry: a zero-area
// triangle along the bottom border (vertices 0, 1, 2 are collinear; the face (2, 1, 0) shares the
// border edges 0-1 and 1-2 with opposite orientation, so the mesh stays manifold) and a face that
// repeats a vertex.
rad::RadianceMesh gridWithDefects() {
    rad::TriangleMesh grid;
    radtest::addGrid(grid, 8);
    rad::AnalyticMaterial material;
    material.exponent = 30.0;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.4, 0.2, 1.0), rad::Rgb(1.0, 0.9, 0.8)});
    rad::MaterialRadianceOptions options;
    options.basis = {rad::BasisKind::HemisphericalPolynomial, 3};
    rad::RadianceMesh mesh;
    mesh.positions = grid.positions;
    mesh.faces = grid.faces;
    mesh.radiance = rad::makeMaterialRadiance(grid.positions.data(), grid.normals.data(), grid.vertexCount(),
                                              material, lighting, options);
    mesh.faces.insert(mesh.faces.end(), {2, 1, 0});    // zero area
    mesh.faces.insert(mesh.faces.end(), {20, 20, 21});  // repeats vertex 20
    return mesh;
}

TEST(RadianceSimplification, ZeroAreaFacesAndFacesRepeatingAVertexAreSimplifiedNotRefused) {
    const rad::RadianceMesh mesh = gridWithDefects();
    ASSERT_EQ(mesh.faceCount(), 100u);
    EXPECT_EQ(rad::checkSimplificationInput(mesh, rad::SimplificationMetric::Radiance), "");
    rad::RadianceSimplificationOptions options;
    options.collapse.targetFaceCount = 40;
    options.collapse.preserveBoundary = false;  // the zero-area face lies on the border
    const rad::RadianceSimplificationResult r = rad::simplifyRadianceMesh(mesh, options);
    EXPECT_EQ(r.facesRepeatingAVertexRemoved, 1u);
    EXPECT_EQ(r.zeroAreaFaces, 1u);
    EXPECT_EQ(r.progressive.base.faceCount(), 99u);
    EXPECT_LE(r.collapse.finalFaceCount, 40u);
    const rad::RadianceMesh coarse = r.progressive.extract(r.progressive.steps.size());
    EXPECT_EQ(coarse.faceCount(), r.collapse.finalFaceCount);
    for (float x : coarse.positions) ASSERT_TRUE(std::isfinite(x));
    for (std::size_t i = 0; i < coarse.radiance->coefficients.size(); ++i)
        ASSERT_TRUE(std::isfinite(coarse.radiance->coefficients[i]));
    // Still a flat grid: no vertex left the plane z = 0.
    for (std::size_t v = 0; v < coarse.vertexCount(); ++v) EXPECT_EQ(coarse.positions[3 * v + 2], 0.0f);
}

TEST(RadianceSimplification, AnOpenScanCountsItsBoundaryAndMergesAlongIt) {
    // The defect-free grid: 8 x 8 vertices, 28 of them on the boundary, 28 boundary edges.
    rad::RadianceMesh mesh = gridWithDefects();
    mesh.faces.resize(mesh.faces.size() - 6);
    ASSERT_EQ(mesh.faceCount(), 98u);
    rad::RadianceSimplificationOptions options;  // the defaults: the radiance quadric, full collapses
    options.collapse.targetFaceCount = 12;
    const rad::RadianceSimplificationResult along = rad::simplifyRadianceMesh(mesh, options);
    EXPECT_EQ(along.boundaryEdges, 28u);
    EXPECT_TRUE(along.collapse.collapsedAlongBoundary);
    // A polygon of 28 kept vertices needs 26 triangles: the target is reached only along the boundary.
    EXPECT_LE(along.collapse.finalFaceCount, 12u);
    const rad::RadianceMesh coarse = along.progressive.extract(along.progressive.steps.size());
    for (std::size_t v = 0; v < coarse.vertexCount(); ++v) EXPECT_EQ(coarse.positions[3 * v + 2], 0.0f);
    int corners = 0;
    for (std::size_t v = 0; v < coarse.vertexCount(); ++v)
        corners += std::abs(coarse.positions[3 * v]) == 1.0f && std::abs(coarse.positions[3 * v + 1]) == 1.0f;
    EXPECT_EQ(corners, 4);  // the boundary planes keep the square's corners

    options.collapse.collapseAlongBoundary = false;
    const rad::RadianceSimplificationResult fixed = rad::simplifyRadianceMesh(mesh, options);
    EXPECT_GE(fixed.collapse.finalFaceCount, 26u);
    EXPECT_FALSE(fixed.collapse.collapsedAlongBoundary);
    options.collapse.collapseAlongBoundary = true;
    options.collapse.kind = rad::CollapseKind::HalfEdge;  // only full collapses under the quadric merge along it
    EXPECT_FALSE(rad::simplifyRadianceMesh(mesh, options).collapse.collapsedAlongBoundary);
    options.collapse.kind = rad::CollapseKind::Full;
    EXPECT_EQ(fixed.collapse.stop, rad::StopReason::NoValidCollapse);

    // A closed mesh has none.
    const rad::TriangleMesh sphere = rad::makeIcosphere(2);
    rad::RadianceMesh closed;
    closed.positions = sphere.positions;
    closed.faces = sphere.faces;
    closed.radiance = rad::RadianceField({rad::BasisKind::HemisphericalPolynomial, 1}, sphere.vertexCount());
    for (std::size_t v = 0; v < sphere.vertexCount(); ++v)
        rad::storeFrame(rad::frameFromNormal(Eigen::Vector3d(sphere.positions[3 * v], sphere.positions[3 * v + 1],
                                                             sphere.positions[3 * v + 2]).normalized()),
                        closed.radiance->frame(v));
    options.collapse.targetFaceCount = 40;
    const rad::RadianceSimplificationResult closedResult = rad::simplifyRadianceMesh(closed, options);
    EXPECT_EQ(closedResult.boundaryEdges, 0u);
    EXPECT_FALSE(closedResult.collapse.collapsedAlongBoundary);  // nothing to look for
}

TEST(RadianceSimplification, DuplicateFacesAreRemovedAndCounted) {
    rad::RadianceMesh mesh = gridWithDefects();
    mesh.faces.insert(mesh.faces.end(), {0, 1, 9});   // the first grid face again
    mesh.faces.insert(mesh.faces.end(), {9, 1, 0});   // and reversed
    ASSERT_EQ(mesh.faceCount(), 102u);
    ASSERT_EQ(std::vector<std::uint32_t>(mesh.faces.begin(), mesh.faces.begin() + 3),
              (std::vector<std::uint32_t>{0, 1, 9}));
    EXPECT_EQ(rad::checkSimplificationInput(mesh, rad::SimplificationMetric::Radiance), "");
    rad::RadianceSimplificationOptions options;
    options.collapse.targetFaceCount = 40;
    options.collapse.preserveBoundary = false;
    const rad::RadianceSimplificationResult r = rad::simplifyRadianceMesh(mesh, options);
    EXPECT_EQ(r.duplicateFacesRemoved, 2u);
    EXPECT_EQ(r.facesRepeatingAVertexRemoved, 1u);
    EXPECT_EQ(r.progressive.base.faceCount(), 99u);  // 98 grid faces and the zero-area one
    EXPECT_LE(r.collapse.finalFaceCount, 40u);
}

TEST(RadianceSimplification, NonManifoldEdgesAreKeptWhereTheyAreOrRefusedWithTheFix) {
    rad::RadianceMesh mesh = gridWithDefects();
    mesh.faces.resize(mesh.faces.size() - 6);  // the defect-free grid
    mesh.faces.insert(mesh.faces.end(), {0, 1, 50});  // with the grid's face: three faces on the
    mesh.faces.insert(mesh.faces.end(), {1, 0, 51});  // border edge (0, 1)
    // A free boundary would let the edge's vertices move: refused, naming both fixes.
    const std::string problem = rad::checkSimplificationInput(mesh, rad::SimplificationMetric::Radiance,
                                                              rad::CollapseKind::HalfEdge, false);
    EXPECT_NE(problem.find("1 non-manifold edge"), std::string::npos) << problem;
    EXPECT_NE(problem.find("Repair non Manifold Edges"), std::string::npos) << problem;
    EXPECT_NE(problem.find("Preserve boundary"), std::string::npos) << problem;
    // A preserved boundary keeps the edge and its two vertices as they are, for both collapse kinds.
    EXPECT_EQ(rad::checkSimplificationInput(mesh, rad::SimplificationMetric::Radiance), "");
    for (const rad::CollapseKind kind : {rad::CollapseKind::Full, rad::CollapseKind::HalfEdge}) {
        rad::RadianceSimplificationOptions options;
        options.collapse.kind = kind;
        options.collapse.targetFaceCount = 20;
        const rad::RadianceSimplificationResult r = rad::simplifyRadianceMesh(mesh, options);
        EXPECT_EQ(r.nonManifoldEdges, 1u);
        EXPECT_LT(r.collapse.finalFaceCount, 60u);  // the rest simplified
        const rad::RadianceMesh coarse = r.progressive.extract(r.progressive.steps.size());
        bool firstKept = false, secondKept = false;
        for (std::size_t v = 0; v < coarse.vertexCount(); ++v) {
            const float* p = &coarse.positions[3 * v];
            firstKept = firstKept || (p[0] == mesh.positions[0] && p[1] == mesh.positions[1] && p[2] == mesh.positions[2]);
            secondKept = secondKept || (p[0] == mesh.positions[3] && p[1] == mesh.positions[4] && p[2] == mesh.positions[5]);
        }
        EXPECT_TRUE(firstKept && secondKept);
        // No edge gained faces: at most the three of the input's non-manifold edge.
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> use;
        for (std::size_t f = 0; f < coarse.faceCount(); ++f)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = coarse.faces[3 * f + k], b = coarse.faces[3 * f + (k + 1) % 3];
                ++use[{std::min(a, b), std::max(a, b)}];
            }
        int most = 0;
        for (const auto& [edge, count] : use) most = std::max(most, count);
        EXPECT_LE(most, 3);
    }
}

TEST(RadianceSimplification, InvalidOptionsAreRefusedBeforeAnyWork) {
    const rad::RadianceMesh mesh = gridWithDefects();
    rad::RadianceSimplificationOptions options;
    options.collapse.targetFaceCount = 40;
    options.collapse.maxNormalDeviationDegrees = -10.0;
    try {
        rad::simplifyRadianceMesh(mesh, options);
        FAIL() << "a negative angle was accepted";
    } catch (const rad::SimplificationError& e) {
        EXPECT_NE(std::string(e.what()).find("[0, 180] degrees (it is -10)"), std::string::npos) << e.what();
    }
    options.collapse.maxNormalDeviationDegrees = 90.0;
    options.collapse.geometryWeight = std::nan("");
    EXPECT_THROW(rad::simplifyRadianceMesh(mesh, options), rad::SimplificationError);
    options.collapse.geometryWeight = 0.01;
    options.collapse.minValence = 8;
    options.collapse.maxValence = 4;
    EXPECT_THROW(rad::simplifyRadianceMesh(mesh, options), rad::SimplificationError);
}

TEST(RadianceSimplification, AMeshLargerThanTheMemoryIsRefusedWithTheFigures) {
    const rad::RadianceMesh mesh = gridWithDefects();
    rad::RadianceSimplificationOptions options;
    options.collapse.targetFaceCount = 40;
    const std::size_t needed = rad::estimatedSimplificationBytes(mesh, options);
    // The radiance quadric holds 20 bytes per world-SH attribute (PB3: 3 x 16) per vertex, at least.
    EXPECT_GT(needed, mesh.vertexCount() * 20 * 48);
    options.memoryLimitBytes = needed / 2;
    try {
        rad::simplifyRadianceMesh(mesh, options);
        FAIL() << "a mesh needing twice the memory limit was simplified";
    } catch (const rad::SimplificationError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("64 vertices needs about"), std::string::npos) << message;
        EXPECT_NE(message.find("are available"), std::string::npos) << message;
    }
    options.memoryLimitBytes = 2 * needed;
    EXPECT_LE(rad::simplifyRadianceMesh(mesh, options).collapse.finalFaceCount, 40u);
}

TEST(RadianceSimplification, TheMemoryEstimateGrowsWithTheVerticesAndTheBasis) {
    const rad::RadianceMesh small = gridWithDefects();
    rad::RadianceSimplificationOptions options;
    rad::RadianceMesh larger = small;
    const std::size_t n = small.vertexCount();
    for (std::size_t copy = 1; copy < 4; ++copy) {  // four disjoint copies of the grid
        larger.positions.insert(larger.positions.end(), small.positions.begin(), small.positions.end());
        for (std::uint32_t i : small.faces) larger.faces.push_back(i + std::uint32_t(copy * n));
    }
    rad::RadianceField four(small.radiance->basis, 4 * n);
    for (std::size_t v = 0; v < 4 * n; ++v) {
        std::copy_n(small.radiance->vertexCoefficients(v % n), four.coefficientsPerVertex(), four.vertexCoefficients(v));
        std::copy_n(small.radiance->frame(v % n), 6, four.frame(v));
    }
    larger.radiance = four;
    const double ratio = double(rad::estimatedSimplificationBytes(larger, options)) /
                         double(rad::estimatedSimplificationBytes(small, options));
    EXPECT_NEAR(ratio, 4.0, 0.05);
    rad::RadianceMesh sh6 = small;
    sh6.radiance = rad::RadianceField({rad::BasisKind::SphericalHarmonics, 6}, n);
    // 147 attributes instead of 48 per vertex: about 2 KB more per vertex.
    EXPECT_GT(rad::estimatedSimplificationBytes(sh6, options),
              rad::estimatedSimplificationBytes(small, options) + n * 20 * (147 - 48));
}

}  // namespace
