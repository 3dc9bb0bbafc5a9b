// The accumulating radiance quadric: geometry and per-vertex radiance functions (RF) in one quadric
// per vertex, summed on every collapse, after Hoppe 1999 (cited by Vanhoey et al. 2015) and Garland &
// Heckbert 1998. Unlike the memoryless eq. 7 of Vanhoey et al. 2015, the error is measured against
// every original face a vertex stands for. The RFs are compared as L2 functions (PB fields converted
// to world-frame SH), positions and radiance are normalised, and a full collapse gives the new vertex
// the quadric's optimal RF. The default simplification metric; its weights and their measurements:
// docs/design-notes.md, "The accumulating radiance quadric".
// Details: docs/simplification.md, "`common/simplify/radiance_quadric.h`: how it works".
#pragma once

#include "radiance/radiance_field.h"
#include "radiance/world_sh_conversion.h"
#include "simplify/collapse_metric.h"

#include <Eigen/Core>

#include <array>
#include <atomic>
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
    // Boundary planes (Garland & Heckbert 1997) on the mesh's boundary edges; false skips looking
    // for them (a caller that knows the mesh is closed).
    bool boundaryPlanes = true;
};

class RadianceQuadricMetric : public CollapseMetric {
public:
    // Builds every vertex's quadric from the alive faces of `mesh`. `field` is read and, on full
    // collapses, the survivor's coefficients are rewritten with the optimal RF. Throws
    // std::invalid_argument when the field does not match the mesh or a weight is negative or not finite.
    RadianceQuadricMetric(const CollapseMesh& mesh, RadianceField& field, RadianceQuadricOptions options = {});

    std::string name() const override { return "radiance quadric (Hoppe 1999)"; }
    bool ownsGeometry() const override { return true; }
    bool costDependsOnEndpointsOnly() const override { return true; }
    bool updatesCanBeDeferred() const override { return true; }  // onCollapse touches its two ends only
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
    struct GradientBlock {
        const float *x, *y, *z, *e;
    };
    GradientBlock gradientBlock(const float* block) const;
    struct Placement {
        const RadianceQuadricMetric* metric = nullptr;
        std::uint64_t collapses = 0;  // the metric's state it was computed in
        std::uint32_t v0 = 0, v1 = 0;
        Eigen::Vector3d position = Eigen::Vector3d::Zero();
        double cost = 0.0;
    };
    static Placement& lastPlacement();  // per thread
    void sumOf(std::uint32_t v0, std::uint32_t v1, Sum& out) const;
    // The sum's local block about v1's origin and reference: v1's, plus v0's moved there.
    void sumLocal(const Sum& q, double* out) const;
    // How a vertex's planes change when moved by t and taken against another reference (delta = r -
    // newReference): g = sum_j delta_j G_j, e = sum_j delta_j (E_j + G_j.t), w = sum_j W_c delta_j^2.
    struct ReferenceShift {
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        double e = 0.0, w = 0.0;
    };
    ReferenceShift referenceShift(const float* planes, const float* reference, const float* newReference,
                                  const double* weight, const Eigen::Vector3d& t) const;
    double evaluateSum(const Sum& q, const Eigen::Vector3d& normalised, const float* attributes) const;
    struct FaceQuadric {  // one face's terms, laid out as a vertex's
        explicit FaceQuadric(int m) : gradients(3 * std::size_t(m)), cornerValues(std::size_t(m)) {}
        std::array<double, 23> geometric{};
        std::vector<double> gradients;     // weight x the attribute planes' gradients: x (m), y (m), z (m)
        std::vector<double> cornerValues;  // weight x the attributes at the first corner (m)
        Eigen::Vector3d firstCorner;       // normalised
    };
    // Adds a face's attribute planes to vertex v's, their offsets taken at v's origin.
    void addFacePlanes(const FaceQuadric& face, std::uint32_t v);
    static std::vector<float> perceptualChannelWeights(const RadianceField& field, double exponent);
    void buildVertexQuadrics(const CollapseMesh& mesh, const std::vector<float>& channelWeight);
    void addBoundaryPlanes(const CollapseMesh& mesh, const std::uint32_t* corners);
    bool faceQuadric(const CollapseMesh& mesh, const std::uint32_t* corners, const std::vector<float>& channelWeight,
                     FaceQuadric& out) const;
    void reduce(const Sum& q, double* reduced) const;  // min over s of Q(p, s), a quadric in p: 10 values
    static double evaluateOptimal(const double* reduced, const Eigen::Vector3d& normalised);
    Eigen::Vector3d normalise(const Eigen::Vector3d& world) const { return positionScale_ * (world - centre_); }
    Eigen::Vector3d origin(std::uint32_t v) const {
        return {origins_[3 * std::size_t(v)], origins_[3 * std::size_t(v) + 1], origins_[3 * std::size_t(v) + 2]};
    }
    void toMetric(std::size_t v, float* attributes) const;

    RadianceField& field_;
    std::atomic<std::uint64_t> collapses_{0};  // onCollapse calls: tells a cached placement's state apart
    RadianceQuadricOptions options_;
    int m_ = 0;  // attributes per vertex (3 x the metric's per channel)
    Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
    double positionScale_ = 1.0, attributeScale_ = 1.0;
    // PB fields are compared as world SH of the same degree (kSh_ functions per channel).
    WorldShConversion conversion_;
    int kSh_ = 0;
    // Per vertex v, about its origin o_v (its normalised position, moved with it) and its reference r_v
    // (its current function, attributes_): sum over the original faces f it stands for of
    // w_f |s - a_f(p)|^2, a_f the face's attribute planes, written with d = p - o_v, u = s - r_v as
    //   C(d) - 2 sum_j u_j (G_j.d + E_j) + W |u|^2,
    // G_j = sum w_f g_fj, E_j = sum w_f (a_fj(o_v) - r_vj), C(d) = sum w_f |a_f(p) - r_v|^2 (a quadric
    // in d). Every term is of the size of the radiance's change over the faces, not of the radiance:
    // the cost, C minus the planes' squares, subtracts no large nearly equal sums, so the planes fit
    // in floats (about the scan's centre, or about 0, the sums cancel to within rounding in doubles
    // only: design-notes, "Precision").
    // The block of doubles: W, the faces' planes (normalised coordinates), C: kGeometric per vertex.
    std::vector<double> geometric_;
    std::vector<float> gradients_;   // G_x, G_y, G_z, then E (m each)
    std::vector<double> origins_;    // o_v: 3 per vertex
    std::vector<float> attributes_;              // m per vertex: the current RF in the metric's space
};

}  // namespace rad
