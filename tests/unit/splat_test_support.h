// Independent 3D Gaussian Splatting helpers for the splat tests (not a core unit): a writer of the
// .ply files the reference implementation (Kerbl et al. 2023, graphdeco-inria/gaussian-splatting)
// saves, written from its save_ply (properties x y z nx ny nz f_dc_0..2 f_rest_0.. opacity scale_0..2
// rot_0..3, float32, f_rest channel-major), and its SH evaluation transcribed from its sh_utils.eval_sh
// (Condon-Shortley phase, evaluated at the camera-to-splat direction). Nothing here calls the code
// under test.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace splattest {

// One splat as the reference implementation holds it before saving (activations not applied).
struct RefSplat {
    Eigen::Vector3f position = Eigen::Vector3f::Zero();
    std::vector<float> sh[3];  // per channel, (d+1)^2 coefficients; [0] = f_dc
    float opacityLogit = 0.0f;
    Eigen::Vector3f logScale = Eigen::Vector3f::Zero();
    Eigen::Vector4f rotation = Eigen::Vector4f(1, 0, 0, 0);  // w x y z
};

// eval_sh of the reference code, for one channel: sum_k sh[k] Y3dgs_k(dir).
inline double referenceEvalSh(int degree, const std::vector<float>& sh, const Eigen::Vector3d& dir) {
    const double C0 = 0.28209479177387814, C1 = 0.4886025119029199;
    const double C2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792,
                          0.5462742152960396};
    const double C3[7] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                          -0.4570457994644658, 1.445305721320277, -0.5900435899266435};
    double result = C0 * sh[0];
    if (degree > 0) {
        const double x = dir.x(), y = dir.y(), z = dir.z();
        result = result - C1 * y * sh[1] + C1 * z * sh[2] - C1 * x * sh[3];
        if (degree > 1) {
            const double xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
            result = result + C2[0] * xy * sh[4] + C2[1] * yz * sh[5] + C2[2] * (2.0 * zz - xx - yy) * sh[6] +
                     C2[3] * xz * sh[7] + C2[4] * (xx - yy) * sh[8];
            if (degree > 2) {
                result = result + C3[0] * y * (3 * xx - yy) * sh[9] + C3[1] * xy * z * sh[10] +
                         C3[2] * y * (4 * zz - xx - yy) * sh[11] + C3[3] * z * (2 * zz - 3 * xx - 3 * yy) * sh[12] +
                         C3[4] * x * (4 * zz - xx - yy) * sh[13] + C3[5] * z * (xx - yy) * sh[14] +
                         C3[6] * x * (xx - 3 * yy) * sh[15];
            }
        }
    }
    return result;
}

// The display colour the reference rasteriser gives a splat seen from a camera at `camera`
// (computeColorFromSH: SH at normalize(pos - campos), + 0.5, clamped at 0).
inline double referenceSplatColor(int degree, const std::vector<float>& sh, const Eigen::Vector3d& position,
                                  const Eigen::Vector3d& camera) {
    const double value = referenceEvalSh(degree, sh, (position - camera).normalized()) + 0.5;
    return value < 0.0 ? 0.0 : value;
}

// IEC 61966-2-1 sRGB decoding of a value in [0, 1].
inline double referenceSrgbDecode(double c) {
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

enum class PlyFormat { BinaryLittleEndian, BinaryBigEndian, Ascii };

// The reference save_ply's property list for SH degree d.
inline std::vector<std::string> referenceProperties(int degree, bool withNormals = true) {
    std::vector<std::string> names = {"x", "y", "z"};
    if (withNormals) names.insert(names.end(), {"nx", "ny", "nz"});
    for (int i = 0; i < 3; ++i) names.push_back("f_dc_" + std::to_string(i));
    const int rest = 3 * ((degree + 1) * (degree + 1) - 1);
    for (int i = 0; i < rest; ++i) names.push_back("f_rest_" + std::to_string(i));
    names.push_back("opacity");
    for (int i = 0; i < 3; ++i) names.push_back("scale_" + std::to_string(i));
    for (int i = 0; i < 4; ++i) names.push_back("rot_" + std::to_string(i));
    return names;
}

// The value of property `name` of a splat (f_rest channel-major: the reference's (K-1, 3) rest
// features transposed to (3, K-1) and flattened).
inline float referenceValue(const RefSplat& s, int degree, const std::string& name) {
    const int k = (degree + 1) * (degree + 1);
    if (name == "x") return s.position.x();
    if (name == "y") return s.position.y();
    if (name == "z") return s.position.z();
    if (name == "nx" || name == "ny" || name == "nz") return 0.0f;
    if (name.rfind("f_dc_", 0) == 0) return s.sh[std::stoi(name.substr(5))][0];
    if (name.rfind("f_rest_", 0) == 0) {
        const int i = std::stoi(name.substr(7));
        if (i >= 3 * (k - 1)) return 0.0f;  // a property beyond the degree (a broken file made by a test)
        return s.sh[i / (k - 1)][1 + i % (k - 1)];
    }
    if (name == "opacity") return s.opacityLogit;
    if (name.rfind("scale_", 0) == 0) return s.logScale[std::stoi(name.substr(6))];
    if (name.rfind("rot_", 0) == 0) return s.rotation[std::stoi(name.substr(4))];
    return 0.0f;  // extra properties of a test
}

// Writes a splat file with the given properties (in that order; names outside the reference's get 0).
inline void writeSplatPly(const std::string& path, const std::vector<RefSplat>& splats, int degree,
                          PlyFormat format = PlyFormat::BinaryLittleEndian,
                          std::vector<std::string> names = {}) {
    if (names.empty()) names = referenceProperties(degree);
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat "
        << (format == PlyFormat::Ascii ? "ascii" : format == PlyFormat::BinaryBigEndian ? "binary_big_endian"
                                                                                         : "binary_little_endian")
        << " 1.0\nelement vertex " << splats.size() << "\n";
    for (const std::string& n : names) out << "property float " << n << "\n";
    out << "end_header\n";
    for (const RefSplat& s : splats) {
        for (std::size_t i = 0; i < names.size(); ++i) {
            const float v = referenceValue(s, degree, names[i]);
            if (format == PlyFormat::Ascii) {
                std::ostringstream text;
                text.precision(9);
                text << v;
                out << (i ? " " : "") << text.str();
            } else {
                unsigned char b[4];
                std::memcpy(b, &v, 4);  // the test machines are little-endian
                if (format == PlyFormat::BinaryBigEndian) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
                out.write(reinterpret_cast<const char*>(b), 4);
            }
        }
        if (format == PlyFormat::Ascii) out << "\n";
    }
}

}  // namespace splattest
