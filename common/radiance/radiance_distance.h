// L2 distance between radiance functions over a hemisphere, Vanhoey et al. 2015
// sec. 3.5, equations (5) and (6):
//     d(L1, L2) = || L~1 - L~2 ||_{L2(Omega)},   ||L||_{L2(Omega)} = ( 1/(2 pi) int_Omega L(w)^2 dw )^(1/2)
// where Omega is the hemisphere around a chosen normal n0 (sec. 4.1: the normal of the vertex where
// the distance is measured) and L~ are the reflected RF (sec. 3.1). Colours are RGB with the 2-norm
// (sec. 7 "Color channels"), so L(w)^2 is the sum of the squared channels. The functions are
// evaluated with the border extension of sec. 7 wherever Omega leaves their own hemisphere
// (radiance_evaluation.h does it for vertex RF; callables must do it themselves).
//
// Numerical integration (sec. 7 "Numerical integration of errors"): a hemisphere rule in the local
// frame of n0 (frameFromNormal(n0)) rotated into the world. Two families are offered:
//  - Gauss product (default): Gauss-Legendre in z = cos(theta) on [0, 1] times the uniform rule in
//    phi. With m z-nodes and q >= p + 1 phi-nodes it integrates EXACTLY every polynomial in
//    (x, y, z) of total degree p <= 2m - 1 over the hemisphere, whatever its parity in z.
//  - Lebedev hemisphere (the paper's choice; lebedev_quadrature.h hemisphereRule): exact only for
//    integrands even in z (e.g. PB functions whose normal is n0); for z-odd parts (any SH, any RF with
//    another normal) its relative error decays slowly: 2e-3 for int z over 302 sphere points, 5e-4
//    with 1202 points.
// Default rule: Gauss product kDefaultDistanceZNodes x kDefaultDistancePhiNodes = 12 x 24 = 288
// points, exact to degree 23. When every normal involved equals n0 (no border extension inside
// Omega) the integrand is a polynomial of degree <= 2 * 10 = 20 for every supported basis (PB
// monomials in (t.w, b.w) are polynomials in w too), so d^2 is exact to rounding. When a normal is
// tilted from n0, Omega crosses that RF's horizon and the border extension puts a kink (continuous,
// non-smooth) in the integrand, which caps the convergence of every rule. Measured relative error of
// d^2 against a 1500 x 3000 midpoint (theta, phi) grid, random RF, worst of 4 (both normals tilted by
// the angle from n0 about random axes):
//                     tilt 10 deg          tilt 30 deg
//     Gauss 8x16      PB4 9e-6  SH6 5e-4   PB4 8e-5  SH6 7e-4     (128 points)
//     Gauss 12x24     PB4 4e-6  SH6 2e-4   PB4 1e-5  SH6 6e-4     (288 points, default)
//     Gauss 24x48     PB4 6e-7  SH6 4e-5   PB4 2e-6  SH6 1e-4     (1152 points)
//     Lebedev 302     PB4 5e-4  SH6 7e-4   PB4 1e-3  SH6 1e-3     (161 points)
//     Lebedev 1202    PB4 1e-4  SH6 3e-4   PB4 3e-4  SH6 2e-4     (621 points)
// and with no tilt the Lebedev hemisphere rules still err by 2e-3 (302) / 5e-4 (1202) on SH6 (z-odd
// integrand) where the Gauss rules are exact. tests/unit/radiance_distance_test.cpp re-checks the
// default rule against brute force.
#pragma once

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace rad {

inline constexpr int kDefaultDistanceZNodes = 12;
inline constexpr int kDefaultDistancePhiNodes = 24;

// A quadrature rule on the hemisphere z >= 0 of a local frame, with weights already divided by 2 pi
// (so they sum to 1 and sum_i weight_i g(x_i) approximates (1/2pi) int_Omega g, eq. 6).
class HemisphereIntegrator {
public:
    // Default: Gauss product rule with the default node counts.
    HemisphereIntegrator();
    // Gauss-Legendre (zNodes, in z = cos theta on [0, 1]) x uniform (phiNodes) product rule.
    static HemisphereIntegrator gaussProduct(int zNodes, int phiNodes);
    // The hemisphere cut out of the Lebedev rule with spherePointCount points (lebedev_quadrature.h).
    static HemisphereIntegrator lebedev(int spherePointCount);

    std::size_t size() const { return weights_.size(); }
    const std::vector<Eigen::Vector3d>& localPoints() const { return points_; }
    const std::vector<double>& weights() const { return weights_; }  // sum to 1

    // The rule's points rotated to the hemisphere around the unit normal n0 (local frame
    // frameFromNormal(n0)): out[i] = frame.toWorld(localPoints()[i]).
    void directions(const Eigen::Vector3d& n0, std::vector<Eigen::Vector3d>& out) const;

    // (1/2pi) int_Omega(n0) g(w) dw for a scalar integrand.
    double integrate(const Eigen::Vector3d& n0, const std::function<double(const Eigen::Vector3d&)>& g) const;

private:
    HemisphereIntegrator(std::vector<Eigen::Vector3d> points, std::vector<double> weights)
        : points_(std::move(points)), weights_(std::move(weights)) {}

    std::vector<Eigen::Vector3d> points_;
    std::vector<double> weights_;
};

// The default rule, built once (thread-safe static).
const HemisphereIntegrator& defaultHemisphereIntegrator();

// w -> RGB.
using RgbFunction = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

// d^2 = (1/2pi) int_Omega(n0) |f(w) - g(w)|^2 dw (sum over RGB channels): eq. (5)-(6) squared, the
// quantity summed in eq. (7). f and g are the functions actually compared, i.e. the r-RF L~.
double squaredRadianceDistance(const RgbFunction& f, const RgbFunction& g, const Eigen::Vector3d& n0,
                               const HemisphereIntegrator& rule = defaultHemisphereIntegrator());
double radianceDistance(const RgbFunction& f, const RgbFunction& g, const Eigen::Vector3d& n0,
                        const HemisphereIntegrator& rule = defaultHemisphereIntegrator());
// ||f||^2 over Omega(n0), eq. (6) squared.
double squaredRadianceNorm(const RgbFunction& f, const Eigen::Vector3d& n0,
                           const HemisphereIntegrator& rule = defaultHemisphereIntegrator());

// Eq. (5) between two vertex RF: the r-RF L~a and L~b (each reflected about its own normal,
// border-extended) compared over Omega(n0). Any storage (plain / reflected), any basis pair.
template <typename ScalarA, typename ScalarB>
double squaredRadianceDistance(const VertexRadianceT<ScalarA>& a, const VertexRadianceT<ScalarB>& b,
                               const Eigen::Vector3d& n0,
                               const HemisphereIntegrator& rule = defaultHemisphereIntegrator());
double squaredRadianceDistance(const RadianceField& fa, std::size_t va, const RadianceField& fb, std::size_t vb,
                               const Eigen::Vector3d& n0,
                               const HemisphereIntegrator& rule = defaultHemisphereIntegrator());
double radianceDistance(const RadianceField& fa, std::size_t va, const RadianceField& fb, std::size_t vb,
                        const Eigen::Vector3d& n0, const HemisphereIntegrator& rule = defaultHemisphereIntegrator());

// The building block of eq. (7): d^2 between the r-RF of `target` and the combination
// sum_i weights[i] L~_{sources[i]} over Omega(n0). With the weights of
// TriangleGradient::extrapolationWeights(p0) (radiance_interpolation.h) the combination is exactly the
// eq. (4) extrapolation L~_t(p0, .) of the triangle's r-RF, so
//     E = sum_t Area(t) * squaredDistanceToCombination(L(p0), t's 3 vertex RF, beta_t(p0), 3, n0)
// (n0 = normal of v0, sec. 4.1). Two sources with weights (1 - s, s) give the 1D interpolation along
// an edge (sec. 4.3). One pass over the rule, no allocation.
template <typename Scalar>
double squaredDistanceToCombination(const VertexRadianceT<Scalar>& target, const VertexRadianceT<Scalar>* sources,
                                    const double* weights, int sourceCount, const Eigen::Vector3d& n0,
                                    const HemisphereIntegrator& rule = defaultHemisphereIntegrator());

// Gauss-Legendre nodes and weights on [a, b] (n >= 1), exact for polynomials of degree <= 2n - 1.
void gaussLegendre(int n, double a, double b, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace rad
