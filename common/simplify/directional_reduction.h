// Directional reduction: the alternative to mesh simplification that Vanhoey et al. 2015
// (Fig. 7 and its discussion) compare against at equal memory. Every vertex is kept, but its
// radiance function (RF) is re-expressed in a basis of lower degree, so the memory saved comes from
// the directional resolution instead of the spatial one.
//
// Definitions (per vertex and colour channel, f the stored function, P the lower basis):
//  - SH(d) -> SH(d'), d' <= d: truncation to bands l <= d'. SH are orthonormal on the sphere, so
//    keeping the first (d'+1)^2 coefficients (index l^2 + l + m, basis.h) IS the L2 projection of f
//    on SH(d') over the whole sphere, exact, with the squared L2 error equal to the sum of the
//    squares of the dropped coefficients (Parseval). The stored function is what is projected,
//    whatever the storage: the reflected RF L~(w) = L(R_n w) (sec. 3.1) is L composed with a rotation,
//    and rotations act inside each band, so truncating L~ gives the reflected function of the
//    truncated L. The storage flag and the frames are kept.
//  - PB(d) -> PB(d'), d' <= d: least-squares (L2) projection over the hemisphere of the vertex,
//        argmin_{g in PB(d')} integral_{n.w >= 0} (f(w) - g(w))^2 dw,
//    the projection of radiance/radiance_projection.h (FunctionProjector: Gram system solved with
//    the exact hemisphere quadrature). PB functions live in the local frame, in which f, g and the
//    measure are the same for every vertex, so the projection is ONE matrix
//        P = G'^-1 M,   G'_jk = <B'_j, B'_k>,   M_jk = <B'_j, B_k>   (K' x K, hemisphere inner product)
//    computed once (each column with FunctionProjector applied to one basis function of PB(d) in
//    the canonical frame) and applied to every vertex and channel. Reflected PB storage is f(-u, -v):
//    the hemisphere measure and PB(d') are invariant under (u, v) -> (-u, -v), so P commutes with
//    the reflection and the storage flag is kept. Polynomials already in PB(d') are reproduced
//    exactly (up to rounding).
//  - Same basis: identity (a copy).
// The PB -> PB projection does not include the border extension (sec. 7): it is defined on the
// hemisphere, like the PB fit.
//
// Equal memory (equalMemoryDegree): with the memory of render/image_space_error.h,
//     mem(V, F, basis) = V * (12 + 12 K(basis) + frame(basis)) + 12 F,
// a simplification keeping a fraction r of the V vertices (and, on a closed manifold, about the same
// fraction of the F faces: F ~ 2V) in the original basis B holds
//     r V (12 + 12 K(B) + frame(B)) + 12 r F,
// a directional reduction to degree d holds V (12 + 12 K(d) + frame) + 12 F. equalMemoryDegree
// returns the degree d in 0..deg(B) of the same kind whose memory is closest to the simplification's
// (ties: the lower degree, i.e. never more memory than necessary), with F = facesPerVertex * V.
#pragma once

#include "radiance/basis.h"
#include "radiance/radiance_field.h"

namespace rad {

// The field re-expressed in `lowerBasis` (see the file comment). Parallel over vertices (OpenMP).
// \pre field.validate() is empty.
// \throw std::invalid_argument when the field is invalid, lowerBasis is invalid, of another kind
//        (PB <-> SH) or of a higher degree than the field's.
RadianceField reduceDirectionalDegree(const RadianceField& field, BasisSpec lowerBasis);

// The degree of the field's basis kind whose directional reduction uses the memory closest to that
// of a simplification keeping the fraction `vertexRatio` of the vertices (file comment).
// facesPerVertex: F / V of the mesh (2 for a closed manifold of genus 0, about 2 for scans).
// \throw std::invalid_argument when the basis is invalid, vertexRatio is not in (0, 1] or
//        facesPerVertex is negative or not finite.
int equalMemoryDegree(const BasisSpec& original, double vertexRatio, double facesPerVertex = 2.0);
inline int equalMemoryDegree(const RadianceField& original, double vertexRatio, double facesPerVertex = 2.0) {
    return equalMemoryDegree(original.basis, vertexRatio, facesPerVertex);
}

}  // namespace rad
