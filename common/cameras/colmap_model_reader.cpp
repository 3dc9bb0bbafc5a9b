#include "cameras/colmap_model_reader.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <sys/stat.h>

namespace rad {

namespace {

const char* const kModelNames[] = {"SIMPLE_PINHOLE", "PINHOLE", "SIMPLE_RADIAL", "RADIAL", "OPENCV",
                                   "OPENCV_FISHEYE", "FULL_OPENCV", "FOV", "SIMPLE_RADIAL_FISHEYE",
                                   "RADIAL_FISHEYE", "THIN_PRISM_FISHEYE", "RAD_TAN_THIN_PRISM_FISHEYE",
                                   "SIMPLE_DIVISION", "DIVISION", "SIMPLE_FISHEYE", "FISHEYE", "EUCM",
                                   "EQUIRECTANGULAR"};
// Parameter counts of the models above (COLMAP's models.h), needed to step over a camera record.
const int kModelParamCounts[] = {3, 4, 4, 5, 8, 8, 12, 5, 4, 5, 12, 16, 4, 5, 3, 4, 6, 2};
constexpr int kModelCount = int(sizeof kModelNames / sizeof kModelNames[0]);

bool isFile(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw CameraFileError("cannot open '" + path + "': check that it exists and is readable");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

struct ColmapCamera {
    int width = 0, height = 0;
    LensModel lens;
};

// Little-endian reader over a whole file with bounds checks (COLMAP writes little-endian).
class BinaryCursor {
public:
    BinaryCursor(std::string bytes, std::string path) : bytes_(std::move(bytes)), path_(std::move(path)) {}
    template <typename T>
    T read() {
        need(sizeof(T));
        T value;
        std::memcpy(&value, bytes_.data() + at_, sizeof(T));
        at_ += sizeof(T);
        return value;
    }
    std::string readNulTerminated() {
        const std::size_t end = bytes_.find('\0', at_);
        if (end == std::string::npos) truncated();
        std::string out = bytes_.substr(at_, end - at_);
        at_ = end + 1;
        return out;
    }
    void skip(std::uint64_t count) {
        if (count > bytes_.size() - at_) truncated();
        at_ += std::size_t(count);
    }
    bool atEnd() const { return at_ == bytes_.size(); }

private:
    void need(std::size_t n) {
        if (n > bytes_.size() - at_) truncated();
    }
    [[noreturn]] void truncated() const {
        throw CameraFileError("'" + path_ + "' is truncated or not a COLMAP binary model file (it ends inside a record); "
                              "export the model again from COLMAP (File > Export model) or give the text model");
    }
    std::string bytes_;
    std::string path_;
    std::size_t at_ = 0;
};

void checkSize(std::uint64_t width, std::uint64_t height, const std::string& where) {
    if (width == 0 || height == 0 || width > 1000000 || height > 1000000)
        throw CameraFileError(where + ": the image size " + std::to_string(width) + " x " + std::to_string(height) +
                              " is not usable; the file is damaged or not a COLMAP model");
}

std::map<std::uint32_t, ColmapCamera> readCamerasBinary(const std::string& path) {
    BinaryCursor in(slurp(path), path);
    const std::uint64_t count = in.read<std::uint64_t>();
    std::map<std::uint32_t, ColmapCamera> cameras;
    for (std::uint64_t i = 0; i < count; ++i) {
        const std::uint32_t id = in.read<std::uint32_t>();
        const std::int32_t model = in.read<std::int32_t>();
        const std::uint64_t width = in.read<std::uint64_t>(), height = in.read<std::uint64_t>();
        const std::string where = "'" + path + "', camera " + std::to_string(id);
        if (model < 0 || model >= kModelCount)
            throw CameraFileError(where + ": camera model id " + std::to_string(model) +
                                  " is not one COLMAP defines (or the file is not a COLMAP cameras.bin); "
                                  "convert the model to OPENCV or PINHOLE with COLMAP, or give the text model");
        checkSize(width, height, where);
        std::vector<double> params(kModelParamCounts[model]);
        for (double& p : params) p = in.read<double>();
        ColmapCamera camera;
        camera.width = int(width);
        camera.height = int(height);
        try {
            camera.lens = colmapLens(kModelNames[model], params);
        } catch (const CameraFileError& e) {
            throw CameraFileError(where + ": " + e.what());
        }
        if (!cameras.emplace(id, camera).second)
            throw CameraFileError(where + " appears twice; the file is damaged: export the model again");
    }
    if (!in.atEnd())
        throw CameraFileError("'" + path + "' has data after its last camera: it is not a COLMAP cameras.bin, or it is damaged");
    return cameras;
}

std::vector<std::string> tokens(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> out;
    for (std::string t; in >> t;) out.push_back(t);
    return out;
}

double number(const std::string& token, const std::string& where) {
    try {
        std::size_t used = 0;
        const double v = std::stod(token, &used);
        if (used == token.size()) return v;
    } catch (const std::exception&) {
    }
    // std::stod refuses "nan" spelled some ways and accepts others: a NaN that parses is caught by
    // the lens / pose validation, text that does not is refused here.
    throw CameraFileError(where + ": '" + token + "' is not a number; the file is damaged or not a COLMAP text model");
}

std::string trim(const std::string& s) {
    const std::size_t a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return {};
    return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

// The data lines of a COLMAP text model, trimmed: blank lines and '#' comments are skipped, and each
// line knows where it is ("'path', line N") for the messages.
class TextModelLines {
public:
    explicit TextModelLines(const std::string& path) : path_(path), in_(slurp(path)) {}
    bool next(std::string& line) {
        for (std::string raw; std::getline(in_, raw);) {
            ++number_;
            line = trim(raw);
            if (!line.empty() && line[0] != '#') return true;
        }
        return false;
    }
    // Consumes the next line whatever it holds (an image's observations line may be empty).
    void skipRawLine() {
        std::string raw;
        if (std::getline(in_, raw)) ++number_;
    }
    std::string where() const { return "'" + path_ + "', line " + std::to_string(number_); }

private:
    std::string path_;
    std::istringstream in_;
    int number_ = 0;
};

std::map<std::uint32_t, ColmapCamera> readCamerasText(const std::string& path) {
    TextModelLines lines(path);
    std::map<std::uint32_t, ColmapCamera> cameras;
    for (std::string line; lines.next(line);) {
        const std::string where = lines.where();
        const std::vector<std::string> t = tokens(line);
        if (t.size() < 4)
            throw CameraFileError(where + ": expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS...; the file is not a COLMAP "
                                  "cameras.txt");
        const double id = number(t[0], where), width = number(t[2], where), height = number(t[3], where);
        if (id < 0 || id != std::floor(id) || width != std::floor(width) || height != std::floor(height) || width < 0 ||
            height < 0)
            throw CameraFileError(where + ": the camera id and image size must be whole numbers");
        checkSize(std::uint64_t(width), std::uint64_t(height), where);
        std::vector<double> params;
        for (std::size_t i = 4; i < t.size(); ++i) params.push_back(number(t[i], where));
        ColmapCamera camera;
        camera.width = int(width);
        camera.height = int(height);
        try {
            camera.lens = colmapLens(t[1], params);
        } catch (const CameraFileError& e) {
            throw CameraFileError(where + ": " + e.what());
        }
        if (!cameras.emplace(std::uint32_t(id), camera).second)
            throw CameraFileError(where + ": camera " + t[0] + " is defined twice; the file is damaged");
    }
    return cameras;
}

ImportedCamera makeCamera(const std::map<std::uint32_t, ColmapCamera>& cameras, std::uint32_t cameraId,
                          const std::string& name, const double q[4], const double t[3], const std::string& where) {
    const auto found = cameras.find(cameraId);
    if (found == cameras.end())
        throw CameraFileError(where + ": image '" + name + "' uses camera " + std::to_string(cameraId) +
                              ", which the cameras file does not define; give the images and cameras files of the same model");
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(q[i]))
            throw CameraFileError(where + ": image '" + name + "' has a rotation that is not a finite number; the model is damaged");
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::abs(norm - 1.0) < 1e-3))
        throw CameraFileError(where + ": image '" + name + "' has a rotation quaternion of norm " + std::to_string(norm) +
                              " (COLMAP writes unit quaternions): it is not a rotation; the model is damaged");
    ImportedCamera camera;
    camera.imageName = name;
    camera.width = found->second.width;
    camera.height = found->second.height;
    camera.lens = found->second.lens;
    camera.rotation = rotationFromQuaternion(q[0], q[1], q[2], q[3]);
    // x_cam = R X + t  =>  the centre, where x_cam = 0, is -R^T t.
    camera.center = -camera.rotation.transpose() * Eigen::Vector3d(t[0], t[1], t[2]);
    const std::string problem = camera.validate();
    if (!problem.empty())
        throw CameraFileError(where + ": " + problem + "; the model is damaged: run COLMAP's bundle adjustment again and "
                              "export the model");
    return camera;
}

std::vector<ImportedCamera> readImagesBinary(const std::string& path, const std::map<std::uint32_t, ColmapCamera>& cameras) {
    BinaryCursor in(slurp(path), path);
    const std::uint64_t count = in.read<std::uint64_t>();
    std::vector<ImportedCamera> out;
    for (std::uint64_t i = 0; i < count; ++i) {
        const std::uint32_t id = in.read<std::uint32_t>();
        double q[4], t[3];
        for (double& v : q) v = in.read<double>();
        for (double& v : t) v = in.read<double>();
        const std::uint32_t cameraId = in.read<std::uint32_t>();
        const std::string name = in.readNulTerminated();
        const std::uint64_t points = in.read<std::uint64_t>();
        if (points > (std::uint64_t(1) << 40)) in.skip(points);  // throws: damaged
        in.skip(points * 24);  // x, y (double) and the 3D point id (64 bits) of each observation
        out.push_back(makeCamera(cameras, cameraId, name, q, t, "'" + path + "', image " + std::to_string(id)));
    }
    if (!in.atEnd())
        throw CameraFileError("'" + path + "' has data after its last image: it is not a COLMAP images.bin, or it is damaged");
    return out;
}

std::vector<ImportedCamera> readImagesText(const std::string& path, const std::map<std::uint32_t, ColmapCamera>& cameras) {
    TextModelLines lines(path);
    std::vector<ImportedCamera> out;
    for (std::string line; lines.next(line);) {
        const std::string where = lines.where();
        // IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME; the name is the rest of the line.
        std::istringstream fields(line);
        std::string t[9];
        for (std::string& f : t) fields >> f;
        std::string name;
        std::getline(fields, name);
        name = trim(name);
        if (name.empty())
            throw CameraFileError(where + ": expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME; the file is not a "
                                  "COLMAP images.txt");
        double q[4], tr[3];
        for (int i = 0; i < 4; ++i) q[i] = number(t[1 + i], where);
        for (int i = 0; i < 3; ++i) tr[i] = number(t[5 + i], where);
        const double cameraId = number(t[8], where);
        out.push_back(makeCamera(cameras, std::uint32_t(cameraId), name, q, tr, where));
        // Every image line is followed by its observations' line (possibly empty), as COLMAP reads it.
        lines.skipRawLine();
    }
    return out;
}

}  // namespace

std::string colmapModelName(int modelId) { return modelId >= 0 && modelId < kModelCount ? kModelNames[modelId] : ""; }

LensModel colmapLens(const std::string& name, const std::vector<double>& p) {
    int model = -1;
    for (int i = 0; i < kModelCount; ++i)
        if (name == kModelNames[i]) model = i;
    if (model < 0)
        throw CameraFileError("camera model '" + name + "' is not a COLMAP camera model; the file is damaged or not a COLMAP model");
    if (int(p.size()) != kModelParamCounts[model])
        throw CameraFileError("camera model " + name + " has " + std::to_string(kModelParamCounts[model]) +
                              " parameters, the file gives " + std::to_string(p.size()) + "; the file is damaged");
    LensModel lens;
    const auto singleFocal = [&] { lens.fx = lens.fy = p[0]; lens.cx = p[1]; lens.cy = p[2]; };
    const auto twoFocals = [&] { lens.fx = p[0]; lens.fy = p[1]; lens.cx = p[2]; lens.cy = p[3]; };
    if (name == "SIMPLE_PINHOLE") {
        singleFocal();
    } else if (name == "PINHOLE") {
        twoFocals();
    } else if (name == "SIMPLE_RADIAL") {
        singleFocal();
        lens.k[0] = p[3];
    } else if (name == "RADIAL") {
        singleFocal();
        lens.k[0] = p[3];
        lens.k[1] = p[4];
    } else if (name == "OPENCV") {
        twoFocals();
        lens.k[0] = p[4];
        lens.k[1] = p[5];
        lens.p1 = p[6];
        lens.p2 = p[7];
    } else if (name == "OPENCV_FISHEYE") {
        // theta_d = theta (1 + k1 theta^2 + ... + k4 theta^8): equidistant, then the radial polynomial in theta.
        twoFocals();
        lens.fisheye = true;
        for (int i = 0; i < 4; ++i) lens.k[i] = p[4 + i];
    } else if (name == "FULL_OPENCV") {
        twoFocals();
        lens.k[0] = p[4];
        lens.k[1] = p[5];
        lens.p1 = p[6];
        lens.p2 = p[7];
        lens.k[2] = p[8];
        lens.d[0] = p[9];
        lens.d[1] = p[10];
        lens.d[2] = p[11];
    } else if (name == "FOV") {
        twoFocals();
        lens.fovOmega = p[4];
    } else if (name == "SIMPLE_RADIAL_FISHEYE") {
        singleFocal();
        lens.fisheye = true;
        lens.k[0] = p[3];
    } else if (name == "RADIAL_FISHEYE") {
        singleFocal();
        lens.fisheye = true;
        lens.k[0] = p[3];
        lens.k[1] = p[4];
    } else if (name == "THIN_PRISM_FISHEYE") {
        twoFocals();
        lens.fisheye = true;
        lens.k[0] = p[4];
        lens.k[1] = p[5];
        lens.p1 = p[6];
        lens.p2 = p[7];
        lens.k[2] = p[8];
        lens.k[3] = p[9];
        lens.s[0] = p[10];  // sx1 r^2
        lens.s[2] = p[11];  // sy1 r^2
    } else if (name == "SIMPLE_FISHEYE") {
        singleFocal();
        lens.fisheye = true;
    } else if (name == "FISHEYE") {
        twoFocals();
        lens.fisheye = true;
    } else {
        throw CameraFileError("camera model " + name +
                              " is not supported by this import (supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, "
                              "OPENCV, OPENCV_FISHEYE, FULL_OPENCV, FOV, SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE, "
                              "THIN_PRISM_FISHEYE, SIMPLE_FISHEYE, FISHEYE); undistort the images with COLMAP's "
                              "image_undistorter and import its PINHOLE model, or refine the cameras with one of these models");
    }
    return lens;
}

CameraImport readColmapModel(const std::string& folder) {
    const std::string base = folder.empty() || folder.back() == '/' ? folder : folder + "/";
    CameraImport out;
    if (isFile(base + "cameras.bin") && isFile(base + "images.bin")) {
        out.format = "COLMAP binary model";
        out.cameras = readImagesBinary(base + "images.bin", readCamerasBinary(base + "cameras.bin"));
    } else if (isFile(base + "cameras.txt") && isFile(base + "images.txt")) {
        out.format = "COLMAP text model";
        out.cameras = readImagesText(base + "images.txt", readCamerasText(base + "cameras.txt"));
    } else {
        throw CameraFileError("'" + folder + "' holds no COLMAP model: it needs cameras.bin and images.bin, or cameras.txt "
                              "and images.txt (COLMAP's sparse/0 folder)");
    }
    if (out.cameras.empty())
        throw CameraFileError("the COLMAP model in '" + folder + "' has no registered image; run COLMAP's mapper first");
    return out;
}

}  // namespace rad
