// The light-field error of Vanhoey et al. 2010, sec. 4 (the predecessor of the radiance error of
// Vanhoey et al. 2015), as a collapse metric: E_L + E_F of eq. 3-4 for a half-edge or full collapse,
// E_L a quadric in the new vertex's coefficients minimised by eq. 6 (with a small ridge), integrated
// over the lune between the two hemispheres by Gauss-Legendre quadrature in coordinates about the
// lune's edge. The engine adds the geometric QEM and the weight (lambda). How the paper's light fields
// map onto this project's radiance functions, the units and bounds, the ridge and the quadrature's
// measured accuracy: docs/simplification.md, "The light-field quadric of Vanhoey et al. 2010, as
// implemented".
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
