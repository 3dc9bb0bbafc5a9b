// Geometric error of a collapse: the memoryless quadric error metric.
//
// Garland & Heckbert 1997 define the quadric of a plane n.x + d = 0 as Q = (n n^T, d n, d^2) so that
// Q(x) = (n.x + d)^2 is the squared distance to the plane; a vertex's quadric is the sum over its
// faces. The MEMORYLESS variant (Lindstrom & Turk 1998, the one Vanhoey et al. 2015
// sec. 4.4 combines with its radiance metric, citing Hoppe 1999) does not accumulate quadrics over
// the history of collapses: a collapse is priced with the planes of the faces that are around the
// edge right now. Hence:
//   - half-edge v0 -> v1:  E_G = sum over the current faces f around v0 of Q_f(p1)
//     (the faces around v1 only contain p1 already, they contribute 0);
//   - full collapse (v0, v1) -> p:  E_G = sum over the faces around v0 or v1 of Q_f(p), with the
//     optimal p = argmin E_G when the 3x3 system is well conditioned, otherwise the best of p0, p1
//     and the midpoint.
// Planes are NOT area-weighted: E_G is then a sum of squared lengths (grows as scale^2), like the
// radiance error of eq. 7 (area x squared colour), so that their linear combination does not depend
// on the scale of the model (sec. 4.4: "our metric has quadratic growth in the mesh size").
#pragma once

#include "simplify/collapse_mesh.h"

#include <Eigen/Core>

#include <cstdint>

namespace rad {

struct Quadric {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    double c = 0.0;

    // (n.x + d)^2 = x^T A x + 2 b.x + c
    double evaluate(const Eigen::Vector3d& x) const { return x.dot(A * x) + 2.0 * b.dot(x) + c; }
    Quadric& operator+=(const Quadric& o) {
        A += o.A;
        b += o.b;
        c += o.c;
        return *this;
    }
    // Adds the plane of triangle (p0, p1, p2); degenerate triangles (no normal) add nothing.
    void addTrianglePlane(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2);
};

// Sum of the planes of the alive faces around v.
Quadric vertexQuadric(const CollapseMesh& mesh, std::uint32_t v);

// The position minimising q: the solution of A x = -b when A's smallest eigenvalue exceeds
// 1e-8 times its largest and the solution lies within twice the edge length of the edge's
// midpoint; otherwise the best of the candidates p0, p1, (p0 + p1) / 2.
Eigen::Vector3d optimalPosition(const Quadric& q, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1);

}  // namespace rad
