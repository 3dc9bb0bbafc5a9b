// The radiance error of a collapse, Vanhoey et al. 2015 sec. 4.1 and 4.3, as a pricing module of the
// edge-collapse engine (collapse_metric.h): for a half-edge collapse v0 -> v1, eq. (7), the
// area-weighted squared distance (eq. 5-6, over the hemisphere of v0's RF normal) between v0's
// reflected RF and the eq. (4) extrapolation to p0 of each post-collapse triangle's RF; for a full
// collapse (SH only) the same at both ends for the RF interpolated along the edge. Degenerate
// post-collapse triangles contribute nothing. The field must outlive the metric; full collapses
// rewrite it.
// Details: docs/simplification.md, "`common/simplify/radiance_collapse_error.h`: how it works".
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
