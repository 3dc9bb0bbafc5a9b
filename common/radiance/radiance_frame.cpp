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

}  // namespace rad
