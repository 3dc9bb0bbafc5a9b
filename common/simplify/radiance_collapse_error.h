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
// The kernel evaluates each function of the ring once at the rule's directions and prices every
// (target, triangle) as a 3 x 3 quadratic form on the Gram matrix of the differences D_j = L~0 - L~_j;
// docs/simplification.md ("The eq. 7 pricing kernel") derives it and gives the measurements behind the
// default quadrature rule. It equals the generic squaredDistanceToCombination path to ~1e-15 relative.
//
// Degenerate post-collapse triangles (TriangleGradient::create fails: zero area, collinear
// vertices) contribute nothing: their gradient (eq. 3) is undefined, and the engine forbids such
// collapses by its own validity checks (flips, degeneracies), so a finite price is harmless and
// keeps the queue ordered. A collapse that kills every face of the source's star (a one-face
// corner) sums over no triangle and costs 0, as eq. (7) says; boundary handling is the engine's.
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
// Measured accuracy and speed: docs/simplification.md, "The eq. 7 pricing kernel".
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
