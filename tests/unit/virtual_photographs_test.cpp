// Tests of acquisition/virtual_photographs.h: a flat quad seen head-on, every pixel against the
// closed-form shading at the hit point computed here by hand (ray through the pixel centre, plane
// intersection, Lambert + normalised Blinn-Phong written out), supersampling as the mean of the
// sub-pixel values, background, antialiased silhouettes, cast shadows, PNG output.
#include "acquisition/virtual_photographs.h"
#include "test_temporary_directory.h"

#include "image/image_io.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace {

using Eigen::Vector3d;
using rad::Rgb;

constexpr double kPi = 3.14159265358979323846;

struct HeadOn {
    rad::AnalyticMaterial material;
    rad::AnalyticLighting lighting;
    Vector3d lightDir = Vector3d(0.3, 0.2, 1.0).normalized();
    double irradiance = 1.5, ambient = 0.05;
    rad::PinholeCamera camera;

    HeadOn() {
        material.albedo = Rgb(0.5, 0.4, 0.3);
        material.specular = Rgb(0.25, 0.25, 0.25);
        material.exponent = 20.0;
        lighting.directional.push_back({lightDir, Rgb::Constant(irradiance)});
        lighting.ambient = Rgb::Constant(ambient);
        // Camera at (0, 0, 3) looking down -z, image up = +y: right = +x, down = -y.
        camera = rad::PinholeCamera::lookAt(Vector3d(0, 0, 3), Vector3d::Zero(), Vector3d::UnitY(), 60.0, 64, 48);
    }

    // Closed form, written out independently of analytic_material.cpp: the ray through image point
    // (u, v) hits z = 0 at p = C + t d; the shading normal is +z everywhere on the quad.
    Rgb expected(double u, double v, bool* onQuad = nullptr) const {
        const double f = 32.0 / std::tan(30.0 * kPi / 180.0);
        const Vector3d d = Vector3d((u - 32.0) / f, -(v - 24.0) / f, -1.0).normalized();
        const double t = 3.0 / -d.z();
        const Vector3d p = Vector3d(0, 0, 3) + t * d;
        if (onQuad) *onQuad = std::fabs(p.x()) < 1.0 && std::fabs(p.y()) < 1.0;
        const Vector3d n(0, 0, 1), wo = -d;
        const Vector3d h = (lightDir + wo).normalized();
        const double cosI = lightDir.z();
        Rgb L;
        for (int c = 0; c < 3; ++c)
            L[c] = material.albedo[c] * ambient +
                   (material.albedo[c] / kPi +
                    material.specular[c] * (material.exponent + 8) / (8 * kPi) * std::pow(h.dot(n), material.exponent)) *
                       irradiance * cosI;
        return L;
    }
};

rad::VirtualSceneOptions noVariation() {
    rad::VirtualSceneOptions o;
    o.variation.enabled = false;
    return o;
}

TEST(VirtualPhotographs, FlatQuadHeadOnMatchesClosedFormShading) {
    const HeadOn s;
    rad::TriangleMesh quad;
    radtest::addQuad(quad, -1, 1, -1, 1, 0);
    const rad::VirtualScene scene(quad, s.material, s.lighting, noVariation());
    rad::PhotographOptions o;
    o.supersampling = 1;
    o.background = Rgb(0.1, 0.2, 0.3);
    const rad::ImageF img = rad::renderPhotograph(scene, s.camera, o);
    ASSERT_EQ(img.width, 64);
    ASSERT_EQ(img.height, 48);
    int inside = 0, outside = 0;
    for (int r = 0; r < 48; ++r)
        for (int c = 0; c < 64; ++c) {
            bool onQuad = false;
            const Rgb L = s.expected(c + 0.5, r + 0.5, &onQuad);
            const float* px = img.pixel(c, r);
            const Rgb want = onQuad ? L : o.background;
            (onQuad ? inside : outside)++;
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(px[k], want[k], 2e-5) << "pixel " << c << "," << r;
        }
    EXPECT_GT(inside, 200);
    EXPECT_GT(outside, 200);
    // The highlight is in the picture: the brightest pixel is well above the diffuse level.
    float brightest = 0;
    for (std::size_t i = 0; i < img.rgb.size(); i += 3) brightest = std::max(brightest, img.rgb[i + 2]);
    EXPECT_GT(brightest, 1.5 * (s.material.albedo[2] / kPi * s.irradiance * s.lightDir.z()));
}

TEST(VirtualPhotographs, SupersamplingAveragesSubPixelCentres) {
    const HeadOn s;
    rad::TriangleMesh quad;
    radtest::addQuad(quad, -1, 1, -1, 1, 0);
    const rad::VirtualScene scene(quad, s.material, s.lighting, noVariation());
    rad::PhotographOptions o;
    o.supersampling = 3;
    const rad::ImageF img = rad::renderPhotograph(scene, s.camera, o);
    for (int r = 14; r < 34; r += 5)
        for (int c = 20; c < 44; c += 6) {
            Rgb mean = Rgb::Zero();
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) mean += s.expected(c + (i + 0.5) / 3, r + (j + 0.5) / 3) / 9.0;
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(img.pixel(c, r)[k], mean[k], 2e-5);
        }
}

TEST(VirtualPhotographs, SilhouettesAreAntialiased) {
    const HeadOn s;
    rad::TriangleMesh quad;
    radtest::addQuad(quad, -1, 1, -1, 1, 0);
    const rad::VirtualScene scene(quad, s.material, s.lighting, noVariation());
    rad::PhotographOptions o;
    o.supersampling = 4;
    o.background = Rgb::Zero();
    const rad::ImageF img = rad::renderPhotograph(scene, s.camera, o);
    // Along the middle row, the quad's left edge falls inside a pixel (x = -1 at u = 32 - f/3):
    // that pixel is strictly between the background and the lit neighbours on its right.
    const double f = 32.0 / std::tan(30.0 * kPi / 180.0);
    const int edge = static_cast<int>(std::floor(32.0 - f / 3.0));
    const double fraction = std::ceil(32.0 - f / 3.0) - (32.0 - f / 3.0);  // covered part of the pixel
    ASSERT_GT(fraction, 0.05);
    ASSERT_LT(fraction, 0.95);
    const float partial = img.pixel(edge, 24)[0];
    const float full = img.pixel(edge + 1, 24)[0];
    EXPECT_GT(partial, 0.0f);
    EXPECT_LT(partial, full);
    // 4 sub-columns: the covered share is a multiple of 1/4 close to `fraction`.
    EXPECT_NEAR(partial / full, std::round(fraction * 4) / 4, 0.1);
}

TEST(VirtualPhotographs, CastShadowsAppearInThePhotograph) {
    HeadOn s;
    s.lighting.directional[0].direction = Vector3d(0, 0, 1);
    rad::TriangleMesh scene2;
    radtest::addQuad(scene2, -1, 1, -1, 1, 0);
    radtest::addQuad(scene2, -0.2f, 0.2f, -0.2f, 0.2f, 1.0f);  // blocker between camera and ground, lit from above
    const rad::VirtualScene scene(scene2, s.material, s.lighting, noVariation());
    rad::PhotographOptions o;
    o.supersampling = 1;
    // Look from the side so the shadow on the ground is visible beside the blocker.
    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Vector3d(2.0, 0.0, 2.5), Vector3d::Zero(), Vector3d::UnitZ(), 50.0, 80, 60);
    const rad::ImageF img = rad::renderPhotograph(scene, cam, o);
    double u, v;
    ASSERT_TRUE(cam.project(Vector3d(-0.1, 0.05, 0.0), u, v));  // in the shadow, not hidden by the blocker?
    // The ground point (-0.1, 0.05, 0) could be hidden behind the blocker from this camera: check it
    // is the ground that is seen, through an independent ray-plane test.
    const Vector3d dir = (Vector3d(-0.1, 0.05, 0.0) - cam.center).normalized();
    const double tBlock = (1.0 - cam.center.z()) / dir.z();
    const Vector3d atBlocker = cam.center + tBlock * dir;
    ASSERT_FALSE(std::fabs(atBlocker.x()) < 0.2 && std::fabs(atBlocker.y()) < 0.2);
    const float* shadowed = img.pixel(static_cast<int>(u), static_cast<int>(v));
    ASSERT_TRUE(cam.project(Vector3d(0.7, -0.6, 0.0), u, v));
    const float* lit = img.pixel(static_cast<int>(u), static_cast<int>(v));
    EXPECT_NEAR(shadowed[0], s.material.albedo[0] * s.ambient, 1e-6);
    EXPECT_GT(lit[0], 5.0f * shadowed[0]);
}

TEST(VirtualPhotographs, PngIsTheSrgbEncoding) {
    const HeadOn s;
    rad::TriangleMesh quad;
    radtest::addQuad(quad, -1, 1, -1, 1, 0);
    const rad::VirtualScene scene(quad, s.material, s.lighting, noVariation());
    const rad::ImageF img = rad::renderPhotograph(scene, s.camera);
    const std::string path = std::string(RADIANCE_TEST_TMPDIR) + "/virtual_photograph_test.png";
    rad::writePhotographPng(path, img, 1.5f);
    const rad::Image8 back = rad::readImage8(path);
    const rad::Image8 want = rad::encodeToSrgb8(img, 1.5f);
    ASSERT_EQ(back.width, want.width);
    ASSERT_EQ(back.height, want.height);
    EXPECT_EQ(back.rgb, want.rgb);
    std::filesystem::remove(path);
}

TEST(VirtualPhotographs, RefusesBadCameraAndOptions) {
    const HeadOn s;
    rad::TriangleMesh quad;
    radtest::addQuad(quad, -1, 1, -1, 1, 0);
    const rad::VirtualScene scene(quad, s.material, s.lighting, noVariation());
    rad::PinholeCamera bad = s.camera;
    bad.fx = 0.0;
    EXPECT_THROW(rad::renderPhotograph(scene, bad), std::invalid_argument);
    rad::PhotographOptions o;
    o.supersampling = 0;
    EXPECT_THROW(rad::renderPhotograph(scene, s.camera, o), std::invalid_argument);
}

}  // namespace
