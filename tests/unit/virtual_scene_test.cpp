// Tests of acquisition/virtual_scene.h: cast shadows by Embree shadow rays, the unshadowed case
// equal to analytic_material.h's outgoingRadiance, the smooth material variation, input checks.
#include "acquisition/virtual_scene.h"

#include "geometry/primitive_meshes.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::Rgb;

constexpr double kPi = 3.14159265358979323846;

// A ground square [-1, 1]^2 at z = 0 under a blocker [-0.3, 0.3]^2 at z = 0.5.
rad::TriangleMesh groundAndBlocker() {
    rad::TriangleMesh m;
    radtest::addQuad(m, -1, 1, -1, 1, 0);
    radtest::addQuad(m, -0.3f, 0.3f, -0.3f, 0.3f, 0.5f);
    return m;
}

rad::AnalyticMaterial glossy() {
    rad::AnalyticMaterial m;
    m.albedo = Rgb(0.6, 0.5, 0.4);
    m.specular = Rgb(0.3, 0.3, 0.3);
    m.exponent = 30;
    return m;
}

rad::VirtualSceneOptions plain() {
    rad::VirtualSceneOptions o;
    o.variation.enabled = false;
    return o;
}

void expectRgbNear(const Rgb& a, const Rgb& b, double tol) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << "channel " << c;
}

TEST(VirtualScene, PointUnderBlockerGetsOnlyAmbientFromDirectionalLight) {
    rad::AnalyticLighting light;
    light.directional.push_back({Vector3d(0.1, 0.05, 1.0), Rgb(2.0, 2.0, 2.0)});
    light.ambient = Rgb(0.1, 0.2, 0.3);
    const rad::VirtualScene scene(groundAndBlocker(), glossy(), light, plain());
    const Vector3d n = Vector3d::UnitZ(), wo = Vector3d(0.2, -0.1, 1.0).normalized();
    // Under the blocker: the shadow ray towards the light crosses the blocker.
    const Rgb shadowed = scene.radiance(Vector3d(0.0, 0.0, 0.0), n, wo);
    expectRgbNear(shadowed, glossy().albedo.cwiseProduct(light.ambient), 1e-12);
    // Far from it: unshadowed, exactly the analytic material's radiance.
    const Vector3d p(0.8, -0.7, 0.0);
    const Rgb lit = scene.radiance(p, n, wo);
    expectRgbNear(lit, rad::outgoingRadiance(glossy(), light, p, n, wo), 1e-12);
    EXPECT_GT(lit.minCoeff(), shadowed.maxCoeff() + 0.1);  // the light really contributes there
    // The blocker's top is lit.
    expectRgbNear(scene.radiance(Vector3d(0.1, 0.1, 0.5), n, wo),
                  rad::outgoingRadiance(glossy(), light, Vector3d(0.1, 0.1, 0.5), n, wo), 1e-12);
}

TEST(VirtualScene, ShadowsCanBeSwitchedOff) {
    rad::AnalyticLighting light;
    light.directional.push_back({Vector3d(0.0, 0.0, 1.0), Rgb(1.5, 1.5, 1.5)});
    rad::VirtualSceneOptions o = plain();
    o.castShadows = false;
    const rad::VirtualScene scene(groundAndBlocker(), glossy(), light, o);
    const Vector3d p(0.05, 0.0, 0.0), n = Vector3d::UnitZ(), wo = Vector3d(0.3, 0.1, 1.0).normalized();
    expectRgbNear(scene.radiance(p, n, wo), rad::outgoingRadiance(glossy(), light, p, n, wo), 1e-12);
}

TEST(VirtualScene, PointLightShadowStopsAtTheLight) {
    const Vector3d p(0.05, -0.02, 0.0), n = Vector3d::UnitZ(), wo = Vector3d(0.1, 0.2, 1.0).normalized();
    rad::AnalyticLighting above;  // light above the blocker: p is in its shadow
    above.points.push_back({Vector3d(0.0, 0.0, 2.0), Rgb(3.0, 3.0, 3.0)});
    const rad::VirtualScene sceneAbove(groundAndBlocker(), glossy(), above, plain());
    expectRgbNear(sceneAbove.radiance(p, n, wo), Rgb::Zero(), 1e-12);
    EXPECT_FALSE(sceneAbove.reaches(above.points[0], p, n));

    rad::AnalyticLighting between;  // light between ground and blocker: the blocker is beyond it
    between.points.push_back({Vector3d(0.0, 0.0, 0.25), Rgb(0.2, 0.2, 0.2)});
    const rad::VirtualScene sceneBetween(groundAndBlocker(), glossy(), between, plain());
    EXPECT_TRUE(sceneBetween.reaches(between.points[0], p, n));
    const Rgb L = sceneBetween.radiance(p, n, wo);
    expectRgbNear(L, rad::outgoingRadiance(glossy(), between, p, n, wo), 1e-12);
    EXPECT_GT(L.minCoeff(), 0.1);
}

// No self-shadowing ("acne") on a closed, curved surface: at every vertex facing the light, the
// shadow ray leaves the surface.
TEST(VirtualScene, ConvexSurfaceDoesNotShadowItself) {
    rad::AnalyticLighting light;
    light.directional.push_back({Vector3d(0.3, -0.5, 0.8), Rgb(1.0, 1.0, 1.0)});
    const rad::TriangleMesh sphere = rad::makeIcosphere(3);
    const rad::VirtualScene scene(sphere, glossy(), light, plain());
    int tested = 0;
    for (std::size_t v = 0; v < sphere.vertexCount(); ++v) {
        const Vector3d p(sphere.positions[3 * v], sphere.positions[3 * v + 1], sphere.positions[3 * v + 2]);
        const Vector3d n(sphere.normals[3 * v], sphere.normals[3 * v + 1], sphere.normals[3 * v + 2]);
        if (n.dot(light.directional[0].direction.normalized()) < 0.05) continue;
        ++tested;
        const Vector3d wo = (n + Vector3d(0.1, 0.2, 0.3)).normalized();
        expectRgbNear(scene.radiance(p, n, wo), rad::outgoingRadiance(glossy(), light, p, n, wo), 1e-12);
    }
    EXPECT_GT(tested, 200);
}

TEST(VirtualScene, WithVariationUnshadowedRadianceIsTheAnalyticOneOfTheLocalMaterial) {
    rad::AnalyticLighting light;
    light.directional.push_back({Vector3d(0.2, 0.3, 1.0), Rgb(1.2, 1.0, 0.9)});
    light.points.push_back({Vector3d(0.5, 0.5, 3.0), Rgb(4.0, 4.0, 4.0)});
    light.ambient = Rgb(0.05, 0.05, 0.05);
    const rad::TriangleMesh sphere = rad::makeIcosphere(2);
    const rad::VirtualScene scene(sphere, glossy(), light);  // variation on by default
    for (std::size_t v = 0; v < sphere.vertexCount(); v += 7) {
        const Vector3d p(sphere.positions[3 * v], sphere.positions[3 * v + 1], sphere.positions[3 * v + 2]);
        const Vector3d n = p.normalized();
        if (n.z() < 0.6) continue;  // both lights reach these points (checked just below)
        ASSERT_TRUE(scene.reaches(light.directional[0], p, n));
        ASSERT_TRUE(scene.reaches(light.points[0], p, n));
        const Vector3d wo = Vector3d(-0.4, 0.2, 1.0).normalized();
        expectRgbNear(scene.radiance(p, n, wo), rad::outgoingRadiance(scene.materialAt(p), light, p, n, wo), 1e-12);
    }
    // Below the horizon w_o is clamped as outgoingRadiance does.
    const Vector3d p(0, 0, 1), n(0, 0, 1), below(1.0, 0.0, -0.3);
    expectRgbNear(scene.radiance(p, n, below), rad::outgoingRadiance(scene.materialAt(p), light, p, n, below), 1e-12);
    // Degenerate input gives zero, not NaN.
    expectRgbNear(scene.radiance(p, Vector3d::Zero(), below), Rgb::Zero(), 0.0);
}

TEST(VirtualScene, VariationIsSmoothBoundedAndVisible) {
    rad::AnalyticLighting light;
    light.directional.push_back({Vector3d(0, 0, 1), Rgb::Ones()});
    const rad::TriangleMesh sphere = rad::makeIcosphere(3, 2.0f);  // bbox diagonal 4 sqrt(3)
    rad::VirtualSceneOptions o;
    const rad::VirtualScene scene(sphere, glossy(), light, o);
    EXPECT_NEAR(scene.variationWavelength(), 0.25 * 4.0 * std::sqrt(3.0), 1e-5);
    const double lambda = scene.variationWavelength();
    const rad::AnalyticMaterial base = glossy();
    double minA = 1e9, maxA = -1e9, minS = 1e9, maxS = -1e9;
    for (std::size_t v = 0; v < sphere.vertexCount(); ++v) {
        const Vector3d p(sphere.positions[3 * v], sphere.positions[3 * v + 1], sphere.positions[3 * v + 2]);
        const rad::AnalyticMaterial m = scene.materialAt(p);
        for (int c = 0; c < 3; ++c) {
            // Within the documented band base * (1 +- amplitude).
            EXPECT_LE(std::fabs(m.albedo[c] / base.albedo[c] - 1.0), o.variation.albedoAmplitude + 1e-12);
            EXPECT_LE(std::fabs(m.specular[c] / base.specular[c] - 1.0), o.variation.specularAmplitude + 1e-12);
        }
        EXPECT_EQ(m.exponent, base.exponent);
        minA = std::min(minA, m.albedo[0]);
        maxA = std::max(maxA, m.albedo[0]);
        minS = std::min(minS, m.specular[0]);
        maxS = std::max(maxS, m.specular[0]);
        // Smooth: a sum of three unit-amplitude sinusoids / 3 has a gradient of norm <= 2 pi / lambda.
        const Vector3d q = p + Vector3d(1e-3, -2e-3, 1.5e-3);
        const rad::AnalyticMaterial mq = scene.materialAt(q);
        const double bound = 2 * kPi / lambda * (q - p).norm();
        EXPECT_LE(std::fabs(mq.albedo[1] - m.albedo[1]), base.albedo[1] * o.variation.albedoAmplitude * bound + 1e-12);
        EXPECT_LE(std::fabs(mq.specular[1] - m.specular[1]),
                  base.specular[1] * o.variation.specularAmplitude * bound + 1e-12);
    }
    // Visible over the object: a good part of the band is used.
    EXPECT_GT(maxA - minA, 0.5 * base.albedo[0] * o.variation.albedoAmplitude);
    EXPECT_GT(maxS - minS, 0.5 * base.specular[0] * o.variation.specularAmplitude);
    // The channels vary differently (hue changes, not only brightness).
    const Vector3d p(1.2, -0.7, 1.4);
    const rad::AnalyticMaterial m = scene.materialAt(p);
    EXPECT_GT(std::fabs(m.albedo[0] / base.albedo[0] - m.albedo[2] / base.albedo[2]), 1e-3);
    // Disabled: the base material everywhere.
    rad::VirtualSceneOptions off;
    off.variation.enabled = false;
    const rad::VirtualScene flat(sphere, glossy(), light, off);
    EXPECT_EQ(flat.materialAt(p).albedo, base.albedo);
    EXPECT_EQ(flat.materialAt(p).specular, base.specular);
}

TEST(VirtualScene, ComputesNormalsWhenMissingAndRefusesBadInput) {
    rad::AnalyticLighting light;
    light.directional.push_back({Vector3d(0, 0, 1), Rgb::Ones()});
    rad::TriangleMesh quad;
    radtest::addQuad(quad, -1, 1, -1, 1, 0);
    quad.normals.clear();
    const rad::VirtualScene scene(quad, glossy(), light, plain());
    for (std::size_t v = 0; v < 4; ++v) EXPECT_FLOAT_EQ(scene.mesh().normals[3 * v + 2], 1.0f);

    rad::TriangleMesh empty;
    EXPECT_THROW(rad::VirtualScene(empty, glossy(), light), rad::VirtualSceneError);
    rad::TriangleMesh zeroNormal;
    radtest::addQuad(zeroNormal, -1, 1, -1, 1, 0);
    zeroNormal.normals[0] = zeroNormal.normals[1] = zeroNormal.normals[2] = 0.0f;
    EXPECT_THROW(rad::VirtualScene(zeroNormal, glossy(), light), rad::VirtualSceneError);
    rad::TriangleMesh badIndex;
    radtest::addQuad(badIndex, -1, 1, -1, 1, 0);
    badIndex.faces[0] = 99;
    EXPECT_THROW(rad::VirtualScene(badIndex, glossy(), light), rad::VirtualSceneError);
    rad::AnalyticLighting zeroDirection;
    zeroDirection.directional.push_back({Vector3d::Zero(), Rgb::Ones()});
    EXPECT_THROW(rad::VirtualScene(groundAndBlocker(), glossy(), zeroDirection), rad::VirtualSceneError);
    rad::VirtualSceneOptions badAmplitude;
    badAmplitude.variation.albedoAmplitude = 1.5;
    EXPECT_THROW(rad::VirtualScene(groundAndBlocker(), glossy(), light, badAmplitude), rad::VirtualSceneError);
}

TEST(VirtualScene, SamplePresets) {
    EXPECT_EQ(rad::parseSampleMaterial("glossy"), rad::SampleMaterial::Glossy);
    EXPECT_EQ(rad::parseSampleMaterial("stripes"), rad::SampleMaterial::Stripes);
    EXPECT_THROW(rad::parseSampleMaterial("shiny"), std::invalid_argument);
    const Eigen::AlignedBox3d box(Vector3d(-1, -2, -3), Vector3d(1, 2, 3));
    const Vector3d up = Vector3d::UnitY();
    EXPECT_TRUE(rad::makeSampleMaterial(rad::SampleMaterial::Diffuse, box, up).specular.isZero());
    EXPECT_FALSE(rad::makeSampleMaterial(rad::SampleMaterial::Glossy, box, up).stripes.enabled);
    const rad::AnalyticMaterial striped = rad::makeSampleMaterial(rad::SampleMaterial::Stripes, box, up);
    ASSERT_TRUE(striped.stripes.enabled);
    EXPECT_EQ(striped.stripes.band(Vector3d(0, -1.99, 0)), 0);  // 8 bands over y in [-2, 2]
    EXPECT_EQ(striped.stripes.band(Vector3d(0, 1.99, 0)), 7);

    Vector3d east, north;
    rad::sampleFrame(up, east, north);
    EXPECT_NEAR(east.dot(up), 0.0, 1e-15);
    EXPECT_NEAR(east.norm(), 1.0, 1e-15);
    EXPECT_NEAR(east.cross(north).dot(up), 1.0, 1e-15);  // right-handed (east, north, up)

    // The point fill light gives the documented irradiance at the centre, from 2.5 radii away.
    const Vector3d centre(1, 2, 3);
    const rad::AnalyticLighting l = rad::makeSampleLighting(centre, 2.0, up);
    ASSERT_EQ(l.points.size(), 1u);
    ASSERT_EQ(l.directional.size(), 1u);
    const double d = (l.points[0].position - centre).norm();
    EXPECT_NEAR(d, 5.0, 1e-12);
    expectRgbNear(l.points[0].intensity / (d * d), Rgb(0.4, 0.45, 0.55), 1e-12);
    EXPECT_GT(l.directional[0].direction.normalized().dot(up), 0.7);  // a key light from above
}

}  // namespace
