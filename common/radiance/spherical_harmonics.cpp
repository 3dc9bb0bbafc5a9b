#include "radiance/spherical_harmonics.h"

#include "radiance/basis.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

// Normalised associated Legendre "polynomial parts"
//     Pbar_l^m(z) = s_m K_l^m P_l^m(z) / sin^m t,        s_0 = 1, s_m = sqrt(2) for m > 0,
// so that Y_l^{+-m} = Pbar_l^m(z) * {Re, Im}((x + i y)^m). They obey (no Condon-Shortley phase)
//     Pbar_m^m     = Pbar_{m-1}^{m-1} sqrt((2m+1)/(2m))         (times sqrt(2) once when going 0 -> 1)
//     Pbar_{m+1}^m = sqrt(2m+3) z Pbar_m^m
//     Pbar_l^m     = a_l^m z Pbar_{l-1}^m - b_l^m Pbar_{l-2}^m,  l >= m+2,
//     a_l^m = sqrt((4l^2 - 1) / (l^2 - m^2)),
//     b_l^m = sqrt(((l-1)^2 - m^2)(2l+1) / ((2l-3)(l^2 - m^2))).
// These follow from the textbook recurrence (l-m) P_l^m = (2l-1) z P_{l-1}^m - (l+m-1) P_{l-2}^m
// by inserting the normalisation; working with normalised values keeps every intermediate O(1)
// (no factorials), which is what makes the recurrence accurate to all degrees we use.
template <typename Real>
struct LegendreTable {
    Real diagonal[kMaxHarmonicDegree + 1];                           // Pbar_m^m (constants)
    Real subDiagonal[kMaxHarmonicDegree + 1];                        // sqrt(2m+3)
    Real a[kMaxHarmonicDegree + 1][kMaxHarmonicDegree + 1];          // a[l][m]
    Real b[kMaxHarmonicDegree + 1][kMaxHarmonicDegree + 1];          // b[l][m]

    LegendreTable() {
        const double pi = 3.14159265358979323846;
        double d = std::sqrt(1.0 / (4.0 * pi));
        for (int m = 0; m <= kMaxHarmonicDegree; ++m) {
            if (m > 0) d *= std::sqrt((2.0 * m + 1.0) / (2.0 * m)) * (m == 1 ? std::sqrt(2.0) : 1.0);
            diagonal[m] = static_cast<Real>(d);
            subDiagonal[m] = static_cast<Real>(std::sqrt(2.0 * m + 3.0));
        }
        for (int l = 0; l <= kMaxHarmonicDegree; ++l)
            for (int m = 0; m <= kMaxHarmonicDegree; ++m) {
                a[l][m] = b[l][m] = Real(0);
                if (l < m + 2) continue;
                const double l2m2 = double(l) * l - double(m) * m;
                a[l][m] = static_cast<Real>(std::sqrt((4.0 * l * l - 1.0) / l2m2));
                b[l][m] = static_cast<Real>(
                    std::sqrt(((l - 1.0) * (l - 1.0) - double(m) * m) * (2.0 * l + 1.0) / ((2.0 * l - 3.0) * l2m2)));
            }
    }
};

template <typename Real>
const LegendreTable<Real>& legendreTable() {
    // Function-local static: thread-safe one-time initialisation (C++11 magic statics) and no
    // static-initialisation-order dependence for callers that run before main.
    static const LegendreTable<Real> table;
    return table;
}

template <typename Real>
void evaluate(int degree, Real x, Real y, Real z, Real* out) {
    if (degree < 0 || degree > kMaxHarmonicDegree)
        throw std::out_of_range("evaluateSphericalHarmonics: degree " + std::to_string(degree) +
                                " outside [0, " + std::to_string(kMaxHarmonicDegree) + "]");
    const LegendreTable<Real>& t = legendreTable<Real>();

    // m = 0 (zonal): Y_l^0 = Pbar_l^0(z).
    {
        Real p2 = t.diagonal[0];
        out[0] = p2;
        if (degree == 0) return;
        Real p1 = t.subDiagonal[0] * z * p2;
        out[2] = p1;
        for (int l = 2; l <= degree; ++l) {
            const Real p = t.a[l][0] * z * p1 - t.b[l][0] * p2;
            p2 = p1;
            p1 = p;
            out[l * l + l] = p;
        }
    }
    // m > 0: c + i s = (x + i y)^m = sin^m t (cos m p + i sin m p), advanced by one complex product
    // per m; then the three-term recurrence in l at fixed m (forward in l: the stable direction).
    Real c = Real(1), s = Real(0);
    for (int m = 1; m <= degree; ++m) {
        const Real cNext = x * c - y * s;
        s = x * s + y * c;
        c = cNext;
        Real p2 = t.diagonal[m];  // l = m
        int centre = m * m + m;
        out[centre + m] = p2 * c;
        out[centre - m] = p2 * s;
        if (m == degree) break;
        Real p1 = t.subDiagonal[m] * z * p2;  // l = m + 1
        centre += 2 * m + 2;
        out[centre + m] = p1 * c;
        out[centre - m] = p1 * s;
        for (int l = m + 2; l <= degree; ++l) {
            const Real p = t.a[l][m] * z * p1 - t.b[l][m] * p2;
            p2 = p1;
            p1 = p;
            centre = l * l + l;
            out[centre + m] = p * c;
            out[centre - m] = p * s;
        }
    }
}

}  // namespace

void evaluateSphericalHarmonics(int degree, double x, double y, double z, double* out) {
    evaluate<double>(degree, x, y, z, out);
}

void evaluateSphericalHarmonics(int degree, float x, float y, float z, float* out) {
    evaluate<float>(degree, x, y, z, out);
}

}  // namespace rad
