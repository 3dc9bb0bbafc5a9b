#include "cameras/lens_model.h"

#include <cmath>
#include <cstdio>

namespace rad {

bool LensModel::distorts() const {
    if (fisheye || fovOmega != 0.0 || skew != 0.0 || p1 != 0.0 || p2 != 0.0) return true;
    for (double c : k)
        if (c != 0.0) return true;
    for (double c : d)
        if (c != 0.0) return true;
    for (double c : s)
        if (c != 0.0) return true;
    return false;
}

Eigen::Vector2d LensModel::distort(const Eigen::Vector2d& ideal) const {
    double x = ideal.x(), y = ideal.y();
    if (fisheye) {
        // Equidistant: the image radius is the angle from the axis, theta = atan(r).
        const double r = std::sqrt(x * x + y * y);
        const double factor = r > 1e-12 ? std::atan(r) / r : 1.0;
        x *= factor;
        y *= factor;
    }
    if (fovOmega != 0.0) {
        const double r = std::sqrt(x * x + y * y);
        const double t = 2.0 * std::tan(0.5 * fovOmega);
        const double factor = r > 1e-12 ? std::atan(r * t) / (fovOmega * r) : t / fovOmega;
        x *= factor;
        y *= factor;
    }
    const double x2 = x * x, y2 = y * y, xy = x * y, r2 = x2 + y2;
    const double numerator = 1.0 + r2 * (k[0] + r2 * (k[1] + r2 * (k[2] + r2 * k[3])));
    const double denominator = 1.0 + r2 * (d[0] + r2 * (d[1] + r2 * d[2]));
    const double radial = numerator / denominator;
    const double xd = x * radial + 2.0 * p1 * xy + p2 * (r2 + 2.0 * x2) + r2 * (s[0] + r2 * s[1]);
    const double yd = y * radial + p1 * (r2 + 2.0 * y2) + 2.0 * p2 * xy + r2 * (s[2] + r2 * s[3]);
    return {xd, yd};
}

Eigen::Vector2d LensModel::pixelOf(const Eigen::Vector2d& ideal) const {
    const Eigen::Vector2d q = distort(ideal);
    return {fx * q.x() + skew * q.y() + cx, fy * q.y() + cy};
}

LensModel LensModel::scaled(double sx, double sy) const {
    // u' = sx u and v' = sy v: every pixel-unit term of step 5 scales with its axis.
    LensModel out = *this;
    out.fx *= sx;
    out.skew *= sx;
    out.cx *= sx;
    out.fy *= sy;
    out.cy *= sy;
    return out;
}

std::string LensModel::validate() const {
    const double all[] = {fx, fy, cx, cy, skew, fovOmega, k[0], k[1], k[2], k[3], d[0], d[1], d[2],
                          p1, p2, s[0], s[1], s[2], s[3]};
    for (double v : all)
        if (!std::isfinite(v)) return "a lens parameter is not a finite number (NaN or infinite)";
    if (!(fx > 0.0) || !(fy > 0.0)) return "the focal length is not positive";
    if (fovOmega < 0.0 || fovOmega >= 3.14159265358979) return "the FOV model's omega is not in [0, pi)";
    return {};
}

std::string LensModel::describe() const {
    char text[640];
    std::snprintf(text, sizeof text,
                  "f %.17g %.17g c %.17g %.17g skew %.17g fisheye %d omega %.17g k %.17g %.17g %.17g %.17g "
                  "d %.17g %.17g %.17g p %.17g %.17g s %.17g %.17g %.17g %.17g",
                  fx, fy, cx, cy, skew, fisheye ? 1 : 0, fovOmega, k[0], k[1], k[2], k[3], d[0], d[1], d[2], p1, p2,
                  s[0], s[1], s[2], s[3]);
    return text;
}

}  // namespace rad
