// Per-vertex orthonormal frames for radiance functions (RF), and the reflection about a normal.
//
// Vanhoey et al. 2015:
//  - sec. 3: the RF of a vertex is defined on the hemisphere centred on the vertex normal n;
//  - sec. 3.1: the reflected RF (r-RF) is L~(w) = L(R_n w) with the reflection about n
//        R_n(w) = 2 (n . w) n - w          (a rotation by pi about n; R_n R_n = identity)
//  - sec. 6: the polynomial basis (PB) lives in a local frame (x = tangent t, y = bitangent b = n x t,
//    z = normal n); spherical harmonics (SH) live in the global frame.
//
// Frame construction from a normal alone (frameFromNormal) follows the closed form of
// J. R. Frisvad, "Building an orthonormal basis from a 3D unit vector without normalization",
// JGT 2012, in the numerically robust form of T. Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 6(1) 2017. Duff et al. pick the sign s = sign(n.z), which makes the frame
// jump across the whole great circle n.z = 0 (i.e. between neighbouring vertices of any closed
// mesh). We instead use s = +1 (continuous everywhere except at n = -z, where no continuous
// tangent field can avoid a singularity) and switch to s = -1 only inside a tiny cap around
// -z (1 + n.z < kFrameSouthCap, an angular radius of ~0.26 degrees), where the s = +1 formula
// loses precision (error ~ 1e-16 / (1 + n.z)). The result is re-orthonormalised, so every frame
// is orthonormal to ~1e-15 and right-handed (t x b = n).
#pragma once

#include <Eigen/Core>

namespace rad {

// 1 + n.z below which frameFromNormal uses the s = -1 branch (see above).
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

// R_n(w) = 2 (n . w) n - w, Vanhoey et al. 2015 sec. 3.1 (n must be unit).
inline Eigen::Vector3d reflect(const Eigen::Vector3d& n, const Eigen::Vector3d& w) { return 2.0 * n.dot(w) * n - w; }

}  // namespace rad
