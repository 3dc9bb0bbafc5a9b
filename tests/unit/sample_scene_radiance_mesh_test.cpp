// The sample scene's radiance on a mesh: the bounds and light radius it documents, and the same
// radiance as the scene built by hand from virtual_scene.h with that radius.
#include "acquisition/sample_scene_radiance_mesh.h"

#include "acquisition/scene_radiance_field.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

// Four vertices: box [0, 4] x [0, 2] x [0, 0] (centre (2, 1, 0)); the farthest vertex from the
// centre is at distance sqrt(5), half the diagonal is sqrt(20) / 2 = sqrt(5) too, so a fifth
// vertex near the centre cannot change either; a flat L shape makes them differ.
rad::TriangleMesh lShape() {
    rad::TriangleMesh mesh;
    mesh.positions = {0, 0, 0, 4, 0, 0, 0, 2, 0, 4, 0.5f, 0};
    mesh.faces = {0, 1, 3, 0, 3, 2};
    return mesh;
}

TEST(SampleSceneRadianceMesh, BoundsAndLightRadiusAreTheDocumentedOnes) {
    Eigen::AlignedBox3d box;
    double radius = 0;
    rad::sampleSceneBounds(lShape(), rad::SampleLightRadius::HalfBoxDiagonal, box, radius);
    EXPECT_DOUBLE_EQ(box.min().x(), 0.0);
    EXPECT_DOUBLE_EQ(box.max().x(), 4.0);
    EXPECT_DOUBLE_EQ(box.max().y(), 2.0);
    EXPECT_NEAR(radius, 0.5 * std::sqrt(16.0 + 4.0), 1e-12);
    rad::sampleSceneBounds(lShape(), rad::SampleLightRadius::FarthestVertex, box, radius);
    // Centre (2, 1, 0); vertices at distance sqrt(5), sqrt(5), sqrt(5) and sqrt(4 + 0.25).
    EXPECT_NEAR(radius, std::sqrt(5.0), 1e-6);
}

TEST(SampleSceneRadianceMesh, EqualsTheSceneBuiltByHandWithTheChosenRadius) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(2);
    // Stretched: the two radii differ (farthest vertex 2, half diagonal sqrt(4 + 1 + 1) = 2.449).
    rad::TriangleMesh mesh = sphere;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) mesh.positions[3 * v] *= 2.0f;
    const rad::BasisSpec basis{rad::BasisKind::SphericalHarmonics, 2};
    std::vector<std::vector<float>> fields;
    for (const auto kind : {rad::SampleLightRadius::FarthestVertex, rad::SampleLightRadius::HalfBoxDiagonal}) {
        rad::SampleSceneRadianceOptions options;
        options.material = rad::SampleMaterial::Glossy;
        options.up = Eigen::Vector3d::UnitZ();
        options.castShadows = false;
        options.lightRadius = kind;
        const rad::RadianceMesh made = rad::sampleSceneRadianceMesh(mesh, basis, options);
        ASSERT_TRUE(made.radiance);
        EXPECT_EQ(made.positions, mesh.positions);
        EXPECT_EQ(made.faces, mesh.faces);
        EXPECT_EQ(made.radiance->vertexCount(), mesh.vertexCount());

        Eigen::AlignedBox3d box;
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
            box.extend(Eigen::Vector3d(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]));
        const double radius = kind == rad::SampleLightRadius::HalfBoxDiagonal ? 0.5 * box.diagonal().norm() : 2.0;
        rad::VirtualSceneOptions sceneOptions;
        sceneOptions.castShadows = false;
        rad::VirtualScene scene(mesh, rad::makeSampleMaterial(rad::SampleMaterial::Glossy, box, options.up),
                                rad::makeSampleLighting(box.center(), radius, options.up), sceneOptions);
        const rad::RadianceField byHand = rad::sceneRadianceField(scene, basis, false);
        ASSERT_EQ(byHand.coefficients.size(), made.radiance->coefficients.size());
        double largest = 0;
        for (std::size_t i = 0; i < byHand.coefficients.size(); ++i)
            largest = std::max(largest, double(std::abs(byHand.coefficients[i] - made.radiance->coefficients[i])));
        EXPECT_LT(largest, 1e-5);
        fields.push_back(made.radiance->coefficients);
    }
    // The two radii light the mesh differently (the fill light moves), so the check above tells them apart.
    double difference = 0;
    for (std::size_t i = 0; i < fields[0].size(); ++i) difference = std::max(difference, double(std::abs(fields[0][i] - fields[1][i])));
    EXPECT_GT(difference, 1e-3);
}

}  // namespace
