#include "cameras/imported_camera.h"

#include <Eigen/Geometry>

#include <cmath>

namespace rad {

bool ImportedCamera::project(const Eigen::Vector3d& X, double& u, double& v) const {
    const Eigen::Vector3d p = rotation * (X - center);
    if (!(p.z() > 0.0)) return false;
    const Eigen::Vector2d pixel = lens.pixelOf({p.x() / p.z(), p.y() / p.z()});
    u = pixel.x();
    v = pixel.y();
    return true;
}

PinholeCamera ImportedCamera::pinholePart() const {
    PinholeCamera camera;
    camera.rotation = rotation;
    camera.center = center;
    camera.fx = lens.fx;
    camera.fy = lens.fy;
    camera.cx = lens.cx;
    camera.cy = lens.cy;
    camera.width = width;
    camera.height = height;
    return camera;
}

void ImportedCamera::takeSizeFromPhotograph(int photographWidth, int photographHeight) {
    width = photographWidth;
    height = photographHeight;
    lens.fx = 0.5 * width / std::tan(0.5 * fieldOfViewX);
    lens.fy = fieldOfViewY > 0.0 ? 0.5 * height / std::tan(0.5 * fieldOfViewY) : lens.fx;
    lens.cx = 0.5 * width;
    lens.cy = 0.5 * height;
}

std::string ImportedCamera::validate() const {
    const std::string who = "camera of image '" + imageName + "': ";
    if (imageName.empty()) return "a camera names no image";
    if (sizedByPhotograph()) {
        const double pi = 3.14159265358979323846;
        for (const double angle : {fieldOfViewX, fieldOfViewY})
            if (!(angle >= 0.0 && angle < pi))  // NaN fails too; fieldOfViewY 0: not given
                return who + "the field of view (camera_angle_x / camera_angle_y) must lie between 0 and pi radians";
        return validatePose(who);  // the rest once the photograph sized it
    }
    const std::string lensProblem = lens.validate();
    if (!lensProblem.empty()) return who + lensProblem;
    if (width <= 0 || height <= 0) return who + "the image size is not positive";
    return validatePose(who);
}

std::string ImportedCamera::validatePose(const std::string& who) const {
    if (!rotation.allFinite() || !center.allFinite()) return who + "the pose holds a value that is not finite";
    const double orthogonality = (rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (orthogonality > 1e-5 || !(rotation.determinant() > 0.0))
        return who + "the pose's rotation is not a rotation (not orthonormal, or a reflection); the file's transform "
                     "holds a scale, shear or mirror that a camera cannot have";
    return {};
}

Eigen::Matrix3d rotationFromQuaternion(double w, double x, double y, double z) {
    Eigen::Quaterniond q(w, x, y, z);
    q.normalize();
    return q.toRotationMatrix();
}

}  // namespace rad
