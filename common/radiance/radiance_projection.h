// Computing the coefficients of a per-vertex radiance function (RF) in a basis (basis.h):
//  (a) weighted, regularised least-squares fit of RGB samples (acquisition data, Vanhoey et al. 2015 sec. 7
//      "Data acquisition and reconstruction": RF "are fitted on photographs");
//  (b) L2 projection of an analytic function f(w) -> RGB (synthetic scenes, tests).
//
// Both produce, for one vertex with frame `frame` (radiance_frame.h), kColorChannels * K doubles
// (channel-major, the vertex layout of radiance_field.h) encoding L, or L~ (Vanhoey et al. 2015 sec. 3.1,
// L~(w) = L(R_n w)) when the reflected storage is requested. Directions are world-frame unit
// vectors; PB coefficients are in the frame's local coordinates, SH coefficients in the global
// frame (basis.h).
#pragma once

#include "radiance/basis.h"
#include "radiance/radiance_field.h"
#include "radiance/radiance_frame.h"

#include <Eigen/Core>
#include <Eigen/Cholesky>

#include <cstddef>
#include <functional>
#include <vector>

namespace rad {

// ---------------------------------------------------------------------------------------------
// (a) Weighted least squares with Tikhonov regularisation.
// ---------------------------------------------------------------------------------------------

struct RadianceSample {
    Eigen::Vector3d direction;  // unit world direction the colour was seen from
    Eigen::Vector3d value;      // RGB
    double weight = 1.0;        // >= 0
};

struct FitOptions {
    // Tikhonov weight, dimensionless (see fitRadiance). 0 = plain weighted least squares.
    double lambda = 0.0;
    // Produce the coefficients of L~ instead of L.
    bool storeReflected = false;
};

// Minimises, independently per channel c,
//     sum_j w_j (sum_k a_k B_k(d_j) - y_jc)^2  +  lambda * s * sum_{k >= 1} a_k^2,
//     s = trace(G) / K,   G = sum_j w_j B(d_j) B(d_j)^T   (the unregularised normal matrix),
// by an LDLT factorisation of the K x K normal equations (G + lambda s D) a = sum_j w_j y_jc B(d_j)
// in double precision, d_j the direction at which the stored function is evaluated
// (basisDirection of radiance_evaluation.h; below the tangent plane, the border direction);
// directions are normalised here.
// lambda is a fraction of the average data term (1e-3..1e-1 are sensible); the constant function
// is not penalised (D = diag(0, 1, ..., 1)), so a large lambda tends to the weighted mean colour.
// Returns false (out untouched) when there is no sample with positive weight, an input is not
// finite, a weight negative or a direction zero, the system is numerically singular (LDLT rcond
// below 1e-14, e.g. lambda = 0 with too few samples, or high-degree SH from one hemisphere) or the
// solution is not finite.
// Details: docs/architecture.md, "`common/radiance/radiance_projection.h`: how it works".
bool fitRadiance(const BasisSpec& basis, const Frame& frame, const RadianceSample* samples, std::size_t count,
                 const FitOptions& options, double* out);
inline bool fitRadiance(const BasisSpec& basis, const Frame& frame, const std::vector<RadianceSample>& samples,
                        const FitOptions& options, double* out) {
    return fitRadiance(basis, frame, samples.data(), samples.size(), options, out);
}

// ---------------------------------------------------------------------------------------------
// (b) L2 projection of an analytic function.
// ---------------------------------------------------------------------------------------------

// f(w) -> RGB for a unit world direction w: the plain RF L (not L~).
using RadianceFunction = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

struct ProjectionOptions {
    // Produce the coefficients of L~ instead of L (the projection of L, then reflectCoefficients of
    // radiance_evaluation.h: exact sign flips for PB, SH rotation by pi about n).
    bool storeReflected = false;
    // SH only: project the border-extended function (f below the tangent plane replaced by its
    // border value, Vanhoey et al. 2015 sec. 7) over the whole sphere, so that the SH approximates exactly what
    // evaluateRadiance returns. false: project f as given on the whole sphere. Ignored for PB.
    bool borderExtension = true;
    // Polynomial precision of the quadrature rule; 0 = automatic: 2 * degree + 10, clamped to the
    // largest Lebedev rule (59). Must be >= 2 * degree so that the basis products are integrated
    // exactly (smaller values are raised to 2 * degree).
    int quadraturePrecision = 0;
};

// Projects functions for many vertices with one basis: the quadrature rule and the basis values at
// its points (and, for PB, the factorised Gram matrix) are computed once.
//  - SH: c_k = sum_i w_i f_ext(x_i) Y_k(x_i) with a Lebedev rule on the whole sphere. SH is
//    orthonormal and the rule integrates every product Y_k Y_k' exactly (precision >= 2d), so this is
//    the exact L2 projection of every function of band <= precision - d, and the discrete L2
//    projection (hyperinterpolation) otherwise.
//  - PB: L2 projection over the hemisphere n.w >= 0: solve G c = sum_i w_i f(x_i) B(x_i) with
//    G_kk' = sum_i w_i B_k(x_i) B_k'(x_i), using the hemisphere rule of lebedev_quadrature.h in the
//    vertex's local frame. PB products are polynomials in (x, y) only, even in z, which that rule
//    integrates exactly up to its precision (>= 2d), so G is the exact Gram matrix.
// Thread-safe: project() and projectIntoField() are const (one small heap buffer per call).
class FunctionProjector {
public:
    FunctionProjector(const BasisSpec& basis, const ProjectionOptions& options = {});

    // out: kColorChannels * K doubles.
    void project(const Frame& frame, const RadianceFunction& f, double* out) const;
    // Projects into vertex v of the field (using the field's frame and its `reflected` flag,
    // overriding options.storeReflected). Throws std::invalid_argument when the field's basis is not
    // the projector's.
    void projectIntoField(RadianceField& field, std::size_t v, const RadianceFunction& f) const;

    const BasisSpec& basis() const { return basis_; }
    int pointCount() const { return static_cast<int>(weights_.size()); }
    int precision() const { return precision_; }

private:
    void projectImpl(const Frame& frame, const RadianceFunction& f, bool reflected, double* out) const;

    BasisSpec basis_;
    ProjectionOptions options_;
    int precision_ = 0;
    std::vector<Eigen::Vector3d> points_;  // SH: global sphere points; PB: local hemisphere points
    std::vector<double> weights_;
    Eigen::MatrixXd basisValues_;          // K x points
    Eigen::LDLT<Eigen::MatrixXd> gram_;    // PB only
};

// One-shot convenience (builds a FunctionProjector).
void projectFunction(const BasisSpec& basis, const Frame& frame, const RadianceFunction& f,
                     const ProjectionOptions& options, double* out);

}  // namespace rad
