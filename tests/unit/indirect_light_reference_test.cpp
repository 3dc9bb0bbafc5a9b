// The CPU reference of indirect light and the images from the grid and from per-vertex irradiance,
// inside a sphere lit from its centre, where every answer has a closed form: the wall's radiance
// after B bounces is uniform, L_B = rho E0 / pi (1 + rho + ... + rho^(B-1)), E0 = I / r^2, so the
// indirect light reflected toward the camera is rho L_B everywhere (and the paper's directional
// interpolation gives rho L_B sum |n_a|^3, the |n_a| weights rho L_B).
#include "render/indirect_light_reference.h"

#include "geometry/primitive_meshes.h"
#include "lighting/irradiance_vector_grid_compute.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

constexpr double kPi = 3.14159265358979323846;

rad::TriangleMesh insideOut(rad::TriangleMesh m) {
    for (std::size_t f = 0; f < m.faceCount(); ++f) std::swap(m.faces[3 * f + 1], m.faces[3 * f + 2]);
    for (float& n : m.normals) n = -n;
    return m;
}

TEST(IndirectLightReference, InsideALitSphereEveryImageMatchesTheClosedForm) {
    const rad::TriangleMesh sphere = insideOut(rad::makeIcosphere(4, 1.0f));
    const double rho = 0.5, intensity = 3.0;
    const std::vector<float> albedo(3 * sphere.vertexCount(), float(rho));
    rad::AnalyticLighting lights;
    rad::PointLight bulb;
    bulb.position = Eigen::Vector3d::Zero();
    bulb.intensity = rad::Rgb::Constant(intensity);
    lights.points.push_back(bulb);
    rad::IndirectLightSetup setup;
    setup.bounces = 2;
    rad::IndirectLightTracer tracer(sphere, albedo, lights, setup);
    const double LB = rho * intensity / kPi * (1.0 + rho);
    const double expected = rho * LB;

    const rad::PinholeCamera camera = rad::PinholeCamera::lookAt(Eigen::Vector3d(0, 0, 0.2), Eigen::Vector3d(1, 0.3, 0),
                                                                 Eigen::Vector3d(0, 0, 1), 90.0, 24, 16);
    const rad::VisibleSurface surface = rad::traceVisibleSurface(tracer, camera);
    ASSERT_EQ(surface.visiblePixels(), 24u * 16u);

    const rad::ImageF reference = rad::renderIndirectReference(tracer, surface, 64);
    for (std::size_t i = 0; i < 24 * 16; ++i)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(reference.rgb[3 * i + c], expected, 0.03 * expected) << "pixel " << i;

    rad::IrradianceGridOptions options;
    options.resolution = 4;
    options.padding = 0.05;
    options.raysPerDirection = 64;
    options.light = setup;
    const rad::IrradianceVectorGrid grid = rad::computeIrradianceVectorGrid(sphere, albedo, lights, options);
    const rad::ImageF paper = rad::renderIndirectFromGrid(grid, surface, rad::DirectionalWeights::Squared);
    const rad::ImageF absolute = rad::renderIndirectFromGrid(grid, surface, rad::DirectionalWeights::Absolute);
    for (std::size_t i = 0; i < 24 * 16; ++i) {
        const float* n = &surface.normals[3 * i];
        const double cubes = std::pow(std::fabs(n[0]), 3) + std::pow(std::fabs(n[1]), 3) + std::pow(std::fabs(n[2]), 3);
        ASSERT_NEAR(paper.rgb[3 * i], expected * cubes, 0.04 * expected) << "pixel " << i;
        ASSERT_NEAR(absolute.rgb[3 * i], expected, 0.04 * expected) << "pixel " << i;
    }

    // Per-vertex irradiance on a coarser sphere (vertex normals inward).
    const rad::TriangleMesh coarse = insideOut(rad::makeIcosphere(2, 1.0f));
    const std::vector<float> E = rad::computeVertexIndirectIrradiance(tracer, coarse, 64);
    for (std::size_t v = 0; v < coarse.vertexCount(); ++v) ASSERT_NEAR(E[3 * v + 1], kPi * LB, 0.03 * kPi * LB);
    const rad::ImageF perVertex = rad::renderIndirectFromVertexIrradiance(coarse, E, surface);
    for (std::size_t i = 0; i < 24 * 16; ++i) ASSERT_NEAR(perVertex.rgb[3 * i + 2], expected, 0.03 * expected);

    const rad::IndirectImageError same = rad::indirectImageError(reference, reference, surface.mask);
    EXPECT_EQ(same.rmse, 0.0);
    EXPECT_EQ(same.pixels, 24u * 16u);
    EXPECT_NEAR(same.meanReference, expected, 0.03 * expected);
    rad::ImageF brighter = reference;
    for (float& x : brighter.rgb) x += 0.1f;
    EXPECT_NEAR(rad::indirectImageError(brighter, reference, surface.mask).rmse, 0.1, 1e-5);
}

TEST(IndirectLightReference, BackFacesAndEmptyPixelsAreMaskedOut) {
    // Seen from outside, the inside-out sphere shows only back faces; beside it, nothing.
    const rad::TriangleMesh sphere = insideOut(rad::makeIcosphere(2, 1.0f));
    rad::AnalyticLighting lights;
    lights.directional.push_back(rad::DirectionalLight{});
    rad::IndirectLightTracer tracer(sphere, {}, lights, {});
    const rad::PinholeCamera camera = rad::PinholeCamera::lookAt(Eigen::Vector3d(0, -5, 0), Eigen::Vector3d(0, 0, 0),
                                                                 Eigen::Vector3d(0, 0, 1), 60.0, 16, 16);
    const rad::VisibleSurface surface = rad::traceVisibleSurface(tracer, camera);
    EXPECT_EQ(surface.visiblePixels(), 0u);
    const rad::ImageF reference = rad::renderIndirectReference(tracer, surface, 4);
    for (float x : reference.rgb) EXPECT_EQ(x, 0.0f);
}

}  // namespace
