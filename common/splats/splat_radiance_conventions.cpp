#include "splats/splat_radiance_conventions.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace rad {

void toViewerShCoefficients(int degree, const float* splatChannel, double* out) {
    const int count = (degree + 1) * (degree + 1);
    for (int k = 0; k < count; ++k) out[k] = splatToViewerShSign(k) * double(splatChannel[k]);
}

double displayToLinear(double display) {
    const double c = std::min(1.0, std::max(0.0, display));
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double splatOpacity(double logit) { return 1.0 / (1.0 + std::exp(-logit)); }

Eigen::Matrix3d splatCovariance(const float* logScale, const float* quaternion) {
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(quaternion[0], quaternion[1], quaternion[2], quaternion[3]).normalized();
    const Eigen::Matrix3d r = q.toRotationMatrix();
    const Eigen::Vector3d variance(std::exp(2.0 * double(logScale[0])), std::exp(2.0 * double(logScale[1])),
                                   std::exp(2.0 * double(logScale[2])));
    return r * variance.asDiagonal() * r.transpose();
}

}  // namespace rad
