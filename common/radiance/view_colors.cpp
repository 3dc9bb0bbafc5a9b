#include "radiance/view_colors.h"

#include "radiance/radiance_evaluation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {

std::uint8_t encodeSrgb8(float linear) {
    const float x = std::clamp(std::isfinite(linear) ? linear : 0.0f, 0.0f, 1.0f);
    const float encoded = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
    return static_cast<std::uint8_t>(std::lround(encoded * 255.0f));
}

void radianceTowardViewpoint(const RadianceField& field, const float* positions, const double eye[3],
                             float exposure, float* rgbOut) {
    if (!std::isfinite(eye[0]) || !std::isfinite(eye[1]) || !std::isfinite(eye[2]))
        throw std::invalid_argument("The viewpoint must be a finite point (e.g. 0 0 5).");
    if (!(exposure >= 0.0f) || !std::isfinite(exposure))
        throw std::invalid_argument("The exposure must be a finite number >= 0 (1 shows the radiance as it is); it is " +
                                    std::to_string(exposure) + ".");
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(field.vertexCount());
    const Eigen::Vector3d eyePoint(eye[0], eye[1], eye[2]);
#pragma omp parallel
    {
        double scratch[kMaxCoefficientsPerChannel];
#pragma omp for schedule(static)
        for (std::ptrdiff_t v = 0; v < n; ++v) {
            const VertexRadiance rf = vertexRadiance(field, static_cast<std::size_t>(v));
            const Eigen::Vector3d p(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
            Eigen::Vector3d w = eyePoint - p;
            const double length = w.norm();
            w = length > 0.0 ? Eigen::Vector3d(w / length) : rf.frame.n;
            const Eigen::Vector3d rgb = evaluateRadiance(rf, w, scratch);
            for (int c = 0; c < 3; ++c) rgbOut[3 * v + c] = exposure * static_cast<float>(rgb[c]);
        }
    }
}

}  // namespace rad
