// The accumulating radiance quadric: geometry and per-vertex radiance functions (RF) in one quadric
// per vertex, summed on every collapse, after
//   H. Hoppe, "New quadric metric for simplifying meshes with appearance attributes", IEEE
//   Visualization 1999 (cited by Vanhoey et al. 2015), and
//   M. Garland, P. S. Heckbert, "Simplifying surfaces with color and texture using quadric error
//   metrics", IEEE Visualization 1998.
//
// Each original face t contributes, for a point p and an attribute vector s (m values),
//     Q_t(p, s) = area_t * [ (n_t.p + d_t)^2 + sum_j (g_tj.p + e_tj - s_j)^2 ]
// where n_t.p + d_t is the distance to the face's plane and g_tj.p + e_tj the attribute j interpolated
// linearly over the face (in its plane, Hoppe 1999 sec. 4) and extended to space. A vertex's quadric
// is the sum over its faces; a collapse adds the two quadrics, so the error is measured against
// every original face a vertex stands for (Garland & Heckbert's accumulation), not against the
// current 1-ring only (the memoryless eq. 7 of Vanhoey et al. 2015).
// Stored in Hoppe 1999's compact form (O(m), not O(m^2)): A = sum a (n n^T + sum_j g_j g_j^T),
// b = sum a (d n + sum_j e_j g_j), c = sum a (d^2 + sum_j e_j^2), W = sum a, G_j = sum a g_j,
// E_j = sum a e_j, so that Q(p, s) = p^T A p + 2 b.p + c - 2 sum_j s_j (G_j.p + E_j) + W |s|^2.
// For a fixed p the best attributes are s*_j = (G_j.p + E_j) / W (the area-weighted average of the
// faces' attribute planes at p), and Q(p, s*) = p^T A' p + 2 b'.p + c' with A' = A - G G^T / W...:
// one 3x3 solve gives the optimal position of a full collapse, and s* the new vertex's RF.
//
// Attributes are the RFs in one space where the Euclidean distance is an L2 distance between the
// functions (Vanhoey et al. 2015 eq. 5-6): SH coefficients as they are (orthonormal, global frame).
// A PB function of degree d lives in its vertex's local frame, but each of its monomials
// (t.w)^i (b.w)^j is a polynomial of degree <= d in the world direction w, so the function is
// exactly an SH expansion of degree d in the world frame: PB fields are converted to it (a sphere
// quadrature exact to degree 2d), so that neighbours with different frames are compared as the
// functions they are; a full collapse's optimal function is projected back onto PB in the
// survivor's frame (least squares over its hemisphere, the basis's Gram matrix there).
//
// Scale: positions are normalised by the bounding-box diagonal and the attributes by the RMS L2
// norm of the field's functions, so neither the scan's size nor the radiance's range changes which
// collapse wins; `radianceWeight` is the one balance between them (the default was chosen once, on
// the benchmark's meshes, and is documented with its measurements).
#pragma once

#include "radiance/radiance_field.h"
#include "simplify/collapse_metric.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rad {

struct RadianceQuadricOptions {
    double geometryWeight = 1.0;   // multiplies the squared distances to the planes
    double radianceWeight = 1.0;   // multiplies the squared (normalised) RF distances
    // Errors weighed as 8-bit photographs see them: each channel's attribute error at a face is
    // multiplied by (d sRGB / d L at the corners' mean colour)^perceptualExponent (normalised to mean
    // 1), so that a dark region's change counts as much as it shows. 0: linear radiance.
    double perceptualExponent = 0.0;
    int threads = 0;               // building the quadrics; 0: OpenMP default
};

// The basis's Gram matrix over the hemisphere z >= 0 (integrals divided by 2 pi), K x K, row major:
// what makes sum_k c_k B_k an element of L2 with |f|^2 = c^T M c.
std::vector<double> hemisphereGramMatrix(const BasisSpec& basis);

class RadianceQuadricMetric : public CollapseMetric {
public:
    // Builds every vertex's quadric from the alive faces of `mesh`. `field` is read and, on full
    // collapses, the survivor's coefficients are rewritten with the optimal RF. Throws
    // std::invalid_argument when the field does not match the mesh or a weight is negative or not finite.
    RadianceQuadricMetric(const CollapseMesh& mesh, RadianceField& field, RadianceQuadricOptions options = {});

    std::string name() const override { return "radiance quadric (Hoppe 1999)"; }
    bool ownsGeometry() const override { return true; }
    bool costDependsOnEndpointsOnly() const override { return true; }
    void priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query, double* costs) const override;
    bool supportsFullCollapse(std::string& why) const override {
        why.clear();
        return true;
    }
    bool placeEdge(const CollapseMesh& mesh, std::uint32_t v0, std::uint32_t v1, Eigen::Vector3d& position) const override;
    double priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const override;
    void onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) override;

    int attributeCount() const { return m_; }
    // Q_v(p, s) for a world position and attributes in the metric's space (tests).
    double evaluate(std::uint32_t v, const Eigen::Vector3d& worldPosition, const double* attributes) const;
    // The attributes of v in the metric's space (m values).
    void attributes(std::uint32_t v, double* out) const;
    double positionScale() const { return positionScale_; }
    double attributeScale() const { return attributeScale_; }
    std::size_t bytes() const;  // memory held by the quadrics and attributes

private:
    struct Sum;  // Q_v0 + Q_v1, unpacked for repeated evaluation
    struct Placement {
        const RadianceQuadricMetric* metric = nullptr;
        std::uint64_t collapses = 0;  // the metric's state it was computed in
        std::uint32_t v0 = 0, v1 = 0;
        Eigen::Vector3d position = Eigen::Vector3d::Zero();
        double cost = 0.0;
    };
    static Placement& lastPlacement();  // per thread
    void sumOf(std::uint32_t v0, std::uint32_t v1, Sum& out) const;
    double evaluateSum(const Sum& q, const Eigen::Vector3d& normalised, const float* attributes) const;
    struct FaceQuadric {  // one face's terms, laid out as a vertex's
        explicit FaceQuadric(int m) : gradients(4 * std::size_t(m)) {}
        std::array<double, 23> geometric{};
        std::vector<double> gradients;
    };
    static std::vector<float> perceptualChannelWeights(const RadianceField& field, double exponent);
    void buildVertexQuadrics(const CollapseMesh& mesh, const std::vector<float>& channelWeight);
    bool faceQuadric(const CollapseMesh& mesh, const std::uint32_t* corners, const std::vector<float>& channelWeight,
                     FaceQuadric& out) const;
    void reduce(const Sum& q, double* reduced) const;  // min over s of Q(p, s), a quadric in p: 10 values
    static double evaluateOptimal(const double* reduced, const Eigen::Vector3d& normalised);
    Eigen::Vector3d normalise(const Eigen::Vector3d& world) const { return positionScale_ * (world - centre_); }
    void toMetric(std::size_t v, const float* coefficients, float* attributes) const;
    void fromMetric(std::size_t v, const double* attributes, float* coefficients) const;

    RadianceField& field_;
    std::uint64_t collapses_ = 0;  // onCollapse calls: tells a cached placement's state apart
    RadianceQuadricOptions options_;
    int k_ = 0, m_ = 0;  // coefficients per channel of the field; attributes per vertex (3 x the metric's)
    Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
    double positionScale_ = 1.0, attributeScale_ = 1.0;
    // PB fields: the world SH of degree d (kSh functions) at the points of a sphere rule, and a
    // hemisphere rule with the PB Gram matrix's inverse for the way back.
    bool convertsFrames_ = false;
    int kSh_ = 0;
    std::vector<Eigen::Vector3d> spherePoints_, hemispherePoints_;
    std::vector<double> sphereWeights_, hemisphereWeights_;
    std::vector<double> sphereSh_;           // kSh per sphere point
    std::vector<double> gramInverse_;        // K x K, PB over the hemisphere
    // Per vertex: the geometric block A (6, upper triangle), b (3), c, W in doubles...
    std::vector<double> geometric_;              // kGeometric per vertex
    // ...and G (3 m) then E (m), in doubles too: the cost subtracts nearly equal sums (c and the
    // squared attribute planes), which float storage turns into noise as large as real costs.
    std::vector<double> gradients_;
    std::vector<float> attributes_;              // m per vertex: the current RF in the metric's space
};

}  // namespace rad
