// L2 distance between radiance functions over a hemisphere, Vanhoey et al. 2015 sec. 3.5,
// eq. (5)-(6): d(L1, L2) = || L~1 - L~2 ||, the norm averaged over the hemisphere Omega(n0) around
// the normal where the distance is measured, RGB channels summed, the reflected RF border-extended
// (sec. 7) wherever Omega leaves their own hemisphere. Integrated numerically by a hemisphere rule:
// Gauss product (default, 12 x 24 points, exact to degree 23) or the paper's Lebedev hemisphere.
// Rules are immutable; the default one is built once (thread-safe).
// Details: docs/simplification.md, "`common/radiance/radiance_distance.h`: how it works".
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
