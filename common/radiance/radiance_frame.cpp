#include "radiance/radiance_frame.h"

#include <Eigen/Geometry>

#include <cmath>

namespace rad {

namespace {
bool isFinite(const Eigen::Vector3d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// Gram-Schmidt of t against the unit n, then b = n x t. t must not be parallel to n.
Frame orthonormalise(const Eigen::Vector3d& n, const Eigen::Vector3d& t) {
    Frame f;
    f.n = n;
    f.t = (t - n.dot(t) * n).normalized();
    f.b = n.cross(f.t);
    return f;
}
}  // namespace

Eigen::Matrix3d Frame::rotation() const {
    Eigen::Matrix3d r;
    r.row(0) = t.transpose();
    r.row(1) = b.transpose();
    r.row(2) = n.transpose();
    return r;
}

Frame frameFromNormal(const Eigen::Vector3d& normal) {
    const double len = normal.norm();
    if (!(len > 0.0) || !std::isfinite(len)) return Frame{};
    const Eigen::Vector3d n = normal / len;
    // Frisvad 2012 / Duff et al. 2017 closed form with sign s (see the header for the choice of s).
    const double s = (1.0 + n.z() < kFrameSouthCap) ? -1.0 : 1.0;
    const double a = -1.0 / (s + n.z());
    const double c = n.x() * n.y() * a;
    const Eigen::Vector3d t(1.0 + s * n.x() * n.x() * a, s * c, -s * n.x());
    return orthonormalise(n, t);
}

Frame frameFromNormalAndTangent(const Eigen::Vector3d& normal, const Eigen::Vector3d& tangentHint) {
    const double len = normal.norm();
    if (!(len > 0.0) || !std::isfinite(len)) return Frame{};
    const Eigen::Vector3d n = normal / len;
    if (!isFinite(tangentHint)) return frameFromNormal(n);
    const double hintLen = tangentHint.norm();
    const Eigen::Vector3d perp = tangentHint - n.dot(tangentHint) * n;
    if (!(hintLen > 0.0) || perp.norm() < 1e-6 * hintLen) return frameFromNormal(n);
    return orthonormalise(n, perp);
}

Frame frameFromStored(const float* f) {
    return frameFromNormalAndTangent(Eigen::Vector3d(f[3], f[4], f[5]), Eigen::Vector3d(f[0], f[1], f[2]));
}

void storeFrame(const Frame& frame, float* f) {
    for (int i = 0; i < 3; ++i) {
        f[i] = static_cast<float>(frame.t[i]);
        f[3 + i] = static_cast<float>(frame.n[i]);
    }
}

Eigen::Vector3d slerpNormal(const Eigen::Vector3d& n0, const Eigen::Vector3d& n1, double s) {
    const Eigen::Vector3d cross = n0.cross(n1);
    const double sine = cross.norm();
    const double alpha = std::atan2(sine, n0.dot(n1));
    if (alpha == 0.0) return n0;
    // Rotation of n0 about axis e by s alpha: cos(s alpha) n0 + sin(s alpha) (e x n0). With
    // e = n0 x n1 / |n0 x n1|, e x n0 is the unit direction of n1's component orthogonal to n0.
    const Eigen::Vector3d e = sine > 1e-12 ? Eigen::Vector3d(cross / sine) : frameFromNormal(n0).t;
    const Eigen::Vector3d n = std::cos(s * alpha) * n0 + std::sin(s * alpha) * e.cross(n0);
    return n.normalized();
}

}  // namespace rad
