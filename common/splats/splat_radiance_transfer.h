// The radiance of a 3D Gaussian Splatting scene (Kerbl et al. 2023) moved onto a mesh's vertices, as
// one spherical-harmonic radiance function (RF) per vertex of the splats' own degree, in our
// conventions (global-frame SH without the Condon-Shortley phase, linear radiance; the frame stores
// the vertex normal). Each vertex blends the colours of the splats near it and in front of it,
// weighted by their Gaussians widened by the vertex footprint (EWA splatting, Zwicker et al. 2001),
// and fits the result over its hemisphere. A vertex no splat reaches gets the zero RF (counted).
// Details: docs/gaussian-splats.md, "Weighting: which splats, how much" and the section after it.
#pragma once

#include "errors/error_categories.h"

#include "progress/progress_callback.h"
#include "radiance/radiance_field.h"
#include "splats/gaussian_splat_ply.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace rad {

// A refusal of the transfer: what is wrong and what to do.
struct SplatTransferError : InputError {
    using InputError::InputError;
};

struct SplatTransferOptions {
    double supportSigmas = 3.0;
    double frontTolerance = 1.0;  // in vertex footprints h
    double maxSplatSize = 0.1;    // fraction of the mesh's bounding-box diagonal
};

struct SplatTransferResult {
    RadianceField field;                 // SH of the splats' degree, plain (not reflected) storage
    std::vector<float> meanColor;        // linear RGB, the RF's exact mean over its hemisphere
    std::vector<std::uint32_t> splatCount;  // splats contributing to each vertex
    std::vector<float> weightSum;        // sum of a_i per vertex
    std::size_t verticesWithoutSplats = 0;
    std::size_t splatsTooLarge = 0;      // ignored by the size limit
    std::size_t splatsFar = 0;           // whose support misses the mesh's bounding box
    std::size_t splatsUsed = 0;          // contributing to at least one vertex
    double meanFootprint = 0.0;          // mean h
};

// positions, normals: 3 floats per vertex (normals unit or not, non-zero); faces: 3 indices each
// (may be empty: then h is 1e-3 of the bounding-box diagonal for every vertex).
// Throws SplatTransferError when no vertex has a splat near it (nothing to transfer) and
// std::invalid_argument on inconsistent input; OperationCancelled on a stop request.
SplatTransferResult transferSplatRadiance(const std::vector<float>& positions, const std::vector<float>& normals,
                                          const std::vector<std::uint32_t>& faces, const GaussianSplats& splats,
                                          const SplatTransferOptions& options = {},
                                          const ProgressCallback& progress = {});

// The footprint h of every vertex (half the mean length of its edges; vertices without an edge get the
// mean over the others, or 1e-3 of the bounding-box diagonal when the mesh has no edge at all).
std::vector<double> vertexFootprints(const std::vector<float>& positions, const std::vector<std::uint32_t>& faces);

}  // namespace rad
