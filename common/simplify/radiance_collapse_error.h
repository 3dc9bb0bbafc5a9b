// The radiance error of a collapse, Vanhoey et al. 2015,
// sec. 4.1 and 4.3, as a pricing module of the edge-collapse engine (collapse_metric.h).
//
// Half-edge collapse v0 -> v1, eq. (7):
//     E = sum_t Area(t) d^2( L~0, L~_t(p0, .) )   over Omega(n0)
// t runs over the post-collapse triangles (v1, a, b), one per face (v0, a, b) of v0's star that does
// not contain v1; Area(t) is the post-collapse area; L~_t(p0, .) is the eq. (4) extrapolation of t's
// reflected RF (sec. 3.1) to p0, which is the linear combination sum_i beta_{t,i}(p0) L~_i with
// beta = TriangleGradient(t).extrapolationWeights(p0) (radiance_interpolation.h); d^2 is eq. (5)-(6)
// squared (RGB channels summed, sec. 7) over the hemisphere Omega(n0) around v0's RF normal n0 (the
// field frame's n, not a geometric normal). Every L~ is border-extended about its own normal
// (sec. 7 "Exceeding hemispheres"), exactly as evaluateReflectedRadiance does.
//
// Full edge collapse (v0, v1) -> v, sec. 4.3 (SH bases only): v sits at query.position; its r-RF is
// eq. (1) restricted to the edge at the parameter s of the position's projection,
// L~v = (1 - s) L~0 + s L~1 on coefficients (sec. 6: SH coefficients of L~ live in the global frame,
// so the combination of functions is the combination of coefficient vectors), its normal
// nv = normalize((1 - s) n0 + s n1), and L~v is border-extended about nv. The cost is eq. (7) at p0
// over the triangles (v, a, b) for the faces (v0, a, b) of star0 (Omega(n0)) plus eq. (7) at p1 over
// the triangles (v, a, b) for the faces of star1 (Omega(n1)); the two stars exclude the faces that
// contain the edge (the blue and green triangles of the paper's Fig. 5). PB cannot do this: its
// coefficients live in a per-vertex tangent frame, and combining two PB functions attached to
// different frames is not a PB function of any frame (sec. 4.3 asks for a rotation-invariant basis).
//
// The fast kernel. All candidate targets of one source share Omega(n0), and every d^2 involved is
// between L~0 and a combination of the ring's L~_j. So each of the m + 1 functions (L~0 and the m
// distinct other vertices: ring and targets) is evaluated ONCE at the P directions of the rule
// rotated to Omega(n0), as (P x K basis values) times (K x 3 coefficients) with the square roots of
// the rule weights folded into the basis values. With D_j = L~0 - L~_j (sampled, weighted) and the
// m x m Gram matrix G_ij = sum_w weight(w) <D_i(w), D_j(w)>_RGB, each triangle costs
//     d^2 = || L~0 - sum_i beta_i L~_i ||^2 = || sum_i beta_i D_i ||^2 = beta^T G beta
// (because sum_i beta_i = 1), a 3 x 3 quadratic form. This is x^T Gfull x with x = (1, -beta) on the
// Gram matrix of the raw functions, written on the differences so that the cancellation happens on
// the small differences between neighbouring RF rather than on |L|^2 (an affine field costs zero to
// rounding of |D|^2, not of |L|^2). Work per source: (m + 1) P K 3 multiply-adds for the samples,
// m^2 P 3 / 2 for G, a few dozen flops per (target, triangle).
//  - Directions go by chunks of 8: a chunk's K basis values stay in L1 and its 8 sums per channel in
//    SIMD registers (Eigen fixed-size arrays). The rule is padded with zero-weight points to a
//    multiple of 8 (50 -> 56 for PB4's default).
//  - PB: monomials of the local (u, v) built column by column, one product each.
//  - SH with reflected storage (always, see the constructor): L~_j(w) = C_j(w) wherever n_j.w >= 0,
//    so the harmonics at the rule's directions are evaluated once per source and shared by every RF;
//    only the directions below RF j's horizon (a band as wide as the tilt between n_j and n0) are
//    re-evaluated at their border direction. This halves the SH cost.
//  - Scratch buffers are thread_local and only grow: no heap allocation once warm (the bench counts
//    them: 0). price*() may run concurrently on different sources.
// Results equal those of the generic squaredDistanceToCombination path with the same rule to ~1e-15
// relative (tests/unit/radiance_collapse_error_test.cpp).
//
// Degenerate post-collapse triangles (TriangleGradient::create fails: zero area, collinear
// vertices) contribute nothing: their gradient (eq. 3) is undefined, and the engine forbids such
// collapses by its own validity checks (flips, degeneracies), so a finite price is harmless and
// keeps the queue ordered. A collapse that kills every face of the source's star (a one-face
// corner) sums over no triangle and costs 0, as eq. (7) says; boundary handling is the engine's.
//
// Default rule, chosen by measurement (bench/bench_radiance_collapse, rule tables): relative error
// |E_rule - E_288| / E_288 of every half-edge cost against the 12 x 24 = 288-point Gauss rule of
// radiance_distance.h, worst over four data sets: random smooth RF on a bumpy patch of 1600
// vertices (normals up to 30 deg apart) and the striped glossy sphere of Vanhoey et al. 2015 Fig. 8
// (analytic material projected per vertex) on icospheres of level 1, 2, 3 (neighbour normals 32-36,
// 16-19, 8-9.5 deg apart); time per source vertex with all its half-edges, 1 thread (CPU time, patch
// data, AMD EPYC, SSE2 build):
//                     PB4                                    SH6
//     rule     p50     p99     max    us/vertex     p50     p99     max    us/vertex
//     3x6    2.6e-2  2.6e-1  4.1e-1     2.6       8.6e-2  5.2e-1  1.0e+0     4.7
//     4x8    5.4e-4  1.0e-2  2.0e-2     3.2       2.4e-2  1.2e-1  3.7e-1     6.1
//     5x10   1.1e-4  5.0e-3  9.4e-3     4.8  <-   2.5e-3  2.6e-2  5.0e-2     9.9
//     6x12   3.8e-5  2.8e-3  5.5e-3     5.8       7.2e-4  1.5e-2  3.8e-2    12.8
//     7x14   2.7e-5  1.2e-3  2.9e-3     7.9       4.6e-4  4.4e-3  1.3e-2    17.9  <-
//     8x16   1.5e-5  7.2e-4  1.5e-3     9.6       3.3e-4  2.5e-3  5.2e-3    21.9
//     12x24     0       0       0      20.0          0       0       0      47.6
//     24x48  4.4e-6  2.1e-4  5.1e-4    75.5       1.2e-4  1.0e-3  2.2e-3   183.9
// The 24x48 line is the 288-point rule's own error: the kink of the border extension (sec. 7)
// caps every rule's convergence, so differences below ~1e-3 are noise. The default is the Gauss
// product (d + 1) x 2 (d + 1) for degree d, the smallest that is exact when all normals agree (see
// defaultCollapseZNodes): PB4 5x10, max error < 1e-2 at 4.2x the speed of 288 points; SH6 7x14,
// p99 4e-3 and max 1.3e-2 at 2.7x (6x12 would be 3.7x but reaches 4e-2). On a 163842-vertex
// icosphere (bench, level 7): PB4 5.0 us/vertex on 1 thread, 2.5 on 2 (288 points: 19.9, 10.0);
// SH6 15.3 on 1 thread (288 points: 40.4).
#pragma once

#include "radiance/radiance_distance.h"
#include "radiance/radiance_field.h"
#include "simplify/collapse_metric.h"

#include <optional>
#include <string>
#include <vector>

namespace rad {

// The default rule for a basis of degree d: Gauss product (rule of radiance_distance.h) with
// m = d + 1 z-nodes and 2m phi-nodes, the smallest Gauss product rule that integrates d^2 exactly
// when every normal involved equals n0 (the integrand is then a polynomial of degree 2d: exact
// needs 2m - 1 >= 2d z-nodes and 2m >= 2d + 1 phi-nodes). PB4: 5 x 10 = 50 points; SH6: 7 x 14 = 98.
// Measured accuracy and speed: see the file comment.
int defaultCollapseZNodes(const BasisSpec& basis);
HemisphereIntegrator defaultCollapseIntegrator(const BasisSpec& basis);

struct RadianceCollapseOptions {
    // Hemisphere rule of eq. (6) (radiance_distance.h); weights must be >= 0 (they are for the Gauss
    // product and Lebedev rules). Empty: defaultCollapseIntegrator(field.basis).
    std::optional<HemisphereIntegrator> rule;
};

class RadianceCollapseMetric : public CollapseMetric {
public:
    // `field` holds one RF per mesh vertex and must outlive the metric; full collapses update it.
    // For SH the field is switched to reflected storage here (setReflectedStorage: coefficients of L~
    // in the global frame, what sec. 4.3 interpolates); PB fields are left as they are.
    // Throws std::invalid_argument when field.validate() fails or the rule is empty or has a
    // negative or non-finite weight.
    explicit RadianceCollapseMetric(RadianceField& field, RadianceCollapseOptions options = {});

    std::string name() const override { return "radiance error (Vanhoey et al. 2015 eq. 7)"; }

    // Eq. (7) for every target (a target that is not a neighbour of the source is priced the same
    // way: every star face becomes (target, a, b)). Throws std::invalid_argument when the mesh and
    // the field do not have the same vertex count.
    void priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query, double* costs) const override;

    // True for SH; for PB false with the reason (sec. 4.3).
    bool supportsFullCollapse(std::string& why) const override;

    // Sec. 4.3 (see the file comment). +infinity for PB (unsupported) and when (1 - s) n0 + s n1
    // vanishes (opposite normals: no interpolated hemisphere). s is clamped to [0, 1].
    double priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const override;

    // Full collapse (query.s != 1): writes the survivor's (slot v1) coefficients
    // (1 - s) c~0 + s c~1 and frame frameFromNormal(nv) as floats. With s == 1 (every half-edge
    // collapse, and a full collapse whose projection clamps onto p1) the survivor's attributes are
    // already v1's: nothing to do. Throws std::logic_error for a full collapse on a PB field.
    void onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) override;

    const RadianceField& field() const { return field_; }
    const HemisphereIntegrator& rule() const { return rule_; }

private:
    void checkMesh(const CollapseMesh& mesh) const;

    RadianceField& field_;
    HemisphereIntegrator rule_;
    // The rule as flat arrays (local points as structure of arrays, square roots of the weights),
    // padded with zero-weight points to a multiple of the kernel's chunk of directions.
    std::vector<double> localX_, localY_, localZ_, sqrtWeights_;
};

}  // namespace rad
