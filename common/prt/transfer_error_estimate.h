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
    NormalDivergence,  // eq. 4 (default, with alpha)
};

// Per radian. The paper leaves alpha to the user; 4 halves the error of a triangle whose normals
// spread ~0.25 rad from n1 (a coarse curved tessellation, e.g. Křivánek et al. 2004's 16-segment column) and
// never divides by more than 1 + 4 pi/2 ~ 7.3. Reasoning in docs/prt-subdivision.md.
constexpr double kDefaultNormalDivergenceAlpha = 4.0;

double triangleTransferError(TransferErrorMeasure measure, double alpha, const float* t1, const float* t2,
                             const float* t3, int width, const float n1[3], const float n2[3], const float n3[3]);

}  // namespace rad
