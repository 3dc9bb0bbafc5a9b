// The baseline "extended colour QEM" of Garland and Heckbert 1998 (GH98 below; cited by Vanhoey et
// al. 2010 sec. 2.2.1): each vertex is a point (position, linear RGB) of R^6, each face the plane
// through its three 6D points, and a vertex's quadric the area-weighted sum of the squared distances
// to the planes of every original face it stands for (accumulated on collapse). Positions are
// normalised by the bounding-box diagonal so that they weigh like colours. The quadric already holds
// the geometric distance, so pure GH98 is run with the engine's geometryWeight = 0.
// Details: docs/simplification.md, "`common/simplify/color_quadric.h`: how it works".
#pragma once

#include "simplify/collapse_metric.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace rad {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// A quadric over R^6 (x, y, z, r, g, b): Q(v) = v^T A v + 2 b.v + c.
struct ColorQuadric {
    Matrix6d A = Matrix6d::Zero();
    Vector6d b = Vector6d::Zero();
    double c = 0.0;

    double evaluate(const Vector6d& v) const { return v.dot(A * v) + 2.0 * b.dot(v) + c; }
    double evaluate(const Eigen::Vector3d& position, const Eigen::Vector3d& color) const {
        Vector6d v;
        v << position, color;
        return evaluate(v);
    }
    ColorQuadric& operator+=(const ColorQuadric& o) {
        A += o.A;
        b += o.b;
        c += o.c;
        return *this;
    }
    ColorQuadric& operator*=(double w) {
        A *= w;
        b *= w;
        c *= w;
        return *this;
    }

    // Squared distance to the plane through p, q, r (unweighted; GH98). The zero quadric
    // when the three points are collinear in R^6 (|e2 before normalisation| <= 1e-12 times the
    // longer of q - p, r - p, or a zero edge).
    static ColorQuadric triangle(const Vector6d& p, const Vector6d& q, const Vector6d& r);

    // argmin over colours c of Q(x, c) for a fixed position x: A_cc c = -(A_cp x + b_c). Directions in
    // which A_cc has no curvature (eigenvalue <= 1e-12 times its largest, or all of them when
    // A_cc = 0) keep the component of `fallback`: the result is the minimiser closest to it.
    Eigen::Vector3d optimalColor(const Eigen::Vector3d& x, const Eigen::Vector3d& fallback) const;
};

struct ColorQuadricOptions {
    // Multiplies positions (after centring) before they meet colours. 0: 1 / bounding-box diagonal
    // of the alive vertices (1 when that diagonal is 0).
    double geometryScale = 0.0;
    bool areaWeighted = true;  // GH98: weight each face quadric by its (normalised) 3D area
};

class ColorQuadricMetric : public CollapseMetric {
public:
    // colors: one linear RGB colour per vertex, 3 floats each (colors[3 v + 0..2]), e.g. the mean
    // colour of each vertex's radiance function (the caller computes it). Builds the vertex
    // quadrics from the alive faces of `mesh`. Throws std::invalid_argument when colors.size() !=
    // 3 * mesh.vertexCount(), a colour is not finite or geometryScale is negative or not finite.
    ColorQuadricMetric(const CollapseMesh& mesh, const std::vector<float>& colors, ColorQuadricOptions options = {});

    std::string name() const override { return "colour quadric (Garland-Heckbert 1998)"; }
    void priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query, double* costs) const override;
    bool supportsFullCollapse(std::string& why) const override {
        why.clear();
        return true;
    }
    double priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const override;
    // Q1 += Q0; the survivor's colour becomes c* (full collapse) or stays (half-edge).
    void onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) override;

    // The current colour of every vertex, colors()[3 v + 0..2] (dead vertices keep their last one):
    // what the caller writes back to the simplified mesh.
    const std::vector<double>& colors() const { return colors_; }
    Eigen::Vector3d color(std::uint32_t v) const { return {colors_[3 * v], colors_[3 * v + 1], colors_[3 * v + 2]}; }
    // The accumulated quadric of v, in normalised coordinates.
    ColorQuadric quadric(std::uint32_t v) const;
    // x' = scale (x - centre), the coordinates the quadrics live in.
    Eigen::Vector3d normalizedPosition(const Eigen::Vector3d& x) const { return scale_ * (x - centre_); }
    double geometryScale() const { return scale_; }
    const Eigen::Vector3d& centre() const { return centre_; }

private:
    void addQuadric(std::uint32_t v, const ColorQuadric& q);
    // Q_v0 + Q_v1 without building two ColorQuadric.
    ColorQuadric sum(std::uint32_t v0, std::uint32_t v1) const;
    // (Q0 + Q1) and the survivor's colour for the query (half-edge: c1).
    Eigen::Vector3d survivorColor(const ColorQuadric& q, const EdgeQuery& query, const Eigen::Vector3d& x) const;

    Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
    double scale_ = 1.0;
    std::vector<double> colors_;    // 3 per vertex
    std::vector<double> quadrics_;  // kPacked per vertex: upper triangle of A (21), b (6), c (1)
};

}  // namespace rad
