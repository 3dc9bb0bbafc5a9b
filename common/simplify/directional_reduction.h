// Directional reduction: the alternative to mesh simplification that Vanhoey et al. 2015 (Fig. 7)
// compare against at equal memory. Every vertex is kept, but its radiance function (RF) is
// re-expressed in a basis of lower degree of the same kind (SH by truncation, PB by least-squares
// projection over the hemisphere), so the memory saved comes from the directional resolution
// instead of the spatial one. equalMemoryDegree picks the degree whose memory (as counted by
// render/image_space_error.h) is closest to that of a simplification keeping a given vertex ratio.
// Details: docs/simplification.md, "`common/simplify/directional_reduction.h`: how it works".
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
