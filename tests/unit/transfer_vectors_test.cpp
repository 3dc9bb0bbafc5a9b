// Tests of prt/transfer_vectors.h (shadowed diffuse transfer, Sloan et al. 2002 sec. 5) against
// oracles that share nothing with the estimator but the SH basis itself:
//   - unoccluded points: the projection of max(0, n.w) / pi onto the SH, by a brute-force
//     (theta, phi) midpoint sum for n = +z, and in closed form by the Funk-Hecke theorem for any n
//     (t_lm = lambda_l / pi * Y_lm(n), lambda_l = 2 pi integral_0^1 x P_l(x) dx computed here by a
//     1-D sum with std::legendre): this checks the local frame and the SH rotation;
//   - a point on a floor next to a wall: the same brute-force sum of V max(0, n.w) Y_k / pi with V
//     decided by intersecting the ray with the wall rectangle analytically (no Embree);
//   - exact cases: band 0 carries no sampling error (Y_0 is constant), so constant unit lighting
//     gives exactly 1 on an unoccluded point; inside a closed box every ray is blocked: exactly 0.
// Tolerances are those of the quasi-Monte-Carlo estimate (the oracles are far more accurate); each
// test says where its number comes from.
#include "geometry/primitive_meshes.h"
#include "prt/transfer_vectors.h"
#include "radiance/spherical_harmonics.h"
#include "raycast/ray_scene.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kDegree = rad::kDefaultTransferDegree;
constexpr int kCount = (kDegree + 1) * (kDegree + 1);

std::vector<double> harmonics(const Eigen::Vector3d& w, int degree = kDegree) {
    std::vector<double> y((degree + 1) * (degree + 1));
    rad::evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), y.data());
    return y;
}

// (1/pi) integral over the hemisphere around n of V(w) (n.w) Y_k(w), every k at once: the
// midpoint rule in (theta, phi) with the sin(theta) weight, as radtest::bruteHemisphere (which
// sums one scalar; here one SH evaluation serves all k), in a frame built here.
template <typename Visible>
std::vector<double> bruteTransfer(const Eigen::Vector3d& n, int thetaSteps, int phiSteps, Visible visible) {
    const Eigen::Vector3d helper = std::fabs(n.x()) < 0.9 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 1, 0);
    const Eigen::Vector3d a = n.cross(helper).normalized(), b = n.cross(a);
    const double dt = 0.5 * kPi / thetaSteps, dp = 2 * kPi / phiSteps;
    std::vector<double> t(kCount, 0.0), y(kCount);
    for (int i = 0; i < thetaSteps; ++i) {
        const double theta = (i + 0.5) * dt, st = std::sin(theta), ct = std::cos(theta);
        for (int j = 0; j < phiSteps; ++j) {
            const double phi = (j + 0.5) * dp;
            const Eigen::Vector3d w = st * std::cos(phi) * a + st * std::sin(phi) * b + ct * n;
            if (!visible(w)) continue;
            rad::evaluateSphericalHarmonics(kDegree, w.x(), w.y(), w.z(), y.data());
            for (int k = 0; k < kCount; ++k) t[k] += ct * y[k] * st;
        }
    }
    for (double& v : t) v *= dt * dp / kPi;
    return t;
}

// Funk-Hecke eigenvalue of the clamped cosine: lambda_l = 2 pi integral_0^1 x P_l(x) dx
// (midpoint sum of a polynomial of degree l + 1: error ~1e-9 at 20000 steps).
double clampedCosineEigenvalue(int l) {
    const int steps = 20000;
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
        const double x = (i + 0.5) / steps;
        sum += x * std::legendre(l, x);
    }
    return 2.0 * kPi * sum / steps;
}

// t(n) of an unoccluded point in closed form (Funk-Hecke): lambda_l / pi * Y_lm(n).
std::vector<double> unoccludedTransfer(const Eigen::Vector3d& n) {
    const std::vector<double> y = harmonics(n);
    std::vector<double> t(kCount);
    for (int l = 0; l <= kDegree; ++l) {
        const double lambda = clampedCosineEigenvalue(l);
        for (int m = -l; m <= l; ++m) t[l * l + l + m] = lambda / kPi * y[l * l + l + m];
    }
    return t;
}

double maxDifference(const std::vector<float>& a, const std::vector<double>& b) {
    double worst = 0.0;
    for (std::size_t k = 0; k < b.size(); ++k) worst = std::max(worst, std::abs(double(a[k]) - b[k]));
    return worst;
}

// Radiance under a lighting with SH coefficients l: L = <t, l>.
double shade(const std::vector<float>& t, const std::vector<double>& lighting) {
    double sum = 0.0;
    for (std::size_t k = 0; k < lighting.size(); ++k) sum += t[k] * lighting[k];
    return sum;
}

// Constant unit lighting: 1 = sqrt(4 pi) Y_0, so l = (sqrt(4 pi), 0, ...).
std::vector<double> constantUnitLighting() {
    std::vector<double> l(kCount, 0.0);
    l[0] = std::sqrt(4.0 * kPi);
    return l;
}

// Appends the parallelogram corner, corner + u, corner + u + v, corner + v (two triangles).
void addRectangle(rad::TriangleMesh& m, const Eigen::Vector3f& corner, const Eigen::Vector3f& u, const Eigen::Vector3f& v) {
    const auto base = static_cast<std::uint32_t>(m.vertexCount());
    for (const Eigen::Vector3f& p : {corner, Eigen::Vector3f(corner + u), Eigen::Vector3f(corner + u + v),
                                     Eigen::Vector3f(corner + v)})
        m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
    m.faces.insert(m.faces.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

rad::RayScene sceneOf(const rad::TriangleMesh& m) {
    return rad::RayScene(m.positions.data(), m.vertexCount(), m.faces.data(), m.faceCount());
}

// The empty scene: every ray escapes.
const rad::RayScene& emptyScene() {
    static const rad::RayScene scene(nullptr, 0, nullptr, 0);
    return scene;
}

rad::TransferOptions optionsWith(int rays, int degree = kDegree) {
    rad::TransferOptions o;
    o.rayCount = rays;
    o.degree = degree;
    return o;
}

// The quasi-Monte-Carlo error of the estimate of an unoccluded point's t_k (smooth integrands:
// Y_k over the cosine-weighted hemisphere, |Y_k| <= 0.94 up to degree 5), largest |error| over the
// 36 coefficients, measured over 2000 random normals: worst 9.3e-3 (mean 7.6e-3) at 256 rays,
// 8.5e-4 at 4096 (it falls ~ N^-0.85, as QMC should, not N^-0.5 like random sampling). The
// tolerances leave ~1.6x room; a wrong frame, rotation or direction set costs O(0.1) (e.g. the
// band-1 coefficient of n = z is 2/3 * 0.4886 = 0.33).
constexpr double kSmoothTolerance256 = 1.5e-2;
constexpr double kSmoothTolerance4096 = 1.5e-3;

TEST(TransferVectors, UnoccludedPointOnAPlaneMatchesTheBruteForceClampedCosine) {
    rad::TriangleMesh floor;
    radtest::addGrid(floor, 5, -1.0f, 1.0f);
    const rad::RayScene scene = sceneOf(floor);
    const rad::TransferEstimator estimator(scene, 2.0f * std::sqrt(2.0f), optionsWith(256));
    ASSERT_EQ(estimator.coefficientCount(), kCount);
    const float position[3] = {0.1f, -0.2f, 0.0f}, normal[3] = {0, 0, 1};
    std::vector<float> t(kCount);
    estimator.computeAt(position, normal, t.data());

    const std::vector<double> expected =
        bruteTransfer(Eigen::Vector3d::UnitZ(), 200, 400, [](const Eigen::Vector3d&) { return true; });
    EXPECT_LT(maxDifference(t, expected), kSmoothTolerance256);
    // Band 0 is exact: every direction contributes the same Y_0 = 1 / (2 sqrt(pi)) (float rounding only).
    EXPECT_NEAR(t[0], 0.5 / std::sqrt(kPi), 1e-6);
    // The oracle itself: Y_0 on band 0 (to its midpoint-rule error), zonal for n = z.
    EXPECT_NEAR(expected[0], 0.5 / std::sqrt(kPi), 1e-5);
    EXPECT_NEAR(expected[1], 0.0, 1e-9);
}

TEST(TransferVectors, MoreRaysConvergeToTheBruteForceClampedCosine) {
    // A consistent estimator: with 16x the rays the error drops ~10x.
    const rad::TransferEstimator estimator(emptyScene(), 1.0f, optionsWith(4096));
    const float position[3] = {0, 0, 0}, normal[3] = {0, 0, 1};
    std::vector<float> t(kCount);
    estimator.computeAt(position, normal, t.data());
    const std::vector<double> expected =
        bruteTransfer(Eigen::Vector3d::UnitZ(), 200, 400, [](const Eigen::Vector3d&) { return true; });
    EXPECT_LT(maxDifference(t, expected), kSmoothTolerance4096);
}

TEST(TransferVectors, TiltedNormalsGiveTheRotatedClampedCosine) {
    const rad::TransferEstimator estimator(emptyScene(), 1.0f, optionsWith(256));
    std::mt19937 rng(5);
    std::vector<Eigen::Vector3d> normals = {Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ(),
                                            Eigen::Vector3d::UnitX(), Eigen::Vector3d(0.6, 0.8, 0.0),
                                            // Both sides of the frame's discontinuity at n.z = 0.
                                            Eigen::Vector3d(0.6, 0.8, 1e-4).normalized(),
                                            Eigen::Vector3d(0.6, 0.8, -1e-4).normalized(),
                                            // Next to -z, where Frisvad's frame would break down.
                                            Eigen::Vector3d(1e-4, -2e-4, -1.0).normalized()};
    for (int i = 0; i < 20; ++i) normals.push_back(radtest::randomUnit(rng));
    for (const Eigen::Vector3d& n : normals) {
        const float position[3] = {0, 0, 0};
        const float normal[3] = {float(n.x()), float(n.y()), float(n.z())};
        std::vector<float> t(kCount);
        estimator.computeAt(position, normal, t.data());
        EXPECT_LT(maxDifference(t, unoccludedTransfer(n)), kSmoothTolerance256) << n.transpose();
    }
    // The oracle agrees with the brute-force sum around a tilted normal too.
    const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
    const std::vector<double> closed = unoccludedTransfer(n);
    const std::vector<double> brute = bruteTransfer(n, 200, 400, [](const Eigen::Vector3d&) { return true; });
    for (int k = 0; k < kCount; ++k) EXPECT_NEAR(closed[k], brute[k], 1e-4) << k;
}

TEST(TransferVectors, ConstantUnitLightingGivesOneInTheOpenAndZeroInsideAClosedBox) {
    // Open: L = sqrt(4 pi) t_0 = sqrt(4 pi) Y_0 = 1 up to float rounding, whatever the normal.
    const rad::TransferEstimator open(emptyScene(), 1.0f, optionsWith(256));
    std::mt19937 rng(9);
    for (int i = 0; i < 10; ++i) {
        const Eigen::Vector3d n = radtest::randomUnit(rng);
        const float position[3] = {1, 2, 3}, normal[3] = {float(n.x()), float(n.y()), float(n.z())};
        std::vector<float> t(kCount);
        open.computeAt(position, normal, t.data());
        EXPECT_NEAR(shade(t, constantUnitLighting()), 1.0, 1e-5);
    }

    // Closed box [-1, 1]^3 (six faces, sharing their edges): every ray from inside is blocked.
    rad::TriangleMesh box;
    const Eigen::Vector3f c(-1, -1, -1);
    addRectangle(box, c, {2, 0, 0}, {0, 2, 0});
    addRectangle(box, {-1, -1, 1}, {2, 0, 0}, {0, 2, 0});
    addRectangle(box, c, {2, 0, 0}, {0, 0, 2});
    addRectangle(box, {-1, 1, -1}, {2, 0, 0}, {0, 0, 2});
    addRectangle(box, c, {0, 2, 0}, {0, 0, 2});
    addRectangle(box, {1, -1, -1}, {0, 2, 0}, {0, 0, 2});
    const rad::RayScene scene = sceneOf(box);
    const rad::TransferEstimator closed(scene, 2.0f * std::sqrt(3.0f), optionsWith(256));
    const float positions[3][3] = {{0.2f, -0.3f, -1.0f}, {0, 0, 0}, {0.9f, 0.9f, 0.9f}};
    const float normals[3][3] = {{0, 0, 1}, {0.3f, 0.4f, -0.5f}, {-1, -1, -1}};
    for (int i = 0; i < 3; ++i) {
        std::vector<float> t(kCount, 1.0f);
        closed.computeAt(positions[i], normals[i], t.data());
        for (int k = 0; k < kCount; ++k) EXPECT_EQ(t[k], 0.0f) << i << " " << k;
        EXPECT_EQ(shade(t, constantUnitLighting()), 0.0);
    }
    EXPECT_EQ(closed.raysCast(), 3u * 256u);
}

// A floor z = 0 and a wall: the rectangle x = kWallX, |y| <= kWallHalfWidth, 0 <= z <= kWallHeight.
constexpr float kWallX = 0.5f, kWallHalfWidth = 2.0f, kWallHeight = 1.5f;

rad::TriangleMesh floorAndWall() {
    rad::TriangleMesh m;
    radtest::addGrid(m, 9, -3.0f, 3.0f);
    addRectangle(m, {kWallX, -kWallHalfWidth, 0.0f}, {0, 2 * kWallHalfWidth, 0}, {0, 0, kWallHeight});
    return m;
}

// Whether the ray o + t w (t > 0) misses the wall, decided in closed form.
bool missesWall(const Eigen::Vector3d& o, const Eigen::Vector3d& w) {
    if (w.x() <= 0.0) return true;
    const double t = (kWallX - o.x()) / w.x();
    const Eigen::Vector3d p = o + t * w;
    return !(std::abs(p.y()) <= kWallHalfWidth && p.z() >= 0.0 && p.z() <= kWallHeight);
}

TEST(TransferVectors, PointNextToAWallMatchesTheQuadratureOfGeometricVisibility) {
    const rad::TriangleMesh mesh = floorAndWall();
    const rad::RayScene scene = sceneOf(mesh);
    const float diagonal = 6.0f * std::sqrt(2.0f);
    const float position[3] = {0.0f, 0.3f, 0.0f}, normal[3] = {0, 0, 1};
    const rad::TransferOptions defaults;
    // The ray origin of the estimator: lifted by the offset along n.
    const Eigen::Vector3d origin(position[0], position[1], position[2] + defaults.relativeRayOffset * diagonal);
    // 1000 x 2000 midpoint cells: the visibility edge makes the oracle's error O(cell size) ~ 1e-3
    // times the edge's share of the hemisphere, i.e. ~1e-4.
    const std::vector<double> expected =
        bruteTransfer(Eigen::Vector3d::UnitZ(), 1000, 2000, [&](const Eigen::Vector3d& w) { return missesWall(origin, w); });
    const std::vector<double> open = unoccludedTransfer(Eigen::Vector3d::UnitZ());
    // The wall matters: the occluded transfer is far from the open one (band 1 tilts away from it).
    double shift = 0.0;
    for (int k = 0; k < kCount; ++k) shift = std::max(shift, std::abs(expected[k] - open[k]));
    ASSERT_GT(shift, 0.1);

    // The QMC error with the wall's silhouette in the integrand, measured at 12 floor positions
    // around this one: at most 8.9e-3 at 256 rays and 9.7e-4 at 4096 (the oracle's own error, from
    // 1000x2000 vs 2000x4000 cells, is <= 1e-4). Tolerances 2e-2 and 2e-3: far under the 0.1+ that a
    // wrong visibility costs (e.g. missing the wall, asserted above).
    for (const auto& [rays, tolerance] : {std::pair<int, double>{256, 2e-2}, {4096, 2e-3}}) {
        const rad::TransferEstimator estimator(scene, diagonal, optionsWith(rays));
        std::vector<float> t(kCount);
        estimator.computeAt(position, normal, t.data());
        EXPECT_LT(maxDifference(t, expected), tolerance) << rays << " rays";
    }
}

TEST(TransferVectors, ResultsAreDeterministicAndIndependentOfTheThreadCount) {
    // A self-shadowing scene: a column on a plane, with its own normals.
    const rad::TriangleMesh mesh = rad::makeColumnOnPlane();
    const rad::RayScene scene = sceneOf(mesh);
    const rad::TransferEstimator estimator(scene, 3.0f, optionsWith(64, 4));
    const std::size_t n = mesh.vertexCount();
    std::vector<float> one, two, again;
    rad::computeTransferVectors(estimator, mesh.positions.data(), mesh.normals.data(), n, one, {}, 1);
    rad::computeTransferVectors(estimator, mesh.positions.data(), mesh.normals.data(), n, two, {}, 2);
    rad::computeTransferVectors(estimator, mesh.positions.data(), mesh.normals.data(), n, again, {}, 2);
    ASSERT_EQ(one.size(), n * 25);
    EXPECT_EQ(one, two);
    EXPECT_EQ(two, again);
    // And the same as one point at a time.
    std::vector<float> single(25);
    int shadowed = 0;
    for (std::size_t v = 0; v < n; ++v) {
        estimator.computeAt(mesh.positions.data() + 3 * v, mesh.normals.data() + 3 * v, single.data());
        for (int k = 0; k < 25; ++k) ASSERT_EQ(single[k], one[v * 25 + k]) << v << " " << k;
        // Band 0 = (visible fraction) Y_0: below Y_0 wherever something is in the way.
        shadowed += single[0] < 0.99f * 0.5f / std::sqrt(float(kPi));
    }
    EXPECT_GT(shadowed, 10);  // the scene does shadow itself (the ground around the column)
    EXPECT_EQ(estimator.raysCast(), 4u * n * 64u);
}

TEST(TransferVectors, ProgressComesFromTheCallingThreadAndFalseCancels) {
    const rad::TriangleMesh mesh = rad::makeIcosphere(4, 1.0f);  // 2562 vertices
    const rad::RayScene scene = sceneOf(mesh);
    const rad::TransferEstimator estimator(scene, 2.0f * std::sqrt(3.0f), optionsWith(16, 2));
    const std::size_t n = mesh.vertexCount();
    const std::thread::id caller = std::this_thread::get_id();
    std::vector<double> fractions;
    bool otherThread = false;
    std::vector<float> out;
    rad::computeTransferVectors(estimator, mesh.positions.data(), mesh.normals.data(), n, out,
                                [&](double f, const char*) {
                                    otherThread |= std::this_thread::get_id() != caller;
                                    fractions.push_back(f);
                                    return true;
                                },
                                2);
    EXPECT_FALSE(otherThread);
    ASSERT_GE(fractions.size(), 2u);
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
    for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);

    // Cancel at the first report after the start: the computation throws, and stops early. (With
    // one thread only: with two, a busy machine may starve the calling thread while the other one
    // finishes everything, which is legitimate.)
    for (int threads : {1, 2}) {
        const std::uint64_t before = estimator.raysCast();
        int calls = 0;
        EXPECT_THROW(rad::computeTransferVectors(estimator, mesh.positions.data(), mesh.normals.data(), n, out,
                                                 [&](double, const char*) { return ++calls < 2; }, threads),
                     rad::OperationCancelled);
        EXPECT_EQ(calls, 2);
        if (threads == 1) EXPECT_LT(estimator.raysCast() - before, n * 16 / 2);
    }

    // The progress of the options is the default; a throwing progress propagates (not terminate).
    rad::TransferOptions options = optionsWith(16, 2);
    options.progress = [](double f, const char*) { return f < 0.5; };
    const rad::TransferEstimator cancelling(scene, 2.0f * std::sqrt(3.0f), options);
    EXPECT_THROW(rad::computeTransferVectors(cancelling, mesh.positions.data(), mesh.normals.data(), n, out),
                 rad::OperationCancelled);
    EXPECT_THROW(rad::computeTransferVectors(estimator, mesh.positions.data(), mesh.normals.data(), n, out,
                                             [](double f, const char*) -> bool {
                                                 if (f > 0.0) throw std::runtime_error("from the callback");
                                                 return true;
                                             }),
                 std::runtime_error);
}

TEST(TransferVectors, ZeroOrNonFiniteNormalGivesZerosAndCastsNoRay) {
    const rad::TransferEstimator estimator(emptyScene(), 1.0f, optionsWith(256));
    const float position[3] = {0, 0, 0};
    const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
    const float bad[][3] = {{0, 0, 0}, {nan, 0, 1}, {0, inf, 0}};
    for (const auto& normal : bad) {
        std::vector<float> t(kCount, 7.0f);
        estimator.computeAt(position, normal, t.data());
        for (float v : t) EXPECT_EQ(v, 0.0f);
    }
    const float badPosition[3] = {nan, 0, 0}, up[3] = {0, 0, 1};
    std::vector<float> t(kCount, 7.0f);
    estimator.computeAt(badPosition, up, t.data());
    for (float v : t) EXPECT_EQ(v, 0.0f);
    EXPECT_EQ(estimator.raysCast(), 0u);

    // In a batch too, next to good points.
    const std::vector<float> positions = {0, 0, 0, 0, 0, 0};
    const std::vector<float> normals = {0, 0, 0, 0, 0, 1};
    std::vector<float> out;
    rad::computeTransferVectors(estimator, positions.data(), normals.data(), 2, out);
    for (int k = 0; k < kCount; ++k) EXPECT_EQ(out[k], 0.0f);
    EXPECT_GT(out[kCount], 0.2f);
    EXPECT_EQ(estimator.raysCast(), 256u);
}

TEST(TransferVectors, NormalsNeedNotBeUnit) {
    const rad::TransferEstimator estimator(emptyScene(), 1.0f, optionsWith(256));
    const float position[3] = {0, 0, 0};
    const float unit[3] = {0.48f, 0.6f, 0.64f}, longer[3] = {4.8f, 6.0f, 6.4f}, tiny[3] = {4.8e-20f, 6e-20f, 6.4e-20f};
    std::vector<float> a(kCount), b(kCount), c(kCount);
    estimator.computeAt(position, unit, a.data());
    estimator.computeAt(position, longer, b.data());
    estimator.computeAt(position, tiny, c.data());
    for (int k = 0; k < kCount; ++k) {
        EXPECT_NEAR(a[k], b[k], 1e-5) << k;
        EXPECT_NEAR(a[k], c[k], 1e-5) << k;
    }
}

TEST(TransferVectors, LocalDirectionsAreACosineWeightedHemisphereSet) {
    const int n = 1024;
    const rad::TransferEstimator estimator(emptyScene(), 1.0f, optionsWith(n));
    const float* d = estimator.localDirections();
    // Under the pdf cos / pi: E[z] = 2/3, E[z^2] = 1/2, E[x] = E[y] = E[xy] = 0, E[x^2] = 1/4.
    double z = 0, z2 = 0, x = 0, y = 0, x2 = 0;
    for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(d[3 * i] * d[3 * i] + d[3 * i + 1] * d[3 * i + 1] + d[3 * i + 2] * d[3 * i + 2], 1.0f, 1e-6f);
        EXPECT_GT(d[3 * i + 2], 0.0f);  // none on the horizon
        z += d[3 * i + 2];
        z2 += d[3 * i + 2] * d[3 * i + 2];
        x += d[3 * i];
        y += d[3 * i + 1];
        x2 += d[3 * i] * d[3 * i];
    }
    EXPECT_NEAR(z / n, 2.0 / 3.0, 2e-3);
    EXPECT_NEAR(z2 / n, 0.5, 2e-3);
    EXPECT_NEAR(x / n, 0.0, 2e-3);
    EXPECT_NEAR(y / n, 0.0, 2e-3);
    EXPECT_NEAR(x2 / n, 0.25, 2e-3);
    EXPECT_NEAR(estimator.rayOffset(), 1e-4f, 1e-9f);
}

TEST(TransferVectors, FrameIsRightHandedOrthonormalWithTheNormalThird) {
    std::mt19937 rng(3);
    std::vector<Eigen::Vector3d> normals = {Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ(),
                                            Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, -1, 0)};
    for (int i = 0; i < 100; ++i) normals.push_back(radtest::randomUnit(rng) * (0.1 + i));
    for (const Eigen::Vector3d& n : normals) {
        const float in[3] = {float(n.x()), float(n.y()), float(n.z())};
        rad::TransferFrame f;
        ASSERT_TRUE(rad::makeTransferFrame(in, f));
        const Eigen::Vector3d t(f.tangent[0], f.tangent[1], f.tangent[2]);
        const Eigen::Vector3d b(f.bitangent[0], f.bitangent[1], f.bitangent[2]);
        const Eigen::Vector3d m(f.normal[0], f.normal[1], f.normal[2]);
        EXPECT_LT((m - n.normalized()).norm(), 1e-6);
        EXPECT_NEAR(t.norm(), 1.0, 1e-6);
        EXPECT_NEAR(b.norm(), 1.0, 1e-6);
        EXPECT_NEAR(t.dot(b), 0.0, 1e-6);
        EXPECT_NEAR(t.dot(m), 0.0, 1e-6);
        EXPECT_LT((t.cross(b) - m).norm(), 1e-6);
    }
    rad::TransferFrame f;
    const float zero[3] = {0, 0, 0};
    EXPECT_FALSE(rad::makeTransferFrame(zero, f));
}

TEST(TransferVectors, MultiplyByAlbedoScalesEachChannel) {
    rad::TransferField field;
    field.degree = 1;  // 4 coefficients
    field.values = {1, 2, 3, 4, -1, 0.5f, 0, 2};
    const std::vector<float> albedo = {0.5f, 1.0f, 0.0f, 0.2f, 0.4f, 0.8f};
    const rad::TransferField rgb = rad::multiplyByAlbedo(field, albedo);
    EXPECT_EQ(rgb.channels, 3);
    EXPECT_EQ(rgb.degree, 1);
    ASSERT_EQ(rgb.vertexCount(), 2u);
    for (std::size_t v = 0; v < 2; ++v)
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 4; ++k)
                EXPECT_EQ(rgb.values[(v * 3 + c) * 4 + k], albedo[3 * v + c] * field.values[v * 4 + k]);
    EXPECT_THROW(rad::multiplyByAlbedo(field, {0.5f, 1.0f, 0.0f}), std::invalid_argument);
    EXPECT_THROW(rad::multiplyByAlbedo(rgb, std::vector<float>(6, 1.0f)), std::invalid_argument);
    rad::TransferField ragged = field;
    ragged.values.pop_back();
    EXPECT_THROW(rad::multiplyByAlbedo(ragged, albedo), std::invalid_argument);
}

TEST(TransferVectors, BadOptionsAreRefused) {
    const rad::RayScene& scene = emptyScene();
    EXPECT_THROW(rad::TransferEstimator(scene, 1.0f, optionsWith(0)), std::invalid_argument);
    EXPECT_THROW(rad::TransferEstimator(scene, 1.0f, optionsWith(16, -1)), std::invalid_argument);
    EXPECT_THROW(rad::TransferEstimator(scene, 1.0f, optionsWith(16, rad::kMaxHarmonicDegree + 1)),
                 std::invalid_argument);
    EXPECT_THROW(rad::TransferEstimator(scene, 0.0f, optionsWith(16)), std::invalid_argument);
    EXPECT_THROW(rad::TransferEstimator(scene, std::nanf(""), optionsWith(16)), std::invalid_argument);
    rad::TransferOptions o;
    o.relativeRayOffset = 0.0;
    EXPECT_THROW(rad::TransferEstimator(scene, 1.0f, o), std::invalid_argument);
    o = rad::TransferOptions();
    o.threads = -1;
    EXPECT_THROW(rad::TransferEstimator(scene, 1.0f, o), std::invalid_argument);
    // Ray counts that are not multiples of the 16-ray packet work (partial last packet).
    const rad::TransferEstimator odd(scene, 1.0f, optionsWith(17, 0));
    const float position[3] = {0, 0, 0}, normal[3] = {0, 0, 1};
    float t0 = 0.0f;
    odd.computeAt(position, normal, &t0);
    EXPECT_NEAR(t0, 0.5 / std::sqrt(kPi), 1e-6);
    EXPECT_EQ(odd.raysCast(), 17u);
}

}  // namespace
