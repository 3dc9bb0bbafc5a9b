// Geometric error of a collapse: the memoryless quadric error metric (Garland & Heckbert 1997's plane
// quadrics, in the memoryless variant of Lindstrom & Turk 1998 that Vanhoey et al. 2015 sec. 4.4
// combine with their radiance metric): a collapse is priced with the planes of the faces around the
// edge now, not accumulated over earlier collapses. Planes are not area-weighted, so E_G grows as
// scale^2 like eq. 7 and the 1 % / 99 % combination does not depend on the model's size.
// Details: docs/simplification.md, "`common/simplify/quadric_error.h`: how it works".
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
