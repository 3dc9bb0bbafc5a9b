// Tests of render/image_space_error.h: a mesh against itself has no error (both shading modes); a
// constant RF scaled by a known factor gives the RMSE computed here by hand (linear and 8-bit sRGB,
// the sRGB curve evaluated here); a plane with half its faces removed gives exactly the error of the
// uncovered pixels (the mask is the union of both silhouettes); the memory formula on a tiny mesh
// against hand arithmetic; the heat map's colour ramp; the PNG output; refusals.
#include "render/image_space_error.h"
#include "test_temporary_directory.h"

#include "geometry/primitive_meshes.h"
#include "image/image_io.h"
#include "radiance/material_radiance.h"
#include "radiance/radiance_frame.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <sys/stat.h>

namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// A radiance mesh whose every RF is the constant `value` (frames from the mesh normals).
rad::RadianceMesh constantRadianceMesh(const rad::TriangleMesh& mesh, rad::BasisSpec basis, const Vector3d& value) {
    rad::RadianceMesh out;
    out.positions = mesh.positions;
    out.faces = mesh.faces;
    rad::RadianceField field(basis, mesh.vertexCount());
    // PB: the monomial u^0 v^0 = 1; SH: Y_0^0 = 1 / (2 sqrt(pi)).
    const double b0 = basis.kind == rad::BasisKind::SphericalHarmonics ? 0.5 / std::sqrt(kPi) : 1.0;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        rad::storeFrame(rad::frameFromNormal(Vector3d(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2])),
                        field.frame(v));
        for (int c = 0; c < 3; ++c) field.channelCoefficients(v, c)[0] = static_cast<float>(value[c] / b0);
    }
    out.radiance = field;
    return out;
}

// The IEC 61966-2-1 encoding to an 8-bit code, written here from the standard.
int srgbCode(double linear) {
    const double x = std::min(1.0, std::max(0.0, linear));
    const double e = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return static_cast<int>(std::lround(255.0 * e));
}

rad::ImageSpaceOptions smallOptions() {
    rad::ImageSpaceOptions o;
    o.viewCount = 6;
    o.width = 64;
    o.height = 48;
    return o;
}

TEST(ImageSpaceError, IdenticalMeshesHaveNoError) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(2);
    rad::AnalyticMaterial material;
    material.albedo = Vector3d(0.5, 0.3, 0.2);
    material.specular = Vector3d::Constant(0.4);
    material.exponent = 20.0;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Vector3d(0.3, -0.2, 1.0).normalized(), Vector3d::Ones()});
    rad::MaterialRadianceOptions mo;
    mo.basis = {rad::BasisKind::HemisphericalPolynomial, 4};
    rad::RadianceMesh mesh;
    mesh.positions = sphere.positions;
    mesh.faces = sphere.faces;
    mesh.radiance = rad::makeMaterialRadiance(sphere.positions.data(), sphere.normals.data(), sphere.vertexCount(),
                                              material, lighting, mo);
    for (rad::RadianceShading mode : {rad::RadianceShading::PerFragment, rad::RadianceShading::PerVertex}) {
        rad::ImageSpaceOptions o = smallOptions();
        o.shading = mode;
        o.supersampling = 2;
        const rad::ImageSpaceError e = rad::compareRadianceMeshes(mesh, mesh, o);
        ASSERT_EQ(e.views.size(), 6u);
        for (const rad::ViewImageError& v : e.views) {
            EXPECT_GT(v.errors.pixelCount, 300u);
            EXPECT_EQ(v.originalPixels, v.otherPixels);
            EXPECT_EQ(v.errors.pixelCount, v.originalPixels);
            EXPECT_EQ(v.errors.rmseLinear, 0.0);
            EXPECT_EQ(v.errors.rmseSrgb8, 0.0);
            EXPECT_TRUE(std::isinf(v.errors.psnrLinear) && v.errors.psnrLinear > 0);
        }
        EXPECT_EQ(e.meanRmseLinear, 0.0);
        EXPECT_EQ(e.meanRmseSrgb8, 0.0);
        EXPECT_TRUE(std::isinf(e.meanPsnrLinear) && e.meanPsnrLinear > 0);
        EXPECT_TRUE(std::isinf(e.meanPsnrSrgb8) && e.meanPsnrSrgb8 > 0);
        EXPECT_TRUE(std::isinf(e.pooled.psnrSrgb8));
        EXPECT_EQ(e.worstView, 0);  // every view ties at zero: the first
        EXPECT_EQ(e.emptyViewCount, 0);
        EXPECT_EQ(e.originalMemoryBytes, e.otherMemoryBytes);
    }
}

// Constant RF c against s c, one sample per pixel (coverage 0 or 1) and the same geometry: every
// masked pixel differs by (1 - s) c, so RMSE_linear = |1 - s| sqrt((c_r^2 + c_g^2 + c_b^2) / 3)
// and the 8-bit RMSE is that of the three sRGB codes.
TEST(ImageSpaceError, ScaledConstantFieldGivesTheAnalyticRmse) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(2);
    const Vector3d c(0.35, 0.6, 0.45);
    const double s = 0.8;
    for (const rad::BasisSpec basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 2},
                                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 3}}) {
        const rad::RadianceMesh original = constantRadianceMesh(sphere, basis, c);
        rad::RadianceMesh scaled = original;
        for (float& x : scaled.radiance->coefficients) x = static_cast<float>(x * s);

        const double wantLinear = std::fabs(1.0 - s) * std::sqrt(c.squaredNorm() / 3.0);
        double sq8 = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double d = srgbCode(c[k]) - srgbCode(s * c[k]);
            sq8 += d * d;
        }
        const double want8 = std::sqrt(sq8 / 3.0);
        ASSERT_GT(want8, 10.0);

        int calls = 0;
        const rad::ImageSpaceOptions o = smallOptions();
        const std::vector<rad::ImageSpaceError> all = rad::compareRadianceMeshes(
            original, {&scaled}, o, {}, [&](const rad::ViewRenderings& r) {
                ++calls;
                EXPECT_EQ(r.otherIndex, 0u);
                EXPECT_EQ(r.original->image.width, 64);
                EXPECT_EQ(r.mask->size(), 64u * 48u);
            });
        EXPECT_EQ(calls, 6);
        ASSERT_EQ(all.size(), 1u);
        const rad::ImageSpaceError& e = all[0];
        for (const rad::ViewImageError& v : e.views) {
            EXPECT_EQ(v.errors.pixelCount, v.originalPixels);
            EXPECT_EQ(v.otherPixels, v.originalPixels);
            EXPECT_NEAR(v.errors.rmseLinear, wantLinear, 1e-5 * wantLinear) << basis.name();
            EXPECT_NEAR(v.errors.psnrLinear, 20.0 * std::log10(1.0 / wantLinear), 1e-3);
            EXPECT_NEAR(v.errors.rmseSrgb8, want8, 1e-9) << basis.name();
            EXPECT_NEAR(v.errors.psnrSrgb8, 20.0 * std::log10(255.0 / want8), 1e-6);
        }
        EXPECT_NEAR(e.meanRmseLinear, wantLinear, 1e-5 * wantLinear);
        EXPECT_NEAR(e.meanRmseSrgb8, want8, 1e-9);
        EXPECT_NEAR(e.meanPsnrSrgb8, 20.0 * std::log10(255.0 / want8), 1e-6);
        EXPECT_NEAR(e.pooled.rmseLinear, wantLinear, 1e-5 * wantLinear);
        EXPECT_GE(e.worstView, 0);
    }
}

// A plane of two unit squares seen from above; the other mesh lost the faces of one square. Where the
// original shows c and the other the (black) background the error is c; elsewhere zero. With one
// sample per pixel: MSE_linear = (|M| - |other|) |c|^2 / 3 / |M| with the mask M the union of the
// silhouettes (here the original's). Also writes the PNG output.
TEST(ImageSpaceError, HoleCountsThroughTheSilhouette) {
    rad::TriangleMesh plane;
    radtest::addQuad(plane, -1.0f, 0.0f, -1.0f, 1.0f, 0.0f);
    radtest::addQuad(plane, 0.0f, 1.0f, -1.0f, 1.0f, 0.0f);
    const Vector3d c(0.5, 0.25, 0.75);
    const rad::RadianceMesh original = constantRadianceMesh(plane, {rad::BasisKind::HemisphericalPolynomial, 1}, c);
    rad::RadianceMesh holed = original;
    holed.faces.resize(6);  // the first square only; the second one's vertices stay, unused

    rad::ImageSpaceOptions o = smallOptions();
    o.minElevationDegrees = 30.0;  // every camera above the plane
    o.maxElevationDegrees = 90.0;
    rad::ImageSpaceImageOutput out;
    out.directory = std::string(RADIANCE_TEST_TMPDIR) + "/image_space_error";
    ::mkdir(out.directory.c_str(), 0755);
    out.renders = true;
    out.labels = {"holed"};
    const rad::ImageSpaceError e = rad::compareRadianceMeshes(original, holed, o, out);
    for (const rad::ViewImageError& v : e.views) {
        ASSERT_EQ(v.errors.pixelCount, v.originalPixels);  // the union is the original's silhouette here
        ASSERT_GT(v.originalPixels, v.otherPixels + 100);
        const double fraction = double(v.originalPixels - v.otherPixels) / double(v.originalPixels);
        EXPECT_NEAR(v.errors.rmseLinear, std::sqrt(fraction * c.squaredNorm() / 3.0), 1e-6);
        EXPECT_GT(v.errors.rmseSrgb8, 10.0);
        EXPECT_TRUE(std::isfinite(v.errors.psnrLinear));
    }
    EXPECT_GT(e.meanRmseLinear, 0.1);
    // Same vertices, fewer faces: 2 triangles (24 B) less.
    EXPECT_EQ(e.originalMemoryBytes, e.otherMemoryBytes + 24);

    // The PNG files, at the image size; a pixel of the lost square is not black in the heat map.
    for (const char* name : {"original_view00.png", "holed_view00.png", "holed_view00_heatmap.png", "holed_view05_heatmap.png"}) {
        const rad::Image8 img = rad::readImage8(out.directory + "/" + name);
        EXPECT_EQ(img.width, 64) << name;
        EXPECT_EQ(img.height, 48) << name;
    }
    const rad::Image8 heat = rad::readImage8(out.directory + "/holed_view00_heatmap.png");
    int hot = 0;
    for (std::size_t i = 0; i < heat.rgb.size(); i += 3) hot += heat.rgb[i] == 255 && heat.rgb[i + 1] > 0;
    EXPECT_GT(hot, 100);  // |c| RMS = 0.54 > the default scale 0.1: white
}

// Memory by hand for the 4-vertex, 2-triangle quad of Fig. 6:
//   PB2 (K = 6):  4 * (12 + 3*6*4 + 24) + 2*12 = 4 * 108 + 24 = 456
//   SH2 (K = 9):  4 * (12 + 3*9*4 + 12) + 24   = 4 * 132 + 24 = 552 (plain and reflected)
//   PB0 (K = 1):  4 * (12 + 12 + 24) + 24       = 216
//   no radiance:  4 * 12 + 24                   = 72
TEST(ImageSpaceError, MemoryFormulaOnATinyMesh) {
    const rad::TriangleMesh quad = rad::makeDivergingQuad(0.3f);
    EXPECT_EQ(rad::radianceMeshMemoryBytes(constantRadianceMesh(quad, {rad::BasisKind::HemisphericalPolynomial, 2}, Vector3d::Ones())), 456u);
    rad::RadianceMesh sh = constantRadianceMesh(quad, {rad::BasisKind::SphericalHarmonics, 2}, Vector3d::Ones());
    EXPECT_EQ(rad::radianceMeshMemoryBytes(sh), 552u);
    sh.radiance->reflected = true;
    EXPECT_EQ(rad::radianceMeshMemoryBytes(sh), 552u);
    EXPECT_EQ(rad::radianceMeshMemoryBytes(constantRadianceMesh(quad, {rad::BasisKind::HemisphericalPolynomial, 0}, Vector3d::Ones())), 216u);
    rad::RadianceMesh bare;
    bare.positions = quad.positions;
    bare.faces = quad.faces;
    EXPECT_EQ(rad::radianceMeshMemoryBytes(bare), 72u);
    EXPECT_EQ(rad::radianceMeshMemoryBytes(4, 2, {rad::BasisKind::SphericalHarmonics, 2}), 552u);
    EXPECT_EQ(rad::vertexBytes({rad::BasisKind::HemisphericalPolynomial, 4}), 12u + 180u + 24u);
}

// The ramp: 0 -> black, scale/3 -> red, 2 scale/3 -> yellow, >= scale -> white; outside the mask blue.
TEST(ImageSpaceError, HeatmapRamp) {
    rad::ImageF a(5, 1), b(5, 1);
    const float diffs[4] = {0.0f, 0.1f, 0.2f, 0.5f};
    for (int x = 0; x < 4; ++x)
        for (int ch = 0; ch < 3; ++ch) {
            a.pixel(x, 0)[ch] = 0.5f + diffs[x];
            b.pixel(x, 0)[ch] = 0.5f;
        }
    a.pixel(4, 0)[0] = 1.0f;  // a difference outside the mask
    const rad::Image8 h = rad::errorHeatmap(a, b, {1, 1, 1, 1, 0}, 0.3);
    const int want[5][3] = {{0, 0, 0}, {255, 0, 0}, {255, 255, 0}, {255, 255, 255}, {40, 60, 110}};
    for (int x = 0; x < 5; ++x)
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(h.rgb[3 * x + ch], want[x][ch], 1) << x << " " << ch;
    EXPECT_THROW(rad::errorHeatmap(a, rad::ImageF(4, 1), {}, 0.3), std::invalid_argument);
    EXPECT_THROW(rad::errorHeatmap(a, b, {1, 1}, 0.3), std::invalid_argument);
    EXPECT_THROW(rad::errorHeatmap(a, b, {}, 0.0), std::invalid_argument);
}

TEST(ImageSpaceError, RefusesMeshesWithoutRadiance) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(1);
    const rad::RadianceMesh good = constantRadianceMesh(sphere, {}, Vector3d::Ones());
    rad::RadianceMesh bare = good;
    bare.radiance.reset();
    auto message = [&](const rad::RadianceMesh& a, const rad::RadianceMesh& b) -> std::string {
        try {
            rad::compareRadianceMeshes(a, b, smallOptions());
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "no exception";
    };
    EXPECT_NE(message(bare, good).find("original mesh has no radiance functions"), std::string::npos) << message(bare, good);
    EXPECT_NE(message(good, bare).find("other mesh has no radiance functions"), std::string::npos) << message(good, bare);
    rad::RadianceMesh wrongCount = good;
    wrongCount.radiance = constantRadianceMesh(rad::makeIcosphere(2), {}, Vector3d::Ones()).radiance;
    EXPECT_NE(message(good, wrongCount).find("radiance functions for"), std::string::npos) << message(good, wrongCount);
    rad::RadianceMesh noFaces = good;
    noFaces.faces.clear();
    EXPECT_THROW(rad::compareRadianceMeshes(good, noFaces, smallOptions()), std::invalid_argument);
    rad::ImageSpaceOptions o = smallOptions();
    o.viewCount = 0;
    EXPECT_THROW(rad::compareRadianceMeshes(good, good, o), std::invalid_argument);
    o = smallOptions();
    o.supersampling = 17;
    EXPECT_THROW(rad::compareRadianceMeshes(good, good, o), std::invalid_argument);
    o = smallOptions();
    o.minElevationDegrees = 50.0;
    o.maxElevationDegrees = 10.0;
    EXPECT_THROW(rad::compareRadianceMeshes(good, good, o), std::invalid_argument);
    EXPECT_THROW(rad::compareRadianceMeshes(good, std::vector<const rad::RadianceMesh*>{nullptr}), std::invalid_argument);
}

}  // namespace
