// The baseline "extended colour QEM": M. Garland and P. S. Heckbert, "Simplifying surfaces with
// color and texture using quadric error metrics", IEEE Visualization 1998 (GH98;
// cited by Vanhoey et al. 2010 sec. 2.2.1 as [GH98]). Each vertex is a point v = (p, c) of R^6
// (position x, y, z and linear RGB colour r, g, b) and each face a 2D affine subspace of R^6, the
// plane through its three 6D points. GH98: with an orthonormal basis e1, e2 of that plane
// (Gram-Schmidt on q - p, r - p), the squared distance of v to it is
//     Q(v) = v^T A v + 2 b.v + c,   A = I - e1 e1^T - e2 e2^T,
//                                   b = (p.e1) e1 + (p.e2) e2 - p,
//                                   c = p.p - (p.e1)^2 - (p.e2)^2.
// Choices made here, with GH98:
//  - face quadrics are weighted by the triangle's 3D area, as GH98 does (area weighting makes the
//    error independent of the tessellation); option areaWeighted = false turns it
//    off. Area is the geometric area in normalised coordinates (below), not the 6D area, so that a
//    colour discontinuity does not make a face weigh more;
//  - a vertex's quadric is the sum of its faces' quadrics, and quadrics are ACCUMULATED on collapse
//    (Q1 += Q0): the error is measured against the planes of every original face the survivor
//    stands for (the "cumulative" QEM of Vanhoey et al. 2010 sec. 3.1, unlike the memoryless E_G of
//    quadric_error.h that the engine adds separately);
//  - geometry is normalised, x' = scale (x - centre) with centre the bounding-box centre and scale
//    1 / bounding-box diagonal by default, so that positions span about [-0.5, 0.5] like linear RGB
//    colours span [0, 1]: GH98 notes that the relative scale of position and colour sets the
//    trade-off between them. The translation changes nothing but rounding (c = p.p stays small).
//    Costs are therefore in normalised units: area' x (squared 6D distance).
// The quadric includes the geometric distance too (the 6D plane contains the face's 3D plane), so
// pure GH98 is obtained with the engine's geometryWeight = 0.
//
// Collapses (collapse_metric.h):
//  - half-edge v0 -> v1: cost (Q0 + Q1)(p1', c1); v1 keeps its colour;
//  - full (v0, v1) -> position: cost (Q0 + Q1)(x', c*) with c* the colour minimising the quadric for
//    the fixed position x' (GH98 optimises all 6 coordinates; the engine fixes the position with its
//    own QEM, so only the colour block is solved): splitting A into blocks [A_pp A_pc; A_cp A_cc] and b
//    into (b_p, b_c), grad_c Q = 0 gives  A_cc c* = -(A_cp x' + b_c).  A_cc is singular only for
//    degenerate stars (no area); in the null directions c* takes the edge interpolation
//    (1 - s) c0 + s c1 (minimum-norm correction from it, see optimalColor).
// Half-edge collapses (EdgeQuery::halfEdge) keep c1; full ones get c*, even when they land at s == 1.
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

    // argmin over colours c of Q(x, c) for a fixed position x (see the file comment). Directions in
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
