// Relighting error of interpolated PRT, measured instead of estimated (Křivánek et al. 2004 eq. 1):
// at dense sample points x inside every triangle, the exact shading <t(x), l> with t(x) ray-cast at
// x against the shading interpolated from the vertices, over many lightings l, relative to the
// shading after Weber's law (with a floor: kWeberFloorFraction of the mean), in Rec. 709 luminance.
// The sample points live on the INPUT mesh, so the same points judge every subdivision of it.
// Details: docs/prt-subdivision.md, "`common/prt/relighting_error.h`: how it works".
#pragma once

#include "prt/adaptive_subdivision.h"
#include "prt/transfer_vectors.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rad {

constexpr double kWeberFloorFraction = 0.01;

struct RelightingSamples {
    std::vector<std::uint32_t> inputFace;  // per sample
    std::vector<float> positions;          // 3 per sample
    std::vector<float> normals;            // 3 per sample (interpolated input vertex normals, unit)
    std::vector<float> weights;            // per sample: area it stands for (sums to the mesh area)
    std::vector<float> groundTruth;        // per sample: width floats, ray-cast at the sample
    int width = 0;
    std::size_t count() const { return inputFace.size(); }
};

// About `targetCount` samples over the input mesh (deterministic for a given seed); the ground
// truth is filled by the oracle (one large batch). Per face of area A_f: n_f = max(1,
// round(targetCount A_f / A)) points, one uniformly jittered in each of n_f equal-area strata (equal
// cells of the unit square mapped by Heitz's area-preserving square-to-triangle map), each of
// weight A_f / n_f. Throws std::invalid_argument on an invalid mesh (sizes, indices, non-finite
// positions, missing normals, width < 1, zero total area) or an empty oracle.
RelightingSamples makeRelightingSamples(const PrtMesh& input, std::size_t targetCount, const TransferOracle& oracle,
                                        unsigned seed = 1);

struct RelightingErrorStats {
    double meanRelativeError = 0.0;   // area-weighted mean of e over samples (and lightings, when aggregated)
    double p95RelativeError = 0.0;    // area-weighted 95th percentile
    double rmsRelativeError = 0.0;
};

// Interpolated transfer of every sample in `mesh` (a subdivision of `input` with its originFace),
// width floats per sample. Throws std::invalid_argument when a sample lies in no sub-face of its
// input face (tolerance 1e-5 in the input face's barycentrics, i.e. the distance outside the
// sub-face in the chart where the input face is the unit right triangle, widened by what float
// rounding of the coordinates can amount to for small faces far from the origin; within it the
// nearest sub-face is used, at its nearest point), and on size, index or width mismatches
// (originFace must have one entry per output face). Sub-faces are found through a per-input-face
// list built once and a small uniform grid per input face: linear in samples + faces.
std::vector<float> interpolateAtSamples(const RelightingSamples& samples, const PrtMesh& input,
                                        const SubdivisionResult& mesh);

// Errors for one lighting (3 * K doubles, prt_lighting.h), `channels` and `degree` those of the
// transfer fields. The weighted 95th percentile is the smallest e whose cumulative weight (of the
// errors <= e) reaches 0.95 of the total (exact: no binning error). Throws std::invalid_argument on
// size mismatches, non-finite values, negative weights, or a lighting whose mean luminance over
// the samples is not positive (no adaptation level, so no Weber normalisation).
RelightingErrorStats relightingError(const RelightingSamples& samples, const std::vector<float>& interpolated,
                                     int degree, int channels, const std::vector<double>& lighting,
                                     int lightingDegree);

// Over many lightings: per-lighting stats and the aggregate (mean of means, RMS of the per-lighting
// mean squares, p95 over all (sample, lighting) pairs with weights). The (sample, lighting) errors
// are never all stored: two passes over the samples (OpenMP), the first locating each quantile in
// a histogram (lightings x 8k bins per thread), the second keeping only the errors of that bin.
struct RelightingErrorReport {
    std::vector<RelightingErrorStats> perLighting;
    RelightingErrorStats overall;
};
// How |L - L_int| is normalised: Weber (the relative error above, the default) or by the lighting's
// mean luminance over the samples (an absolute error on a common scale, where dark regions weigh
// little; the fields named "RelativeError" then hold it).
enum class RelightingErrorNormalisation { Weber, MeanLuminance };
RelightingErrorReport relightingErrorOverLightings(const RelightingSamples& samples,
                                                   const std::vector<float>& interpolated, int degree, int channels,
                                                   const std::vector<std::vector<double>>& lightings,
                                                   int lightingDegree,
                                                   RelightingErrorNormalisation normalisation =
                                                       RelightingErrorNormalisation::Weber);

}  // namespace rad
