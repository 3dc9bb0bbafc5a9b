#include "camera/gl_view_camera.h"

#include <Eigen/Dense>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace rad {

namespace {

// Element (row i, column j) of a column-major 4x4 matrix.
Eigen::Matrix4d fromColumnMajor(const std::array<double, 16>& m) {
    Eigen::Matrix4d out;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) out(i, j) = m[4 * j + i];
    return out;
}

std::string str(double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}

}  // namespace

PinholeCamera cameraFromGlView(const GlView& view) {
    const auto& vp = view.viewport;
    for (double v : vp)
        if (!std::isfinite(v)) throw std::invalid_argument("the GL viewport has non-finite values");
    const double W = vp[2], H = vp[3];
    if (!(W >= 1.0 && H >= 1.0) || W != std::floor(W) || H != std::floor(H) || W > 1e6 || H > 1e6)
        throw std::invalid_argument("the GL viewport " + str(W) + " x " + str(H) +
                                    " is degenerate: its width and height must be positive whole numbers of pixels");

    const Eigen::Matrix4d MV = fromColumnMajor(view.modelview), P = fromColumnMajor(view.projection);
    if (!MV.allFinite()) throw std::invalid_argument("the modelview matrix has non-finite values");
    if (!P.allFinite()) throw std::invalid_argument("the projection matrix has non-finite values");

    // Modelview: [s R | t; 0 0 0 1].
    const Eigen::Matrix3d A = MV.topLeftCorner<3, 3>();
    const double scaleOfMatrix = std::max(A.cwiseAbs().maxCoeff(), MV.col(3).head<3>().cwiseAbs().maxCoeff());
    if (MV.row(3).head<3>().cwiseAbs().maxCoeff() > 1e-9 * std::max(1.0, scaleOfMatrix) ||
        std::abs(MV(3, 3) - 1.0) > 1e-9)
        throw std::invalid_argument("the modelview matrix's last row is not (0 0 0 1): it is not an affine transform");
    const double det = A.determinant();
    if (!(det > 0.0))
        throw std::invalid_argument("the modelview matrix's 3x3 part has determinant " + str(det) +
                                    " (mirror or collapse): it must be a positive uniform scale times a rotation");
    const double s = std::cbrt(det);
    const Eigen::Matrix3d R0 = A / s;
    const double deviation = (R0 * R0.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (deviation > 1e-4)
        throw std::invalid_argument("the modelview matrix's 3x3 part is not a uniform scale times a rotation "
                                    "(non-uniform scale or shear: R R^T differs from the identity by " +
                                    str(deviation) + " after dividing by the scale " + str(s) + ")");
    // Exactly orthonormal (nearest rotation, polar decomposition by SVD): float noise of the GL
    // matrices must not reach PinholeCamera::validate's own 1e-4 check.
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(R0, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
    const Eigen::Vector3d t = MV.col(3).head<3>();

    // Projection: (P00 0 P02 0), (0 P11 P12 0), (. . P22 P23), (0 0 -w 0).
    const double w = -P(3, 2);
    const double pScale = P.cwiseAbs().maxCoeff();
    const double tol = 1e-9 * std::max(1.0, pScale);
    if (!(w > 0.0) || std::abs(P(3, 3)) > tol * std::max(1.0, w) || std::abs(P(3, 0)) > tol || std::abs(P(3, 1)) > tol)
        throw std::invalid_argument(
            "the projection matrix is not a perspective one (its last row is (" + str(P(3, 0)) + " " + str(P(3, 1)) +
            " " + str(P(3, 2)) + " " + str(P(3, 3)) +
            "), not (0 0 -1 0)); MeshLab switches to an orthographic projection when its field of view is below 5 degrees");
    const Eigen::Matrix4d Pn = P / w;
    if (std::abs(Pn(0, 1)) > 1e-9 * std::abs(Pn(0, 0)) || std::abs(Pn(1, 0)) > 1e-9 * std::abs(Pn(1, 1)))
        throw std::invalid_argument("the projection matrix is skewed (P01 = " + str(Pn(0, 1)) + ", P10 = " +
                                    str(Pn(1, 0)) + "): a pinhole camera has none");
    if (std::abs(Pn(0, 3)) > 1e-9 * std::max(1.0, std::abs(Pn(0, 0))) ||
        std::abs(Pn(1, 3)) > 1e-9 * std::max(1.0, std::abs(Pn(1, 1))))
        throw std::invalid_argument("the projection matrix translates in clip space (P03 = " + str(Pn(0, 3)) +
                                    ", P13 = " + str(Pn(1, 3)) + "): not a pinhole camera");
    if (!(Pn(0, 0) > 0.0) || !(Pn(1, 1) > 0.0))
        throw std::invalid_argument("the projection matrix mirrors the image (P00 = " + str(Pn(0, 0)) +
                                    ", P11 = " + str(Pn(1, 1)) + "; both must be positive)");

    PinholeCamera cam;
    const Eigen::Matrix3d flip = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
    cam.rotation = flip * R;
    cam.center = -R.transpose() * t / s;
    cam.width = static_cast<int>(W);
    cam.height = static_cast<int>(H);
    cam.fx = 0.5 * W * Pn(0, 0);
    cam.cx = 0.5 * W * (1.0 - Pn(0, 2));
    cam.fy = 0.5 * H * Pn(1, 1);
    cam.cy = 0.5 * H * (1.0 + Pn(1, 2));
    return cam;
}

ScreenRect viewportInScreen(const DecorationViewFile& file) {
    const auto& vp = file.view.viewport;
    for (double v : vp)
        if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e6)
            throw std::invalid_argument("the GL viewport's values must be whole numbers of pixels");
    if (vp[2] < 1 || vp[3] < 1) throw std::invalid_argument("the GL viewport is empty");
    const double R = file.devicePixelRatio;
    ScreenRect r;
    r.width = static_cast<int>(vp[2]);
    r.height = static_cast<int>(vp[3]);
    r.x = static_cast<int>(std::lround(file.widgetOrigin[0] * R)) + static_cast<int>(vp[0]);
    r.y = static_cast<int>(std::lround(file.widgetOrigin[1] * R)) + static_cast<int>(std::lround(file.widgetSize[1] * R)) -
          static_cast<int>(vp[1] + vp[3]);
    return r;
}

DecorationViewFile readDecorationViewFile(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open the decoration view file");

    DecorationViewFile out;
    std::map<std::string, int> seen;  // key -> line
    std::string line;
    int lineNo = 0;
    bool header = false;
    auto fail = [&](const std::string& why) -> std::runtime_error {
        return std::runtime_error(path + ":" + std::to_string(lineNo) + ": " + why);
    };

    while (std::getline(in, line)) {
        ++lineNo;
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream words(line);
        std::string key;
        if (!(words >> key)) continue;
        std::vector<std::string> values;
        for (std::string w; words >> w;) values.push_back(w);

        auto number = [&](const std::string& text) {
            const char* begin = text.c_str();
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(begin, &end);
            if (end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(v))
                throw fail("'" + key + "' needs finite numbers, got '" + text + "'");
            return v;
        };
        auto expectCount = [&](std::size_t n) {
            if (values.size() != n)
                throw fail("'" + key + "' needs " + std::to_string(n) + " value" + (n == 1 ? "" : "s") + ", got " +
                           std::to_string(values.size()));
        };

        if (!header) {
            if (key != "radiance-decoration-view")
                throw fail("not a decoration view file: the first line must be 'radiance-decoration-view 1'");
            expectCount(1);
            if (values[0] != "1") throw fail("unsupported view file version '" + values[0] + "' (this reader knows 1)");
            header = true;
            continue;
        }
        if (auto it = seen.find(key); it != seen.end())
            throw fail("'" + key + "' repeated (first on line " + std::to_string(it->second) + ")");
        seen[key] = lineNo;

        if (key == "frame") {
            expectCount(1);
            const double f = number(values[0]);
            if (f != std::floor(f) || f < 0 || f > 9e15) throw fail("'frame' needs a non-negative integer, got '" + values[0] + "'");
            out.frame = static_cast<long long>(f);
        } else if (key == "mode") {
            expectCount(1);
            if (values[0] != "per-vertex" && values[0] != "per-fragment" && values[0] != "prt" &&
                values[0] != "cpu-per-vertex")
                throw fail("unknown mode '" + values[0] + "' (per-vertex, per-fragment, prt or cpu-per-vertex)");
            out.mode = values[0];
        } else if (key == "viewport") {
            expectCount(4);
            for (int i = 0; i < 4; ++i) out.view.viewport[i] = number(values[i]);
        } else if (key == "widget_origin") {
            expectCount(2);
            for (int i = 0; i < 2; ++i) out.widgetOrigin[i] = number(values[i]);
        } else if (key == "widget_size") {
            expectCount(2);
            for (int i = 0; i < 2; ++i) out.widgetSize[i] = number(values[i]);
            if (!(out.widgetSize[0] > 0 && out.widgetSize[1] > 0)) throw fail("'widget_size' must be positive");
        } else if (key == "device_pixel_ratio") {
            expectCount(1);
            out.devicePixelRatio = number(values[0]);
            if (!(out.devicePixelRatio > 0)) throw fail("'device_pixel_ratio' must be positive");
        } else if (key == "modelview" || key == "projection") {
            expectCount(16);
            auto& m = key == "modelview" ? out.view.modelview : out.view.projection;
            for (int i = 0; i < 16; ++i) m[i] = number(values[i]);
        } else if (key == "exposure") {
            expectCount(1);
            out.exposureStops = number(values[0]);
        } else if (key == "tonemap") {
            expectCount(1);
            if (values[0] != "clamp" && values[0] != "reinhard")
                throw fail("unknown tone curve '" + values[0] + "' (clamp or reinhard)");
            out.toneMap = values[0];
        } else {
            throw fail("unknown key '" + key + "'");
        }
    }
    if (in.bad()) throw std::runtime_error(path + ": read error");
    if (!header) throw std::runtime_error(path + ": empty file, not a decoration view file");
    for (const char* key : {"frame", "mode", "viewport", "widget_origin", "widget_size", "device_pixel_ratio",
                            "modelview", "projection", "exposure", "tonemap"})
        if (!seen.count(key)) throw std::runtime_error(path + ": the line '" + std::string(key) + "' is missing");
    return out;
}

}  // namespace rad
