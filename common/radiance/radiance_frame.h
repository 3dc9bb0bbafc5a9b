// Per-vertex orthonormal frames for radiance functions (RF), and the reflection about a normal
// (Vanhoey et al. 2015): an RF lives on the hemisphere around the vertex normal n (sec. 3), the
// reflected RF is L~(w) = L(R_n w) with R_n(w) = 2 (n.w) n - w (sec. 3.1), PB lives in the local frame
// (t, b = n x t, n) and SH in the global frame (sec. 6). frameFromNormal is the closed form of Frisvad
// 2012 in the robust form of Duff et al. 2017, but with the sign s = +1, continuous everywhere except
// at n = -z, switching to s = -1 only within kFrameSouthCap of -z; frames are orthonormal to ~1e-15
// and right-handed (t x b = n).
// Details: docs/architecture.md, "`common/radiance/radiance_frame.h`: how it works".
#pragma once

#include <Eigen/Core>

namespace rad {

// 1 + n.z below which frameFromNormal uses the s = -1 branch (an angular radius of ~0.26 degrees).
inline constexpr double kFrameSouthCap = 1e-5;

struct Frame {
    Eigen::Vector3d t{1.0, 0.0, 0.0};  // tangent    (local x)
    Eigen::Vector3d b{0.0, 1.0, 0.0};  // bitangent  (local y) = n x t
    Eigen::Vector3d n{0.0, 0.0, 1.0};  // normal     (local z)

    // World direction -> local coordinates (t.w, b.w, n.w).
    Eigen::Vector3d toLocal(const Eigen::Vector3d& w) const { return {t.dot(w), b.dot(w), n.dot(w)}; }
    // Local coordinates -> world direction x t + y b + z n.
    Eigen::Vector3d toWorld(const Eigen::Vector3d& l) const { return l.x() * t + l.y() * b + l.z() * n; }
    // Rows t, b, n: local = rotation() * world.
    Eigen::Matrix3d rotation() const;
};

// Orthonormal right-handed frame with the given normal (normalised here; a zero or non-finite
// normal yields the canonical frame (x, y, z)). Continuous in n except at n = -z (see above).
Frame frameFromNormal(const Eigen::Vector3d& normal);

// Frame with the given normal whose tangent is the hint projected on the tangent plane
// (Gram-Schmidt). Falls back to frameFromNormal(normal) when the hint is (nearly) parallel to
// the normal (|t_perp| < 1e-6 |hint|), zero or non-finite.
Frame frameFromNormalAndTangent(const Eigen::Vector3d& normal, const Eigen::Vector3d& tangentHint);

// The frame stored in a RadianceField: f[0..2] = tangent, f[3..5] = normal (radiance_field.h).
// Re-orthonormalised in double (the stored floats are only orthonormal to float precision).
Frame frameFromStored(const float* f);
// Writes tangent and normal as the 6 floats of radiance_field.h.
void storeFrame(const Frame& frame, float* f);

// slerp(n0, n1, s) for unit normals (Vanhoey et al. 2010 sec. 4.3.2): the rotation of n0 towards n1
// by s alpha, alpha the angle between them. For opposite normals (no unique great circle) the
// rotation axis is frameFromNormal(n0).t.
Eigen::Vector3d slerpNormal(const Eigen::Vector3d& n0, const Eigen::Vector3d& n1, double s);

// R_n(w) = 2 (n . w) n - w, Vanhoey et al. 2015 sec. 3.1 (n must be unit).
inline Eigen::Vector3d reflect(const Eigen::Vector3d& n, const Eigen::Vector3d& w) { return 2.0 * n.dot(w) * n - w; }

}  // namespace rad
