// The light-field error of Vanhoey et al. 2010 (Vanhoey, Sauvage, Dischler, "Simplification de maillages
// surfaciques avec champs de lumière") sec. 4, the
// predecessor of the radiance error of Vanhoey et al. 2015:
//     E = E_G + lambda (E_L + E_F)                                                         (eq. 2)
// for a collapse (v1, v2) -> v, with, for the new vertex's light field (F, L) against each endpoint k,
//     E_L(L, L_k) = int_{H cap H_k} (L(h) - L_k(h))^2 dh                                  (eq. 3)
//     E_F(F, F_k) = int_{H_k \ H} E_max^2 dh = 2 alpha_k E_max^2                          (eq. 4)
// where H, H_k are the hemispheres of definition (around the RF normals), h the unit solid angle
// and alpha_k the angle between the normals (H_k \ H is a lune of area 2 alpha_k; H cap H_k is the
// lune of area 2 (pi - alpha_k)), both summed over the two endpoints. E_L is a quadric in the new
// coefficients a: a^T A_k a + 2 a.b_k + c_k (eq. 5), additive over endpoints, minimised by
// A a = -b with A = A_1 + A_2, b = b_1 + b_2 (eq. 6).
//
// What this unit computes: E_L + E_F only (lambda-free). E_G is the memoryless QEM that the engine
// adds itself (quadric_error.h; Vanhoey et al. 2010 sec. 4.4 also uses the memoryless one) and the engine's
// attributeWeight plays the role of lambda.
//
// Mapping onto this project's radiance functions (radiance_field.h, radiance_evaluation.h):
//  - "light field" (F_k, L_k) = the RF of vertex k: frame F_k and normal n_k = the RadianceField
//    frame (not the mesh normal), L_k(w) = evaluateRadiance (plain L, whatever the storage). The
//    paper compares the functions at the same view direction after "geometric transformations that
//    describe both functions in a common domain", i.e. it compares L(w) at world directions w;
//    option compareReflected = true compares the reflected RF L~ of Vanhoey et al. 2015 sec. 3.1 instead.
//    Inside H cap H_k neither function needs the border extension (w is above both horizons).
//  - colours: RGB, every channel treated alike (paper sec. 4.1); E_L sums the three channels'
//    squared differences (the 2-norm of Vanhoey et al. 2015 sec. 7), so E_F counts every lost direction as a
//    maximal error on each channel: E_F = 2 alpha * kColorChannels * E_max^2, E_max = option
//    channelMaxDifference (paper: "RGB components are normalised, so E_max = 1").
//  - units: solid angle in steradians, no 1/(2 pi) (unlike Vanhoey et al. 2015 eq. 6), as in eq. 3-4. With
//    every channel in [0, E_max], a half-edge collapse costs 0 <= E_L + E_F <= 2 pi * 3 * E_max^2
//    (the paper's bound 2 pi per channel, sec. 4.4): E_L <= 2 (pi - alpha) 3 E_max^2 and E_F =
//    2 alpha 3 E_max^2. A full collapse sums two such terms, and slerp splits alpha between them
//    (E_F(F, F_1) + E_F(F, F_2) = 2 alpha 3 E_max^2 since the angles add up to alpha).
//  - coefficients of the new function: in the field's storage (plain or reflected, PB in the new
//    local frame, SH in the global frame); the quadric is built on the basis functions evaluated at
//    basisDirection(basis, F, w, ...), so the same code serves both bases and storages.
//
// Collapses (collapse_metric.h):
//  - half-edge v0 -> v1 (sec. 4.3.1): v1 keeps (F_1, L_1), so E = E_L(L_1, L_0) + E_F(F_1, F_0)
//    (+ E_L(L_1, L_1) = E_F(F_1, F_1) = 0). Both terms are symmetric in 0 and 1, so of the two
//    half-collapses of an edge the paper's argmin_i E((v1, v2) -> v_i) is decided by E_G.
//  - full (v0, v1) -> v (sec. 4.3.2): n = slerp(n0, n1, s) with s = query.s (the projection of the
//    QEM position on the edge, clamped: as the paper with [Hop99]), frame = frameFromNormal(n), a =
//    argmin of eq. 5 summed over both endpoints = solution of eq. 6, cost = E_L(L, L0) + E_L(L, L1)
//    + E_F at that optimum (evaluated as the integral of the residual, not as c - b A^-1 b, which
//    cancels catastrophically for good fits). Eq. 6 is solved as (A + mu I) a = -b, mu = ridge *
//    trace(A) / K (Cholesky). A is positive definite in exact arithmetic (a polynomial vanishing on a
//    lune vanishes everywhere) but SH of high degree are barely constrained on the half sphere
//    opposite n, which no lune covers (and which the border extension never reads): unregularised,
//    two unrelated random SH8/SH10 functions give coefficients up to 1e4-1e5, whose float rounding
//    would then damage the function inside H. Measured on such adversarial pairs (normals 20-170
//    degrees apart, s = 0.4), the default ridge 1e-8 keeps max |a| below 2e2 and raises the optimal
//    E_L by at most 0.7 % (SH8), 0.4 % (SH10), 1e-6 (PB8), 1e-8 (PB4, SH4) relative.
//  - Half-edge collapses (EdgeQuery::halfEdge) keep (F1, L1); a full collapse solves eq. 6 even
//    when its position projects onto p1 (s == 1).
//
// Quadrature over H cap H' (the lune between two half great circles): spherical coordinates about
// the lune's edge axis e = n x n' / |n x n'|,
//     w(theta, phi) = cos(theta) e + sin(theta) (cos(phi) n + sin(phi) (e x n)),
// in which the lune is the rectangle theta in [0, pi], phi in [alpha - pi/2, pi/2] (length pi - alpha)
// with dh = sin(theta) dtheta dphi; Gauss-Legendre in theta and in phi. The integrands (squared
// differences of polynomials of degree d in w, times sin theta) are trigonometric polynomials in
// (theta, phi), so the rule converges spectrally; no indicator function cuts the domain. When
// n x n' vanishes (same or opposite normals) e is any unit vector orthogonal to n.
// Default node counts (per axis): 2 d + 8, d the basis degree. Measured relative error of E_L against
// a 200 x 200 reference, worst of 4 random pairs for each of PB4, PB8, SH4, SH8, SH10 with normals 0,
// 30, 90, 150 and 170 degrees apart: 3e-10 (it falls to ~1e-14 at 2 d + 12 nodes).
// tests/unit/light_field_quadric_test.cpp re-checks against a brute-force sphere grid.
#pragma once

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_field.h"
#include "radiance/radiance_frame.h"
#include "simplify/collapse_metric.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace rad {

struct LightFieldQuadricOptions {
    int thetaNodes = 0;                  // 0: 2 d + 8 for a basis of degree d
    int phiNodes = 0;                    // 0: idem
    double channelMaxDifference = 1.0;   // E_max of eq. 4, per colour channel
    double ridge = 1e-8;                 // relative Tikhonov term of the eq. 6 solve (see above)
    bool compareReflected = false;       // compare L~ (Vanhoey et al. 2015) instead of L (Vanhoey et al. 2010)
};

// Unit directions and weights (sum = 2 (pi - alpha)) integrating over H(n1) cap H(n2), the
// rule described in the file comment. n1, n2 unit. thetaNodes * phiNodes points.
void hemisphereIntersectionRule(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2, int thetaNodes, int phiNodes,
                                std::vector<Eigen::Vector3d>& directions, std::vector<double>& weights);

// The angle alpha between two unit normals, in [0, pi] (atan2 form, accurate near 0 and pi).
double normalAngle(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2);

// Eq. 4 summed over the colour channels: 2 alpha * kColorChannels * channelMaxDifference^2.
double orientationError(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2, double channelMaxDifference = 1.0);

// Eq. 3 summed over the colour channels between two vertex RF, over H(a) cap H(b), with the rule
// above (compareReflected: L~ instead of L).
template <typename ScalarA, typename ScalarB>
double lightFieldError(const VertexRadianceT<ScalarA>& a, const VertexRadianceT<ScalarB>& b, int thetaNodes,
                       int phiNodes, bool compareReflected = false);

// slerp(n0, n1, s) of sec. 4.3.2 for unit normals: the rotation of n0 towards n1 by s alpha. For
// opposite normals (no unique great circle) the rotation axis is frameFromNormal(n0).t.
Eigen::Vector3d slerpNormal(const Eigen::Vector3d& n0, const Eigen::Vector3d& n1, double s);

// The new vertex of a full collapse (sec. 4.3.2) and its error.
struct LightFieldCollapse {
    Frame frame;                       // frameFromNormal(slerp(n0, n1, s))
    std::vector<double> coefficients;  // kColorChannels * K, in the field's storage
    double lightError = 0.0;           // E_L(L, L0) + E_L(L, L1)
    double orientationError = 0.0;     // E_F(F, F0) + E_F(F, F1)
    double cost() const { return lightError + orientationError; }
};

class LightFieldQuadricMetric : public CollapseMetric {
public:
    // Holds `field` by reference (one RF per mesh vertex) and writes the survivors' coefficients and
    // frames into it in onCollapse. Throws std::invalid_argument when the field is invalid
    // (RadianceField::validate), its vertex count differs from the mesh's, or an option is out of
    // range (node counts < 0, channelMaxDifference < 0, ridge < 0, non-finite values).
    LightFieldQuadricMetric(const CollapseMesh& mesh, RadianceField& field, LightFieldQuadricOptions options = {});

    std::string name() const override { return "light-field quadric (Vanhoey et al. 2010)"; }
    void priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query, double* costs) const override;
    bool supportsFullCollapse(std::string& why) const override {
        why.clear();
        return true;
    }
    double priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const override;
    // Full collapse (s < 1): writes the optimal coefficients and the slerped frame into slot v1.
    // Half-edge: nothing to do, v1 keeps its RF.
    void onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) override;

    // E_L(L1, L0) + E_F(F1, F0): the cost of the half-edge collapse v0 -> v1.
    double halfEdgeCost(std::uint32_t v0, std::uint32_t v1) const;
    // The full collapse at parameter s in [0, 1] (clamped).
    LightFieldCollapse optimalCollapse(std::uint32_t v0, std::uint32_t v1, double s) const;
    // E_L(C, L0) + E_L(C, L1) + E_F(F_C, F0) + E_F(F_C, F1) for any candidate RF C (e.g. to compare
    // the optimum with other choices). The candidate's basis must be the field's.
    template <typename Scalar>
    double collapseCost(std::uint32_t v0, std::uint32_t v1, const VertexRadianceT<Scalar>& candidate) const;

    const RadianceField& field() const { return field_; }
    const LightFieldQuadricOptions& options() const { return options_; }  // node counts resolved

private:
    // Solves eq. 6 for the collapse at s; writes frame and coefficients (kColorChannels * K) and
    // returns E_L at the optimum. Thread-local scratch only.
    double solve(std::uint32_t v0, std::uint32_t v1, double s, Frame& frame, double* coefficients) const;

    RadianceField& field_;
    LightFieldQuadricOptions options_;
};

}  // namespace rad
