// Tests of radiance_interpolation.h: Vanhoey et al. 2015 eq. (1)-(4) and (8), function and SH coefficient level.
#include "radiance/radiance_interpolation.h"

#include "radiance/basis.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::BasisKind;
using rad::BasisSpec;
using rad::RadianceField;

using radtest::randomUnit;

struct TestTriangle {
    RadianceField field;
    Vector3d p[3];
    mutable RadianceField otherStorage;  // `field` in the other storage, for mixed-storage views

    // Views on the three vertices; vertex 1 is taken from a copy in the other storage (same RF), so
    // every operator sees mixed plain / reflected storage.
    rad::TriangleRadiance tri() const {
        otherStorage = field;
        rad::setReflectedStorage(otherStorage, !field.reflected);
        rad::TriangleRadiance t = rad::triangleRadiance(field, 0, 1, 2, p[0], p[1], p[2]);
        t.vertices[1] = rad::vertexRadiance(otherStorage, 1);
        return t;
    }
};

// A random triangle around a mean normal, vertex normals spread by `spread`.
TestTriangle randomTriangle(BasisSpec basis, std::mt19937& rng, double spread = 0.3) {
    TestTriangle t;
    t.field = RadianceField(basis, 3);
    std::uniform_real_distribution<float> u(-1, 1);
    for (float& c : t.field.coefficients) c = u(rng);
    const Vector3d mean = randomUnit(rng);
    const rad::Frame frame = rad::frameFromNormal(mean);
    std::uniform_real_distribution<double> pos(-1, 1);
    for (int i = 0; i < 3; ++i) {
        t.p[i] = Vector3d(pos(rng), pos(rng), pos(rng)) * 0.1 + frame.toWorld(Vector3d(pos(rng), pos(rng), 0));
        rad::storeFrame(rad::frameFromNormalAndTangent((mean + spread * randomUnit(rng)).normalized(), randomUnit(rng)),
                        t.field.frame(i));
    }
    return t;
}

// Barycentrics of p (in the plane) computed independently by area ratios.
Vector3d barycentrics(const Vector3d& p1, const Vector3d& p2, const Vector3d& p3, const Vector3d& p) {
    const Vector3d n = (p2 - p1).cross(p3 - p1);
    const double area = n.squaredNorm();
    const double a1 = (p3 - p2).cross(p - p2).dot(n) / area;
    const double a2 = (p1 - p3).cross(p - p3).dot(n) / area;
    return {a1, a2, 1 - a1 - a2};
}

Vector3d randomAlpha(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    Vector3d a(u(rng), u(rng), u(rng));
    return a / a.sum();
}

const std::vector<BasisSpec>& bases() {
    static const std::vector<BasisSpec> b = {{BasisKind::HemisphericalPolynomial, 4}, {BasisKind::SphericalHarmonics, 6}};
    return b;
}

TEST(RadianceInterpolation, VertexBarycentricsReproduceVertexRadiance) {
    std::mt19937 rng(1);
    for (const BasisSpec& basis : bases()) {
        SCOPED_TRACE(basis.name());
        const TestTriangle t = randomTriangle(basis, rng);
        const rad::TriangleRadiance tri = t.tri();
        for (int i = 0; i < 3; ++i) {
            const Vector3d alpha = Vector3d::Unit(i);
            for (int k = 0; k < 20; ++k) {
                const Vector3d w = randomUnit(rng);  // both hemispheres: border extension is consistent
                const auto l = rad::interpolateRadiance(tri, alpha, w);
                ASSERT_TRUE(l.has_value());
                const Vector3d expected = rad::evaluateRadiance(t.field, i, w);
                // (vertex 1 is viewed through the other storage: float rounding of the conversion)
                EXPECT_LT((*l - expected).norm(), 1e-6 * (1 + expected.norm()));
                const Vector3d lt = rad::interpolateReflectedRadiance(tri, alpha, w);
                EXPECT_LT((lt - rad::evaluateReflectedRadiance(t.field, i, w)).norm(), 1e-6 * (1 + lt.norm()));
            }
        }
    }
}

TEST(RadianceInterpolation, EqualNormalsReduceToLinearInterpolation) {
    std::mt19937 rng(2);
    for (const BasisSpec& basis : bases()) {
        SCOPED_TRACE(basis.name());
        TestTriangle t = randomTriangle(basis, rng, 0.0);
        const rad::Frame frame = rad::frameFromNormal(randomUnit(rng));
        for (int i = 0; i < 3; ++i)  // same normal, different tangents
            rad::storeFrame(rad::frameFromNormalAndTangent(frame.n, randomUnit(rng)), t.field.frame(i));
        const rad::TriangleRadiance tri = t.tri();
        for (int k = 0; k < 30; ++k) {
            const Vector3d alpha = randomAlpha(rng), w = randomUnit(rng);
            const auto l = rad::interpolateRadiance(tri, alpha, w);
            ASSERT_TRUE(l.has_value());
            Vector3d expected = Vector3d::Zero();
            for (int i = 0; i < 3; ++i) expected += alpha[i] * rad::evaluateRadiance(t.field, i, w);
            EXPECT_LT((*l - expected).norm(), 1e-6 * (1 + expected.norm()));  // float frames
        }
    }
}

TEST(RadianceInterpolation, Equation2FromPlainRadiance) {
    // Eq. (2) written with the plain RF and explicit reflections: sum alpha_i L_i(R_{n_i} R_n w).
    std::mt19937 rng(3);
    for (const BasisSpec& basis : bases()) {
        SCOPED_TRACE(basis.name());
        for (bool reflected : {false, true}) {
            TestTriangle t = randomTriangle(basis, rng);
            if (reflected) rad::setReflectedStorage(t.field, true);
            const rad::TriangleRadiance tri = t.tri();
            for (int k = 0; k < 30; ++k) {
                const Vector3d alpha = randomAlpha(rng), w = randomUnit(rng);
                Vector3d nSum = Vector3d::Zero();
                for (int i = 0; i < 3; ++i) nSum += alpha[i] * rad::frameFromStored(t.field.frame(i)).n;
                const Vector3d n = nSum.normalized();
                const Vector3d rw = 2 * n.dot(w) * n - w;
                Vector3d expected = Vector3d::Zero();
                for (int i = 0; i < 3; ++i) {
                    const Vector3d ni = rad::frameFromStored(t.field.frame(i)).n;
                    expected += alpha[i] * rad::evaluateRadiance(t.field, i, 2 * ni.dot(rw) * ni - rw);
                }
                const auto l = rad::interpolateRadiance(tri, alpha, w);
                ASSERT_TRUE(l.has_value());
                EXPECT_LT((*l - expected).norm(), 1e-6 * (1 + expected.norm()));  // mixed storage rounding
            }
        }
    }
}

TEST(RadianceInterpolation, GradientMatchesCentralFiniteDifferences) {
    std::mt19937 rng(4);
    for (const BasisSpec& basis : bases()) {
        SCOPED_TRACE(basis.name());
        const TestTriangle t = randomTriangle(basis, rng);
        const rad::TriangleRadiance tri = t.tri();
        const Vector3d normal = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).normalized();
        const Vector3d e1 = (t.p[1] - t.p[0]).normalized(), e2 = normal.cross(e1);  // in-plane basis
        for (int k = 0; k < 20; ++k) {
            const Vector3d w = randomUnit(rng);
            const auto grad = rad::reflectedRadianceGradient(tri, w);
            ASSERT_TRUE(grad.has_value());
            // Eq. (1) as a function of p in the plane, barycentrics by area ratios.
            const auto f = [&](const Vector3d& p) {
                return rad::interpolateReflectedRadiance(tri, barycentrics(t.p[0], t.p[1], t.p[2], p), w);
            };
            const Vector3d center = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
            const double h = 1e-4;
            for (const Vector3d& dir : {e1, e2}) {
                const Vector3d fd = (f(center + h * dir) - f(center - h * dir)) / (2 * h);
                EXPECT_LT((*grad * dir - fd).norm(), 1e-7 * (1 + fd.norm()));
            }
            // The gradient lies in the triangle's plane (each channel's row orthogonal to the normal).
            EXPECT_LT((*grad * normal).norm(), 1e-10 * (1 + grad->norm()));
        }
    }
}

TEST(RadianceInterpolation, ExtrapolationEqualsInterpolationInTheTriangleAndIsLinear) {
    std::mt19937 rng(5);
    for (const BasisSpec& basis : bases()) {
        SCOPED_TRACE(basis.name());
        const TestTriangle t = randomTriangle(basis, rng);
        const rad::TriangleRadiance tri = t.tri();
        const Vector3d normal = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).normalized();
        const auto gradientOp = rad::TriangleGradient::create(t.p[0], t.p[1], t.p[2]);
        ASSERT_TRUE(gradientOp.has_value());
        EXPECT_LT((gradientOp->normal() - normal).norm(), 1e-12);
        for (int k = 0; k < 20; ++k) {
            const Vector3d w = randomUnit(rng), alpha = randomAlpha(rng);
            const Vector3d p = alpha[0] * t.p[0] + alpha[1] * t.p[1] + alpha[2] * t.p[2];
            const auto e = rad::extrapolateReflectedRadiance(tri, p, w);
            ASSERT_TRUE(e.has_value());
            const Vector3d i = rad::interpolateReflectedRadiance(tri, alpha, w);
            EXPECT_LT((*e - i).norm(), 1e-10 * (1 + i.norm()));
            // Constant along the triangle's normal ("(spatially) constant color in the normal direction").
            const auto off = rad::extrapolateReflectedRadiance(tri, p + 0.7 * normal, w);
            EXPECT_LT((*off - *e).norm(), 1e-10 * (1 + i.norm()));
            // Linear in p anywhere in space: second differences vanish, midpoint = average.
            const Vector3d q = p + Vector3d(0.3, -1.2, 2.0), r = p + Vector3d(-2.0, 0.5, 0.4);
            const auto eq = rad::extrapolateReflectedRadiance(tri, q, w);
            const auto er = rad::extrapolateReflectedRadiance(tri, r, w);
            const auto em = rad::extrapolateReflectedRadiance(tri, 0.5 * (q + r), w);
            EXPECT_LT((*em - 0.5 * (*eq + *er)).norm(), 1e-10 * (1 + eq->norm() + er->norm()));
            // Extrapolation weights: the same value as a combination of the vertex r-RF.
            const Vector3d beta = gradientOp->extrapolationWeights(q);
            EXPECT_NEAR(beta.sum(), 1.0, 1e-12);
            EXPECT_LT((rad::interpolateReflectedRadiance(tri, beta, w) - *eq).norm(), 1e-10 * (1 + eq->norm()));
        }
        // At the vertices: exactly the vertex r-RF.
        for (int v = 0; v < 3; ++v) {
            const Vector3d w = randomUnit(rng);
            const auto e = rad::extrapolateReflectedRadiance(tri, t.p[v], w);
            EXPECT_LT((*e - rad::evaluateReflectedRadiance(t.field, v, w)).norm(), 1e-6);  // mixed storage
        }
    }
}

TEST(RadianceInterpolation, ScalarGradientOperator) {
    // A linear function g(p) = a . p + c sampled at the vertices has gradient = projection of a onto
    // the triangle's plane.
    const Vector3d p1(0, 0, 0), p2(2, 0, 0.5), p3(0.3, 1.5, -0.2);
    const auto op = rad::TriangleGradient::create(p1, p2, p3);
    ASSERT_TRUE(op.has_value());
    const Vector3d a(0.7, -1.1, 2.3);
    const Vector3d grad = op->gradient(a.dot(p1) + 1, a.dot(p2) + 1, a.dot(p3) + 1);
    const Vector3d n = op->normal();
    EXPECT_LT((grad - (a - a.dot(n) * n)).norm(), 1e-12);
    // RGB version, row per channel.
    const Eigen::Matrix3d g = op->gradient(Vector3d(a.dot(p1), 0, 1), Vector3d(a.dot(p2), 0, 1), Vector3d(a.dot(p3), 0, 1));
    EXPECT_LT((g.row(0).transpose() - grad).norm(), 1e-12);
    EXPECT_LT(g.row(1).norm() + g.row(2).norm(), 1e-15);
    EXPECT_LT((rad::extrapolate(Vector3d(1, 2, 3), g, p1, p1 + n) - Vector3d(1, 2, 3)).norm(), 1e-12);
}

TEST(RadianceInterpolation, DegenerateInputIsReportedNotNaN) {
    std::mt19937 rng(6);
    TestTriangle t = randomTriangle({BasisKind::SphericalHarmonics, 2}, rng);
    const Vector3d w(0, 0, 1);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // Collinear, coincident, needle (1e-11 rad), NaN.
    const std::vector<std::array<Vector3d, 3>> bad = {
        {Vector3d(0, 0, 0), Vector3d(1, 1, 1), Vector3d(2, 2, 2)},
        {Vector3d(1, 2, 3), Vector3d(1, 2, 3), Vector3d(1, 2, 3)},
        {Vector3d(0, 0, 0), Vector3d(0, 0, 0), Vector3d(1, 0, 0)},
        {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(2, 2e-11, 0)},
        {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(nan, 0, 0)},
    };
    std::vector<double> coef(3 * 9 * 3);
    for (const auto& p : bad) {
        EXPECT_FALSE(rad::TriangleGradient::create(p[0], p[1], p[2]).has_value());
        const rad::TriangleRadiance tri = rad::triangleRadiance(t.field, 0, 1, 2, p[0], p[1], p[2]);
        EXPECT_FALSE(rad::reflectedRadianceGradient(tri, w).has_value());
        EXPECT_FALSE(rad::extrapolateReflectedRadiance(tri, Vector3d(0.1, 0.1, 0), w).has_value());
        EXPECT_FALSE(rad::reflectedShGradient(tri, coef.data()));
        EXPECT_FALSE(rad::extrapolateReflectedSh(tri, Vector3d(0.1, 0.1, 0), coef.data()));
    }
    // A thin but valid triangle still works and is finite.
    const auto thin = rad::TriangleGradient::create(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0.5, 1e-6, 0));
    ASSERT_TRUE(thin.has_value());
    EXPECT_TRUE(thin->op().allFinite());
    // Opposite normals interpolated half-way: no normal, no eq. (2).
    rad::storeFrame(rad::frameFromNormal(Vector3d(0, 0, 1)), t.field.frame(0));
    rad::storeFrame(rad::frameFromNormal(Vector3d(0, 0, -1)), t.field.frame(1));
    const rad::TriangleRadiance tri = t.tri();
    EXPECT_FALSE(rad::interpolatedNormal(tri, Vector3d(0.5, 0.5, 0)).has_value());
    EXPECT_FALSE(rad::interpolateRadiance(tri, Vector3d(0.5, 0.5, 0), w).has_value());
    EXPECT_TRUE(rad::interpolateReflectedRadiance(tri, Vector3d(0.5, 0.5, 0), w).allFinite());
    EXPECT_FALSE(rad::interpolateRadiance(tri, Vector3d(nan, 0.5, 0), w).has_value());
}

// ---- SH coefficient level ---------------------------------------------------------------------

// Evaluates a coefficient vector (L~, global frame) at w without border extension.
Vector3d evalSh(const BasisSpec& basis, const std::vector<double>& c, const Vector3d& w) {
    double scratch[rad::kMaxCoefficientsPerChannel];
    return rad::evaluateCoefficients(basis, c.data(), w, scratch);
}

// A direction inside the hemispheres of all three vertex normals (they are within ~35 degrees).
Vector3d directionAboveAll(const TestTriangle& t, std::mt19937& rng) {
    for (;;) {
        const Vector3d w = randomUnit(rng);
        bool ok = true;
        for (int i = 0; i < 3; ++i) ok = ok && w.dot(rad::frameFromStored(t.field.frame(i)).n) > 0.05;
        if (ok) return w;
    }
}

TEST(RadianceInterpolation, ShCoefficientLevelMatchesFunctionLevel) {
    std::mt19937 rng(7);
    const BasisSpec basis{BasisKind::SphericalHarmonics, 5};
    const int count = 3 * basis.coefficientCount();
    for (bool reflected : {false, true}) {
        TestTriangle t = randomTriangle(basis, rng, 0.3);
        if (reflected) rad::setReflectedStorage(t.field, true);
        const rad::TriangleRadiance tri = t.tri();
        std::vector<double> interp(count), grad(3 * count), extrap(count);
        for (int k = 0; k < 10; ++k) {
            const Vector3d alpha = randomAlpha(rng);
            ASSERT_TRUE(rad::interpolateReflectedSh(tri, alpha, interp.data()));
            ASSERT_TRUE(rad::reflectedShGradient(tri, grad.data()));
            const Vector3d p = Vector3d(0.3, -0.2, 0.5) + alpha[0] * t.p[0] + alpha[1] * t.p[1] + alpha[2] * t.p[2];
            ASSERT_TRUE(rad::extrapolateReflectedSh(tri, p, extrap.data()));
            for (int j = 0; j < 5; ++j) {
                const Vector3d w = directionAboveAll(t, rng);
                // Eq. (1)
                const Vector3d fi = rad::interpolateReflectedRadiance(tri, alpha, w);
                EXPECT_LT((evalSh(basis, interp, w) - fi).norm(), 1e-9 * (1 + fi.norm()));
                // Eq. (3): sum_j grad_j Y_j(w) per channel.
                const auto fg = rad::reflectedRadianceGradient(tri, w);
                ASSERT_TRUE(fg.has_value());
                double y[rad::kMaxCoefficientsPerChannel];
                rad::evaluateBasis(basis, w.x(), w.y(), w.z(), y);
                const int K = basis.coefficientCount();
                for (int ch = 0; ch < 3; ++ch) {
                    Vector3d g = Vector3d::Zero();
                    for (int kk = 0; kk < K; ++kk)
                        g += y[kk] * Vector3d(grad[(ch * K + kk) * 3], grad[(ch * K + kk) * 3 + 1], grad[(ch * K + kk) * 3 + 2]);
                    EXPECT_LT((g - fg->row(ch).transpose()).norm(), 1e-8 * (1 + g.norm()));
                }
                // Eq. (4)
                const auto fe = rad::extrapolateReflectedRadiance(tri, p, w);
                ASSERT_TRUE(fe.has_value());
                EXPECT_LT((evalSh(basis, extrap, w) - *fe).norm(), 1e-8 * (1 + fe->norm()));
            }
        }
        // The interpolated r-RF, attached to the interpolated normal, gives eq. (8) inside the hemispheres.
        const Vector3d alpha = randomAlpha(rng);
        ASSERT_TRUE(rad::interpolateReflectedSh(tri, alpha, interp.data()));
        const auto n = rad::interpolatedNormal(tri, alpha);
        ASSERT_TRUE(n.has_value());
        const rad::VertexRadianceD rf{basis, interp.data(), rad::frameFromNormal(*n), true};
        double scratch[rad::kMaxCoefficientsPerChannel];
        int checked = 0;
        for (int j = 0; j < 40; ++j) {
            const Vector3d w = directionAboveAll(t, rng);
            const Vector3d rw = rad::reflect(*n, w);
            bool inside = true;
            for (int i = 0; i < 3; ++i) inside = inside && rw.dot(rad::frameFromStored(t.field.frame(i)).n) >= 0;
            if (!inside) continue;
            const auto expected = rad::interpolateRadiance(tri, alpha, w);
            EXPECT_LT((rad::evaluateRadiance(rf, w, scratch) - *expected).norm(), 1e-9 * (1 + expected->norm()));
            ++checked;
        }
        EXPECT_GT(checked, 5);
    }
}

TEST(RadianceInterpolation, ShCoefficientLevelRejectsOtherBases) {
    std::mt19937 rng(8);
    const TestTriangle pb = randomTriangle({BasisKind::HemisphericalPolynomial, 3}, rng);
    std::vector<double> out(3 * 10 * 3, 7.0);
    EXPECT_FALSE(rad::interpolateReflectedSh(pb.tri(), Vector3d(1, 0, 0), out.data()));
    EXPECT_FALSE(rad::reflectedShGradient(pb.tri(), out.data()));
    EXPECT_FALSE(rad::extrapolateReflectedSh(pb.tri(), Vector3d(0, 0, 0), out.data()));
    EXPECT_FALSE(rad::reflectedShCoefficients(pb.tri().vertices[0], out.data()));
    for (double x : out) EXPECT_EQ(x, 7.0);
    // Mismatched SH degrees.
    const TestTriangle sh = randomTriangle({BasisKind::SphericalHarmonics, 2}, rng);
    rad::TriangleRadiance tri = sh.tri();
    tri.vertices[2].basis.degree = 3;
    EXPECT_FALSE(rad::interpolateReflectedSh(tri, Vector3d(1, 0, 0), out.data()));
}

}  // namespace
