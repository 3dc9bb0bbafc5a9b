// Per-triangle estimates of the PRT interpolation error, Křivánek et al. 2004
// "Adaptive Mesh Subdivision for Precomputed Radiance Transfer") sec. 3.3. The triangle error is
// the sum of the three edge errors (eq. 2 or eq. 3), or eq. 4:
//   eq. 2 (Contrast):          e(v1, v2) = |t1 - t2| / |t1 + t2|   (0 when t1 + t2 = 0)
//   eq. 3 (Difference):        e(v1, v2) = |t1 - t2|
//   eq. 4 (NormalDivergence):  e = (|t1 - t2| + |t2 - t3| + |t3 - t1|)
//                                  / (1 + alpha * angle(n1, normalize(n1 + n2 + n3)))
// t_i: the vertices' transfer vectors (all channels, width floats), n_i: the vertices' unit normals,
// angle in radians. |.| is the Euclidean norm. When n1 + n2 + n3 = 0 the angle is taken as pi/2.
#pragma once

#include <cstddef>

namespace rad {

enum class TransferErrorMeasure {
    Contrast,          // eq. 2
    Difference,        // eq. 3
    NormalDivergence,  // eq. 4 (with alpha)
    // Not estimates from the corners but the interpolation error itself, probed: the transfer is
    // ray-cast at each edge's midpoint (where a split would put a vertex, so the probe is reused
    // then) and compared with the linear interpolation of the edge's ends. The triangle's value is
    // its share of the surface times the mean over its edges of
    //   ProbedRelative: |t_m - (t_a + t_b) / 2| / max(|t_m|, floor)   (floor: kProbedRelativeFloor x mean |t|)
    //   ProbedAbsolute: |t_m - (t_a + t_b) / 2| / mean |t|
    // i.e. the triangle's contribution to the area-weighted mean error, which is what a greedy split
    // order should lower first. It sees what eq. 2-4 miss on curved, self-shadowing scans: the
    // normal's variation inside the triangle, the terminator, shadow edges crossing it.
    // ProbedRelative is the default (README, "Precomputed radiance transfer": it wins on the paper's
    // relative measure and on the absolute one, on the column and on real scans).
    ProbedRelative,
    ProbedAbsolute,
};

// The relative form's floor as a fraction of the mean |t|: above the evaluation's Weber floor (1 % of
// the mean luminance) because |t| is not the luminance of any one lighting; 10 % keeps near-black
// regions from taking the whole budget (1 %: column 0.40 of uniform's mean error but its 95th
// percentile 1.18x; 10 %: 0.48 and 1.09x; 30 %: 0.49 and 1.06x; bunny 0.35 / 0.33 / 0.34).
constexpr double kProbedRelativeFloor = 0.1;

inline bool isProbed(TransferErrorMeasure m) {
    return m == TransferErrorMeasure::ProbedRelative || m == TransferErrorMeasure::ProbedAbsolute;
}

// One edge's probed deviation |t_m - (t_a + t_b) / 2| (all channels, Euclidean) divided by
// max(|t_m|, floor) for ProbedRelative or by `floor` (then the mean |t|) for ProbedAbsolute.
double probedEdgeError(TransferErrorMeasure measure, const float* ta, const float* tb, const float* tm, int width,
                       double floor);

// Per radian. The paper leaves alpha to the user; 4 halves the error of a triangle whose normals
// spread ~0.25 rad from n1 (a coarse curved tessellation, e.g. Křivánek et al. 2004's 16-segment column) and
// never divides by more than 1 + 4 pi/2 ~ 7.3. Reasoning in docs/prt-subdivision.md.
constexpr double kDefaultNormalDivergenceAlpha = 4.0;

// eq. 2-4 from the corners (the probed measures are computed by the subdivision, which owns the probes;
// here they fall back to eq. 3).
double triangleTransferError(TransferErrorMeasure measure, double alpha, const float* t1, const float* t2,
                             const float* t3, int width, const float n1[3], const float n2[3], const float n3[3]);

}  // namespace rad
