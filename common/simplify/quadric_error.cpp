#include "simplify/quadric_error.h"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace rad {

void Quadric::addTrianglePlane(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2) {
    Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    const double length = n.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return;
    n /= length;
    const double d = -n.dot(p0);
    A += n * n.transpose();
    b += d * n;
    c += d * d;
}

Quadric vertexQuadric(const CollapseMesh& mesh, std::uint32_t v) {
    Quadric q;
    for (std::uint32_t f : mesh.incidentFaces(v)) {
        const std::uint32_t* t = mesh.face(f);
        q.addTrianglePlane(mesh.position(t[0]), mesh.position(t[1]), mesh.position(t[2]));
    }
    return q;
}

Eigen::Vector3d optimalPosition(const Quadric& q, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(q.A);
    const Eigen::Vector3d lambda = eigen.eigenvalues();  // increasing
    if (lambda(2) > 0.0 && lambda(0) > 1e-8 * lambda(2)) {
        const Eigen::Vector3d x = eigen.eigenvectors() *
                                  (eigen.eigenvectors().transpose() * (-q.b)).cwiseQuotient(lambda);
        // A nearly flat configuration can put the minimiser far from the edge: keep it only near.
        if (x.allFinite() && (x - 0.5 * (p0 + p1)).norm() <= 2.0 * (p1 - p0).norm()) return x;
    }
    const Eigen::Vector3d mid = 0.5 * (p0 + p1);
    Eigen::Vector3d best = p0;
    double bestCost = q.evaluate(p0);
    for (const Eigen::Vector3d& candidate : {p1, mid}) {
        const double cost = q.evaluate(candidate);
        if (cost < bestCost) {
            bestCost = cost;
            best = candidate;
        }
    }
    return best;
}

}  // namespace rad
