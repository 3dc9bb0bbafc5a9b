// The irradiance vector grid's display (Granier et al. 2007; render_gl/irradiance_grid_textures.h,
// irradiance_grid_shaders.h, through the normal-map renderer) in a real OpenGL context (Mesa under
// Xvfb): a mesh lit only by a grid built here from an analytic field, read back and compared pixel by
// pixel with the CPU evaluation of the same compressed grid (rad::reflectedRadianceCompressed) at the
// point and normal the pixel sees (ray cast on the analytic plane or sphere), tone-mapped and encoded
// to 8-bit sRGB as the shader does (render/tone_mapping.h).
//
// Tolerance, in 8-bit sRGB codes: the GPU stores the compressed grid in half floats (relative rounding
// 2^-11 on each colour and direction component, so about 0.15 % on a radiance, well below one code at
// the radiances used, 0.1 to 0.9), filters with the hardware's subtexel weights (llvmpipe: 8 fractional
// bits, an error of at most gradient x cell / 512), and the float shader and the double CPU may round to
// neighbouring codes (render/tone_mapping.h): at most 2 codes on any pixel, mean below 0.5. On the
// sphere the mesh is a level-5 icosphere, not the analytic sphere: its interpolated normals and its
// positions differ from the ray-cast ones by about 1e-3, a fraction of a code here.
// The maximum and mean differences are printed (README, "Irradiance vector grid decoration").
#include "normal_map_gl_renderer.h"
#include "gl_test_context.h"
#include "irradiance_grid_textures.h"
#include "offscreen_gl.h"

#include "bake/normal_baker.h"
#include "geometry/primitive_meshes.h"
#include "image/rgb_image.h"
#include "lighting/irradiance_vector_grid.h"
#include "render/tone_mapping.h"

#include <Eigen/Geometry>
#include <GL/glew.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

namespace {

using gltest::capabilities;
using gltest::gl;
using gltest::kHeight;
using gltest::kWidth;
using radgl::IndirectLight;
using radgl::NormalMapShading;
const double kPi = 3.14159265358979323846;

// I_{c,delta}(p) for channel c, direction delta (0..5) at point p: 3 floats.
using Field = std::function<Eigen::Vector3d(int channel, int direction, const Eigen::Vector3d& p)>;

rad::IrradianceVectorGrid gridFrom(const Field& field, const std::array<int, 3>& cells) {
    rad::IrradianceVectorGrid grid = rad::IrradianceVectorGrid::covering({{-1.0f, -1.1f, -0.9f}}, {{1.05f, 1.0f, 1.0f}}, cells);
    for (int k = 0; k <= cells[2]; ++k)
        for (int j = 0; j <= cells[1]; ++j)
            for (int i = 0; i <= cells[0]; ++i) {
                const std::array<float, 3> x = grid.vertexPosition(i, j, k);
                const Eigen::Vector3d p(x[0], x[1], x[2]);
                for (int d = 0; d < 6; ++d) {
                    float* out = grid.at(grid.vertexIndex(i, j, k), d);
                    for (int c = 0; c < 3; ++c) {
                        const Eigen::Vector3d v = field(c, d, p);
                        for (int a = 0; a < 3; ++a) out[3 * c + a] = static_cast<float>(v[a]);
                    }
                }
            }
    return grid;
}

Eigen::Vector3d direction(int d) {
    const std::array<float, 3> v = rad::gridDirection(d);
    return Eigen::Vector3d(v[0], v[1], v[2]);
}

// A uniform sky of radiance L: I_delta = pi L delta for every channel (the integral of L w over the
// hemisphere around delta).
Field uniformSky(const Eigen::Vector3d& L) {
    return [L](int c, int d, const Eigen::Vector3d&) -> Eigen::Vector3d { return kPi * L[c] * direction(d); };
}

// A field varying linearly in space, red growing toward +x, blue toward -x, with a component across
// delta (so that the paper's compression to one direction per (vertex, delta) is lossy).
Field linearField() {
    return [](int c, int d, const Eigen::Vector3d& p) -> Eigen::Vector3d {
        const Eigen::Vector3d delta = direction(d);
        const Eigen::Vector3d across = direction((d + 2) % 6);
        const double gradient[3][3] = {{0.9, 0.2, 0.1}, {0.1, -0.3, 0.25}, {-0.8, 0.1, -0.15}};
        const double base[3] = {1.6, 1.3, 1.7};
        double magnitude = base[c] + 0.1 * d;
        for (int a = 0; a < 3; ++a) magnitude += gradient[c][a] * p[a];
        return magnitude * delta + (0.15 * c + 0.05 * p.y()) * across;
    };
}

struct Comparison {
    int maxDiff = 0;
    double meanDiff = 0;
    int pixels = 0;
};

// Compares the rendering with the CPU evaluation; hit(pixel) -> false when the pixel is skipped,
// else point, normal and albedo.
using Hit = std::function<bool(const Eigen::Vector3d& ray, Eigen::Vector3d& point, Eigen::Vector3d& normal)>;

Comparison compare(const std::vector<std::uint8_t>& picture, const rad::PinholeCamera& camera, const Hit& hit,
                   const rad::IrradianceVectorGrid& grid, const Eigen::Vector3d& albedo,
                   const std::function<Eigen::Vector3d(const Eigen::Vector3d&, const Eigen::Vector3d&)>& extra = {},
                   const rad::ToneMapping& tm = {},
                   rad::DirectionalWeights weights = rad::DirectionalWeights::Squared) {
    const std::vector<float> compressed = rad::gpuCompressed(grid);
    Comparison out;
    double sum = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            Eigen::Vector3d p, n;
            if (!hit(camera.rayDirection(x + 0.5, y + 0.5), p, n)) continue;
            const float point[3] = {float(p.x()), float(p.y()), float(p.z())};
            const float normal[3] = {float(n.x()), float(n.y()), float(n.z())};
            const float rho[3] = {float(albedo.x()), float(albedo.y()), float(albedo.z())};
            float rgb[3];
            rad::reflectedRadianceCompressed(grid, compressed, point, normal, rho, rgb, weights);
            Eigen::Vector3d linear(rgb[0], rgb[1], rgb[2]);
            if (extra) linear += extra(p, n);
            const Eigen::Vector3d display = rad::toneMap(tm, linear);
            for (int c = 0; c < 3; ++c) {
                const int d = std::abs(int(picture[3 * (y * kWidth + x) + c]) - int(rad::toSrgb8(display[c])));
                out.maxDiff = std::max(out.maxDiff, d);
                sum += d;
            }
            ++out.pixels;
        }
    out.meanDiff = out.pixels ? sum / (3.0 * out.pixels) : 0.0;
    return out;
}

void report(const char* name, const Comparison& c) {
    std::printf("[ivg-gl] %s: %d pixels, max %d codes, mean %.3f codes\n", name, c.pixels, c.maxDiff, c.meanDiff);
}

// The analytic sphere of radius r at the origin, pixels whose normal faces the camera by more than
// 0.25 (the tessellated silhouette differs from the analytic one).
Hit sphereHit(const rad::PinholeCamera& camera, double r) {
    return [&camera, r](const Eigen::Vector3d& d, Eigen::Vector3d& p, Eigen::Vector3d& n) {
        const Eigen::Vector3d o = camera.center;
        const double b = o.dot(d), c = o.squaredNorm() - r * r, disc = b * b - c;
        if (disc <= 0) return false;
        const double t = -b - std::sqrt(disc);
        p = o + t * d;
        n = p / r;
        return -n.dot(d) > 0.25;
    };
}

// Every 7th pixel of the picture on the sphere of radius 0.8 against a closed form of the normal
// (linear radiance, sRGB-encoded here): at most 2 codes apart, on more than 50 pixels.
void expectClosedFormOnTheSphere(const std::vector<std::uint8_t>& picture, const rad::PinholeCamera& camera,
                                 const char* what, const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& expected) {
    int checked = 0, worst = 0;
    const Hit hit = sphereHit(camera, 0.8);
    for (int y = 0; y < kHeight; y += 7)
        for (int x = 0; x < kWidth; x += 7) {
            Eigen::Vector3d p, n;
            if (!hit(camera.rayDirection(x + 0.5, y + 0.5), p, n)) continue;
            const Eigen::Vector3d linear = expected(n);
            for (int ch = 0; ch < 3; ++ch)
                worst = std::max(worst, std::abs(int(picture[3 * (y * kWidth + x) + ch]) - int(rad::toSrgb8(linear[ch]))));
            ++checked;
        }
    std::printf("[ivg-gl] %s: %d pixels, max %d codes\n", what, checked, worst);
    EXPECT_GT(checked, 50);
    EXPECT_LE(worst, 2);
}

struct Plane {
    Eigen::Vector3d normal, u, v;  // orthonormal; the square |s|, |t| < half around the origin
    double half = 0.7;
};

Plane tiltedPlane() {
    Plane q;
    q.normal = Eigen::Vector3d(0.35, -0.45, 0.82).normalized();
    q.u = q.normal.cross(Eigen::Vector3d(0, 0, 1)).normalized();
    q.v = q.normal.cross(q.u);
    return q;
}

Hit planeHit(const rad::PinholeCamera& camera, const Plane& q, const Eigen::Vector3d& shadingNormal, double margin) {
    return [&camera, q, shadingNormal, margin](const Eigen::Vector3d& d, Eigen::Vector3d& p, Eigen::Vector3d& n) {
        const double denominator = q.normal.dot(d);
        if (std::fabs(denominator) < 1e-9) return false;
        const double t = -q.normal.dot(camera.center) / denominator;
        if (t <= 0) return false;
        p = camera.center + t * d;
        n = shadingNormal;
        return std::fabs(p.dot(q.u)) < q.half - margin && std::fabs(p.dot(q.v)) < q.half - margin;
    };
}

struct MeshData {
    std::vector<float> positions, normals, wedgeUv;
    std::vector<std::uint32_t> faces;
};

MeshData planeMesh(const Plane& q, const Eigen::Vector3d& vertexNormal) {
    MeshData m;
    const double s[4] = {-1, 1, 1, -1}, t[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p = q.half * (s[k] * q.u + t[k] * q.v);
        for (int a = 0; a < 3; ++a) {
            m.positions.push_back(float(p[a]));
            m.normals.push_back(float(vertexNormal[a]));
        }
    }
    m.faces = {0, 1, 2, 0, 2, 3};
    for (std::uint32_t v : m.faces) m.wedgeUv.insert(m.wedgeUv.end(), {float(0.5 * (s[v] + 1)), float(0.5 * (t[v] + 1))});
    return m;
}

MeshData sphereMesh(double radius) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(5, float(radius));
    MeshData m;
    m.positions = sphere.positions;
    m.normals = sphere.normals;
    m.faces = sphere.faces;
    m.wedgeUv.assign(2 * m.faces.size(), 0.5f);  // no normal map on the sphere: any UVs
    return m;
}

void upload(radgl::NormalMapGlRenderer& r, const MeshData& m) {
    ASSERT_EQ(r.setMesh(m.positions.data(), m.normals.data(), m.positions.size() / 3, m.faces.data(), m.faces.size() / 3,
                        m.wedgeUv.data()),
              "");
}

std::vector<std::uint8_t> render(radgl::NormalMapGlRenderer& r, NormalMapShading mode, const rad::PinholeCamera& camera,
                                 const radgl::NormalMapLighting& lighting, const rad::ToneMapping& tm = {}) {
    gl().beginFrame(camera, 0.05, 20.0);
    EXPECT_EQ(r.draw(mode, lighting, tm, camera.center), "");
    EXPECT_EQ(r.takeGlErrors(), "");
    return gl().readRgb();
}

radgl::NormalMapLighting indirectOnly(const Eigen::Vector3d& albedo) {
    radgl::NormalMapLighting l;
    l.indirect = IndirectLight::Indirect;
    l.albedo = albedo;
    l.specular.setZero();
    return l;
}

rad::PinholeCamera sphereCamera() {
    return rad::PinholeCamera::lookAt({1.3, 1.1, 2.2}, {0, 0, 0}, {0, 1, 0}, 40.0, kWidth, kHeight);
}

TEST(IrradianceGridGl, UniformSkyOnASphereMatchesTheCpuAndTheClosedForm) {
    radgl::NormalMapGlRenderer r(capabilities());
    ASSERT_EQ(r.shaderProblem(), "");
    const MeshData sphere = sphereMesh(0.8);
    upload(r, sphere);
    const Eigen::Vector3d L(0.9, 0.7, 0.5), rho(0.8, 0.6, 0.9);
    // rho as vertex colours (the decoration's albedo from the layer's colours).
    std::vector<float> colours;
    for (std::size_t v = 0; v < sphere.positions.size() / 3; ++v)
        for (int c = 0; c < 3; ++c) colours.push_back(float(rho[c]));
    ASSERT_EQ(r.setVertexColors(colours.data(), colours.size() / 3), "");
    const rad::IrradianceVectorGrid grid = gridFrom(uniformSky(L), {{3, 4, 2}});
    std::string note;
    ASSERT_EQ(r.setIrradianceGrid(grid, note), "");
    EXPECT_EQ(note, "");
    EXPECT_TRUE(r.hasIrradianceGrid());
    EXPECT_EQ(r.irradianceGridBytes(), grid.vertexCount() * 72);

    const rad::PinholeCamera camera = sphereCamera();
    const std::vector<std::uint8_t> picture = render(r, NormalMapShading::VertexNormals, camera, indirectOnly({0.1, 0.1, 0.1}));
    const Comparison c = compare(picture, camera, sphereHit(camera, 0.8), grid, rho);
    report("uniform sky, sphere", c);
    EXPECT_GT(c.pixels, 3000);
    EXPECT_LE(c.maxDiff, 2);
    EXPECT_LT(c.meanDiff, 0.5);

    // The closed form of the interpolation under a uniform sky: I_n = pi L sum_a n_a^2 sign(n_a) e_a,
    // so L_r = rho L (|n_x|^3 + |n_y|^3 + |n_z|^3): 1 along an axis, 1/sqrt(3) on a diagonal.
    expectClosedFormOnTheSphere(picture, camera, "uniform sky, sphere, closed form", [&](const Eigen::Vector3d& n) {
        const double sum = std::pow(std::fabs(n.x()), 3) + std::pow(std::fabs(n.y()), 3) + std::pow(std::fabs(n.z()), 3);
        return Eigen::Vector3d(rho.cwiseProduct(L) * sum);
    });
}

TEST(IrradianceGridGl, LinearFieldOnATiltedPlaneAndASphereMatchesTheCpu) {
    radgl::NormalMapGlRenderer r(capabilities());
    const rad::IrradianceVectorGrid grid = gridFrom(linearField(), {{4, 3, 5}});
    std::string note;
    ASSERT_EQ(r.setIrradianceGrid(grid, note), "");
    const Eigen::Vector3d rho(0.7, 0.5, 0.6);

    const Plane q = tiltedPlane();
    upload(r, planeMesh(q, q.normal));
    const rad::PinholeCamera planeCamera =
        rad::PinholeCamera::lookAt(2.2 * q.normal + Eigen::Vector3d(0.2, 0.1, 0.0), {0, 0, 0}, {0, 1, 0}, 45.0, kWidth, kHeight);
    const Comparison onPlane = compare(render(r, NormalMapShading::VertexNormals, planeCamera, indirectOnly(rho)), planeCamera,
                                       planeHit(planeCamera, q, q.normal, 0.01), grid, rho);
    report("linear field, tilted plane", onPlane);
    EXPECT_GT(onPlane.pixels, 5000);
    EXPECT_LE(onPlane.maxDiff, 2);
    EXPECT_LT(onPlane.meanDiff, 0.5);

    upload(r, sphereMesh(0.8));  // the grid stays
    const rad::PinholeCamera camera = sphereCamera();
    const Comparison onSphere = compare(render(r, NormalMapShading::VertexNormals, camera, indirectOnly(rho)), camera,
                                        sphereHit(camera, 0.8), grid, rho);
    report("linear field, sphere", onSphere);
    EXPECT_GT(onSphere.pixels, 3000);
    EXPECT_LE(onSphere.maxDiff, 2);
    EXPECT_LT(onSphere.meanDiff, 0.5);

    // The comparison sees the field: the same picture against a uniform grid differs a lot.
    const rad::IrradianceVectorGrid other = gridFrom(uniformSky({0.5, 0.5, 0.5}), {{2, 2, 2}});
    const Comparison wrong = compare(render(r, NormalMapShading::VertexNormals, camera, indirectOnly(rho)), camera,
                                     sphereHit(camera, 0.8), other, rho);
    EXPECT_GT(wrong.meanDiff, 10.0);
}

// The |n_a| directional weights: the shader against the CPU on the linear field, and exact (rho L
// everywhere) under a uniform sky.
TEST(IrradianceGridGl, AbsoluteWeightsMatchTheCpuAndAreExactUnderAUniformSky) {
    radgl::NormalMapGlRenderer r(capabilities());
    upload(r, sphereMesh(0.8));
    const rad::PinholeCamera camera = sphereCamera();
    const Eigen::Vector3d rho(0.7, 0.5, 0.6);
    radgl::NormalMapLighting lighting = indirectOnly(rho);
    lighting.gridAbsoluteWeights = true;
    std::string note;
    const rad::IrradianceVectorGrid field = gridFrom(linearField(), {{4, 3, 5}});
    ASSERT_EQ(r.setIrradianceGrid(field, note), "");
    const std::vector<std::uint8_t> picture = render(r, NormalMapShading::VertexNormals, camera, lighting);
    const Comparison c = compare(picture, camera, sphereHit(camera, 0.8), field, rho, {}, {}, rad::DirectionalWeights::Absolute);
    report("linear field, sphere, |n| weights", c);
    EXPECT_GT(c.pixels, 3000);
    EXPECT_LE(c.maxDiff, 2);
    EXPECT_LT(c.meanDiff, 0.5);
    // The same picture is not the paper's weights' picture.
    const Comparison paper = compare(picture, camera, sphereHit(camera, 0.8), field, rho);
    EXPECT_GT(paper.maxDiff, 5);

    const Eigen::Vector3d L(0.9, 0.7, 0.5);
    ASSERT_EQ(r.setIrradianceGrid(gridFrom(uniformSky(L), {{3, 4, 2}}), note), "");
    const std::vector<std::uint8_t> sky = render(r, NormalMapShading::VertexNormals, camera, lighting);
    expectClosedFormOnTheSphere(sky, camera, "uniform sky, sphere, |n| weights vs rho L",
                                [&](const Eigen::Vector3d&) { return Eigen::Vector3d(rho.cwiseProduct(L)); });
}

TEST(IrradianceGridGl, DirectPlusIndirectAddsTheLambertTermAndExposureApplies) {
    radgl::NormalMapGlRenderer r(capabilities());
    const rad::IrradianceVectorGrid grid = gridFrom(linearField(), {{4, 3, 5}});
    std::string note;
    ASSERT_EQ(r.setIrradianceGrid(grid, note), "");
    upload(r, sphereMesh(0.8));
    const Eigen::Vector3d rho(0.3, 0.25, 0.35);
    radgl::NormalMapLighting lighting = indirectOnly(rho);
    lighting.indirect = IndirectLight::DirectAndIndirect;
    lighting.lightDirection = Eigen::Vector3d(0.2, 0.9, 0.4).normalized();
    lighting.lightColor = Eigen::Vector3d(0.8, 0.7, 0.6);
    lighting.ambient = Eigen::Vector3d(0.05, 0.05, 0.05);
    rad::ToneMapping tm;
    tm.exposureStops = -0.5;
    tm.curve = rad::ToneCurve::Reinhard;
    const rad::PinholeCamera camera = sphereCamera();
    const auto direct = [&](const Eigen::Vector3d&, const Eigen::Vector3d& n) -> Eigen::Vector3d {
        const double ndl = std::max(0.0, n.dot(lighting.lightDirection));
        return lighting.ambient.cwiseProduct(rho) + lighting.lightColor.cwiseProduct(rho) * ndl;
    };
    const Comparison c =
        compare(render(r, NormalMapShading::VertexNormals, camera, lighting, tm), camera, sphereHit(camera, 0.8), grid, rho, direct, tm);
    report("direct + indirect, Reinhard, -0.5 stops, sphere", c);
    EXPECT_GT(c.pixels, 3000);
    EXPECT_LE(c.maxDiff, 2);
    EXPECT_LT(c.meanDiff, 0.5);
}

// Granier et al. 2007's point: the grid is evaluated with the normal of the normal map, not the
// mesh's. A flat quad (vertex normals +z) with a constant object-space map of another normal equals
// the CPU evaluation with the mapped normal, and differs from the one with the vertex normal.
TEST(IrradianceGridGl, NormalMapModeEvaluatesTheGridWithTheMappedNormal) {
    radgl::NormalMapGlRenderer r(capabilities());
    const rad::IrradianceVectorGrid grid = gridFrom(linearField(), {{4, 3, 5}});
    std::string note;
    ASSERT_EQ(r.setIrradianceGrid(grid, note), "");
    Plane q;
    q.normal = Eigen::Vector3d(0, 0, 1);
    q.u = Eigen::Vector3d(1, 0, 0);
    q.v = Eigen::Vector3d(0, 1, 0);
    upload(r, planeMesh(q, q.normal));
    const Eigen::Vector3d mapped = Eigen::Vector3d(-0.45, 0.3, 0.84).normalized();
    std::vector<float> map(32 * 32 * 3);
    for (std::size_t i = 0; i < map.size(); ++i) map[i] = float(mapped[i % 3]);
    ASSERT_EQ(r.setNormalMap(rad::buildNormalPyramid(map.data(), 32, 32), false), "");
    const Eigen::Vector3d rho(0.7, 0.6, 0.5);
    const rad::PinholeCamera camera = rad::PinholeCamera::lookAt({0.2, -0.3, 1.8}, {0, 0, 0}, {0, 1, 0}, 45.0, kWidth, kHeight);
    const std::vector<std::uint8_t> picture = render(r, NormalMapShading::NormalMap, camera, indirectOnly(rho));
    const Comparison withMap = compare(picture, camera, planeHit(camera, q, mapped, 0.01), grid, rho);
    report("linear field, normal map", withMap);
    EXPECT_GT(withMap.pixels, 5000);
    EXPECT_LE(withMap.maxDiff, 2);
    EXPECT_LT(withMap.meanDiff, 0.5);
    const Comparison withVertexNormal = compare(picture, camera, planeHit(camera, q, q.normal, 0.01), grid, rho);
    EXPECT_GT(withVertexNormal.meanDiff, 5.0);
}

// rho from a diffuse map (the bake's B_diffuse.png: 8-bit sRGB, decoded to linear by GL), which
// takes precedence over vertex colours: a map whose left half (u < 0.5) and right half have two
// colours, on a quad facing +z under a uniform sky, L = rho L_sky.
TEST(IrradianceGridGl, DiffuseMapGivesTheAlbedo) {
    radgl::NormalMapGlRenderer r(capabilities());
    const Eigen::Vector3d sky(0.9, 0.85, 0.8);
    const rad::IrradianceVectorGrid grid = gridFrom(uniformSky(sky), {{2, 2, 2}});
    std::string note;
    ASSERT_EQ(r.setIrradianceGrid(grid, note), "");
    Plane q;
    q.normal = Eigen::Vector3d(0, 0, 1);
    q.u = Eigen::Vector3d(1, 0, 0);
    q.v = Eigen::Vector3d(0, 1, 0);
    q.half = 0.5;
    const MeshData quad = planeMesh(q, q.normal);  // u = x + 0.5, v = y + 0.5
    upload(r, quad);
    std::vector<float> grey(12, 0.2f);
    ASSERT_EQ(r.setVertexColors(grey.data(), 4), "");
    const std::uint8_t left[3] = {200, 120, 60}, right[3] = {60, 140, 210};
    rad::Image8 map(64, 64);
    for (int row = 0; row < 64; ++row)
        for (int column = 0; column < 64; ++column)
            for (int c = 0; c < 3; ++c) map.pixel(column, row)[c] = column < 32 ? left[c] : right[c];
    ASSERT_EQ(r.setDiffuseMap(map), "");
    EXPECT_TRUE(r.hasDiffuseMap());
    const rad::PinholeCamera camera = rad::PinholeCamera::lookAt({0.1, 0.05, 1.5}, {0, 0, 0}, {0, 1, 0}, 45.0, kWidth, kHeight);
    const std::vector<std::uint8_t> picture = render(r, NormalMapShading::VertexNormals, camera, indirectOnly({0.5, 0.5, 0.5}));
    int maxDiff = 0, pixels = 0;
    const Hit hit = planeHit(camera, q, q.normal, 0.01);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            Eigen::Vector3d p, n;
            if (!hit(camera.rayDirection(x + 0.5, y + 0.5), p, n) || std::fabs(p.x()) < 0.04) continue;  // the colour edge
            const std::uint8_t* code = p.x() < 0 ? left : right;
            for (int c = 0; c < 3; ++c) {
                const double expected = rad::srgbToLinear(code[c]) * sky[c];
                maxDiff = std::max(maxDiff, std::abs(int(picture[3 * (y * kWidth + x) + c]) - int(rad::toSrgb8(expected))));
            }
            ++pixels;
        }
    std::printf("[ivg-gl] diffuse map: %d pixels, max %d codes\n", pixels, maxDiff);
    EXPECT_GT(pixels, 5000);
    EXPECT_LE(maxDiff, 2);
}

TEST(IrradianceGridGl, LimitsAreCheckedAndARefusedGridDrawsNothingExtra) {
    radgl::GlCapabilities caps = capabilities();
    EXPECT_GE(caps.max3dTextureSize, 256);          // GL 3.0 minimum
    EXPECT_GE(caps.maxFragmentTextureUnits, 16);    // GL 3.2 minimum
    std::printf("[ivg-gl] GL_MAX_3D_TEXTURE_SIZE %d, GL_MAX_TEXTURE_IMAGE_UNITS %d\n", caps.max3dTextureSize,
                caps.maxFragmentTextureUnits);
    EXPECT_EQ(radgl::irradianceGridTextureProblem(caps, {{9, 9, 9}}, 2), "");
    radgl::GlCapabilities small = caps;
    small.max3dTextureSize = 8;
    const std::string tooBig = radgl::irradianceGridTextureProblem(small, {{5, 9, 5}}, 2);
    EXPECT_NE(tooBig.find("3D texture size (8)"), std::string::npos) << tooBig;
    EXPECT_NE(tooBig.find("at most 7 cells"), std::string::npos) << tooBig;
    radgl::GlCapabilities fewUnits = caps;
    fewUnits.maxFragmentTextureUnits = 8;
    EXPECT_NE(radgl::irradianceGridTextureProblem(fewUnits, {{3, 3, 3}}, 3).find("15 fragment texture units"), std::string::npos);
    radgl::GlCapabilities old = caps;
    radgl::capGlVersion(old, 2, 1);
    EXPECT_NE(radgl::irradianceGridTextureProblem(old, {{3, 3, 3}}, 2), "");

    // A renderer whose GL cannot hold the grid refuses it; asking for indirect light then says why
    // and draws nothing; the direct light still draws.
    radgl::NormalMapGlRenderer r(small);
    ASSERT_EQ(r.shaderProblem(), "");
    upload(r, sphereMesh(0.8));
    std::string note;
    EXPECT_NE(r.setIrradianceGrid(gridFrom(uniformSky({1, 1, 1}), {{8, 2, 2}}), note), "");
    EXPECT_FALSE(r.hasIrradianceGrid());
    const rad::PinholeCamera camera = sphereCamera();
    gl().beginFrame(camera, 0.05, 20.0);
    EXPECT_EQ(r.draw(NormalMapShading::VertexNormals, indirectOnly({0.5, 0.5, 0.5}), {}, camera.center), "no irradiance vector grid");
    radgl::NormalMapLighting direct;
    EXPECT_EQ(r.draw(NormalMapShading::VertexNormals, direct, {}, camera.center), "");
    EXPECT_EQ(r.takeGlErrors(), "");
    // Bad vertex colours are refused.
    std::vector<float> three(9, 0.5f);
    EXPECT_NE(r.setVertexColors(three.data(), 3), "");
}

TEST(IrradianceGridGl, DrawRestoresTheThreeDimensionalTextureBindings) {
    radgl::NormalMapGlRenderer r(capabilities());
    upload(r, sphereMesh(0.5));
    std::string note;
    ASSERT_EQ(r.setIrradianceGrid(gridFrom(uniformSky({1, 1, 1}), {{2, 2, 2}}), note), "");
    GLuint mine = 0;
    glGenTextures(1, &mine);
    glActiveTexture(GL_TEXTURE5);
    glBindTexture(GL_TEXTURE_3D, mine);
    glActiveTexture(GL_TEXTURE0);
    const rad::PinholeCamera camera = sphereCamera();
    render(r, NormalMapShading::VertexNormals, camera, indirectOnly({0.5, 0.5, 0.5}));
    GLint bound = 0, active = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    glActiveTexture(GL_TEXTURE5);
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &bound);
    glActiveTexture(GL_TEXTURE0);
    EXPECT_EQ(active, GL_TEXTURE0);
    EXPECT_EQ(GLuint(bound), mine);
    glDeleteTextures(1, &mine);
}

}  // namespace
