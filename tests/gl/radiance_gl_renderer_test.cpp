// The decoration's GL renderer (render_gl/radiance_gl_renderer.h) against the CPU reference renderer
// (render/radiance_renderer.h, Embree ray casting, double precision) at the same camera, in a real
// OpenGL context (Mesa under Xvfb in CI): every basis kind and a range of degrees, plain and
// reflected storage, per-vertex and per-fragment (eq. 8) shading, the tone mapping, the CPU
// fallback of an old GL, vertex colours (PRT), no GL error, GL state restored.
#include "gl_test_context.h"
#include "offscreen_gl.h"
#include "radiance_gl_renderer.h"

#include "geometry/primitive_meshes.h"
#include "radiance/material_radiance.h"
#include "radiance/view_colors.h"
#include "render/radiance_renderer.h"
#include "render/tone_mapping.h"

#include <GL/glew.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace {

using radgl::GlShading;

using gltest::capabilities;
using gltest::gl;
using gltest::kHeight;
using gltest::kWidth;

rad::PinholeCamera testCamera() {
    return rad::PinholeCamera::lookAt({0.4, 0.5, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 45.0, kWidth, kHeight);
}

rad::TriangleMesh coarseSphere() { return rad::makeIcosphere(2); }  // large triangles: eq. 8 matters

rad::RadianceField glossyField(const rad::TriangleMesh& mesh, rad::BasisSpec basis, bool reflected) {
    rad::AnalyticMaterial material;
    material.albedo = rad::Rgb(0.6, 0.25, 0.15);
    material.specular = rad::Rgb(0.5, 0.5, 0.5);
    material.exponent = 30.0;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.3, 0.6, 1.0), rad::Rgb(2.0, 2.0, 2.0)});
    lighting.ambient = rad::Rgb(0.05, 0.05, 0.05);
    rad::MaterialRadianceOptions options;
    options.basis = basis;
    options.reflected = reflected;
    return rad::makeMaterialRadiance(mesh.positions.data(), mesh.normals.data(), mesh.vertexCount(), material, lighting,
                                     options);
}

struct Comparison {
    double rmse = 0;   // 8-bit levels, over the compared pixels and channels
    int maxDiff = 0;
    int pixels = 0;
};

// Pixels fully covered in the reference whose 8 neighbours are too (rasterisation and ray casting
// may disagree on edge pixels).
Comparison compare(const std::vector<std::uint8_t>& glRgb, const rad::Image8& reference, const rad::Rendering& coverage) {
    Comparison c;
    double sum = 0;
    for (int y = 1; y + 1 < kHeight; ++y)
        for (int x = 1; x + 1 < kWidth; ++x) {
            bool inside = true;
            for (int dy = -1; dy <= 1 && inside; ++dy)
                for (int dx = -1; dx <= 1 && inside; ++dx)
                    inside = coverage.coverage[static_cast<std::size_t>(y + dy) * kWidth + x + dx] == 255;
            if (!inside) continue;
            const std::uint8_t* r = reference.rgb.data() + (static_cast<std::size_t>(y) * kWidth + x) * 3;
            const std::uint8_t* g = glRgb.data() + (static_cast<std::size_t>(y) * kWidth + x) * 3;
            for (int ch = 0; ch < 3; ++ch) {
                const int d = std::abs(int(r[ch]) - int(g[ch]));
                sum += double(d) * d;
                c.maxDiff = std::max(c.maxDiff, d);
            }
            ++c.pixels;
        }
    c.rmse = c.pixels ? std::sqrt(sum / (3.0 * c.pixels)) : 1e9;
    return c;
}

std::vector<std::uint8_t> drawGl(radgl::RadianceGlRenderer& renderer, GlShading shading, const rad::ToneMapping& tm) {
    const rad::PinholeCamera camera = testCamera();
    gl().beginFrame(camera, 0.5, 10.0);
    renderer.draw(shading, tm, camera.center);
    EXPECT_EQ(renderer.takeGlErrors(), "");
    return gl().readRgb();
}

struct Case {
    rad::BasisSpec basis;
    bool reflected;
};

class GlMatchesCpu : public ::testing::TestWithParam<Case> {};

TEST_P(GlMatchesCpu, BothShadingsMatchTheReferenceAndDifferFromEachOther) {
    const Case param = GetParam();
    const rad::TriangleMesh mesh = coarseSphere();
    const rad::RadianceField field = glossyField(mesh, param.basis, param.reflected);
    radgl::RadianceGlRenderer renderer(capabilities());
    ASSERT_EQ(renderer.shaderProblem(), "");
    renderer.setMesh(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    ASSERT_EQ(renderer.setRadiance(field), "");
    ASSERT_TRUE(renderer.gpuRadiance());

    const rad::MeshRenderer cpu(mesh);
    const rad::ToneMapping tm;
    std::vector<std::uint8_t> images[2];
    const rad::Rendering perVertexReference = cpu.renderRadiance(field, testCamera(), rad::RadianceShading::PerVertex);
    const rad::Image8 perVertexExpected = rad::toneMapToSrgb8(perVertexReference.image, tm);
    const GlShading modes[2] = {GlShading::PerVertex, GlShading::PerFragment};
    for (int m = 0; m < 2; ++m) {
        images[m] = drawGl(renderer, modes[m], tm);
        const rad::Rendering reference =
            m == 0 ? perVertexReference : cpu.renderRadiance(field, testCamera(), rad::RadianceShading::PerFragment);
        const Comparison c = compare(images[m], m == 0 ? perVertexExpected : rad::toneMapToSrgb8(reference.image, tm), reference);
        SCOPED_TRACE(param.basis.name() + (param.reflected ? " reflected" : " plain") + (m ? " per fragment" : " per vertex"));
        EXPECT_GT(c.pixels, 5000);
        EXPECT_LT(c.rmse, 1.0) << "max " << c.maxDiff;
        EXPECT_LE(c.maxDiff, 12);
    }
    // The two shadings must really differ on this coarse glossy sphere (else the test above could
    // pass with one shader drawn twice): the per-fragment picture is further from the per-vertex
    // reference than the per-vertex picture is. Not for degree 0 (a constant RF).
    if (param.basis.degree >= 2) {
        const Comparison sameMode = compare(images[0], perVertexExpected, perVertexReference);
        const Comparison otherMode = compare(images[1], perVertexExpected, perVertexReference);
        EXPECT_GT(otherMode.rmse, sameMode.rmse + 1.0);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Bases, GlMatchesCpu,
    ::testing::Values(Case{{rad::BasisKind::HemisphericalPolynomial, 0}, false},
                      Case{{rad::BasisKind::HemisphericalPolynomial, 2}, false},
                      Case{{rad::BasisKind::HemisphericalPolynomial, 4}, false},
                      Case{{rad::BasisKind::HemisphericalPolynomial, 4}, true},
                      Case{{rad::BasisKind::HemisphericalPolynomial, 8}, true},
                      Case{{rad::BasisKind::SphericalHarmonics, 0}, false},
                      Case{{rad::BasisKind::SphericalHarmonics, 3}, false},
                      Case{{rad::BasisKind::SphericalHarmonics, 6}, true},
                      Case{{rad::BasisKind::SphericalHarmonics, 10}, false}));

TEST(GlRenderer, ToneMappingMatchesTheCpuCurves) {
    const rad::TriangleMesh mesh = coarseSphere();
    const rad::RadianceField field = glossyField(mesh, {rad::BasisKind::HemisphericalPolynomial, 4}, false);
    radgl::RadianceGlRenderer renderer(capabilities());
    renderer.setMesh(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    ASSERT_EQ(renderer.setRadiance(field), "");
    const rad::MeshRenderer cpu(mesh);
    const rad::Rendering reference = cpu.renderRadiance(field, testCamera(), rad::RadianceShading::PerFragment);
    for (const rad::ToneMapping tm : {rad::ToneMapping{1.5, rad::ToneCurve::Clamp}, rad::ToneMapping{2.0, rad::ToneCurve::Reinhard},
                                      rad::ToneMapping{-1.0, rad::ToneCurve::Reinhard}}) {
        const Comparison c = compare(drawGl(renderer, GlShading::PerFragment, tm), rad::toneMapToSrgb8(reference.image, tm), reference);
        EXPECT_LT(c.rmse, 1.0) << "stops " << tm.exposureStops;
    }
    // And a different tone mapping gives a visibly different picture.
    const Comparison off = compare(drawGl(renderer, GlShading::PerFragment, {1.5, rad::ToneCurve::Clamp}),
                                   rad::toneMapToSrgb8(reference.image, {}), reference);
    EXPECT_GT(off.rmse, 10.0);
}

TEST(GlRenderer, OldGlFallsBackToCpuPerVertexColours) {
    const rad::TriangleMesh mesh = coarseSphere();
    const rad::RadianceField field = glossyField(mesh, {rad::BasisKind::SphericalHarmonics, 4}, false);
    radgl::GlCapabilities caps = capabilities();
    radgl::capGlVersion(caps, 2, 1);
    ASSERT_FALSE(caps.supportsShaders());
    radgl::RadianceGlRenderer renderer(caps);
    renderer.setMesh(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    EXPECT_NE(renderer.setRadiance(field), "");  // says why the GPU path is off
    EXPECT_FALSE(renderer.gpuRadiance());
    EXPECT_EQ(renderer.activeShading(GlShading::PerFragment), GlShading::PerVertex);
    // The fixed-function pipeline interpolates the 8-bit sRGB vertex colours: the reference does the
    // same (the RF toward the eye per vertex, tone-mapped and encoded per vertex, then interpolated).
    const double eye[3] = {testCamera().center.x(), testCamera().center.y(), testCamera().center.z()};
    std::vector<float> linear(3 * mesh.vertexCount()), encoded(3 * mesh.vertexCount());
    rad::radianceTowardViewpoint(field, mesh.positions.data(), eye, 1.0f, linear.data());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const Eigen::Vector3d display = rad::toneMap({}, Eigen::Vector3d(linear[3 * v], linear[3 * v + 1], linear[3 * v + 2]));
        for (int c = 0; c < 3; ++c) encoded[3 * v + c] = rad::toSrgb8(display[c]) / 255.0f;
    }
    const rad::MeshRenderer cpu(mesh);
    const rad::Rendering reference = cpu.renderVertexColors(encoded.data(), testCamera());
    rad::Image8 expected(kWidth, kHeight);
    for (std::size_t i = 0; i < expected.rgb.size(); ++i)
        expected.rgb[i] = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(reference.image.rgb[i], 0.0f, 1.0f)));
    const Comparison c = compare(drawGl(renderer, GlShading::PerFragment, {}), expected, reference);
    EXPECT_GT(c.pixels, 5000);
    EXPECT_LT(c.rmse, 1.0) << "max " << c.maxDiff;
    // Moving the eye re-evaluates the colours on the CPU.
    gl().beginFrame(testCamera(), 0.5, 10.0);
    renderer.draw(GlShading::PerVertex, {}, Eigen::Vector3d(-3.0, 0.5, 0.4));
    const std::vector<std::uint8_t> otherEye = gl().readRgb();
    EXPECT_GT(compare(otherEye, expected, reference).rmse, 3.0);
}

TEST(GlRenderer, VertexColoursWithAndWithoutShaders) {
    const rad::TriangleMesh mesh = coarseSphere();
    std::vector<float> linear(3 * mesh.vertexCount());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int c = 0; c < 3; ++c) linear[3 * v + c] = 0.05f + 0.9f * std::fabs(mesh.positions[3 * v + c]);
    const rad::MeshRenderer cpu(mesh);
    const rad::Rendering reference = cpu.renderVertexColors(linear.data(), testCamera());
    for (bool shaders : {true, false}) {
        radgl::GlCapabilities caps = capabilities();
        if (!shaders) radgl::capGlVersion(caps, 2, 1);
        radgl::RadianceGlRenderer renderer(caps);
        renderer.setMesh(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
        renderer.setVertexColors(linear.data());
        const Comparison c = compare(drawGl(renderer, GlShading::VertexColors, {}), rad::toneMapToSrgb8(reference.image, {}), reference);
        EXPECT_LT(c.rmse, shaders ? 1.0 : 4.0) << (shaders ? "shaders" : "fixed function");
    }
}

TEST(GlRenderer, RestoresTheGlStateItTouches) {
    const rad::TriangleMesh mesh = coarseSphere();
    const rad::RadianceField field = glossyField(mesh, {rad::BasisKind::HemisphericalPolynomial, 3}, false);
    radgl::RadianceGlRenderer renderer(capabilities());
    renderer.setMesh(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    ASSERT_EQ(renderer.setRadiance(field), "");
    gl().beginFrame(testCamera(), 0.5, 10.0);
    GLuint buffer = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glDepthFunc(GL_LESS);
    glEnable(GL_LIGHTING);
    glActiveTexture(GL_TEXTURE3);
    for (GlShading s : {GlShading::PerVertex, GlShading::PerFragment}) renderer.draw(s, {}, testCamera().center);
    GLint value = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &value);
    EXPECT_EQ(value, 0);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &value);
    EXPECT_EQ(value, static_cast<GLint>(buffer));
    glGetIntegerv(GL_DEPTH_FUNC, &value);
    EXPECT_EQ(value, GL_LESS);
    EXPECT_TRUE(glIsEnabled(GL_LIGHTING));
    EXPECT_FALSE(glIsEnabled(GL_POLYGON_OFFSET_FILL));
    glGetIntegerv(GL_ACTIVE_TEXTURE, &value);
    EXPECT_EQ(value, GL_TEXTURE3);
    EXPECT_EQ(renderer.takeGlErrors(), "");
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &buffer);
    glDisable(GL_LIGHTING);
    glActiveTexture(GL_TEXTURE0);
}

TEST(GlRenderer, RefusesInconsistentInput) {
    radgl::RadianceGlRenderer renderer(capabilities());
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::uint32_t badFace[3] = {0, 1, 3};
    EXPECT_THROW(renderer.setMesh(positions, 3, badFace, 1), radgl::GlRendererError);
    const std::uint32_t face[3] = {0, 1, 2};
    renderer.setMesh(positions, 3, face, 1);
    rad::RadianceField wrongSize({rad::BasisKind::HemisphericalPolynomial, 2}, 4);
    EXPECT_THROW(renderer.setRadiance(wrongSize), radgl::GlRendererError);
}

}  // namespace
