#include "radiance/sh_rotation.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

namespace {

// Band-1 order (m = -1, 0, 1) -> Cartesian axis (y, z, x), because Y_1^{-1}, Y_1^0, Y_1^1 are c*y,
// c*z, c*x (spherical_harmonics.h).
constexpr int kAxisOfBand1[3] = {1, 2, 0};

// Read access to one band-(l-1) block and the band-1 block with signed indices.
struct Bands {
    const double* r1;    // 3 x 3, D^1
    const double* prev;  // (2l-1) x (2l-1), D^(l-1)
    int lPrev;           // l - 1

    double d1(int i, int j) const { return r1[(i + 1) * 3 + (j + 1)]; }
    double dPrev(int a, int b) const { return prev[(a + lPrev) * (2 * lPrev + 1) + (b + lPrev)]; }

    // Ivanic & Ruedenberg's auxiliary function P^l_{i,a,b} (Table 2 of the 1996 paper, corrected 1998).
    double P(int i, int l, int a, int b) const {
        if (b == l) return d1(i, 1) * dPrev(a, l - 1) - d1(i, -1) * dPrev(a, -l + 1);
        if (b == -l) return d1(i, 1) * dPrev(a, -l + 1) + d1(i, -1) * dPrev(a, l - 1);
        return d1(i, 0) * dPrev(a, b);
    }
};

// The coefficients u, v, w of the recurrence (Ivanic & Ruedenberg 1996, Table 1, corrected) depend
// on (l, m, m') only: computed once, laid out like the blocks, so that building a rotation per vertex
// takes no square root.
struct RecurrenceCoefficients {
    double u, v, w;
};

const std::vector<RecurrenceCoefficients>& recurrenceCoefficients() {
    static const std::vector<RecurrenceCoefficients> table = [] {
        std::vector<RecurrenceCoefficients> t(detail::shRotationBlockOffset(kMaxHarmonicDegree + 1));
        for (int l = 2; l <= kMaxHarmonicDegree; ++l)
            for (int m = -l; m <= l; ++m) {
                const int am = m < 0 ? -m : m;
                const double delta0 = m == 0 ? 1.0 : 0.0;
                for (int mp = -l; mp <= l; ++mp) {
                    const int amp = mp < 0 ? -mp : mp;
                    const double denom = amp == l ? double(2 * l) * (2 * l - 1) : double(l + mp) * (l - mp);
                    RecurrenceCoefficients& c =
                        t[detail::shRotationBlockOffset(l) + (m + l) * (2 * l + 1) + (mp + l)];
                    c.u = std::sqrt(double(l + m) * (l - m) / denom);
                    c.v = 0.5 * std::sqrt((1.0 + delta0) * (l + am - 1) * (l + am) / denom) * (1.0 - 2.0 * delta0);
                    c.w = -0.5 * std::sqrt(double(l - am - 1) * (l - am) / denom) * (1.0 - delta0);
                }
            }
        return t;
    }();
    return table;
}

}  // namespace

ShRotation::ShRotation(int degree) : degree_(degree) {
    if (degree < 0 || degree > kMaxHarmonicDegree)
        throw std::out_of_range("ShRotation: degree " + std::to_string(degree) + " outside [0, " +
                                std::to_string(kMaxHarmonicDegree) + "]");
    // Only the bands up to the degree are used (and read): the rest of the storage stays unset.
    std::fill(blocks_.begin(), blocks_.begin() + offset(degree_ + 1), 0.0);
    for (int l = 0; l <= degree_; ++l)
        for (int m = 0; m < 2 * l + 1; ++m) blocks_[offset(l) + m * (2 * l + 1) + m] = 1.0;
}

ShRotation::ShRotation(int degree, const Eigen::Matrix3d& R) : ShRotation(degree) {
    if (degree_ == 0) return;
    // Improper matrix: rotate by -R and apply the parity (-1)^l afterwards (see the header).
    const bool improper = R.determinant() < 0.0;
    const Eigen::Matrix3d rot = improper ? Eigen::Matrix3d(-R) : R;

    // D^1: coefficient of input Y_1^{m'} in output Y_1^m. g(w) = f(R^T w); with f = c * (axis j of
    // w) we get g(w) = c * (R^T w)_j = c * sum_i R_ij w_i, so the output on axis i is R(i, j).
    double* d1 = blocks_.data() + offset(1);
    for (int m = -1; m <= 1; ++m)
        for (int mp = -1; mp <= 1; ++mp) d1[(m + 1) * 3 + (mp + 1)] = rot(kAxisOfBand1[m + 1], kAxisOfBand1[mp + 1]);

    const std::vector<RecurrenceCoefficients>& coefficients = recurrenceCoefficients();
    constexpr double kSqrt2 = 1.41421356237309504880;
    for (int l = 2; l <= degree_; ++l) {
        const Bands bands{d1, blocks_.data() + offset(l - 1), l - 1};
        double* dl = blocks_.data() + offset(l);
        const RecurrenceCoefficients* band = coefficients.data() + offset(l);
        for (int m = -l; m <= l; ++m) {
            for (int mp = -l; mp <= l; ++mp) {
                const RecurrenceCoefficients& c = band[(m + l) * (2 * l + 1) + (mp + l)];
                const double u = c.u, v = c.v, w = c.w;

                double value = 0.0;
                // Each term is only formed when its coefficient is nonzero: there its indices are
                // inside band l-1 (|m| <= l-1 for U, |m+-1| <= l-1 for W).
                if (u != 0.0) value += u * bands.P(0, l, m, mp);
                if (v != 0.0) {
                    double V;
                    if (m == 0) {
                        V = bands.P(1, l, 1, mp) + bands.P(-1, l, -1, mp);
                    } else if (m > 0) {
                        V = m == 1 ? bands.P(1, l, 0, mp) * kSqrt2
                                   : bands.P(1, l, m - 1, mp) - bands.P(-1, l, -m + 1, mp);
                    } else {
                        V = m == -1 ? bands.P(-1, l, 0, mp) * kSqrt2
                                    : bands.P(1, l, m + 1, mp) + bands.P(-1, l, -m - 1, mp);
                    }
                    value += v * V;
                }
                if (w != 0.0) {
                    const double W = m > 0 ? bands.P(1, l, m + 1, mp) + bands.P(-1, l, -m - 1, mp)
                                           : bands.P(1, l, m - 1, mp) - bands.P(-1, l, -m + 1, mp);
                    value += w * W;
                }
                dl[(m + l) * (2 * l + 1) + (mp + l)] = value;
            }
        }
    }

    if (improper)
        for (int l = 1; l <= degree_; l += 2)
            for (int k = 0; k < (2 * l + 1) * (2 * l + 1); ++k) blocks_[offset(l) + k] = -blocks_[offset(l) + k];
}

template <typename Real>
void ShRotation::applyImpl(const Real* in, Real* out) const {
    double buffer[2 * kMaxHarmonicDegree + 1];
    for (int l = 0; l <= degree_; ++l) {
        const int size = 2 * l + 1;
        const Real* src = in + l * l;
        const double* b = block(l);
        for (int i = 0; i < size; ++i) {
            double sum = 0.0;
            for (int j = 0; j < size; ++j) sum += b[i * size + j] * static_cast<double>(src[j]);
            buffer[i] = sum;
        }
        Real* dst = out + l * l;
        for (int i = 0; i < size; ++i) dst[i] = static_cast<Real>(buffer[i]);
    }
}

void ShRotation::apply(const double* in, double* out) const { applyImpl(in, out); }
void ShRotation::apply(const float* in, float* out) const { applyImpl(in, out); }

Eigen::Matrix3d reflectionAbout(const Eigen::Vector3d& n) {
    const Eigen::Vector3d u = n.normalized();
    return 2.0 * u * u.transpose() - Eigen::Matrix3d::Identity();
}

ShRotation reflectionAboutAxisSH(const Eigen::Vector3d& n, int degree) { return ShRotation(degree, reflectionAbout(n)); }

}  // namespace rad
