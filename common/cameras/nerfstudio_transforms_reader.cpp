#include "cameras/nerfstudio_transforms_reader.h"

#include "io/json_value.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace rad {

namespace {

// A number member of `frame`, else of `top`, else `fallback`; NaN when `required` and absent.
double member(const JsonValue& frame, const JsonValue& top, const char* key, double fallback, const std::string& where) {
    for (const JsonValue* object : {&frame, &top}) {
        if (const JsonValue* v = object->find(key)) {
            if (!v->isNumber()) throw CameraFileError(where + ": '" + key + "' is not a number");
            return v->number;
        }
    }
    return fallback;
}

std::string memberString(const JsonValue& frame, const JsonValue& top, const char* key, const std::string& fallback) {
    for (const JsonValue* object : {&frame, &top})
        if (const JsonValue* v = object->find(key))
            if (v->type == JsonValue::Type::String) return v->string;
    return fallback;
}

// The focal lengths, principal point and image size: nerfstudio's fl_x, fl_y, cx, cy, w, h, or the
// original NeRF's camera_angle_x (and camera_angle_y) with the size of the photograph itself (or w, h
// when given).
void readIntrinsics(const JsonValue& frame, const JsonValue& top, const std::string& where, ImportedCamera& camera) {
    const auto has = [&](const char* key) { return frame.find(key) != nullptr || top.find(key) != nullptr; };
    const bool sized = has("w") && has("h");
    if (!has("fl_x") && has("camera_angle_x")) {
        camera.fieldOfViewX = member(frame, top, "camera_angle_x", 0, where);
        camera.fieldOfViewY = member(frame, top, "camera_angle_y", 0, where);
        if (!(camera.fieldOfViewX > 0.0))
            throw CameraFileError(where + ": 'camera_angle_x' must be a positive angle in radians");
        if (!sized) return;  // sized by the photograph (ImportedCamera::takeSizeFromPhotograph)
    } else if (!has("fl_x") || !sized) {
        const char* missing = !has("fl_x") ? "fl_x" : !has("w") ? "w" : "h";
        throw CameraFileError(where + ": no '" + std::string(missing) + "' (focal length and image size in pixels, "
                              "or the field of view camera_angle_x); give nerfstudio's intrinsics, as "
                              "nerfstudio's ns-process-data writes them");
    }
    const double w = member(frame, top, "w", 0, where), h = member(frame, top, "h", 0, where);
    if (!(w >= 1 && h >= 1 && w == std::floor(w) && h == std::floor(h)))
        throw CameraFileError(where + ": 'w' and 'h' must be positive whole numbers");
    if (camera.fieldOfViewX > 0.0) {
        camera.takeSizeFromPhotograph(int(w), int(h));
        camera.fieldOfViewX = camera.fieldOfViewY = 0.0;
        return;
    }
    camera.width = int(w);
    camera.height = int(h);
    camera.lens.fx = member(frame, top, "fl_x", 0, where);
    camera.lens.fy = member(frame, top, "fl_y", camera.lens.fx, where);
    camera.lens.cx = member(frame, top, "cx", 0.5 * w, where);
    camera.lens.cy = member(frame, top, "cy", 0.5 * h, where);
}

ImportedCamera readFrame(const JsonValue& frame, const JsonValue& top, const std::string& where) {
    ImportedCamera camera;
    const JsonValue* file = frame.find("file_path");
    if (file == nullptr || file->type != JsonValue::Type::String || file->string.empty())
        throw CameraFileError(where + ": no 'file_path'; the file is not a nerfstudio transforms.json");
    camera.imageName = file->string;
    if (camera.imageName.rfind("./", 0) == 0) camera.imageName.erase(0, 2);
    readIntrinsics(frame, top, where, camera);
    LensModel& lens = camera.lens;
    const std::string model = memberString(frame, top, "camera_model", "OPENCV");
    const char* radial[] = {"k1", "k2", "k3", "k4"};
    for (int i = 0; i < 4; ++i) lens.k[i] = member(frame, top, radial[i], 0.0, where);
    if (model == "OPENCV") {
        lens.p1 = member(frame, top, "p1", 0.0, where);
        lens.p2 = member(frame, top, "p2", 0.0, where);
    } else if (model == "OPENCV_FISHEYE") {
        lens.fisheye = true;
    } else if (model == "PINHOLE" || model == "SIMPLE_PINHOLE") {
        if (lens.distorts())
            throw CameraFileError(where + ": camera_model " + model + " with distortion coefficients; give camera_model OPENCV");
    } else {
        throw CameraFileError(where + ": camera_model '" + model + "' is not supported (OPENCV, OPENCV_FISHEYE, PINHOLE); "
                              "undistort the images with nerfstudio or COLMAP first");
    }
    const JsonValue* m = frame.find("transform_matrix");
    Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
    bool ok = m != nullptr && m->type == JsonValue::Type::Array && (m->array.size() == 4 || m->array.size() == 3);
    for (std::size_t i = 0; ok && i < m->array.size(); ++i) {
        const JsonValue& row = m->array[i];
        ok = row.type == JsonValue::Type::Array && row.array.size() == 4;
        for (std::size_t j = 0; ok && j < 4; ++j) {
            ok = row.array[j].isNumber();
            if (ok) c2w(int(i), int(j)) = row.array[j].number;
        }
    }
    if (!ok) throw CameraFileError(where + ": 'transform_matrix' must be 4 rows of 4 numbers (camera to world)");
    // OpenGL camera axes (right, up, backward) -> ours (right, down, forward): negate the 2nd and
    // 3rd columns of the camera-to-world rotation; its transpose maps world to camera.
    Eigen::Matrix3d rotation = c2w.topLeftCorner<3, 3>();
    rotation.col(1) *= -1.0;
    rotation.col(2) *= -1.0;
    camera.rotation = rotation.transpose();
    camera.center = c2w.topRightCorner<3, 1>();
    const std::string problem = camera.validate();
    if (!problem.empty()) throw CameraFileError(where + ": " + problem);
    return camera;
}

}  // namespace

CameraImport readNerfstudioTransforms(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw CameraFileError("cannot open '" + path + "': check that it exists and is readable");
    std::ostringstream text;
    text << in.rdbuf();
    JsonValue top;
    try {
        top = parseJson(text.str(), path);
    } catch (const JsonError& e) {
        throw CameraFileError(std::string(e.what()) + "; give a nerfstudio transforms.json");
    }
    const JsonValue* frames = top.find("frames");
    if (frames == nullptr || frames->type != JsonValue::Type::Array)
        throw CameraFileError("'" + path + "' is JSON but not a nerfstudio transforms.json (no 'frames' list)");
    CameraImport out;
    out.format = "nerfstudio transforms.json";
    for (std::size_t i = 0; i < frames->array.size(); ++i)
        out.cameras.push_back(readFrame(frames->array[i], top, "'" + path + "', frame " + std::to_string(i)));
    if (out.cameras.empty()) throw CameraFileError("'" + path + "' lists no frame");
    return out;
}

}  // namespace rad
