// Triangle error estimates of Křivánek et al. 2004 sec. 3.3: eq. 2 (edge contrast
// |t1 - t2| / |t1 + t2|), eq. 3 (edge difference |t1 - t2|), both summed over the three edges, and
// eq. 4 (the eq. 3 sum divided by 1 + alpha * the angle between n1 and the mean normal).
#include "prt/transfer_error_estimate.h"

#include <algorithm>
#include <cmath>

namespace rad {

namespace {

// |a - b| and |a + b| over all channels, in double so that long SH vectors do not lose digits.
void differenceAndSumNorms(const float* a, const float* b, int width, double& difference, double& sum) {
    double d2 = 0.0, s2 = 0.0;
    for (int i = 0; i < width; ++i) {
        const double x = a[i], y = b[i];
        d2 += (x - y) * (x - y);
        s2 += (x + y) * (x + y);
    }
    difference = std::sqrt(d2);
    sum = std::sqrt(s2);
}

double differenceNorm(const float* a, const float* b, int width) {
    double d2 = 0.0;
    for (int i = 0; i < width; ++i) {
        const double x = double(a[i]) - double(b[i]);
        d2 += x * x;
    }
    return std::sqrt(d2);
}

// Angle between n1 and normalize(n1 + n2 + n3). atan2(|n1 x m|, n1 . m) rather than acos: exact
// for the small angles of finely tessellated surfaces, and independent of |n1| and |m|.
double normalDivergenceAngle(const float n1[3], const float n2[3], const float n3[3]) {
    const double m[3] = {double(n1[0]) + n2[0] + n3[0], double(n1[1]) + n2[1] + n3[1], double(n1[2]) + n2[2] + n3[2]};
    if (m[0] == 0.0 && m[1] == 0.0 && m[2] == 0.0) return 0.5 * 3.14159265358979323846;  // documented convention
    const double a[3] = {n1[0], n1[1], n1[2]};
    const double cross[3] = {a[1] * m[2] - a[2] * m[1], a[2] * m[0] - a[0] * m[2], a[0] * m[1] - a[1] * m[0]};
    const double sine = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
    const double cosine = a[0] * m[0] + a[1] * m[1] + a[2] * m[2];
    return std::atan2(sine, cosine);
}

}  // namespace

double triangleTransferError(TransferErrorMeasure measure, double alpha, const float* t1, const float* t2,
                             const float* t3, int width, const float n1[3], const float n2[3], const float n3[3]) {
    switch (measure) {
        case TransferErrorMeasure::Contrast: {
            double total = 0.0;
            const float* ends[3][2] = {{t1, t2}, {t2, t3}, {t3, t1}};
            for (const auto& e : ends) {
                double difference, sum;
                differenceAndSumNorms(e[0], e[1], width, difference, sum);
                // t1 + t2 = 0: both vertices black (or exactly opposite); the edge contributes nothing.
                if (sum > 0.0) total += difference / sum;
            }
            return total;
        }
        case TransferErrorMeasure::Difference:
        case TransferErrorMeasure::ProbedRelative:
        case TransferErrorMeasure::ProbedAbsolute:
            return differenceNorm(t1, t2, width) + differenceNorm(t2, t3, width) + differenceNorm(t3, t1, width);
        case TransferErrorMeasure::NormalDivergence: {
            const double numerator =
                differenceNorm(t1, t2, width) + differenceNorm(t2, t3, width) + differenceNorm(t3, t1, width);
            return numerator / (1.0 + alpha * normalDivergenceAngle(n1, n2, n3));
        }
    }
    return 0.0;
}

double probedEdgeError(TransferErrorMeasure measure, const float* ta, const float* tb, const float* tm, int width,
                       double floor) {
    double d2 = 0.0, m2 = 0.0;
    for (int i = 0; i < width; ++i) {
        const double m = tm[i];
        const double d = m - 0.5 * (double(ta[i]) + double(tb[i]));
        d2 += d * d;
        m2 += m * m;
    }
    const double denominator = measure == TransferErrorMeasure::ProbedRelative ? std::max(std::sqrt(m2), floor) : floor;
    return denominator > 0.0 ? std::sqrt(d2) / denominator : 0.0;
}

}  // namespace rad
