// The radiance of a 3D Gaussian Splatting scene (Kerbl et al. 2023) moved onto a mesh's vertices, as
// one spherical-harmonic radiance function (RF) per vertex of the splats' own degree, in our
// conventions (global-frame SH without the Condon-Shortley phase, linear radiance; the frame stores the
// vertex normal: radiance/radiance_field.h).
//
// For a vertex p with normal n and footprint h (half the mean length of its edges: the part of the
// surface the vertex stands for), a splat i (centre mu, covariance S, opacity o) contributes with weight
//     a_i = o * exp(-m^2 / 2),   m^2 = (p - mu)^T (S + h^2 I)^-1 (p - mu)
// (its Gaussian, widened by the vertex footprint as in EWA splatting, Zwicker et al. 2001, so that a
// thin splat lying a little off the mesh still reaches it), and only when it is near and in front:
//   - near:     m <= supportSigmas (3, the extent the reference rasteriser gives a splat);
//   - in front: (mu - p) . n >= -frontTolerance * h (a splat whose centre lies deeper than that below
//               the vertex's tangent plane belongs to another surface: the back of a thin part, the
//               inside);
//   - not a background splat: its largest standard deviation is at most maxSplatSize times the
//               mesh's bounding-box diagonal (huge splats are sky, walls and floaters).
// The vertex's display colour toward a viewer in direction w (hemisphere n.w >= 0) is the weighted
// mean of the splats' colours, each clamped at 0 as the rasteriser does,
//     C(w) = sum_i a_i max(0, S_i(w) + 0.5) / sum_i a_i      (S_i: splat_radiance_conventions.h),
// its linear radiance L(w) = sRGB-decode(clamp(C(w), 0, 1)), and the RF is the least-squares fit of L
// over the hemisphere (a Lebedev hemisphere rule of precision 17, quadrature weights; the RF is
// evaluated border-extended below the horizon, so only the hemisphere matters). A vertex no splat
// reaches gets the zero RF (black) and is counted.
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
