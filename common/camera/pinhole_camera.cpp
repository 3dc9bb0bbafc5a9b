#include "camera/pinhole_camera.h"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rad {

bool PinholeCamera::project(const Eigen::Vector3d& X, double& u, double& v) const {
    const Eigen::Vector3d p = toCamera(X);
    if (!(p.z() > 0.0)) return false;
    u = fx * p.x() / p.z() + cx;
    v = fy * p.y() / p.z() + cy;
    return true;
}

Eigen::Vector3d PinholeCamera::rayDirection(double u, double v) const {
    const Eigen::Vector3d local((u - cx) / fx, (v - cy) / fy, 1.0);
    return (rotation.transpose() * local).normalized();
}

PinholeCamera PinholeCamera::lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                                    const Eigen::Vector3d& up, double horizontalFovDegrees, int width, int height) {
    if (!(horizontalFovDegrees > 0.0 && horizontalFovDegrees < 179.0))
        throw std::invalid_argument("PinholeCamera::lookAt: the field of view must be in (0, 179) degrees, got " +
                                    std::to_string(horizontalFovDegrees));
    PinholeCamera cam;
    const Eigen::Vector3d forward = (target - eye).normalized();
    Eigen::Vector3d right = forward.cross(up);
    if (right.norm() < 1e-9) right = forward.cross(std::abs(forward.x()) < 0.9 ? Eigen::Vector3d::UnitX()
                                                                                 : Eigen::Vector3d::UnitY());
    right.normalize();
    const Eigen::Vector3d down = forward.cross(right);  // right-handed: right x down = forward
    cam.rotation.row(0) = right.transpose();
    cam.rotation.row(1) = down.transpose();
    cam.rotation.row(2) = forward.transpose();
    cam.center = eye;
    cam.width = width;
    cam.height = height;
    const double halfFov = 0.5 * horizontalFovDegrees * M_PI / 180.0;
    cam.fx = cam.fy = 0.5 * width / std::tan(halfFov);
    cam.cx = 0.5 * width;
    cam.cy = 0.5 * height;
    return cam;
}

std::string PinholeCamera::validate() const {
    std::ostringstream why;
    if (!rotation.allFinite() || !center.allFinite() || !std::isfinite(fx) || !std::isfinite(fy) ||
        !std::isfinite(cx) || !std::isfinite(cy))
        why << "the camera has non-finite values";
    else if (!(fx > 0.0) || !(fy > 0.0))
        why << "the focal length is not positive (fx = " << fx << ", fy = " << fy << " pixels)";
    else if (width <= 0 || height <= 0)
        why << "the image size " << width << " x " << height << " is empty";
    else if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
             rotation.determinant() < 0.0)
        why << "the rotation is not a proper orthonormal matrix";
    return why.str();
}

}  // namespace rad
