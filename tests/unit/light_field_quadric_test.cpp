// Tests of light_field_quadric.h: the light-field error E_L + E_F of Vanhoey et al. 2010 (eq. 3-6) as a
// collapse metric.
#include "simplify/light_field_quadric.h"

#include "radiance/basis.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_field.h"
#include "radiance/radiance_frame.h"
#include "simplify/collapse_mesh.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::BasisKind;
using rad::BasisSpec;
using rad::LightFieldQuadricMetric;
using rad::RadianceField;

using radtest::randomUnit;

constexpr double kPi = 3.14159265358979323846;
const BasisSpec kPB4{BasisKind::HemisphericalPolynomial, 4};
const BasisSpec kSH4{BasisKind::SphericalHarmonics, 4};

// Two triangles (0, 1, 2) and (0, 2, 3) forming a square: the collapsed edge is (0, 1).
rad::CollapseMesh square() {
    const float p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::uint32_t f[] = {0, 1, 2, 0, 2, 3};
    return rad::CollapseMesh(p, 4, f, 2);
}

// n0 tilted by `degrees` about an axis orthogonal to it.
Vector3d tilted(const Vector3d& n0, double degrees, std::mt19937& rng) {
    const Vector3d axis = n0.cross(randomUnit(rng)).normalized();
    return Eigen::AngleAxisd(degrees * kPi / 180, axis) * n0;
}

// A 4-vertex field with random coefficients in [-1, 1]; vertex 1's normal is `degrees` away from
// vertex 0's, both with random tangents; vertices 2 and 3 copy vertex 0.
RadianceField pairField(const BasisSpec& basis, double degrees, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1, 1);
    RadianceField f(basis, 4);
    for (float& c : f.coefficients) c = u(rng);
    const Vector3d n0 = randomUnit(rng), n1 = tilted(n0, degrees, rng);
    rad::storeFrame(rad::frameFromNormalAndTangent(n0, randomUnit(rng)), f.frame(0));
    rad::storeFrame(rad::frameFromNormalAndTangent(n1, randomUnit(rng)), f.frame(1));
    for (std::size_t v = 2; v < 4; ++v) {
        std::copy(f.frame(0), f.frame(0) + 6, f.frame(v));
        std::copy(f.vertexCoefficients(0), f.vertexCoefficients(0) + f.coefficientsPerVertex(), f.vertexCoefficients(v));
    }
    return f;
}

std::vector<double> coefficientsOf(const RadianceField& f, std::size_t v) {
    return std::vector<double>(f.vertexCoefficients(v), f.vertexCoefficients(v) + f.coefficientsPerVertex());
}

// The plain RF of a vertex with plain-storage coefficients c, written independently of the unit
// (test_support's PB and SH evaluations, no border extension: only used inside the hemisphere).
Vector3d independentValue(const BasisSpec& basis, const std::vector<double>& c, const rad::Frame& frame,
                          const Vector3d& w) {
    return basis.usesLocalFrame() ? radtest::polynomialValue(basis, c, frame, w) : radtest::harmonicValue(basis, c, w);
}

// E_L of eq. 3 by brute force: the hemisphere midpoint grid of test_support around n_a, restricted to
// H_b by an indicator, times 2 pi (the helper normalises by 1/(2 pi)). `reflected`: compare
// L~(w) = L(R_n w) instead.
double bruteLightFieldError(const RadianceField& f, std::size_t a, std::size_t b, bool reflected, int steps) {
    const rad::Frame fa = rad::frameFromStored(f.frame(a)), fb = rad::frameFromStored(f.frame(b));
    const std::vector<double> ca = coefficientsOf(f, a), cb = coefficientsOf(f, b);
    const auto value = [&](const std::vector<double>& c, const rad::Frame& frame, const Vector3d& w) {
        const Vector3d d = reflected ? Vector3d(2 * frame.n.dot(w) * frame.n - w) : w;
        return independentValue(f.basis, c, frame, d);
    };
    return 2 * kPi * radtest::bruteHemisphere(fa.n, steps, 2 * steps, [&](const Vector3d& w) {
               if (fb.n.dot(w) < 0) return 0.0;
               return (value(ca, fa, w) - value(cb, fb, w)).squaredNorm();
           });
}

TEST(LightFieldQuadric, LuneRuleIntegratesTheLuneArea) {
    std::mt19937 rng(21);
    std::vector<Vector3d> dirs;
    std::vector<double> weights;
    for (double degrees : {0.0, 10.0, 90.0, 135.0, 179.0, 180.0}) {
        const Vector3d n1 = randomUnit(rng), n2 = tilted(n1, degrees, rng);
        rad::hemisphereIntersectionRule(n1, n2, 10, 12, dirs, weights);
        ASSERT_EQ(dirs.size(), 120u);
        double area = 0;
        for (std::size_t i = 0; i < dirs.size(); ++i) {
            area += weights[i];
            EXPECT_NEAR(dirs[i].norm(), 1.0, 1e-14);
            EXPECT_GE(dirs[i].dot(n1), -1e-12) << degrees;
            EXPECT_GE(dirs[i].dot(n2), -1e-12) << degrees;
        }
        EXPECT_NEAR(area, 2 * (kPi - degrees * kPi / 180), 1e-10) << degrees;
    }
}

TEST(LightFieldQuadric, OrientationErrorIsTwoAlphaEmaxSquared) {
    std::mt19937 rng(22);
    for (double degrees : {0.0, 5.0, 45.0, 90.0, 150.0, 180.0}) {
        const Vector3d n1 = randomUnit(rng), n2 = tilted(n1, degrees, rng);
        const double alpha = degrees * kPi / 180;
        // Independent measure of H1 \ H2 (the lune of lost viewpoints, fig. 8): brute-force area.
        const double lost = 2 * kPi * radtest::bruteHemisphere(n1, 400, 800, [&](const Vector3d& w) {
                                return n2.dot(w) < 0 ? 1.0 : 0.0;
                            });
        EXPECT_NEAR(lost, 2 * alpha, 2e-3) << degrees;
        for (double emax : {1.0, 0.5}) {
            // Eq. 4 per channel, summed over the three channels.
            EXPECT_NEAR(rad::orientationError(n1, n2, emax), 3 * 2 * alpha * emax * emax, 1e-12) << degrees;
            EXPECT_NEAR(rad::orientationError(n1, n2, emax), 3 * lost * emax * emax, 6e-3) << degrees;
        }
        EXPECT_NEAR(rad::normalAngle(n1, n2), alpha, 1e-12);
    }
}

TEST(LightFieldQuadric, HalfEdgeCostOfEqualFunctionsIsTheOrientationError) {
    // The same constant colour in both frames: E_L = 0, only E_F remains.
    std::mt19937 rng(23);
    const rad::CollapseMesh mesh = square();
    for (double degrees : {0.0, 30.0, 120.0}) {
        RadianceField f = pairField(kPB4, degrees, rng);
        std::fill(f.coefficients.begin(), f.coefficients.end(), 0.0f);
        for (std::size_t v = 0; v < 4; ++v)
            for (int c = 0; c < 3; ++c) f.channelCoefficients(v, c)[0] = 0.25f * (c + 1);
        rad::LightFieldQuadricOptions options;
        options.channelMaxDifference = 0.7;
        const LightFieldQuadricMetric metric(mesh, f, options);
        const Vector3d n0 = rad::frameFromStored(f.frame(0)).n, n1 = rad::frameFromStored(f.frame(1)).n;
        EXPECT_NEAR(metric.halfEdgeCost(0, 1), 2 * rad::normalAngle(n0, n1) * 3 * 0.49, 1e-12) << degrees;
    }
}

TEST(LightFieldQuadric, MaximalColourDifferenceCostsTwoPiPerChannelAtAnyAngle) {
    // Vanhoey et al. 2010 sec. 4.2.3-4.4: E_L + E_F is continuous in alpha and bounded by 2 pi (per channel,
    // E_max = 1). A black RF against a white one reaches the bound whatever the angle.
    std::mt19937 rng(24);
    const rad::CollapseMesh mesh = square();
    for (double degrees : {0.0, 20.0, 90.0, 170.0, 180.0}) {
        RadianceField f = pairField(kPB4, degrees, rng);
        std::fill(f.coefficients.begin(), f.coefficients.end(), 0.0f);
        for (int c = 0; c < 3; ++c) f.channelCoefficients(1, c)[0] = 1.0f;
        const LightFieldQuadricMetric metric(mesh, f);
        EXPECT_NEAR(metric.halfEdgeCost(0, 1), 3 * 2 * kPi, 1e-9) << degrees;
        EXPECT_NEAR(metric.halfEdgeCost(1, 0), 3 * 2 * kPi, 1e-9) << degrees;
    }
}

TEST(LightFieldQuadric, LightFieldErrorMatchesABruteForceIntegral) {
    std::mt19937 rng(25);
    for (const BasisSpec& basis : {kPB4, kSH4}) {
        for (double degrees : {0.0, 40.0, 100.0, 160.0}) {
            RadianceField f = pairField(basis, degrees, rng);
            const rad::VertexRadiance a = rad::vertexRadiance(f, 0), b = rad::vertexRadiance(f, 1);
            for (bool reflected : {false, true}) {
                // The indicator of H_b limits the grid to ~1e-4 (worst measured 4.5e-4 at 300 steps);
                // the lune rule itself is exact to ~1e-10 here.
                const double brute = bruteLightFieldError(f, 0, 1, reflected, 300);
                const double rule = rad::lightFieldError(a, b, 16, 16, reflected);
                EXPECT_NEAR(rule, brute, 1e-3 * brute) << basis.name() << " " << degrees << " reflected " << reflected;
                // Symmetric, and what the metric charges for a half-edge collapse.
                EXPECT_NEAR(rad::lightFieldError(b, a, 16, 16, reflected), rule, 1e-10 * rule);
            }
            const LightFieldQuadricMetric metric(square(), f);
            EXPECT_NEAR(metric.halfEdgeCost(0, 1),
                        rad::lightFieldError(b, a, 16, 16) + rad::orientationError(a.frame.n, b.frame.n), 1e-9);
        }
    }
}

TEST(LightFieldQuadric, IdenticalFunctionsAndNormalsCostNothing) {
    std::mt19937 rng(26);
    const rad::CollapseMesh mesh = square();
    for (const BasisSpec& basis : {kPB4, kSH4}) {
        RadianceField f = pairField(basis, 0.0, rng);
        // Vertex 1 = vertex 0 (same coefficients, same frame).
        std::copy(f.frame(0), f.frame(0) + 6, f.frame(1));
        std::copy(f.vertexCoefficients(0), f.vertexCoefficients(0) + f.coefficientsPerVertex(), f.vertexCoefficients(1));
        const LightFieldQuadricMetric metric(mesh, f);
        EXPECT_EQ(metric.halfEdgeCost(0, 1), 0.0) << basis.name();
        double cost = -1;
        const std::uint32_t target = 1;
        rad::HalfEdgeQuery q;
        q.source = 0;
        q.targets = &target;
        q.targetCount = 1;
        metric.priceHalfEdges(mesh, q, &cost);
        EXPECT_EQ(cost, 0.0);
        // Full collapse: the new frame has another tangent (frameFromNormal), yet the optimum
        // reproduces the function and costs (almost) nothing: the ridge's bias only.
        const rad::LightFieldCollapse c = metric.optimalCollapse(0, 1, 0.5);
        EXPECT_LT(c.cost(), 1e-9) << basis.name();
        const rad::VertexRadianceD optimum{basis, c.coefficients.data(), c.frame, false};
        double scratch[rad::kMaxCoefficientsPerChannel];
        for (int k = 0; k < 20; ++k) {
            Vector3d w = randomUnit(rng);
            if (w.dot(c.frame.n) < 0) w = -w;
            EXPECT_LT((rad::evaluateRadiance(optimum, w, scratch) - rad::evaluateRadiance(f, 0, w)).norm(), 1e-5);
        }
    }
}

TEST(LightFieldQuadric, OptimumBeatsEndpointsAndPerturbations) {
    std::mt19937 rng(27);
    const rad::CollapseMesh mesh = square();
    std::normal_distribution<double> g;
    for (const BasisSpec& basis : {kPB4, kSH4}) {
        for (double degrees : {0.0, 50.0, 120.0}) {
            RadianceField f = pairField(basis, degrees, rng);
            const LightFieldQuadricMetric metric(mesh, f);
            for (double s : {0.3, 0.5}) {
                const rad::LightFieldCollapse c = metric.optimalCollapse(0, 1, s);
                const rad::VertexRadianceD optimum{basis, c.coefficients.data(), c.frame, false};
                EXPECT_NEAR(metric.collapseCost(0, 1, optimum), c.cost(), 1e-9 * c.cost());
                rad::EdgeQuery query;
                query.v0 = 0;
                query.v1 = 1;
                query.s = s;
                EXPECT_NEAR(metric.priceEdge(mesh, query), c.cost(), 1e-12 * c.cost());
                // Eq. 4 for both endpoints: slerp splits alpha.
                const Vector3d n0 = rad::frameFromStored(f.frame(0)).n, n1 = rad::frameFromStored(f.frame(1)).n;
                EXPECT_NEAR(c.orientationError, rad::orientationError(n0, n1), 1e-9);
                // Small perturbations of the coefficients cost more.
                for (int k = 0; k < 10; ++k) {
                    std::vector<double> perturbed = c.coefficients;
                    for (double& x : perturbed) x += 1e-3 * g(rng);
                    const rad::VertexRadianceD p{basis, perturbed.data(), c.frame, false};
                    EXPECT_GT(metric.collapseCost(0, 1, p), c.cost()) << basis.name() << " " << degrees;
                }
                // Any other coefficients in the same frame cost more: each endpoint's coefficients
                // (for SH the very same functions, which are global).
                for (std::size_t v : {0u, 1u}) {
                    const std::vector<double> ends = coefficientsOf(f, v);
                    const rad::VertexRadianceD e{basis, ends.data(), c.frame, false};
                    EXPECT_GT(metric.collapseCost(0, 1, e), c.cost());
                    // And so do the endpoints themselves, the half-collapse alternatives (sec. 4.3.1).
                    EXPECT_GT(metric.collapseCost(0, 1, rad::vertexRadiance(f, v)), c.cost());
                }
            }
        }
    }
}

TEST(LightFieldQuadric, FullCollapseWritesCoefficientsAndFrame) {
    std::mt19937 rng(28);
    for (const BasisSpec& basis : {kPB4, kSH4}) {
        rad::CollapseMesh mesh = square();
        RadianceField f = pairField(basis, 60.0, rng);
        const RadianceField before = f;
        LightFieldQuadricMetric metric(mesh, f);
        const double s = 0.3;
        const rad::LightFieldCollapse c = metric.optimalCollapse(0, 1, s);
        const Vector3d n0 = rad::frameFromStored(f.frame(0)).n, n1 = rad::frameFromStored(f.frame(1)).n;
        // slerp: in the plane of n0, n1 at s alpha from n0.
        EXPECT_NEAR(rad::normalAngle(c.frame.n, n0), s * rad::normalAngle(n0, n1), 1e-12);
        EXPECT_NEAR(rad::normalAngle(c.frame.n, n1), (1 - s) * rad::normalAngle(n0, n1), 1e-12);

        // Half-edge: priced as v0 -> v1 by priceEdge too, and leaves the field alone.
        rad::EdgeQuery half;
        half.halfEdge = true;
        half.v0 = 0;
        half.v1 = 1;
        half.s = 1.0;
        half.position = mesh.position(1);
        EXPECT_EQ(metric.priceEdge(mesh, half), metric.halfEdgeCost(0, 1));
        half.v0 = 2;
        half.v1 = 3;
        half.position = mesh.position(3);
        metric.onCollapse(mesh, half);
        EXPECT_EQ(f.coefficients, before.coefficients);
        EXPECT_EQ(f.frames, before.frames);

        rad::EdgeQuery query;
        query.v0 = 0;
        query.v1 = 1;
        query.s = s;
        query.position = (1 - s) * mesh.position(0) + s * mesh.position(1);
        mesh.setPosition(1, query.position);
        mesh.collapse(0, 1);
        metric.onCollapse(mesh, query);
        const rad::Frame written = rad::frameFromStored(f.frame(1));
        EXPECT_LT((written.n - c.frame.n).norm(), 1e-6);
        EXPECT_LT((written.t - c.frame.t).norm(), 1e-6);
        for (int k = 0; k < f.coefficientsPerVertex(); ++k)
            EXPECT_EQ(f.vertexCoefficients(1)[k], static_cast<float>(c.coefficients[k])) << k;
        // Vertex 0 and the others are untouched.
        EXPECT_TRUE(std::equal(f.vertexCoefficients(0), f.vertexCoefficients(0) + f.coefficientsPerVertex(),
                               before.vertexCoefficients(0)));
        EXPECT_EQ(f.validate(), "");
    }
}

TEST(LightFieldQuadric, ReflectedStorageYieldsTheSameFunctions) {
    // The same RF stored plain or reflected: same costs, and the new vertex is the same function.
    std::mt19937 rng(29);
    for (const BasisSpec& basis : {kPB4, kSH4}) {
        RadianceField plain = pairField(basis, 45.0, rng);
        RadianceField reflected = plain;
        rad::setReflectedStorage(reflected, true);
        const LightFieldQuadricMetric a(square(), plain), b(square(), reflected);
        EXPECT_NEAR(a.halfEdgeCost(0, 1), b.halfEdgeCost(0, 1), 1e-5 * a.halfEdgeCost(0, 1));
        const rad::LightFieldCollapse ca = a.optimalCollapse(0, 1, 0.6), cb = b.optimalCollapse(0, 1, 0.6);
        EXPECT_NEAR(ca.cost(), cb.cost(), 1e-5 * ca.cost());
        const rad::VertexRadianceD fa{basis, ca.coefficients.data(), ca.frame, false};
        const rad::VertexRadianceD fb{basis, cb.coefficients.data(), cb.frame, true};
        double scratch[rad::kMaxCoefficientsPerChannel];
        for (int k = 0; k < 20; ++k) {
            Vector3d w = randomUnit(rng);
            if (w.dot(ca.frame.n) < 0) w = -w;
            EXPECT_LT((rad::evaluateRadiance(fa, w, scratch) - rad::evaluateRadiance(fb, w, scratch)).norm(), 1e-4);
        }
    }
}

TEST(LightFieldQuadric, ConcurrentPricingMatchesSerial) {
    std::mt19937 rng(30);
    const rad::CollapseMesh mesh = square();
    RadianceField f = pairField(kSH4, 70.0, rng);
    const LightFieldQuadricMetric metric(mesh, f);
    const double half = metric.halfEdgeCost(0, 1);
    rad::EdgeQuery query;
    query.v0 = 0;
    query.v1 = 1;
    query.s = 0.4;
    const double full = metric.priceEdge(mesh, query);
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int i = 0; i < 50; ++i) {
                if (metric.halfEdgeCost(0, 1) != half) ++mismatches[t];
                if (metric.priceEdge(mesh, query) != full) ++mismatches[t];
            }
        });
    for (std::thread& t : threads) t.join();
    for (int m : mismatches) EXPECT_EQ(m, 0);
}

TEST(LightFieldQuadric, RejectsInconsistentInput) {
    std::mt19937 rng(31);
    const rad::CollapseMesh mesh = square();
    RadianceField f = pairField(kPB4, 10.0, rng);
    RadianceField small(kPB4, 3);
    EXPECT_THROW(LightFieldQuadricMetric(mesh, small), std::invalid_argument);
    rad::LightFieldQuadricOptions options;
    options.ridge = -1;
    EXPECT_THROW(LightFieldQuadricMetric(mesh, f, options), std::invalid_argument);
    options = {};
    options.thetaNodes = -2;
    EXPECT_THROW(LightFieldQuadricMetric(mesh, f, options), std::invalid_argument);
    options = {};
    const LightFieldQuadricMetric metric(mesh, f, options);
    EXPECT_EQ(metric.options().thetaNodes, 2 * 4 + 8);  // automatic: 2 d + 8
    std::string why;
    EXPECT_TRUE(metric.supportsFullCollapse(why));
    EXPECT_TRUE(why.empty());
}

}  // namespace
