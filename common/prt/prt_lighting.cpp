// SH lightings for PRT relighting and the relit colour L = <t, l> of Křivánek et al. 2004, sec. 3.3 (the
// shading whose interpolation error eq. 1 measures); see prt_lighting.h for the conventions, the
// Hanning window (Sloan, "Stupid Spherical Harmonics Tricks", GDC 2008) and the layout.
#include "prt/prt_lighting.h"

#include "radiance/basis.h"
#include "radiance/sh_rotation.h"
#include "radiance/spherical_harmonics.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;

void checkDegree(const char* who, int degree) {
    if (degree < 0 || degree > kMaxHarmonicDegree)
        throw std::out_of_range(std::string(who) + ": degree " + std::to_string(degree) + " outside [0, " +
                                std::to_string(kMaxHarmonicDegree) + "]");
}

// directionalLightSH with a Hanning window of width `width` > 0 (h_l = 0 for l >= width).
std::vector<double> windowedDirectionalLight(const char* who, int degree, const Eigen::Vector3d& toLight,
                                             const Eigen::Vector3d& rgb, double width) {
    checkDegree(who, degree);
    const double length = toLight.norm();
    if (!(length > 0.0) || !std::isfinite(length))
        throw std::invalid_argument(std::string(who) + ": the light direction must be non-zero and finite");
    if (!rgb.allFinite()) throw std::invalid_argument(std::string(who) + ": the light colour must be finite");
    const Eigen::Vector3d d = toLight / length;

    const int K = (degree + 1) * (degree + 1);
    std::vector<double> y(K);
    evaluateSphericalHarmonics(degree, d.x(), d.y(), d.z(), y.data());
    // Windowing band by band keeps the delta's rotational symmetry about d (a zonal filter), so
    // the windowed light is still "a light from d", only blurred.
    for (int l = 0; l <= degree; ++l) {
        const double window = l < width ? 0.5 * (1.0 + std::cos(kPi * l / width)) : 0.0;
        for (int m = -l; m <= l; ++m) y[harmonicIndex(l, m)] *= window;
    }
    std::vector<double> coefficients(static_cast<std::size_t>(kColorChannels) * K);
    for (int ch = 0; ch < kColorChannels; ++ch)
        for (int k = 0; k < K; ++k) coefficients[static_cast<std::size_t>(ch) * K + k] = rgb[ch] * y[k];
    return coefficients;
}

std::string formatNumber(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

std::string formatVector(const Eigen::Vector3d& v) {
    return "(" + formatNumber(v.x()) + ", " + formatNumber(v.y()) + ", " + formatNumber(v.z()) + ")";
}

}  // namespace

std::vector<double> directionalLightSH(int degree, const Eigen::Vector3d& toLight, const Eigen::Vector3d& rgb) {
    return windowedDirectionalLight("directionalLightSH", degree, toLight, rgb, degree + 1.0);
}

std::vector<double> environmentLightSH(const EnvironmentMap& map, int degree, double rotationRadians) {
    checkDegree("environmentLightSH", degree);
    if (!std::isfinite(rotationRadians)) throw std::invalid_argument("environmentLightSH: the rotation must be finite");
    // Projecting a copy of the map with rotation rotationAboutZ(a) * R would copy every texel;
    // environment_map.h guarantees projection(map with R' R) = ShRotation(R') of projection(map
    // with R) exactly (rotations map each band onto itself), so rotating the projection's
    // coefficients is the same result at O(degree^3) instead of O(W H).
    std::vector<double> coefficients = projectOntoSphericalHarmonics(map, degree);
    const ShRotation turn(degree, rotationAboutZ(rotationRadians));
    const int K = (degree + 1) * (degree + 1);
    for (int ch = 0; ch < kColorChannels; ++ch) {
        double* channel = coefficients.data() + static_cast<std::size_t>(ch) * K;
        turn.apply(channel, channel);
    }
    return coefficients;
}

std::vector<float> relightVertices(const float* transfer, std::size_t vertexCount, int transferDegree, int channels,
                                   const std::vector<double>& lighting, int lightingDegree) {
    checkDegree("relightVertices (transfer)", transferDegree);
    checkDegree("relightVertices (lighting)", lightingDegree);
    if (channels != 1 && channels != kColorChannels)
        throw std::invalid_argument("relightVertices: the transfer has " + std::to_string(channels) +
                                    " channels, expected 1 or 3");
    if (lightingDegree < transferDegree)
        throw std::invalid_argument("relightVertices: the lighting's degree " + std::to_string(lightingDegree) +
                                    " is below the transfer's " + std::to_string(transferDegree));
    const int K = (transferDegree + 1) * (transferDegree + 1);
    const int lightingK = (lightingDegree + 1) * (lightingDegree + 1);
    if (lighting.size() != static_cast<std::size_t>(kColorChannels) * lightingK)
        throw std::invalid_argument("relightVertices: the lighting has " + std::to_string(lighting.size()) +
                                    " coefficients, expected 3 x " + std::to_string(lightingK));
    if (vertexCount > 0 && transfer == nullptr) throw std::invalid_argument("relightVertices: no transfer values");
    const int width = channels * K;
    std::size_t nonFinite = 0;
    for (std::size_t i = 0; i < vertexCount * static_cast<std::size_t>(width); ++i)
        nonFinite += std::isfinite(transfer[i]) ? 0 : 1;
    if (nonFinite > 0)
        throw std::invalid_argument(std::to_string(nonFinite) + " transfer values are NaN or infinite (a damaged file?): "
                                    "compute the transfer again with 'Radiance: Compute PRT Transfer'.");

    std::vector<float> out(vertexCount * kColorChannels);
    const auto count = static_cast<std::ptrdiff_t>(vertexCount);
    // Bands below transferDegree sit at the same indices l*l + l + m in both vectors, so the
    // truncated dot product needs no re-indexing.
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t v = 0; v < count; ++v) {
        const float* t = transfer + static_cast<std::size_t>(v) * width;
        for (int ch = 0; ch < kColorChannels; ++ch) {
            const float* tc = t + (channels == 1 ? 0 : ch * K);
            const double* lc = lighting.data() + static_cast<std::size_t>(ch) * lightingK;
            double sum = 0.0;
            for (int k = 0; k < K; ++k) sum += static_cast<double>(tc[k]) * lc[k];
            out[static_cast<std::size_t>(v) * kColorChannels + ch] = static_cast<float>(sum);
        }
    }
    return out;
}

Eigen::Matrix3d zenithToAxis(int upAxis) {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    if (upAxis == 1) R << 0, 1, 0, 0, 0, 1, 1, 0, 0;       // z -> y (x -> z, y -> x)
    else if (upAxis == 0) R << 0, 0, 1, 1, 0, 0, 0, 1, 0;  // z -> x (x -> y, y -> z)
    else if (upAxis != 2) throw std::invalid_argument("zenithToAxis: the up axis must be 0 (X), 1 (Y) or 2 (Z)");
    return R;
}

void rotateLighting(std::vector<double>& lighting, int degree, const Eigen::Matrix3d& R) {
    const std::size_t k = static_cast<std::size_t>((degree + 1) * (degree + 1));
    if (lighting.size() != 3 * k) throw std::invalid_argument("rotateLighting: the lighting does not have 3 (degree + 1)^2 coefficients");
    const ShRotation rotation(degree, R);
    for (int ch = 0; ch < 3; ++ch) rotation.apply(lighting.data() + ch * k, lighting.data() + ch * k);
}

Eigen::Vector3d upAxisVector(UpAxis axis) {
    const int index = static_cast<int>(axis);
    if (index < 0 || index >= kUpAxisCount)
        throw std::invalid_argument("upAxis " + std::to_string(index) + " outside [0, 2] (0 = +X, 1 = +Y, 2 = +Z)");
    return Eigen::Vector3d::Unit(index);
}

std::vector<double> prtLightingSH(const PrtLightingSettings& s, const EnvironmentMap* map) {
    const std::string who = "PRT lighting: ";
    if (s.degree < 0 || s.degree > kMaxHarmonicDegree)
        throw std::invalid_argument(who + "degree " + std::to_string(s.degree) + " outside [0, " +
                                    std::to_string(kMaxHarmonicDegree) + "]");
    const int axis = static_cast<int>(s.upAxis);
    if (axis < 0 || axis >= kUpAxisCount)
        throw std::invalid_argument(who + "upAxis " + std::to_string(axis) + " outside [0, 2] (0 = +X, 1 = +Y, 2 = +Z)");
    const int source = static_cast<int>(s.source);
    if (source != static_cast<int>(PrtLightSource::EnvironmentMap) && source != static_cast<int>(PrtLightSource::Directional))
        throw std::invalid_argument(who + "source " + std::to_string(source) +
                                    " outside [0, 1] (0 = environment map, 1 = directional light)");
    if (!std::isfinite(s.rotationDegrees))
        throw std::invalid_argument(who + "rotation " + formatNumber(s.rotationDegrees) +
                                    " degrees is not finite (valid: any finite number of degrees)");
    if (!std::isfinite(s.intensity) || !(s.intensity >= 0.0))
        throw std::invalid_argument(who + "intensity " + formatNumber(s.intensity) + " outside [0, +inf) (finite, >= 0)");
    if (!std::isfinite(s.windowWidth) || !(s.windowWidth >= 0.0))
        throw std::invalid_argument(who + "window width " + formatNumber(s.windowWidth) +
                                    " outside [0, +inf) (finite; 0 = degree + 1)");

    const double radians = s.rotationDegrees * (kPi / 180.0);
    const Eigen::Vector3d up = Eigen::Vector3d::Unit(axis);
    if (s.source == PrtLightSource::EnvironmentMap) {
        if (map == nullptr) throw std::invalid_argument(who + "the environment map source needs a map (none given)");
        // World from map frame: zenithToAxis(up) * rotationAboutZ(a) = AngleAxis(a, up) * zenithToAxis(up)
        // (zenithToAxis is a proper rotation taking +Z to up), i.e. the map turned about the world up axis.
        std::vector<double> lighting = environmentLightSH(*map, s.degree, radians);
        rotateLighting(lighting, s.degree, zenithToAxis(axis));
        for (double& c : lighting) c *= s.intensity;
        return lighting;
    }
    const double length = s.direction.norm();
    if (!s.direction.allFinite() || !(length > 0.0) || !std::isfinite(length))
        throw std::invalid_argument(who + "direction " + formatVector(s.direction) +
                                    " must be finite and non-zero (toward the light)");
    const Eigen::Vector3d turned = Eigen::AngleAxisd(radians, up) * (s.direction / length);
    const double width = s.windowWidth > 0.0 ? s.windowWidth : s.degree + 1.0;
    return windowedDirectionalLight("PRT lighting", s.degree, turned, Eigen::Vector3d::Constant(s.intensity), width);
}

}  // namespace rad
