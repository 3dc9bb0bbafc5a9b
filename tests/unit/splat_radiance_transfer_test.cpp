// Splat radiance onto mesh vertices. The main test makes a splat scene from a KNOWN radiance function
// (our SH3, linear, varying over a sphere's surface): the splats' display-referred 3DGS coefficients
// are fitted by the test itself, with the reference implementation's SH (splat_test_support.h), to the
// sRGB-encoded known radiance seen from each direction, written as a 3DGS .ply by the test's own writer
// and read back; the transfer must then give back the known radiance within 3 8-bit levels on average
// (the target), both its mean colour and toward directions over each vertex's hemisphere.
// The other tests pin down the weighting rules: near, in front, size limit, counting, refusal.
#include "splats/splat_radiance_transfer.h"
#include "test_temporary_directory.h"

#include "geometry/primitive_meshes.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/spherical_harmonics.h"
#include "splats/gaussian_splat_ply.h"

#include "splat_test_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <filesystem>
#include <random>

namespace {

using splattest::RefSplat;

std::string tmp(const std::string& name) {
    std::filesystem::create_directories(RADIANCE_TEST_TMPDIR);
    return std::string(RADIANCE_TEST_TMPDIR) + "/splat_radiance_transfer_" + name;
}

// 8-bit sRGB code of a linear value, written from IEC 61966-2-1 here.
double srgbLevel(double linear) {
    const double c = std::min(1.0, std::max(0.0, linear));
    const double e = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    return std::round(255.0 * e);
}

// The known radiance: per channel, SH3 coefficients (our convention, global frame) that vary
// linearly over the surface: a(p) = base + slope * p.x. Positive everywhere on the sphere.
struct KnownField {
    double base[3][16], slope[3][16];
    explicit KnownField(unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        const double mean[3] = {0.45, 0.25, 0.12};  // linear radiance of an orange-ish surface
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 16; ++k) {
                const int l = k == 0 ? 0 : k < 4 ? 1 : k < 9 ? 2 : 3;
                base[c][k] = k == 0 ? mean[c] / 0.28209479177387814 : 0.35 * mean[c] * u(rng) / (l + 1);
                slope[c][k] = k == 0 ? 0.3 * mean[c] / 0.28209479177387814 : 0.05 * mean[c] * u(rng);
            }
    }
    Eigen::Vector3d operator()(const Eigen::Vector3d& p, const Eigen::Vector3d& w) const {
        double y[16];
        rad::evaluateSphericalHarmonics(3, w.x(), w.y(), w.z(), y);
        Eigen::Vector3d value = Eigen::Vector3d::Zero();
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 16; ++k) value[c] += (base[c][k] + slope[c][k] * p.x()) * y[k];
        return value;
    }
};

// Directions of a Fibonacci sphere (the test's own sampling).
std::vector<Eigen::Vector3d> fibonacciSphere(int count) {
    std::vector<Eigen::Vector3d> out;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - (i + 0.5) * 2.0 / count, r = std::sqrt(1.0 - z * z);
        out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
    return out;
}

// A quaternion (w x y z) of the rotation whose columns are (t, b, n).
Eigen::Vector4f quaternionOfFrame(const Eigen::Vector3d& t, const Eigen::Vector3d& b, const Eigen::Vector3d& n) {
    Eigen::Matrix3d r;
    r.col(0) = t;
    r.col(1) = b;
    r.col(2) = n;
    const Eigen::Quaterniond q(r);
    return Eigen::Vector4f(float(q.w()), float(q.x()), float(q.y()), float(q.z()));
}

// The splat scene of the known field on and near the unit sphere: flat splats tangent to the surface, their
// 3DGS coefficients fitted (least squares over 400 directions) so that the reference rasteriser's
// colour seen from direction w is the sRGB encoding of the known radiance toward w.
std::vector<RefSplat> splatsOfKnownField(const KnownField& field, int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> offset;
    const std::vector<Eigen::Vector3d> dirs = fibonacciSphere(400);
    // Design matrix: B(i, k) = Y3dgs_k(-w_i) (camera-to-splat direction is -w for a viewer toward w).
    Eigen::MatrixXd design(dirs.size(), 16);
    for (std::size_t i = 0; i < dirs.size(); ++i)
        for (int k = 0; k < 16; ++k) {
            std::vector<float> unit(16, 0.0f);
            unit[k] = 1.0f;
            design(i, k) = splattest::referenceEvalSh(3, unit, -dirs[i]);
        }
    const Eigen::MatrixXd solve = (design.transpose() * design).ldlt().solve(design.transpose());
    std::vector<RefSplat> splats(count);
    for (RefSplat& s : splats) {
        const Eigen::Vector3d n = radtest::randomUnit(rng);
        const Eigen::Vector3d t = n.unitOrthogonal(), b = n.cross(t);
        // On or near the surface: centres off the sphere by a normal offset of standard deviation
        // 0.005 (a tenth of the mesh's edge), as trained splats scatter about a surface.
        s.position = (n * (1.0 + 0.005 * offset(rng))).cast<float>();
        Eigen::MatrixXd display(dirs.size(), 3);
        for (std::size_t i = 0; i < dirs.size(); ++i) {
            const Eigen::Vector3d linear = field(n, dirs[i]);
            for (int c = 0; c < 3; ++c) {
                const double x = std::min(1.0, std::max(0.0, linear[c]));
                display(i, c) = (x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055) - 0.5;
            }
        }
        const Eigen::MatrixXd g = solve * display;
        for (int c = 0; c < 3; ++c) {
            s.sh[c].resize(16);
            for (int k = 0; k < 16; ++k) s.sh[c][k] = float(g(k, c));
        }
        s.opacityLogit = 2.0f;
        s.logScale = Eigen::Vector3f(std::log(0.02f), std::log(0.02f), std::log(0.002f));
        s.rotation = quaternionOfFrame(t, b, n);
    }
    return splats;
}

TEST(SplatRadianceTransfer, KnownRadianceComesBackWithinThreeLevels) {
    const KnownField field(7);
    const std::string path = tmp("known_field.ply");
    splattest::writeSplatPly(path, splatsOfKnownField(field, 4000, 3), 3);
    const rad::GaussianSplats splats = rad::readGaussianSplatPly(path);

    const rad::TriangleMesh sphere = rad::makeIcosphere(3);
    const rad::SplatTransferResult result =
        rad::transferSplatRadiance(sphere.positions, sphere.normals, sphere.faces, splats);
    ASSERT_EQ(result.verticesWithoutSplats, 0u);
    ASSERT_EQ(result.field.basis, (rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 3}));

    std::mt19937 rng(5);
    double meanError = 0.0, directionalError = 0.0, worstMean = 0.0;
    std::size_t directional = 0;
    const std::size_t n = sphere.vertexCount();
    for (std::size_t v = 0; v < n; ++v) {
        const Eigen::Vector3d p(sphere.positions[3 * v], sphere.positions[3 * v + 1], sphere.positions[3 * v + 2]);
        const Eigen::Vector3d normal = p.normalized();
        for (int c = 0; c < 3; ++c) {
            const double expected = radtest::bruteHemisphere(normal, 24, 48, [&](const Eigen::Vector3d& w) { return field(p, w)[c]; });
            const double error = std::fabs(srgbLevel(result.meanColor[3 * v + c]) - srgbLevel(expected));
            meanError += error / (3.0 * n);
            worstMean = std::max(worstMean, error);
        }
        for (int d = 0; d < 8; ++d) {
            Eigen::Vector3d w = radtest::randomUnit(rng);
            if (w.dot(normal) < 0.0) w = -w;
            const Eigen::Vector3d got = rad::evaluateRadiance(result.field, v, w), expected = field(p, w);
            for (int c = 0; c < 3; ++c) directionalError += std::fabs(srgbLevel(got[c]) - srgbLevel(expected[c]));
            directional += 3;
        }
    }
    directionalError /= double(directional);
    std::printf("known field: mean-colour error %.2f levels (worst %.0f), directional %.2f levels, %.1f splats per vertex\n",
                meanError, worstMean, directionalError,
                double(std::accumulate(result.splatCount.begin(), result.splatCount.end(), 0.0)) / n);
    // The target is 3 levels of mean colour. Measured: 0.16 (mean colour) and 0.16 (toward
    // directions); the same scene with the direction flip left out of the conversion (only the
    // Condon-Shortley phase undone) gives 2.75 and 6.47, so the directional bound is 1 level.
    EXPECT_LE(meanError, 3.0);
    EXPECT_LE(directionalError, 1.0);
}

// One splat of constant display colour (0.8, 0.5, 0.2), flat in the z = 0 plane, at `centre`.
RefSplat constantSplat(const Eigen::Vector3f& centre, float sigma = 0.1f) {
    RefSplat s;
    const float colour[3] = {0.8f, 0.5f, 0.2f};
    for (int c = 0; c < 3; ++c) s.sh[c] = {float((colour[c] - 0.5) / 0.28209479177387814)};
    s.position = centre;
    s.opacityLogit = 0.0f;
    s.logScale = Eigen::Vector3f(std::log(sigma), std::log(sigma), std::log(0.01f));
    return s;
}

rad::GaussianSplats readBack(const std::vector<RefSplat>& splats, const std::string& name) {
    const std::string path = tmp(name);
    splattest::writeSplatPly(path, splats, 0);
    return rad::readGaussianSplatPly(path);
}

// Two triangles in z = 0: vertices (0,0), (1,0), (1,1), (0,1), normals +z (optionally a fifth
// vertex in no face, far away).
struct Square {
    std::vector<float> positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    std::vector<std::uint32_t> faces = {0, 1, 2, 0, 2, 3};
    explicit Square(bool farVertex = false) {
        if (!farVertex) return;
        positions.insert(positions.end(), {5, 5, 0});
        normals.insert(normals.end(), {0, 0, 1});
    }
};
// Vertex 0's footprint: its edges seen from its two faces, 1 and sqrt 2 from each: h = (1 + sqrt 2) / 4.
const double kH0 = (1.0 + std::sqrt(2.0)) / 4.0;

TEST(SplatRadianceTransfer, ConstantSplatGivesItsDecodedColourAndFarVerticesAreCounted) {
    const Square square(true);
    const rad::SplatTransferResult r =
        rad::transferSplatRadiance(square.positions, square.normals, square.faces, readBack({constantSplat({0, 0, 0})}, "constant.ply"));
    const double expected[3] = {splattest::referenceSrgbDecode(0.8), splattest::referenceSrgbDecode(0.5),
                                splattest::referenceSrgbDecode(0.2)};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.meanColor[c], expected[c], 1e-4);
    EXPECT_EQ(r.splatCount[0], 1u);
    EXPECT_EQ(r.splatsUsed, 1u);
    // The far vertex (5, 5, 0) is beyond 3 sigma: no splat, black, counted.
    EXPECT_EQ(r.splatCount[4], 0u);
    EXPECT_EQ(r.meanColor[12], 0.0f);
    EXPECT_EQ(r.verticesWithoutSplats, 1u);
    // The weight is the opacity (sigmoid(0) = 0.5) at the splat's centre.
    EXPECT_NEAR(r.weightSum[0], 0.5, 1e-6);
}

TEST(SplatRadianceTransfer, WeightsAreOpacityTimesTheWidenedGaussian) {
    // Two splats at vertex 0's position and 0.3 away along x, different colours: the vertex colour is
    // their blend with weights o_i exp(-m_i^2 / 2), m^2 = d^2 / (sigma^2 + h^2) along x.
    const Square square;
    RefSplat a = constantSplat({0, 0, 0}), b = constantSplat({0.3f, 0, 0});
    b.sh[0] = {float((0.2 - 0.5) / 0.28209479177387814)};
    b.opacityLogit = 1.0f;
    const rad::SplatTransferResult r =
        rad::transferSplatRadiance(square.positions, square.normals, square.faces, readBack({a, b}, "blend.ply"));
    const double h = kH0;
    const double wa = 0.5, wb = 1.0 / (1.0 + std::exp(-1.0)) * std::exp(-0.5 * 0.09 / (0.01 + h * h));
    const double display = (wa * 0.8 + wb * 0.2) / (wa + wb);
    EXPECT_NEAR(r.meanColor[0], splattest::referenceSrgbDecode(display), 1e-4);
    EXPECT_NEAR(r.weightSum[0], wa + wb, 1e-5);
}

TEST(SplatRadianceTransfer, EachSplatIsClampedAtZeroBeforeTheBlend) {
    // Two equal splats at vertex 0: A shows 0.3 + 0.6 w_x (negative for w_x < -0.5, so the rasteriser
    // clamps it there), B a constant 0.7. The vertex's mean colour is the hemisphere mean of
    // decode(0.5 max(0, 0.3 + 0.6 w_x) + 0.35), computed here by brute force; without the clamp it
    // would be measurably different.
    const Square square;
    const double c0 = 0.28209479177387814, c1 = 0.4886025119029199;
    RefSplat a = constantSplat({0, 0, 0}), b = constantSplat({0, 0, 0});
    for (int c = 0; c < 3; ++c) {
        // 3DGS: value(d) = C0 g0 - C1 x_d g3 + ...; with d = -w, -C1 (-w_x) g3 = C1 w_x g3.
        a.sh[c] = {float(-0.2 / c0), 0.0f, 0.0f, float(0.6 / c1)};
        b.sh[c] = {float(0.2 / c0), 0.0f, 0.0f, 0.0f};
    }
    const std::string path = tmp("clamp.ply");
    splattest::writeSplatPly(path, {a, b}, 1);
    const rad::SplatTransferResult r =
        rad::transferSplatRadiance(square.positions, square.normals, square.faces, rad::readGaussianSplatPly(path));
    const Eigen::Vector3d n(0, 0, 1);
    const double clamped = radtest::bruteHemisphere(n, 64, 128, [](const Eigen::Vector3d& w) {
        return splattest::referenceSrgbDecode(0.5 * std::max(0.0, 0.3 + 0.6 * w.x()) + 0.35);
    });
    const double unclamped = radtest::bruteHemisphere(n, 64, 128, [](const Eigen::Vector3d& w) {
        return splattest::referenceSrgbDecode(0.5 * (0.3 + 0.6 * w.x()) + 0.35);
    });
    std::printf("clamp test: transferred %.5f, clamped %.5f, unclamped %.5f\n", r.meanColor[0], clamped, unclamped);
    EXPECT_NEAR(r.meanColor[0], clamped, 1e-3);
    EXPECT_GT(std::fabs(clamped - unclamped), 5e-3);
}

TEST(SplatRadianceTransfer, SplatsBehindTheSurfaceOrTooLargeAreLeftOut) {
    const Square square;
    // Below vertex 0's tangent plane by 2 footprints: behind; a huge splat: larger than 10 % of the
    // diagonal (sqrt 2); one in front at the same depth above: used.
    const double h = kH0;
    RefSplat behind = constantSplat({0, 0, float(-2.0 * h)});
    RefSplat huge = constantSplat({0.5f, 0.5f, 0}, 0.5f);
    const auto splats = readBack({behind, huge}, "behind.ply");
    EXPECT_THROW(rad::transferSplatRadiance(square.positions, square.normals, square.faces, splats), rad::SplatTransferError);
    RefSplat front = constantSplat({0, 0, float(2.0 * h)});
    const rad::SplatTransferResult r = rad::transferSplatRadiance(square.positions, square.normals, square.faces,
                                                                  readBack({behind, huge, front}, "front.ply"));
    EXPECT_EQ(r.splatsTooLarge, 1u);
    EXPECT_EQ(r.splatCount[0], 1u);
    EXPECT_EQ(r.splatsUsed, 1u);
}

TEST(SplatRadianceTransfer, RefusalSaysWhatToCheck) {
    const Square square;
    try {
        rad::transferSplatRadiance(square.positions, square.normals, square.faces,
                                   readBack({constantSplat({50, 50, 50})}, "far.ply"));
        FAIL() << "no refusal";
    } catch (const rad::SplatTransferError& e) {
        const std::string why = e.what();
        EXPECT_NE(why.find("no vertex of the mesh has a splat near it"), std::string::npos) << why;
        EXPECT_NE(why.find("1 far from the mesh's bounding box"), std::string::npos) << why;
        EXPECT_NE(why.find("same coordinate frame"), std::string::npos) << why;
    }
}

TEST(SplatRadianceTransfer, FootprintsAreHalfTheMeanEdge) {
    const Square square;
    const std::vector<double> h = rad::vertexFootprints(square.positions, square.faces);
    // Vertex 1 is in face 0 only, whose edges 0-1 and 1-2 have length 1: h = 0.5.
    EXPECT_NEAR(h[1], 0.5, 1e-12);
    EXPECT_NEAR(h[0], kH0, 1e-12);
    // No faces: 1e-3 of the diagonal.
    const std::vector<double> none = rad::vertexFootprints(square.positions, {});
    EXPECT_NEAR(none[3], 1e-3 * std::sqrt(2.0), 1e-12);
}

TEST(SplatRadianceTransfer, CancelStops) {
    const Square square;
    EXPECT_THROW(rad::transferSplatRadiance(square.positions, square.normals, square.faces,
                                            readBack({constantSplat({0, 0, 0})}, "cancel.ply"), {},
                                            [](double, const char*) { return false; }),
                 rad::OperationCancelled);
}

}  // namespace
