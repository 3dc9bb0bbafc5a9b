// Tests of simplify/radiance_collapse_error.h: the radiance error of Vanhoey et al. 2015
// eq. (7) for half-edge collapses and its sec. 4.3 variant for full edge collapses. Expected values
// come from the slow generic path (TriangleGradient + squaredDistanceToCombination, one direction at
// a time, evaluateReflectedRadiance with its own border extension) or from closed forms worked out
// here, never from the Gram-matrix kernel under test.
#include "simplify/radiance_collapse_error.h"

#include "radiance/radiance_distance.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "radiance/radiance_interpolation.h"
#include "simplify/collapse_mesh.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::BasisKind;
using rad::BasisSpec;
using rad::CollapseMesh;
using rad::RadianceField;
using rad::StarFace;
using radtest::randomUnit;

constexpr double kPi = 3.14159265358979323846;
const BasisSpec kPB4{BasisKind::HemisphericalPolynomial, 4};
const BasisSpec kSH6{BasisKind::SphericalHarmonics, 6};

struct Patch {
    std::vector<float> positions;
    std::vector<std::uint32_t> faces;
    int n = 0;  // grid side
    std::uint32_t at(int i, int j) const { return static_cast<std::uint32_t>(j * n + i); }
    CollapseMesh mesh() const { return CollapseMesh(positions.data(), positions.size() / 3, faces.data(), faces.size() / 3); }
};

// A jittered, bumpy triangular grid of n x n vertices (valence 6 inside), counter-clockwise from +z.
Patch makePatch(int n, std::mt19937& rng, double bump = 0.25) {
    Patch p;
    p.n = n;
    std::uniform_real_distribution<double> jitter(-0.15, 0.15);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = i + 0.5 * j + jitter(rng), y = j * std::sqrt(3.0) / 2 + jitter(rng);
            const double z = bump * std::sin(1.3 * x) * std::cos(0.9 * y) + 0.5 * jitter(rng);
            p.positions.insert(p.positions.end(), {float(x), float(y), float(z)});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            p.faces.insert(p.faces.end(), {p.at(i, j), p.at(i + 1, j), p.at(i, j + 1)});
            p.faces.insert(p.faces.end(), {p.at(i + 1, j), p.at(i + 1, j + 1), p.at(i, j + 1)});
        }
    return p;
}

// Random coefficients (decaying with the order, like fitted data) and normals tilted from +z by up to
// `tiltDegrees` about random axes (so neighbours differ by up to twice that), random tangents.
RadianceField randomField(BasisSpec basis, std::size_t count, double tiltDegrees, std::mt19937& rng,
                          bool reflected = false) {
    RadianceField f(basis, count, reflected);
    std::uniform_real_distribution<float> u(-1, 1);
    std::uniform_real_distribution<double> angle(0, tiltDegrees * kPi / 180);
    for (float& c : f.coefficients) c = u(rng);
    for (std::size_t v = 0; v < count; ++v) {
        const Vector3d axis = Vector3d::UnitZ().cross(randomUnit(rng)).normalized();
        const Vector3d n = Eigen::AngleAxisd(angle(rng), axis) * Vector3d::UnitZ();
        rad::storeFrame(rad::frameFromNormalAndTangent(n, randomUnit(rng)), f.frame(v));
    }
    return f;
}

// The faces of v's star that do not contain `other` (what the engine passes as star0 / star1).
std::vector<StarFace> starWithout(const CollapseMesh& mesh, std::uint32_t v, std::uint32_t other) {
    std::vector<StarFace> star, out;
    mesh.star(v, star);
    for (const StarFace& f : star)
        if (f.a != other && f.b != other) out.push_back(f);
    return out;
}

double area(const Vector3d& a, const Vector3d& b, const Vector3d& c) { return 0.5 * (b - a).cross(c - a).norm(); }

// Eq. (7) the slow way: one squaredDistanceToCombination per post-collapse triangle.
double genericHalfEdge(const RadianceField& field, const CollapseMesh& mesh, std::uint32_t v0, std::uint32_t v1,
                       const rad::HemisphereIntegrator& rule) {
    std::vector<StarFace> star;
    mesh.star(v0, star);
    const rad::VertexRadiance target = rad::vertexRadiance(field, v0);
    const Vector3d p0 = mesh.position(v0), p1 = mesh.position(v1);
    double cost = 0;
    for (const StarFace& f : star) {
        if (f.a == v1 || f.b == v1) continue;
        const Vector3d pa = mesh.position(f.a), pb = mesh.position(f.b);
        const auto gradient = rad::TriangleGradient::create(p1, pa, pb);
        if (!gradient) continue;
        const Vector3d beta = gradient->extrapolationWeights(p0);
        const rad::VertexRadiance sources[3] = {rad::vertexRadiance(field, v1), rad::vertexRadiance(field, f.a),
                                                rad::vertexRadiance(field, f.b)};
        cost += area(p1, pa, pb) * rad::squaredDistanceToCombination(target, sources, beta.data(), 3, target.frame.n, rule);
    }
    return cost;
}

std::vector<double> priceAll(const rad::RadianceCollapseMetric& metric, const CollapseMesh& mesh, std::uint32_t v0,
                             const std::vector<std::uint32_t>& targets) {
    std::vector<StarFace> star;
    mesh.star(v0, star);
    rad::HalfEdgeQuery q;
    q.source = v0;
    q.star = star.data();
    q.starSize = static_cast<int>(star.size());
    q.targets = targets.data();
    q.targetCount = static_cast<int>(targets.size());
    std::vector<double> costs(targets.size(), -1.0);
    metric.priceHalfEdges(mesh, q, costs.data());
    return costs;
}

TEST(RadianceCollapse, HalfEdgeMatchesGenericPath) {
    std::mt19937 rng(11);
    const Patch patch = makePatch(6, rng);
    const CollapseMesh mesh = patch.mesh();
    // Empty: the metric's default for the basis (read back through metric.rule()).
    const std::vector<std::optional<rad::HemisphereIntegrator>> rules = {
        std::nullopt, rad::HemisphereIntegrator::gaussProduct(4, 9), rad::HemisphereIntegrator::lebedev(302)};
    // Interior sources (closed stars), a boundary source, a two-face corner and a one-face corner
    // (open stars).
    const std::vector<std::uint32_t> sources = {patch.at(2, 2), patch.at(3, 2), patch.at(2, 3), patch.at(0, 3),
                                                patch.at(0, 5), patch.at(5, 5)};
    for (const BasisSpec& basis : {kPB4, kSH6})
        for (bool reflected : {false, true})
            for (std::size_t r = 0; r < rules.size(); ++r) {
                SCOPED_TRACE(basis.name() + (reflected ? " reflected" : " plain") + " rule " + std::to_string(r));
                RadianceField field = randomField(basis, mesh.vertexCount(), 15.0, rng, reflected);
                rad::RadianceCollapseOptions options;
                options.rule = rules[r];
                const rad::RadianceCollapseMetric metric(field, options);
                // SH is switched to reflected storage by the metric (float rounding once); the generic
                // path reads the field as it is now.
                EXPECT_EQ(field.reflected, basis.kind == BasisKind::SphericalHarmonics ? true : reflected);
                for (std::uint32_t v0 : sources) {
                    std::vector<std::uint32_t> targets;
                    mesh.neighbours(v0, targets);
                    targets.push_back(patch.at(5, 0) == v0 ? patch.at(0, 5) : patch.at(5, 0));  // not a neighbour
                    const std::vector<double> costs = priceAll(metric, mesh, v0, targets);
                    for (std::size_t t = 0; t < targets.size(); ++t) {
                        const double expected = genericHalfEdge(field, mesh, v0, targets[t], metric.rule());
                        if (starWithout(mesh, v0, targets[t]).empty()) {
                            // Every face of the star dies with the collapse: eq. (7) sums over nothing.
                            EXPECT_EQ(costs[t], 0.0) << v0 << " -> " << targets[t];
                            continue;
                        }
                        EXPECT_GT(expected, 0.0);
                        EXPECT_NEAR(costs[t], expected, 1e-10 * expected) << v0 << " -> " << targets[t];
                    }
                }
            }
}

TEST(RadianceCollapse, ShPlainInputIsConvertedToTheSameFunctions) {
    // The metric's reflected copy of a plain SH field prices like the plain original (generic path on
    // the untouched original), up to the float rounding of the conversion.
    std::mt19937 rng(12);
    const Patch patch = makePatch(4, rng);
    const CollapseMesh mesh = patch.mesh();
    const RadianceField original = randomField(kSH6, mesh.vertexCount(), 15.0, rng, false);
    RadianceField field = original;
    const rad::RadianceCollapseMetric metric(field);
    ASSERT_TRUE(field.reflected);
    const std::uint32_t v0 = patch.at(1, 1);
    std::vector<std::uint32_t> targets;
    mesh.neighbours(v0, targets);
    const std::vector<double> costs = priceAll(metric, mesh, v0, targets);
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const double expected = genericHalfEdge(original, mesh, v0, targets[t], metric.rule());
        EXPECT_NEAR(costs[t], expected, 1e-5 * expected);
    }
}

TEST(RadianceCollapse, DiffuseFunctionsGiveAreaTimesColourError) {
    // Sec. 4.2: constant RF reduce eq. (7) to sum_t Area(t) |c0 - sum_i beta_i c_i|^2, with beta the
    // barycentrics of p0's projection on t's plane (eq. 4), solved here from the 2x2 normal equations.
    std::mt19937 rng(13);
    const Patch patch = makePatch(5, rng);
    const CollapseMesh mesh = patch.mesh();
    std::uniform_real_distribution<double> colour(0, 1);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 2}, BasisSpec{BasisKind::SphericalHarmonics, 3}}) {
        SCOPED_TRACE(basis.name());
        const double constant = basis.usesLocalFrame() ? 1.0 : 0.5 / std::sqrt(kPi);  // basis function 0
        RadianceField field = randomField(basis, mesh.vertexCount(), 30.0, rng);
        std::fill(field.coefficients.begin(), field.coefficients.end(), 0.0f);
        std::vector<Vector3d> colours(mesh.vertexCount());
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
            colours[v] = Vector3d(colour(rng), colour(rng), colour(rng));
            for (int c = 0; c < 3; ++c) {
                field.channelCoefficients(v, c)[0] = static_cast<float>(colours[v][c] / constant);
                colours[v][c] = field.channelCoefficients(v, c)[0] * constant;  // what the floats hold
            }
        }
        const rad::RadianceCollapseMetric metric(field);
        for (std::uint32_t v0 : {patch.at(2, 2), patch.at(1, 3), patch.at(0, 0)}) {
            std::vector<std::uint32_t> targets;
            mesh.neighbours(v0, targets);
            const std::vector<double> costs = priceAll(metric, mesh, v0, targets);
            std::vector<StarFace> star;
            mesh.star(v0, star);
            const Vector3d p0 = mesh.position(v0);
            for (std::size_t t = 0; t < targets.size(); ++t) {
                const std::uint32_t v1 = targets[t];
                const Vector3d p1 = mesh.position(v1);
                double expected = 0;
                for (const StarFace& f : star) {
                    if (f.a == v1 || f.b == v1) continue;
                    const Vector3d e1 = mesh.position(f.a) - p1, e2 = mesh.position(f.b) - p1, d = p0 - p1;
                    const double a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2);
                    const double det = a11 * a22 - a12 * a12;
                    const double b2 = (a22 * e1.dot(d) - a12 * e2.dot(d)) / det;
                    const double b3 = (a11 * e2.dot(d) - a12 * e1.dot(d)) / det;
                    const Vector3d extrapolated = (1 - b2 - b3) * colours[v1] + b2 * colours[f.a] + b3 * colours[f.b];
                    expected += 0.5 * e1.cross(e2).norm() * (colours[v0] - extrapolated).squaredNorm();
                }
                EXPECT_NEAR(costs[t], expected, 1e-10 * expected + 1e-15) << v0 << " -> " << v1;
            }
        }
    }
}

TEST(RadianceCollapse, AffineFieldOnPlanarFanCostsNothing) {
    // Eq. (4) reproduces affine functions of position, so when every coefficient is an affine function
    // of the (planar) position and all vertices share one frame, every half-edge collapse is free.
    // Positions and coefficients are dyadic so that the floats hold the affine field exactly.
    const std::vector<float> positions = {0.125f, 0.0625f, 0,  1, 0, 0,  0.5f, 0.875f, 0,  -0.5f, 0.875f, 0,
                                          -1, 0, 0,  -0.5f, -0.875f, 0,  0.5f, -0.875f, 0};
    const std::vector<std::uint32_t> faces = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 1};
    const CollapseMesh mesh(positions.data(), 7, faces.data(), 6);
    std::mt19937 rng(14);
    std::uniform_int_distribution<int> sixteenth(-16, 16);
    for (const BasisSpec& basis : {kPB4, kSH6})
        for (bool diffuseOnly : {true, false}) {
            SCOPED_TRACE(basis.name() + (diffuseOnly ? " constant RF" : " full RF"));
            RadianceField field(basis, 7, false);
            const int count = field.coefficientsPerVertex();
            const rad::Frame frame = rad::frameFromNormalAndTangent(Vector3d::UnitZ(), Vector3d(1, 0.25, 0));
            std::vector<float> A(count), B(count), C(count);
            for (int k = 0; k < count; ++k) {
                const bool used = !diffuseOnly || k % field.coefficientsPerChannel() == 0;
                A[k] = used ? sixteenth(rng) / 16.0f : 0.0f;
                B[k] = used ? sixteenth(rng) / 16.0f : 0.0f;
                C[k] = used ? sixteenth(rng) / 16.0f : 0.0f;
            }
            double scale = 0;  // |L~0|^2 magnitude, for the tolerance
            for (std::uint32_t v = 0; v < 7; ++v) {
                rad::storeFrame(frame, field.frame(v));
                for (int k = 0; k < count; ++k)
                    field.vertexCoefficients(v)[k] = A[k] + B[k] * positions[3 * v] + C[k] * positions[3 * v + 1];
            }
            for (int k = 0; k < count; ++k) scale += double(field.vertexCoefficients(0)[k]) * field.vertexCoefficients(0)[k];
            const rad::RadianceCollapseMetric metric(field);
            for (std::uint32_t v0 = 0; v0 < 7; ++v0) {
                std::vector<std::uint32_t> targets;
                mesh.neighbours(v0, targets);
                for (double cost : priceAll(metric, mesh, v0, targets)) EXPECT_NEAR(cost, 0.0, 1e-12 * scale) << v0;
            }
            // The same positions with a non-affine perturbation of one vertex do cost something.
            field.vertexCoefficients(3)[0] += 0.5f;
            const rad::RadianceCollapseMetric perturbed(field);
            const std::vector<double> costs = priceAll(perturbed, mesh, 0, {1});
            EXPECT_GT(costs[0], 1e-4);
        }
}

TEST(RadianceCollapse, DegeneratePostCollapseTriangleIsSkipped) {
    // Ring r0 = (1,-1), r1 = (1,0), r2 = (1,1) collinear: collapsing v0 onto r0 turns (v0, r1, r2) into
    // the degenerate (r0, r1, r2), which contributes nothing; the other two faces are priced as usual.
    const std::vector<float> positions = {0, 0, 0.1f,  1, -1, 0,  1, 0, 0,  1, 1, 0,  -1, 1, 0,  -1, -1, 0};
    const std::vector<std::uint32_t> faces = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 1};
    const CollapseMesh mesh(positions.data(), 6, faces.data(), 5);
    std::mt19937 rng(15);
    RadianceField field = randomField(kPB4, 6, 20.0, rng);
    const rad::RadianceCollapseMetric metric(field);
    const double cost = priceAll(metric, mesh, 0, {1})[0];
    const rad::VertexRadiance target = rad::vertexRadiance(field, 0);
    double expected = 0;
    for (const auto& [a, b] : {std::pair<std::uint32_t, std::uint32_t>{3, 4}, {4, 5}}) {
        const Vector3d p1 = mesh.position(1), pa = mesh.position(a), pb = mesh.position(b);
        const Vector3d beta = rad::TriangleGradient::create(p1, pa, pb)->extrapolationWeights(mesh.position(0));
        const rad::VertexRadiance sources[3] = {rad::vertexRadiance(field, 1), rad::vertexRadiance(field, a),
                                                rad::vertexRadiance(field, b)};
        expected += area(p1, pa, pb) *
                    rad::squaredDistanceToCombination(target, sources, beta.data(), 3, target.frame.n, metric.rule());
    }
    EXPECT_TRUE(std::isfinite(cost));
    EXPECT_NEAR(cost, expected, 1e-10 * expected);
}

TEST(RadianceCollapse, FullCollapseMatchesGenericPath) {
    std::mt19937 rng(16);
    const Patch patch = makePatch(6, rng);
    CollapseMesh mesh = patch.mesh();
    RadianceField field = randomField(kSH6, mesh.vertexCount(), 15.0, rng);
    rad::RadianceCollapseMetric metric(field);
    std::string why = "unchanged";
    EXPECT_TRUE(metric.supportsFullCollapse(why));
    EXPECT_TRUE(why.empty());

    const std::uint32_t v0 = patch.at(2, 2), v1 = patch.at(3, 2);
    const std::vector<StarFace> star0 = starWithout(mesh, v0, v1), star1 = starWithout(mesh, v1, v0);
    ASSERT_EQ(star0.size(), 4u);
    ASSERT_EQ(star1.size(), 4u);
    const Vector3d p0 = mesh.position(v0), p1 = mesh.position(v1);
    const Vector3d position = 0.65 * p0 + 0.35 * p1 + Vector3d(0.02, 0.05, 0.08);
    const double s = std::clamp((position - p0).dot(p1 - p0) / (p1 - p0).squaredNorm(), 0.0, 1.0);

    // The new vertex built here: coefficients (1 - s) c~0 + s c~1 in double, normal interpolated.
    const int count = field.coefficientsPerVertex();
    std::vector<double> cv(count);
    for (int k = 0; k < count; ++k)
        cv[k] = (1 - s) * double(field.vertexCoefficients(v0)[k]) + s * double(field.vertexCoefficients(v1)[k]);
    const Vector3d n0 = rad::vertexRadiance(field, v0).frame.n, n1 = rad::vertexRadiance(field, v1).frame.n;
    rad::VertexRadianceD newVertex;
    newVertex.basis = field.basis;
    newVertex.coefficients = cv.data();
    newVertex.frame = rad::frameFromNormal(((1 - s) * n0 + s * n1).normalized());
    newVertex.reflected = true;
    // Double copies of the field's vertices (squaredDistanceToCombination takes one scalar type).
    std::vector<double> all(field.coefficients.begin(), field.coefficients.end());
    const auto viewD = [&](std::uint32_t v) {
        rad::VertexRadianceD r;
        r.basis = field.basis;
        r.coefficients = all.data() + std::size_t(v) * count;
        r.frame = rad::vertexRadiance(field, v).frame;
        r.reflected = field.reflected;
        return r;
    };
    const auto side = [&](std::uint32_t vt, const std::vector<StarFace>& star) {
        const rad::VertexRadianceD target = viewD(vt);
        double cost = 0;
        for (const StarFace& f : star) {
            const Vector3d pa = mesh.position(f.a), pb = mesh.position(f.b);
            const Vector3d beta = rad::TriangleGradient::create(position, pa, pb)->extrapolationWeights(mesh.position(vt));
            const rad::VertexRadianceD sources[3] = {newVertex, viewD(f.a), viewD(f.b)};
            cost += area(position, pa, pb) *
                    rad::squaredDistanceToCombination(target, sources, beta.data(), 3, target.frame.n, metric.rule());
        }
        return cost;
    };
    const double expected = side(v0, star0) + side(v1, star1);

    rad::EdgeQuery q;
    q.v0 = v0;
    q.v1 = v1;
    q.star0 = star0.data();
    q.star0Size = static_cast<int>(star0.size());
    q.star1 = star1.data();
    q.star1Size = static_cast<int>(star1.size());
    q.position = position;
    q.s = s;
    const double cost = metric.priceEdge(mesh, q);
    EXPECT_GT(expected, 0.0);
    EXPECT_NEAR(cost, expected, 1e-10 * expected);

    // At s = 1, position = p1 the full collapse is the half-edge collapse v0 -> v1 (the green side
    // costs nothing: extrapolating to p1 gives L~1 itself).
    rad::EdgeQuery half = q;
    half.s = 1.0;
    half.position = p1;
    const double halfCost = priceAll(metric, mesh, v0, {v1})[0];
    EXPECT_NEAR(metric.priceEdge(mesh, half), halfCost, 1e-9 * halfCost);

    // onCollapse: the survivor gets float((1 - s) c~0 + s c~1) and frameFromNormal(nv); the others
    // are untouched.
    const RadianceField before = field;
    mesh.setPosition(v1, position);
    mesh.collapse(v0, v1);
    metric.onCollapse(mesh, q);
    for (int k = 0; k < count; ++k) EXPECT_EQ(field.vertexCoefficients(v1)[k], static_cast<float>(cv[k])) << k;
    const rad::Frame stored = rad::frameFromStored(field.frame(v1));
    EXPECT_NEAR((stored.n - newVertex.frame.n).norm(), 0.0, 1e-6);
    EXPECT_NEAR((stored.t - newVertex.frame.t).norm(), 0.0, 1e-6);
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        if (v == v1) continue;
        for (int k = 0; k < count; ++k) ASSERT_EQ(field.vertexCoefficients(v)[k], before.vertexCoefficients(v)[k]);
        for (int k = 0; k < 6; ++k) ASSERT_EQ(field.frame(v)[k], before.frame(v)[k]);
    }
}

TEST(RadianceCollapse, HalfEdgeOnCollapseLeavesTheFieldAlone) {
    std::mt19937 rng(17);
    const Patch patch = makePatch(4, rng);
    CollapseMesh mesh = patch.mesh();
    for (const BasisSpec& basis : {kPB4, kSH6}) {
        RadianceField field = randomField(basis, mesh.vertexCount(), 15.0, rng);
        rad::RadianceCollapseMetric metric(field);
        const RadianceField before = field;
        CollapseMesh m = mesh;
        rad::EdgeQuery q;
        q.v0 = patch.at(1, 1);
        q.v1 = patch.at(2, 1);
        q.position = m.position(q.v1);
        q.s = 1.0;
        m.collapse(q.v0, q.v1);
        metric.onCollapse(m, q);
        EXPECT_EQ(field.coefficients, before.coefficients);
        EXPECT_EQ(field.frames, before.frames);
    }
}

TEST(RadianceCollapse, PolynomialBasisRefusesFullCollapse) {
    std::mt19937 rng(18);
    const Patch patch = makePatch(4, rng);
    CollapseMesh mesh = patch.mesh();
    RadianceField field = randomField(kPB4, mesh.vertexCount(), 15.0, rng);
    rad::RadianceCollapseMetric metric(field);
    EXPECT_FALSE(field.reflected);  // PB storage is left as it was
    std::string why;
    EXPECT_FALSE(metric.supportsFullCollapse(why));
    EXPECT_NE(why.find("4.3"), std::string::npos) << why;
    EXPECT_NE(why.find("PB4"), std::string::npos) << why;
    rad::EdgeQuery q;
    q.v0 = patch.at(1, 1);
    q.v1 = patch.at(2, 1);
    const std::vector<StarFace> star0 = starWithout(mesh, q.v0, q.v1), star1 = starWithout(mesh, q.v1, q.v0);
    q.star0 = star0.data();
    q.star0Size = int(star0.size());
    q.star1 = star1.data();
    q.star1Size = int(star1.size());
    q.position = 0.5 * (mesh.position(q.v0) + mesh.position(q.v1));
    q.s = 0.5;
    EXPECT_EQ(metric.priceEdge(mesh, q), std::numeric_limits<double>::infinity());
    EXPECT_THROW(metric.onCollapse(mesh, q), std::logic_error);
}

TEST(RadianceCollapse, OppositeNormalsForbidFullCollapse) {
    std::mt19937 rng(19);
    const Patch patch = makePatch(4, rng);
    const CollapseMesh mesh = patch.mesh();
    RadianceField field = randomField(kSH6, mesh.vertexCount(), 0.0, rng);
    rad::EdgeQuery q;
    q.v0 = patch.at(1, 1);
    q.v1 = patch.at(2, 1);
    rad::storeFrame(rad::frameFromNormal(-Vector3d::UnitZ()), field.frame(q.v1));
    rad::RadianceCollapseMetric metric(field);
    const std::vector<StarFace> star0 = starWithout(mesh, q.v0, q.v1), star1 = starWithout(mesh, q.v1, q.v0);
    q.star0 = star0.data();
    q.star0Size = int(star0.size());
    q.star1 = star1.data();
    q.star1Size = int(star1.size());
    q.position = 0.5 * (mesh.position(q.v0) + mesh.position(q.v1));
    q.s = 0.5;
    EXPECT_EQ(metric.priceEdge(mesh, q), std::numeric_limits<double>::infinity());
}

TEST(RadianceCollapse, RejectsInvalidFieldsAndMismatchedMeshes) {
    std::mt19937 rng(20);
    const Patch patch = makePatch(3, rng);
    const CollapseMesh mesh = patch.mesh();
    RadianceField nan = randomField(kPB4, mesh.vertexCount(), 10.0, rng);
    nan.coefficients[5] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(rad::RadianceCollapseMetric{nan}, std::invalid_argument);
    RadianceField truncated = randomField(kPB4, mesh.vertexCount(), 10.0, rng);
    truncated.coefficients.pop_back();
    EXPECT_THROW(rad::RadianceCollapseMetric{truncated}, std::invalid_argument);
    RadianceField good = randomField(kPB4, mesh.vertexCount(), 10.0, rng);
    rad::RadianceCollapseOptions onePoint;  // the smallest rule is accepted
    onePoint.rule = rad::HemisphereIntegrator::gaussProduct(1, 1);
    EXPECT_NO_THROW((rad::RadianceCollapseMetric{good, onePoint}));

    RadianceField larger = randomField(kPB4, mesh.vertexCount() + 1, 10.0, rng);
    const rad::RadianceCollapseMetric metric(larger);
    std::vector<std::uint32_t> targets = {patch.at(1, 0)};
    EXPECT_THROW(priceAll(metric, mesh, patch.at(0, 0), targets), std::invalid_argument);
}

TEST(RadianceCollapse, ConcurrentPricingMatchesSerial) {
    // Scratch is per thread: pricing every vertex from several threads gives the serial results.
    std::mt19937 rng(21);
    const Patch patch = makePatch(12, rng);
    const CollapseMesh mesh = patch.mesh();
    RadianceField field = randomField(kPB4, mesh.vertexCount(), 15.0, rng);
    const rad::RadianceCollapseMetric metric(field);
    const int n = static_cast<int>(mesh.vertexCount());
    std::vector<std::vector<double>> serial(n), parallel(n);
    for (int v = 0; v < n; ++v) {
        std::vector<std::uint32_t> targets;
        mesh.neighbours(v, targets);
        serial[v] = priceAll(metric, mesh, v, targets);
    }
#pragma omp parallel for num_threads(4) schedule(dynamic, 1)
    for (int v = 0; v < n; ++v) {
        std::vector<std::uint32_t> targets;
        mesh.neighbours(v, targets);
        parallel[v] = priceAll(metric, mesh, v, targets);
    }
    for (int v = 0; v < n; ++v) EXPECT_EQ(serial[v], parallel[v]) << v;
}

}  // namespace
