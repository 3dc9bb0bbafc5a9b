// The normal-map renderer (render_gl/normal_map_gl_renderer.h) in a real OpenGL context (Mesa
// under Xvfb): a constant object-space map equals tilted vertex normals; a tangent-space map in a
// rotated and in a mirrored UV layout decodes to the same normal (vectors computed by hand in the
// frame of normal_baker.h); far away, LEAN mapping (Weber and Stamminger) is closer to a supersampled
// Blinn-Phong ground truth than the mip-mapped normal map; up close LEAN equals the normal map;
// a MikkTSpace bake of a torus decodes to the picture of its object-space bake; refusals, GL state
// restored, no GL error.
#include "normal_map_gl_renderer.h"
#include "gl_test_context.h"
#include "offscreen_gl.h"

#include "bake/lean_maps.h"
#include "bake/map_filling.h"
#include "bake/normal_baker.h"
#include "bake/texture_atlas.h"
#include "geometry/primitive_meshes.h"
#include "lod/pop_level.h"
#include "render/tone_mapping.h"

#include <GL/glew.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace {

using radgl::NormalMapShading;

using gltest::capabilities;
using gltest::gl;
using gltest::kHeight;
using gltest::kWidth;
const double kPi = 3.14159265358979323846;

// The unit quad [-0.5, 0.5]^2 at z = 0, facing +z, two faces; UVs given per corner (x, y) -> (u, v).
struct Quad {
    std::vector<float> positions{-0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0, -0.5f, 0.5f, 0};
    std::vector<float> normals;
    std::vector<std::uint32_t> faces{0, 1, 2, 0, 2, 3};
    std::vector<float> wedgeUv;
};

enum class UvLayout { Plain, Rotated90, Mirrored };

Quad makeQuad(const Eigen::Vector3d& vertexNormal, UvLayout layout) {
    Quad q;
    for (int v = 0; v < 4; ++v)
        for (int a = 0; a < 3; ++a) q.normals.push_back(static_cast<float>(vertexNormal[a]));
    for (std::uint32_t v : q.faces) {
        const float x = q.positions[3 * v] + 0.5f, y = q.positions[3 * v + 1] + 0.5f;  // in [0, 1]
        switch (layout) {
            case UvLayout::Plain: q.wedgeUv.insert(q.wedgeUv.end(), {x, y}); break;
            case UvLayout::Rotated90: q.wedgeUv.insert(q.wedgeUv.end(), {y, 1.0f - x}); break;  // u along +y, v along -x
            case UvLayout::Mirrored: q.wedgeUv.insert(q.wedgeUv.end(), {y, x}); break;          // u along +y, v along +x
        }
    }
    return q;
}

std::vector<rad::MipImage> constantPyramid(int size, const Eigen::Vector3d& n) {
    std::vector<float> data(static_cast<std::size_t>(size) * size * 3);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<float>(n[i % 3]);
    return rad::buildNormalPyramid(data.data(), size, size);
}

double rmse(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, const std::vector<char>* mask = nullptr,
            int* maxDiff = nullptr) {
    double sum = 0;
    int count = 0, worst = 0;
    for (std::size_t p = 0; p < a.size() / 3; ++p) {
        if (mask && !(*mask)[p]) continue;
        for (int c = 0; c < 3; ++c) {
            const int d = std::abs(int(a[3 * p + c]) - int(b[3 * p + c]));
            sum += double(d) * d;
            worst = std::max(worst, d);
        }
        ++count;
    }
    if (maxDiff) *maxDiff = worst;
    return count ? std::sqrt(sum / (3.0 * count)) : 1e9;
}

struct Scene {
    rad::PinholeCamera camera;
    radgl::NormalMapLighting lighting;
};

std::vector<std::uint8_t> render(radgl::NormalMapGlRenderer& r, NormalMapShading mode, const Scene& scene) {
    gl().beginFrame(scene.camera, 0.05, 20.0);
    EXPECT_EQ(r.draw(mode, scene.lighting, {}, scene.camera.center), "");
    EXPECT_EQ(r.takeGlErrors(), "");
    return gl().readRgb();
}

Scene closeScene() {
    Scene s;
    s.camera = rad::PinholeCamera::lookAt({0.3, -0.4, 1.6}, {0, 0, 0}, {0, 1, 0}, 45.0, kWidth, kHeight);
    s.lighting.lightDirection = Eigen::Vector3d(0.5, 0.3, 1.0);
    s.lighting.albedo = Eigen::Vector3d(0.5, 0.3, 0.2);
    s.lighting.specular = Eigen::Vector3d(0.5, 0.5, 0.5);
    s.lighting.shininess = 30.0;
    s.lighting.ambient = Eigen::Vector3d(0.1, 0.1, 0.1);
    return s;
}

// Pixels whose centre sees the quad well inside its border (the quad covers most of closeScene()).
std::vector<char> quadMask(const rad::PinholeCamera& camera, double margin) {
    std::vector<char> mask(kWidth * kHeight, 0);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const Eigen::Vector3d d = camera.rayDirection(x + 0.5, y + 0.5);
            if (d.z() >= 0) continue;
            const Eigen::Vector3d p = camera.center - camera.center.z() / d.z() * d;
            mask[y * kWidth + x] = std::fabs(p.x()) < 0.5 - margin && std::fabs(p.y()) < 0.5 - margin;
        }
    return mask;
}

const Eigen::Vector3d kTilted(std::sin(kPi / 6), 0.0, std::cos(kPi / 6));  // 30 degrees toward +x

TEST(NormalMapGl, ConstantObjectSpaceMapEqualsTiltedVertexNormals) {
    radgl::NormalMapGlRenderer r(capabilities());
    ASSERT_EQ(r.shaderProblem(), "");
    const Scene scene = closeScene();
    const std::vector<char> mask = quadMask(scene.camera, 0.02);
    ASSERT_GT(std::count(mask.begin(), mask.end(), 1), 8000);

    const Quad tilted = makeQuad(kTilted, UvLayout::Plain);
    ASSERT_EQ(r.setMesh(tilted.positions.data(), tilted.normals.data(), 4, tilted.faces.data(), 2, tilted.wedgeUv.data()), "");
    const std::vector<std::uint8_t> expected = render(r, NormalMapShading::VertexNormals, scene);

    const Quad flat = makeQuad({0, 0, 1}, UvLayout::Plain);
    ASSERT_EQ(r.setMesh(flat.positions.data(), flat.normals.data(), 4, flat.faces.data(), 2, flat.wedgeUv.data()), "");
    const std::vector<std::uint8_t> flatPicture = render(r, NormalMapShading::VertexNormals, scene);
    ASSERT_EQ(r.setNormalMap(constantPyramid(64, kTilted), false), "");
    int maxDiff = 0;
    const double e = rmse(render(r, NormalMapShading::NormalMap, scene), expected, &mask, &maxDiff);
    EXPECT_LT(e, 1.0) << "max " << maxDiff;
    EXPECT_LE(maxDiff, 3);
    EXPECT_GT(rmse(flatPicture, expected, &mask), 10.0);  // the tilt is visible: the comparison means something
}

// Tangent-space maps in the frame of normal_baker.h, N = (0, 0, 1):
//  - rotated UVs (u along +y, v along -x): T = (0, 1, 0), dP/du x dP/dv = +N so B = N x T = (-1, 0, 0);
//    n = (sin 30, 0, cos 30) is (n.T, n.B, n.N) = (0, -0.5, cos 30);
//  - mirrored UVs (u along +y, v along +x): dP/du x dP/dv = -N so B = -(N x T) = (1, 0, 0): (0, 0.5, cos 30).
TEST(NormalMapGl, TangentSpaceMapDecodesInTheBakersFrame) {
    radgl::NormalMapGlRenderer r(capabilities());
    const Scene scene = closeScene();
    const std::vector<char> mask = quadMask(scene.camera, 0.02);
    const Quad tilted = makeQuad(kTilted, UvLayout::Plain);
    r.setMesh(tilted.positions.data(), tilted.normals.data(), 4, tilted.faces.data(), 2, tilted.wedgeUv.data());
    const std::vector<std::uint8_t> expected = render(r, NormalMapShading::VertexNormals, scene);
    const double c30 = std::cos(kPi / 6);
    struct Case {
        UvLayout layout;
        Eigen::Vector3d tangentSpace;
        const char* name;
    };
    for (const Case& c : {Case{UvLayout::Rotated90, {0, -0.5, c30}, "rotated"}, Case{UvLayout::Mirrored, {0, 0.5, c30}, "mirrored"}}) {
        const Quad q = makeQuad({0, 0, 1}, c.layout);
        ASSERT_EQ(r.setMesh(q.positions.data(), q.normals.data(), 4, q.faces.data(), 2, q.wedgeUv.data()), "");
        ASSERT_EQ(r.setNormalMap(constantPyramid(64, c.tangentSpace), true), "");
        int maxDiff = 0;
        EXPECT_LT(rmse(render(r, NormalMapShading::NormalMap, scene), expected, &mask, &maxDiff), 1.0) << c.name << " max " << maxDiff;
        // The wrong handedness gives another picture.
        const Eigen::Vector3d wrong(c.tangentSpace.x(), -c.tangentSpace.y(), c.tangentSpace.z());
        ASSERT_EQ(r.setNormalMap(constantPyramid(64, wrong), true), "");
        EXPECT_GT(rmse(render(r, NormalMapShading::NormalMap, scene), expected, &mask), 5.0) << c.name;
    }
    // LEAN needs object-space normals.
    EXPECT_NE(r.setLeanMoments(std::vector<rad::MipImage>(6)), "");
    EXPECT_NE(r.draw(NormalMapShading::Lean, scene.lighting, {}, scene.camera.center), "");
    EXPECT_FALSE(r.hasLeanMoments());
}

// A torus layout with shared corners: u = major angle / 2 pi, v = minor angle / 2 pi per corner, a
// face crossing a seam taking u + 1 (or v + 1) at its low corners, everything scaled into
// [0.02, 0.98].
std::vector<float> torusUv(const rad::TriangleMesh& m, int majorSegments, int minorSegments) {
    std::vector<float> uv(6 * m.faceCount());
    for (std::size_t f = 0; f < m.faceCount(); ++f) {
        double u[3], v[3];
        for (int k = 0; k < 3; ++k) {
            const float* p = m.positions.data() + 3 * m.faces[3 * f + k];
            u[k] = std::atan2(p[1], p[0]) / (2 * kPi);
            if (u[k] < 0) u[k] += 1;
            v[k] = std::atan2(p[2], std::hypot(p[0], p[1]) - 1.0) / (2 * kPi);
            if (v[k] < 0) v[k] += 1;
        }
        for (double* w : {u, v}) {
            const double hi = std::max({w[0], w[1], w[2]});
            for (int k = 0; k < 3; ++k)
                if (hi - w[k] > 0.5) w[k] += 1;
        }
        for (int k = 0; k < 3; ++k) {
            uv[6 * f + 2 * k] = float(0.02 + 0.96 * u[k] / (1.0 + 1.0 / majorSegments));
            uv[6 * f + 2 * k + 1] = float(0.02 + 0.96 * v[k] / (1.0 + 1.0 / minorSegments));
        }
    }
    return uv;
}

TEST(NormalMapGl, MikkTSpaceMapShadesLikeTheObjectSpaceMapOfTheSameBake) {
    // A fine torus baked onto a coarse one (12 x 6 segments, so that vertex normals and per-face
    // frames differ by tens of degrees) with a seamed but shared UV layout, in object space and in
    // MikkTSpace tangent space (the baker's default). Decoded by the renderer with the mesh's own
    // MikkTSpace tangents, the tangent-space map gives the object-space map's picture; decoded in
    // the per-face frame, it does not.
    const rad::TriangleMesh source = rad::makeTorus(1.0f, 0.35f, 256, 128), target = rad::makeTorus(1.0f, 0.35f, 12, 6);
    const std::vector<float> uv = torusUv(target, 12, 6);
    const int size = 512;
    const auto bake = [&](rad::NormalSpace space) {
        rad::NormalBakeOptions options;
        options.width = options.height = size;
        options.space = space;
        rad::NormalBakeResult r = rad::bakeNormalMap(target, uv.data(), source, nullptr, options);
        rad::fillByPullPush(r.normals.data(), 3, size, size, r.valid, nullptr);
        rad::normalizeTexelVectors(r.normals.data(), r.normals.size() / 3);
        return rad::buildNormalPyramid(r.normals.data(), size, size);
    };
    radgl::NormalMapGlRenderer r(capabilities());
    ASSERT_EQ(r.setMesh(target.positions.data(), target.normals.data(), target.vertexCount(), target.faces.data(),
                        target.faceCount(), uv.data()),
              "");
    Scene scene = closeScene();
    scene.camera = rad::PinholeCamera::lookAt({0.9, -1.2, 1.1}, {0.6, 0, 0}, {0, 0, 1}, 45.0, kWidth, kHeight);
    ASSERT_EQ(r.setNormalMap(bake(rad::NormalSpace::Object), false), "");
    const std::vector<std::uint8_t> objectPicture = render(r, NormalMapShading::NormalMap, scene);
    const std::vector<rad::MipImage> tangentMap = bake(rad::NormalSpace::Tangent);
    ASSERT_EQ(r.setNormalMap(tangentMap, true, rad::TangentFrame::MikkTSpace), "");
    int maxDiff = 0;
    const double mikk = rmse(render(r, NormalMapShading::NormalMap, scene), objectPicture, nullptr, &maxDiff);
    ASSERT_EQ(r.setNormalMap(tangentMap, true, rad::TangentFrame::PerFaceUvDerivative), "");
    const double perFace = rmse(render(r, NormalMapShading::NormalMap, scene), objectPicture);
    std::printf("MikkTSpace map vs object-space map: rmse %.3f (max %d); decoded per face: %.3f\n", mikk, maxDiff, perFace);
    EXPECT_LT(mikk, 0.5);
    // Measured: 0.141 against 0.718 decoded per face.
    EXPECT_GT(perFace, 3 * mikk);
}

// The bumpy surface: slopes (a cos(2 pi u / P), a cos(2 pi v / P)) with a period P of 4 texels of
// a 512 x 512 map, n = normalize(-sx, -sy, 1); texels hold n at their centres.
constexpr int kBumpSize = 512;
constexpr double kBumpPeriodTexels = 4.0, kBumpSlope = 0.25;

Eigen::Vector3d bumpNormal(double u, double v) {
    const double w = 2 * kPi * kBumpSize / kBumpPeriodTexels;
    return Eigen::Vector3d(-kBumpSlope * std::cos(w * u), -kBumpSlope * std::cos(w * v), 1.0).normalized();
}

rad::LeanMaps bumpMaps() {
    std::vector<float> normals(kBumpSize * kBumpSize * 3), tangents(normals.size());
    for (int r = 0; r < kBumpSize; ++r)
        for (int c = 0; c < kBumpSize; ++c) {
            const Eigen::Vector3d n = bumpNormal((c + 0.5) / kBumpSize, 1.0 - (r + 0.5) / kBumpSize);
            const std::size_t i = (static_cast<std::size_t>(r) * kBumpSize + c) * 3;
            for (int a = 0; a < 3; ++a) normals[i + a] = static_cast<float>(n[a]);
            tangents[i] = 1.0f;  // dP/du = +x, orthogonal to the quad's normal
        }
    return rad::buildLeanMaps(normals.data(), tangents.data(), kBumpSize, kBumpSize);
}

// The scene's light is the mirror of the eye direction about the quad's normal at the quad centre,
// so that the highlight sits in the middle of the quad.
Scene bumpScene(const Eigen::Vector3d& eye) {
    Scene s;
    s.camera = rad::PinholeCamera::lookAt(eye, {0, 0, 0}, {0, 1, 0}, 45.0, kWidth, kHeight);
    s.lighting.lightDirection = Eigen::Vector3d(-eye.x(), -eye.y(), eye.z()).normalized();
    s.lighting.albedo = Eigen::Vector3d(0.1, 0.1, 0.1);
    s.lighting.specular = Eigen::Vector3d(0.8, 0.8, 0.8);
    s.lighting.shininess = 200.0;
    s.lighting.ambient = Eigen::Vector3d(0.2, 0.2, 0.2);
    return s;
}

// Linear Blinn-Phong radiance at a point of the quad with normal n (the lighting model of
// normal_map_gl_renderer.h, written out here).
double blinnPhong(const Scene& s, const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    const Eigen::Vector3d L = s.lighting.lightDirection.normalized();
    const Eigen::Vector3d V = (s.camera.center - p).normalized();
    const Eigen::Vector3d H = (L + V).normalized();
    const double ndl = n.dot(L), hn = n.dot(H);
    const double spec = (ndl > 0 && hn > 0) ? std::pow(hn, s.lighting.shininess) : 0.0;
    return s.lighting.ambient.x() * s.lighting.albedo.x() + s.lighting.albedo.x() * std::max(ndl, 0.0) + s.lighting.specular.x() * spec;
}

// Ground truth: the bumpy surface's Blinn-Phong radiance averaged over each pixel (16 x 16 jittered
// samples, each intersecting the quad's plane), tone-mapped once per pixel. mask: pixels whose
// every sample hits the quad, and those of their 8 neighbours too.
std::vector<std::uint8_t> supersampledTruth(const Scene& s, std::vector<char>& mask) {
    std::vector<std::uint8_t> out(kWidth * kHeight * 3, 0);
    std::vector<char> inside(kWidth * kHeight, 0);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const int n = 16;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            double sum = 0;
            bool all = true;
            for (int j = 0; j < n && all; ++j)
                for (int i = 0; i < n && all; ++i) {
                    const Eigen::Vector3d d = s.camera.rayDirection(x + (i + U(rng)) / n, y + (j + U(rng)) / n);
                    if (d.z() >= 0) {
                        all = false;
                        break;
                    }
                    const Eigen::Vector3d p = s.camera.center - s.camera.center.z() / d.z() * d;
                    if (std::fabs(p.x()) >= 0.5 || std::fabs(p.y()) >= 0.5) {
                        all = false;
                        break;
                    }
                    sum += blinnPhong(s, p, bumpNormal(p.x() + 0.5, p.y() + 0.5));
                }
            if (!all) continue;
            inside[y * kWidth + x] = 1;
            const double L = sum / (n * n);
            const std::uint8_t code = rad::toSrgb8(rad::toneMap({}, Eigen::Vector3d(L, L, L)).x());
            for (int c = 0; c < 3; ++c) out[(y * kWidth + x) * 3 + c] = code;
        }
    mask.assign(kWidth * kHeight, 0);
    for (int y = 1; y + 1 < kHeight; ++y)
        for (int x = 1; x + 1 < kWidth; ++x) {
            bool ok = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) ok = ok && inside[(y + dy) * kWidth + x + dx];
            mask[y * kWidth + x] = ok;
        }
    return out;
}

TEST(NormalMapGl, FarAwayLeanIsCloserToTheSupersampledTruthThanTheMipMappedNormalMap) {
    const rad::LeanMaps maps = bumpMaps();
    const Quad q = makeQuad({0, 0, 1}, UvLayout::Plain);
    radgl::NormalMapGlRenderer r(capabilities());
    ASSERT_EQ(r.setMesh(q.positions.data(), q.normals.data(), 4, q.faces.data(), 2, q.wedgeUv.data()), "");
    ASSERT_EQ(r.setNormalMap(maps.normals, false), "");
    ASSERT_EQ(r.setLeanMoments(maps.moments), "");
    const Scene scene = bumpScene({0.0, -1.2, 4.0});  // ~45 pixels across 512 texels: lambda ~ 3.5
    std::vector<char> mask;
    const std::vector<std::uint8_t> truth = supersampledTruth(scene, mask);
    const long pixels = std::count(mask.begin(), mask.end(), 1);
    ASSERT_GT(pixels, 1000);
    const std::vector<std::uint8_t> normalMap = render(r, NormalMapShading::NormalMap, scene);
    const std::vector<std::uint8_t> lean = render(r, NormalMapShading::Lean, scene);
    int maxMap = 0, maxLean = 0;
    const double errorMap = rmse(normalMap, truth, &mask, &maxMap);
    const double errorLean = rmse(lean, truth, &mask, &maxLean);
    auto mean = [&](const std::vector<std::uint8_t>& img) {
        double sum = 0;
        for (std::size_t p = 0; p < mask.size(); ++p)
            if (mask[p]) sum += img[3 * p];
        return sum / pixels;
    };
    std::printf("far bumpy quad, %ld pixels: RMSE vs supersampled truth: normal map %.2f (max %d), LEAN %.2f (max %d) levels; "
                "mean sRGB code: truth %.1f, normal map %.1f, LEAN %.1f\n",
                pixels, errorMap, maxMap, errorLean, maxLean, mean(truth), mean(normalMap), mean(lean));
    EXPECT_LT(errorLean, 0.5 * errorMap);
    EXPECT_GT(errorMap, 5.0);  // the mip-mapped map really loses the roughness here
}

// Aliasing on the level of detail: the far bumpy quad as a jittered 33 x 33 grid drawn at POP
// levels (Limper et al. 2013) with the texture-coordinate correction (Weber & Stamminger, Alg. 1;
// exact on this plane, so the level shows the same bumps): LEAN stays much closer to the
// supersampled truth than the mip-mapped normal map, as on the full quad.
TEST(NormalMapGl, FarAwayLeanOnAPopLevelIsCloserToTheSupersampledTruth) {
    const rad::LeanMaps maps = bumpMaps();
    const int n = 33;
    rad::TriangleMesh grid;
    std::vector<float> normals, uv;
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            grid.positions.insert(grid.positions.end(), {(i + (border ? 0 : jitter(rng))) / (n - 1) - 0.5f,
                                                         (j + (border ? 0 : jitter(rng))) / (n - 1) - 0.5f, 0.0f});
            normals.insert(normals.end(), {0, 0, 1});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const std::uint32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            grid.faces.insert(grid.faces.end(), {a, b, c, a, c, d});
        }
    for (std::uint32_t v : grid.faces) uv.insert(uv.end(), {grid.positions[3 * v] + 0.5f, grid.positions[3 * v + 1] + 0.5f});
    const rad::PopBuffer pop = rad::buildPopBuffer(grid);
    const rad::TexCoordDerivatives derivatives = rad::computeTexCoordDerivatives(grid, uv);
    radgl::NormalMapGlRenderer r(capabilities());
    ASSERT_EQ(r.setPopMesh(grid.positions.data(), normals.data(), grid.vertexCount(), grid.faces.data(),
                           grid.faceCount(), uv.data(), pop, &derivatives), "");
    ASSERT_EQ(r.setNormalMap(maps.normals, false), "");
    ASSERT_EQ(r.setLeanMoments(maps.moments), "");
    const Scene scene = bumpScene({0.0, -1.2, 4.0});
    std::vector<char> mask;
    const std::vector<std::uint8_t> truth = supersampledTruth(scene, mask);
    // Snapping pulls the border in by up to half a cell (level 3: a sixteenth of the quad): compare
    // inside what the level draws.
    for (int level : {3, 4, 6}) {
        ASSERT_EQ(r.setPopLevel(level, true), "");
        const std::vector<std::uint8_t> normalMap = render(r, NormalMapShading::NormalMap, scene);
        const std::vector<std::uint8_t> lean = render(r, NormalMapShading::Lean, scene);
        std::vector<char> drawn = mask;
        for (std::size_t p = 0; p < drawn.size(); ++p) drawn[p] = drawn[p] && (lean[3 * p] || lean[3 * p + 1] || lean[3 * p + 2]);
        const long pixels = std::count(drawn.begin(), drawn.end(), 1);
        ASSERT_GT(pixels, 1000) << "level " << level;
        int maxMap = 0, maxLean = 0;
        const double errorMap = rmse(normalMap, truth, &drawn, &maxMap);
        const double errorLean = rmse(lean, truth, &drawn, &maxLean);
        std::printf("far bumpy grid, POP level %d (%zu of %zu triangles), %ld pixels: RMSE vs supersampled truth: normal "
                    "map %.2f (max %d), LEAN %.2f (max %d) levels\n",
                    level, r.drawnFaceCount(), grid.faceCount(), pixels, errorMap, maxMap, errorLean, maxLean);
        EXPECT_LT(errorLean, 0.5 * errorMap) << "level " << level;
        EXPECT_GT(errorMap, 5.0) << "level " << level;
    }
}

TEST(NormalMapGl, UpCloseLeanEqualsTheNormalMap) {
    const rad::LeanMaps maps = bumpMaps();
    const Quad q = makeQuad({0, 0, 1}, UvLayout::Plain);
    radgl::NormalMapGlRenderer r(capabilities());
    r.setMesh(q.positions.data(), q.normals.data(), 4, q.faces.data(), 2, q.wedgeUv.data());
    ASSERT_EQ(r.setNormalMap(maps.normals, false), "");
    ASSERT_EQ(r.setLeanMoments(maps.moments), "");
    const Scene scene = bumpScene({0.02, -0.04, 0.15});  // a texel covers ~2.5 pixels: lambda ~ -1.3
    const std::vector<std::uint8_t> normalMap = render(r, NormalMapShading::NormalMap, scene);
    const std::vector<std::uint8_t> lean = render(r, NormalMapShading::Lean, scene);
    int maxDiff = 0;
    const double e = rmse(lean, normalMap, nullptr, &maxDiff);
    std::printf("up close: RMSE LEAN vs normal map %.3f (max %d) levels\n", e, maxDiff);
    EXPECT_LT(e, 1.0);
    EXPECT_LE(maxDiff, 6);  // exp(-s/2 tan^2) vs cos^s: at most 0.54 / s in linear units
    // The picture has bumps and highlights, so the comparison is not between two flat images.
    const auto [lo, hi] = std::minmax_element(normalMap.begin(), normalMap.end());
    EXPECT_GT(int(*hi) - int(*lo), 60);
}

// The POP-buffer mode (Limper et al. 2013; Weber & Stamminger Alg. 1 in the vertex shader) against
// the level evaluated on the CPU (lod/pop_level.h, tested on its own) and drawn as a plain mesh by
// the same renderer: a jittered, gently curved grid under a striped object-space normal map.
TEST(NormalMapGl, PopLevelInTheVertexShaderEqualsTheCpuEvaluatedLevel) {
    const int n = 25;
    rad::TriangleMesh mesh;
    std::vector<float> normals, uv;
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            const float x = (i + (border ? 0 : jitter(rng))) / (n - 1) - 0.5f;
            const float y = (j + (border ? 0 : jitter(rng))) / (n - 1) - 0.5f;
            mesh.positions.insert(mesh.positions.end(), {x, y, 0.1f * x * x});
            const Eigen::Vector3d nn = Eigen::Vector3d(-0.2 * x, 0, 1).normalized();
            normals.insert(normals.end(), {float(nn.x()), float(nn.y()), float(nn.z())});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const std::uint32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            mesh.faces.insert(mesh.faces.end(), {a, b, c, a, c, d});
        }
    for (std::uint32_t v : mesh.faces) uv.insert(uv.end(), {mesh.positions[3 * v] + 0.5f, mesh.positions[3 * v + 1] + 0.5f});
    const int size = 256;  // stripes of 32 texels along u, normals tilted by +-35 degrees about y
    std::vector<float> map(std::size_t(size) * size * 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double angle = ((x / 32) % 2 ? 35.0 : -35.0) * kPi / 180;
            float* t = &map[(std::size_t(y) * size + x) * 3];
            t[0] = float(std::sin(angle));
            t[1] = 0;
            t[2] = float(std::cos(angle));
        }
    const rad::PopBuffer pop = rad::buildPopBuffer(mesh);
    const rad::TexCoordDerivatives derivatives = rad::computeTexCoordDerivatives(mesh, uv);
    radgl::NormalMapGlRenderer gpu(capabilities()), reference(capabilities());
    ASSERT_EQ(gpu.setPopMesh(mesh.positions.data(), normals.data(), mesh.vertexCount(), mesh.faces.data(),
                             mesh.faceCount(), uv.data(), pop, &derivatives), "");
    ASSERT_EQ(gpu.setNormalMap(rad::buildNormalPyramid(map.data(), size, size), false), "");
    ASSERT_EQ(reference.setNormalMap(rad::buildNormalPyramid(map.data(), size, size), false), "");
    Scene scene = closeScene();
    scene.lighting.lightDirection = Eigen::Vector3d(0.8, 0.0, 0.6);
    for (int level : {3, 4, 5}) {
        std::vector<std::uint8_t> images[2];
        for (int correct = 0; correct < 2; ++correct) {
            ASSERT_EQ(gpu.setPopLevel(level, correct == 1), "");
            EXPECT_EQ(gpu.drawnFaceCount(), pop.levelEnd[level]);
            images[correct] = render(gpu, NormalMapShading::NormalMap, scene);

            rad::PopLevelRequest request;
            request.mesh = &mesh;
            request.pop = &pop;
            request.level = level;
            request.wedgeUv = &uv;
            request.correction = correct ? &derivatives : nullptr;
            const rad::PopLevelMesh lod = rad::evaluatePopLevel(request);
            std::vector<float> lodNormals;
            for (std::uint32_t s : lod.sourceVertex) lodNormals.insert(lodNormals.end(), &normals[3 * s], &normals[3 * s + 3]);
            ASSERT_EQ(reference.setMesh(lod.mesh.positions.data(), lodNormals.data(), lod.mesh.vertexCount(),
                                        lod.mesh.faces.data(), lod.mesh.faceCount(), lod.wedgeUv.data()), "");
            const std::vector<std::uint8_t> cpu = render(reference, NormalMapShading::NormalMap, scene);
            int worst = 0;
            const double error = rmse(images[correct], cpu, nullptr, &worst);
            std::size_t differing = 0;
            for (std::size_t i = 0; i < cpu.size(); ++i) differing += std::abs(int(cpu[i]) - int(images[correct][i])) > 8;
            std::printf("POP level %d %s: GPU vs CPU-evaluated level RMSE %.3f (max %d), %zu values differ by > 8\n", level,
                        correct ? "corrected" : "plain", error, worst, differing);
            EXPECT_LT(error, 0.5) << "level " << level << (correct ? " corrected" : " plain") << ", max " << worst;
            EXPECT_LT(double(differing) / cpu.size(), 0.002) << "level " << level;
        }
        // The correction changes the picture (the stripes stay where the full mesh has them).
        const double effect = rmse(images[0], images[1]);
        std::printf("POP level %d: plain vs corrected RMSE %.2f\n", level, effect);
        EXPECT_GT(effect, 3.0) << "level " << level;
    }
    ASSERT_EQ(gpu.setPopLevel(0, false), "");
    EXPECT_EQ(gpu.drawnFaceCount(), mesh.faceCount());
    EXPECT_NE(gpu.setPopLevel(17, false), "");
    EXPECT_NE(reference.setPopLevel(4, false), "");  // no POP buffer uploaded
}

// The erase pass under a coarser level: where the full mesh is visible its pixels take the
// background gradient and the far depth, so the same mesh drawn again is not hidden by itself.
TEST(NormalMapGl, EraseFullMeshPaintsTheBackgroundAndResetsTheDepth) {
    const Quad q = makeQuad(Eigen::Vector3d(0, 0, 1), UvLayout::Plain);
    radgl::NormalMapGlRenderer r(capabilities());
    ASSERT_EQ(r.setMesh(q.positions.data(), q.normals.data(), 4, q.faces.data(), 2, q.wedgeUv.data()), "");
    const Scene scene = closeScene();
    const std::vector<char> inside = quadMask(scene.camera, 0.05);
    gl().beginFrame(scene.camera, 0.05, 20.0);
    const std::vector<std::uint8_t> background = gl().readRgb();
    ASSERT_EQ(r.draw(NormalMapShading::VertexNormals, scene.lighting, {}, scene.camera.center), "");
    const std::vector<std::uint8_t> drawn = gl().readRgb();
    // Top and bottom green, so the gradient is a constant colour: (0, 255, 0).
    ASSERT_EQ(r.eraseFullMesh(Eigen::Vector3f(0, 1, 0), Eigen::Vector3f(0, 1, 0)), "");
    const std::vector<std::uint8_t> erased = gl().readRgb();
    ASSERT_EQ(r.draw(NormalMapShading::VertexNormals, scene.lighting, {}, scene.camera.center), "");
    const std::vector<std::uint8_t> again = gl().readRgb();
    EXPECT_EQ(r.takeGlErrors(), "");
    std::size_t insideCount = 0;
    for (std::size_t p = 0; p < inside.size(); ++p) {
        if (inside[p]) {
            ++insideCount;
            EXPECT_EQ(erased[3 * p], 0);
            EXPECT_EQ(erased[3 * p + 1], 255);
            EXPECT_EQ(erased[3 * p + 2], 0);
            for (int c = 0; c < 3; ++c) EXPECT_EQ(again[3 * p + c], drawn[3 * p + c]);  // depth was reset
        }
    }
    EXPECT_GT(insideCount, 1000u);
    // Outside the quad (well away from its border) nothing changed.
    const std::vector<char> near = quadMask(scene.camera, -0.05);
    for (std::size_t p = 0; p < near.size(); ++p)
        if (!near[p])
            for (int c = 0; c < 3; ++c) ASSERT_EQ(erased[3 * p + c], background[3 * p + c]) << p;
}

TEST(NormalMapGl, RestoresTheGlStateAndRefusesWhatItCannotDraw) {
    const Quad q = makeQuad({0, 0, 1}, UvLayout::Plain);
    {
        radgl::GlCapabilities caps = capabilities();
        radgl::capGlVersion(caps, 2, 1);
        radgl::NormalMapGlRenderer old(caps);
        EXPECT_NE(old.shaderProblem(), "");
        EXPECT_NE(old.setMesh(q.positions.data(), q.normals.data(), 4, q.faces.data(), 2, q.wedgeUv.data()), "");
        EXPECT_NE(old.draw(NormalMapShading::VertexNormals, {}, {}, {0, 0, 2}), "");
    }
    radgl::NormalMapGlRenderer r(capabilities());
    EXPECT_NE(r.draw(NormalMapShading::VertexNormals, {}, {}, {0, 0, 2}), "");  // no mesh
    const std::uint32_t badFaces[6] = {0, 1, 4, 0, 2, 3};
    EXPECT_THROW(r.setMesh(q.positions.data(), q.normals.data(), 4, badFaces, 2, q.wedgeUv.data()), radgl::GlRendererError);
    ASSERT_EQ(r.setMesh(q.positions.data(), q.normals.data(), 4, q.faces.data(), 2, q.wedgeUv.data()), "");
    EXPECT_NE(r.draw(NormalMapShading::NormalMap, {}, {}, {0, 0, 2}), "");  // no map
    std::vector<rad::MipImage> broken = constantPyramid(16, {0, 0, 1});
    broken.pop_back();
    EXPECT_NE(r.setNormalMap(broken, false), "");
    ASSERT_EQ(r.setNormalMap(constantPyramid(16, {0, 0, 1}), false), "");
    EXPECT_NE(r.draw(NormalMapShading::Lean, {}, {}, {0, 0, 2}), "");  // no moments
    std::vector<rad::MipImage> moments = constantPyramid(8, {0, 0, 0});
    moments.pop_back();  // 4 levels 8..1 for a 16 x 16 map: 8, 4, 2, 1
    moments.push_back(constantPyramid(1, {0, 0, 0})[0]);
    EXPECT_NE(r.setLeanMoments(std::vector<rad::MipImage>(moments.begin(), moments.end() - 1)), "");  // one level short
    ASSERT_EQ(r.setLeanMoments(moments), "");

    const Scene scene = closeScene();
    gl().beginFrame(scene.camera, 0.05, 20.0);
    GLuint buffer = 0, texture = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glGenTextures(1, &texture);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, texture);
    glActiveTexture(GL_TEXTURE3);
    glDepthFunc(GL_LESS);
    glEnable(GL_LIGHTING);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (NormalMapShading m : {NormalMapShading::VertexNormals, NormalMapShading::NormalMap, NormalMapShading::Lean})
        EXPECT_EQ(r.draw(m, scene.lighting, {}, scene.camera.center), "");
    ASSERT_EQ(r.setNormalMap(constantPyramid(16, {0, 0, 1}), false), "");  // uploads too
    GLint value = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &value);
    EXPECT_EQ(value, 0);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &value);
    EXPECT_EQ(value, static_cast<GLint>(buffer));
    glGetIntegerv(GL_ACTIVE_TEXTURE, &value);
    EXPECT_EQ(value, GL_TEXTURE3);
    glActiveTexture(GL_TEXTURE1);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &value);
    EXPECT_EQ(value, static_cast<GLint>(texture));
    glActiveTexture(GL_TEXTURE0);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &value);
    EXPECT_EQ(value, 0);
    glGetIntegerv(GL_DEPTH_FUNC, &value);
    EXPECT_EQ(value, GL_LESS);
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &value);
    EXPECT_EQ(value, 1);
    EXPECT_TRUE(glIsEnabled(GL_LIGHTING));
    EXPECT_FALSE(glIsEnabled(GL_POLYGON_OFFSET_FILL));
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    EXPECT_EQ(r.takeGlErrors(), "");
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &buffer);
    glDeleteTextures(1, &texture);
    glDisable(GL_LIGHTING);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

}  // namespace
