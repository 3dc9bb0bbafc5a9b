// Tests of render/radiance_renderer.h: a constant RF renders its constant (both modes, plain and
// reflected storage, with exact coverage blending at silhouettes), the paper's Fig. 6 toy
// (per-fragment eq. (8) keeps the highlight inside a quad with diverging normals, per-vertex loses
// it), plain vertex colours against hand-computed barycentrics, input checks.
#include "render/radiance_renderer.h"

#include "geometry/primitive_meshes.h"
#include "radiance/material_radiance.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// A field whose every RF is the constant `value` (frames from the mesh normals).
rad::RadianceField constantField(const rad::TriangleMesh& mesh, rad::BasisSpec basis, const Vector3d& value,
                                 bool reflected) {
    rad::RadianceField field(basis, mesh.vertexCount(), reflected);
    // PB: the monomial u^0 v^0 = 1; SH: Y_0^0 = 1 / (2 sqrt(pi)).
    const double b0 = basis.kind == rad::BasisKind::SphericalHarmonics ? 0.5 / std::sqrt(kPi) : 1.0;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        rad::storeFrame(rad::frameFromNormal(Vector3d(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2])),
                        field.frame(v));
        for (int c = 0; c < 3; ++c) field.channelCoefficients(v, c)[0] = static_cast<float>(value[c] / b0);
    }
    return field;
}

TEST(RadianceRenderer, ConstantFieldRendersItsConstantInBothModes) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(3);
    const rad::MeshRenderer renderer(sphere);
    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Vector3d(0.5, -3.0, 2.0), Vector3d::Zero(), Vector3d::UnitZ(), 50.0, 80, 60);
    const Vector3d value(0.2, 0.5, 0.7), background(0.05, 0.0, 0.1);
    rad::RenderOptions o;
    o.supersampling = 2;
    o.background = background;
    for (const rad::BasisSpec basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 3},
                                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 2}})
        for (bool reflected : {false, true})
            for (rad::RadianceShading mode : {rad::RadianceShading::PerVertex, rad::RadianceShading::PerFragment}) {
                const rad::RadianceField field = constantField(sphere, basis, value, reflected);
                const rad::Rendering r = renderer.renderRadiance(field, cam, mode, o);
                ASSERT_EQ(r.image.width, 80);
                ASSERT_EQ(r.coverage.size(), 80u * 60u);
                int full = 0, empty = 0, partial = 0;
                for (int y = 0; y < 60; ++y)
                    for (int x = 0; x < 80; ++x) {
                        const int cov = r.coverage[y * 80 + x];
                        const double hits = std::round(cov * 4.0 / 255.0);  // of 2 x 2 samples
                        ASSERT_EQ(cov, static_cast<int>(std::lround(255.0 * hits / 4.0)));
                        full += cov == 255;
                        empty += cov == 0;
                        partial += cov > 0 && cov < 255;
                        const Vector3d want = value * (hits / 4.0) + background * (1.0 - hits / 4.0);
                        for (int c = 0; c < 3; ++c)
                            ASSERT_NEAR(r.image.pixel(x, y)[c], want[c], 1e-5) << basis.name() << " pixel " << x << "," << y;
                    }
                EXPECT_GT(full, 500);
                EXPECT_GT(empty, 500);
                EXPECT_GT(partial, 20);  // the silhouette
                const std::vector<std::uint8_t> m = r.mask();
                const std::vector<std::uint8_t> touched = r.mask(1);
                int nm = 0, nt = 0;
                for (std::size_t i = 0; i < m.size(); ++i) {
                    nm += m[i];
                    nt += touched[i];
                }
                EXPECT_EQ(nm, full);
                EXPECT_EQ(nt, full + partial);
            }
}

// Vanhoey et al. 2015 Fig. 6: a quad whose four normals diverge by 30 degrees, glossy RF, light and eye
// straight above the centre. At the centre the interpolated normal is +z and the eye direction
// reflects onto the light: eq. (8) shows the peak. Every vertex, seen from the eye, is ~42 degrees
// off its own highlight: per-vertex shading shows no highlight anywhere in the quad.
TEST(RadianceRenderer, PerFragmentKeepsTheHighlightThatPerVertexLoses) {
    const rad::TriangleMesh quad = rad::makeDivergingQuad(static_cast<float>(30.0 * kPi / 180.0), 1.0f);
    rad::AnalyticMaterial material;
    material.albedo = Vector3d::Constant(0.2);
    material.specular = Vector3d::Constant(0.5);
    material.exponent = 40.0;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Vector3d::UnitZ(), Vector3d::Ones()});
    rad::MaterialRadianceOptions mo;
    mo.basis = {rad::BasisKind::SphericalHarmonics, 8};
    const rad::RadianceField field =
        rad::makeMaterialRadiance(quad.positions.data(), quad.normals.data(), 4, material, lighting, mo);
    rad::RadianceField reflected = field;
    rad::setReflectedStorage(reflected, true);

    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Vector3d(0, 0, 3), Vector3d::Zero(), Vector3d::UnitY(), 60.0, 96, 96);
    const rad::MeshRenderer renderer(quad);
    const rad::Rendering vertex = renderer.renderRadiance(field, cam, rad::RadianceShading::PerVertex);
    const rad::Rendering fragment = renderer.renderRadiance(field, cam, rad::RadianceShading::PerFragment);
    const rad::Rendering fragmentR = renderer.renderRadiance(reflected, cam, rad::RadianceShading::PerFragment);
    const rad::Rendering vertexR = renderer.renderRadiance(reflected, cam, rad::RadianceShading::PerVertex);

    // The storage does not matter.
    for (std::size_t i = 0; i < fragment.image.rgb.size(); ++i) {
        ASSERT_NEAR(fragment.image.rgb[i], fragmentR.image.rgb[i], 1e-4);
        ASSERT_NEAR(vertex.image.rgb[i], vertexR.image.rgb[i], 1e-4);
    }
    // Centre pixel (its centre projects within 1/50 of the quad's size from the quad centre).
    const float centreFragment = fragment.image.pixel(48, 48)[0];
    const float centreVertex = vertex.image.pixel(48, 48)[0];
    const double peak = rad::outgoingRadiance(material, lighting, Vector3d::Zero(), Vector3d::UnitZ(), Vector3d::UnitZ())[0];
    const double diffuse = material.albedo[0] / kPi;
    EXPECT_NEAR(centreFragment, peak, 0.25 * peak);  // SH(8) smooths the lobe a little
    EXPECT_LT(centreVertex, diffuse + 0.1 * (peak - diffuse));
    // Per-vertex: no pixel of the quad carries a highlight.
    for (std::size_t i = 0; i < vertex.coverage.size(); ++i)
        if (vertex.coverage[i] == 255) ASSERT_LT(vertex.image.rgb[3 * i], diffuse + 0.1 * (peak - diffuse));
    // Near a corner the two modes agree (alpha -> (1, 0, 0): eq. (8) gives L_1 toward the eye).
    double u, v;
    ASSERT_TRUE(cam.project(Vector3d(-0.97, -0.97, 0.0), u, v));
    const int cu = static_cast<int>(u), cv = static_cast<int>(v);
    ASSERT_EQ(fragment.coverage[cv * 96 + cu], 255);
    EXPECT_NEAR(fragment.image.pixel(cu, cv)[0], vertex.image.pixel(cu, cv)[0], 0.02);
}

// A flat quad [-1, 1]^2 with four vertex colours seen head-on: every covered pixel is the
// barycentric blend of its triangle, barycentrics computed here from the hit point by hand.
TEST(RadianceRenderer, VertexColorsAreInterpolatedWithBarycentrics) {
    rad::TriangleMesh quad;
    quad.positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    quad.faces = {0, 1, 2, 0, 2, 3};
    const float colors[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0};
    const rad::MeshRenderer renderer(quad);
    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Vector3d(0, 0, 3), Vector3d::Zero(), Vector3d::UnitY(), 60.0, 64, 48);
    const rad::Rendering r = renderer.renderVertexColors(colors, cam);
    const double f = 32.0 / std::tan(30.0 * kPi / 180.0);
    int checked = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            // Camera right = +x, down = -y: the pixel centre's ray meets z = 0 at (3 dx, -3 dy).
            const double px = 3.0 * (x + 0.5 - 32.0) / f, py = -3.0 * (y + 0.5 - 24.0) / f;
            const bool inside = std::fabs(px) < 1.0 && std::fabs(py) < 1.0;
            ASSERT_EQ(r.coverage[y * 64 + x], inside ? 255 : 0);
            if (!inside || std::fabs(px - py) < 1e-3) continue;
            double a[4] = {0, 0, 0, 0};
            if (px > py) {  // triangle (0, 1, 2)
                a[0] = (1 - px) / 2;
                a[1] = (px - py) / 2;
                a[2] = (1 + py) / 2;
            } else {  // triangle (0, 2, 3)
                a[0] = (1 - py) / 2;
                a[2] = (1 + px) / 2;
                a[3] = (py - px) / 2;
            }
            for (int c = 0; c < 3; ++c) {
                double want = 0;
                for (int k = 0; k < 4; ++k) want += a[k] * colors[3 * k + c];
                ASSERT_NEAR(r.image.pixel(x, y)[c], want, 1e-5) << x << "," << y;
            }
            ++checked;
        }
    EXPECT_GT(checked, 1000);
}

TEST(RadianceRenderer, RefusesMismatchedInput) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(1);
    const rad::MeshRenderer renderer(sphere);
    const rad::TriangleMesh other = rad::makeIcosphere(2);
    const rad::RadianceField wrongSize = constantField(other, {}, Vector3d::Ones(), false);
    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Vector3d(0, 0, 3), Vector3d::Zero(), Vector3d::UnitY(), 60.0, 16, 16);
    EXPECT_THROW(renderer.renderRadiance(wrongSize, cam, rad::RadianceShading::PerFragment), std::invalid_argument);
    const rad::RadianceField field = constantField(sphere, {}, Vector3d::Ones(), false);
    rad::PinholeCamera bad = cam;
    bad.width = 0;
    EXPECT_THROW(renderer.renderRadiance(field, bad, rad::RadianceShading::PerVertex), std::invalid_argument);
    rad::RenderOptions o;
    o.supersampling = 17;
    EXPECT_THROW(renderer.renderRadiance(field, cam, rad::RadianceShading::PerVertex, o), std::invalid_argument);
    rad::TriangleMesh noFaces;
    noFaces.positions = {0, 0, 0};
    EXPECT_THROW(rad::MeshRenderer{noFaces}, std::invalid_argument);
    rad::TriangleMesh badIndex = sphere;
    badIndex.faces[5] = 100000;
    EXPECT_THROW(rad::MeshRenderer{badIndex}, std::invalid_argument);
}

}  // namespace
