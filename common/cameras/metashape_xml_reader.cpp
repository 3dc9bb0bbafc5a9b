#include "cameras/metashape_xml_reader.h"

#include "io/xml_tree.h"

#include <Eigen/Core>
#include <Eigen/LU>

#include <cmath>
#include <map>
#include <sstream>

namespace rad {

namespace {

// A similarity X_world = scale * rotation * X + translation.
struct Similarity {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    double scale = 1.0;
    Similarity then(const Similarity& outer) const {  // outer applied after *this
        Similarity out;
        out.rotation = outer.rotation * rotation;
        out.translation = outer.scale * (outer.rotation * translation) + outer.translation;
        out.scale = outer.scale * scale;
        return out;
    }
};

struct Sensor {
    int width = 0, height = 0;
    LensModel lens;
    std::string problem;  // why its cameras cannot be imported (empty: usable)
};

std::string where(const std::string& path, const XmlElement& e) { return "'" + path + "', line " + std::to_string(e.line); }

std::vector<double> numbers(const std::string& text, const std::string& context) {
    std::istringstream in(text);
    std::vector<double> out;
    std::string token;
    while (in >> token) {
        try {
            std::size_t used = 0;
            const double v = std::stod(token, &used);
            if (used != token.size()) throw std::invalid_argument(token);
            out.push_back(v);
        } catch (const std::exception&) {
            // std::stod throws out_of_range for "nan" spelled with a payload and for huge values.
            if (token == "nan" || token == "NaN" || token == "-nan") {
                out.push_back(std::nan(""));
            } else {
                throw CameraFileError(context + ": '" + token + "' is not a number; the file is damaged");
            }
        }
    }
    return out;
}

double number(const XmlElement* e, double fallback, const std::string& context) {
    if (e == nullptr) return fallback;
    const std::vector<double> v = numbers(e->text, context);
    if (v.size() != 1) throw CameraFileError(context + ": <" + e->name + "> must hold one number");
    return v[0];
}

bool isRotation(const Eigen::Matrix3d& r) {
    return r.allFinite() && (r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-5 &&
           r.determinant() > 0.0;
}

// A <transform> with <rotation> (9 numbers, row-major), <translation> (3), <scale> (1), each optional.
Similarity readSimilarity(const XmlElement& transform, const std::string& path) {
    const std::string context = where(path, transform) + ", chunk transform";
    Similarity s;
    if (const XmlElement* r = transform.child("rotation")) {
        const std::vector<double> v = numbers(r->text, context);
        if (v.size() != 9) throw CameraFileError(context + ": <rotation> must hold 9 numbers");
        for (int i = 0; i < 9; ++i) s.rotation(i / 3, i % 3) = v[i];
    }
    if (const XmlElement* t = transform.child("translation")) {
        const std::vector<double> v = numbers(t->text, context);
        if (v.size() != 3) throw CameraFileError(context + ": <translation> must hold 3 numbers");
        s.translation = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    s.scale = number(transform.child("scale"), 1.0, context);
    if (!isRotation(s.rotation))
        throw CameraFileError(context + ": the rotation is not a rotation (not orthonormal, or a reflection); "
                                        "export the cameras again from Metashape, or remove the chunk transform");
    if (!(s.scale > 0.0) || !std::isfinite(s.scale) || !s.translation.allFinite())
        throw CameraFileError(context + ": the scale must be a positive number and the translation finite");
    return s;
}

Sensor readSensor(const XmlElement& sensor, const std::string& path) {
    Sensor out;
    const std::string label = sensor.attribute("label", sensor.attribute("id"));
    const std::string context = where(path, sensor) + ", sensor '" + label + "'";
    const std::string type = sensor.attribute("type", "frame");
    if (type != "frame" && type != "fisheye") {
        out.problem = context + " is of type '" + type + "', which this import does not read (frame and fisheye "
                                "only); export undistorted images from Metashape instead";
        return out;
    }
    // The adjusted calibration when there is one, else the last one given.
    const XmlElement* calibration = nullptr;
    for (const XmlElement* c : sensor.childrenNamed("calibration"))
        if (calibration == nullptr || c->attribute("class") == "adjusted") calibration = c;
    if (calibration == nullptr) {
        out.problem = context + " has no <calibration>; align the photographs in Metashape before exporting the cameras";
        return out;
    }
    const XmlElement* resolution = calibration->child("resolution");
    if (resolution == nullptr) resolution = sensor.child("resolution");
    if (resolution == nullptr) throw CameraFileError(context + ": no <resolution> (image size); the file is damaged");
    out.width = std::atoi(resolution->attribute("width").c_str());
    out.height = std::atoi(resolution->attribute("height").c_str());
    if (out.width <= 0 || out.height <= 0)
        throw CameraFileError(context + ": the resolution is not a positive image size; the file is damaged");
    if (calibration->child("f") == nullptr)
        throw CameraFileError(context + ": the calibration has no focal length <f>; the file is damaged");
    const auto value = [&](const char* name) { return number(calibration->child(name), 0.0, context); };
    if (value("p3") != 0.0 || value("p4") != 0.0)
        throw CameraFileError(context + ": the calibration uses p3 / p4, which this import does not read; fix them "
                                        "to 0 in Metashape's camera calibration and optimise the cameras again");
    const double f = value("f");
    out.lens.fx = f + value("b1");
    out.lens.fy = f;
    out.lens.skew = value("b2");
    out.lens.cx = 0.5 * out.width + value("cx");
    out.lens.cy = 0.5 * out.height + value("cy");
    out.lens.fisheye = type == "fisheye";
    out.lens.k[0] = value("k1");
    out.lens.k[1] = value("k2");
    out.lens.k[2] = value("k3");
    out.lens.k[3] = value("k4");
    out.lens.p1 = value("p2");  // Metashape's P2 multiplies OpenCV's p1 terms, and P1 OpenCV's p2 terms
    out.lens.p2 = value("p1");
    return out;
}

bool isDisabled(const XmlElement& camera) {
    const std::string enabled = camera.attribute("enabled", "true");
    return enabled == "false" || enabled == "0";
}

// The cameras of a <cameras> element or of a <group> inside it, in document order.
void collectCameras(const XmlElement& parent, std::vector<const XmlElement*>& out) {
    for (const XmlElement& c : parent.children) {
        if (c.name == "camera") out.push_back(&c);
        if (c.name == "group") collectCameras(c, out);
    }
}

void readChunk(const XmlElement& chunk, const std::string& path, CameraImport& out) {
    std::map<std::string, Sensor> sensors;
    if (const XmlElement* list = chunk.child("sensors"))
        for (const XmlElement* s : list->childrenNamed("sensor")) sensors[s->attribute("id")] = readSensor(*s, path);

    Similarity chunkTransform;
    if (const XmlElement* t = chunk.child("transform")) chunkTransform = readSimilarity(*t, path);
    // Components (Metashape 1.6+): each its own transform, for the cameras of its partition (all of
    // them when there is a single component without a partition).
    std::map<std::string, Similarity> cameraComponent;
    Similarity onlyComponent;
    bool hasOnlyComponent = false;
    if (const XmlElement* components = chunk.child("components")) {
        const std::vector<const XmlElement*> list = components->childrenNamed("component");
        for (const XmlElement* component : list) {
            const XmlElement* t = component->child("transform");
            if (t == nullptr) continue;
            const Similarity s = readSimilarity(*t, path);
            const XmlElement* partition = component->child("partition");
            const XmlElement* ids = partition ? partition->child("camera_ids") : nullptr;
            if (ids != nullptr) {
                for (double id : numbers(ids->text, where(path, *ids))) cameraComponent[std::to_string(long(id))] = s;
            } else if (list.size() == 1) {
                onlyComponent = s;
                hasOnlyComponent = true;
            }
        }
    }

    std::vector<const XmlElement*> cameras;
    if (const XmlElement* list = chunk.child("cameras")) collectCameras(*list, cameras);
    for (const XmlElement* camera : cameras) {
        const std::string label = camera->attribute("label", camera->attribute("id"));
        const std::string context = where(path, *camera) + ", camera '" + label + "'";
        if (isDisabled(*camera)) {
            out.skipped.push_back("camera '" + label + "' is disabled");
            continue;
        }
        const XmlElement* transform = camera->child("transform");
        if (transform == nullptr) {
            out.skipped.push_back("camera '" + label + "' is not aligned (no transform)");
            continue;
        }
        const auto sensor = sensors.find(camera->attribute("sensor_id"));
        if (sensor == sensors.end())
            throw CameraFileError(context + " uses sensor '" + camera->attribute("sensor_id") +
                                  "', which the file does not define; export the cameras again");
        if (!sensor->second.problem.empty()) throw CameraFileError(sensor->second.problem);
        const std::vector<double> m = numbers(transform->text, context);
        if (m.size() != 16) throw CameraFileError(context + ": the <transform> must hold 16 numbers (4 x 4, row-major)");
        Similarity cameraToChunk;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) cameraToChunk.rotation(i, j) = m[4 * i + j];
            cameraToChunk.translation[i] = m[4 * i + 3];
        }
        if (!isRotation(cameraToChunk.rotation))
            throw CameraFileError(context + ": the camera's transform is not a rotation and a translation (it holds a "
                                            "scale, shear or mirror); the file is damaged: export the cameras again");
        Similarity toWorld = cameraToChunk;
        const auto component = cameraComponent.find(camera->attribute("id"));
        if (component != cameraComponent.end()) toWorld = toWorld.then(component->second);
        else if (hasOnlyComponent) toWorld = toWorld.then(onlyComponent);
        toWorld = toWorld.then(chunkTransform);
        ImportedCamera imported;
        imported.imageName = label;
        imported.width = sensor->second.width;
        imported.height = sensor->second.height;
        imported.lens = sensor->second.lens;
        // Camera-to-world is a similarity; its rotation's transpose maps world directions to the
        // camera axes (the scale does not change where a point projects).
        imported.rotation = toWorld.rotation.transpose();
        imported.center = toWorld.translation;
        const std::string problem = imported.validate();
        if (!problem.empty()) throw CameraFileError(context + ": " + problem + "; fix the calibration in Metashape and export again");
        out.cameras.push_back(imported);
    }
}

}  // namespace

CameraImport readMetashapeXml(const std::string& path) {
    XmlElement root;
    try {
        root = readXmlFile(path);
    } catch (const XmlError& e) {
        throw CameraFileError(std::string(e.what()) + "; give a Metashape camera XML (File > Export > Export Cameras)");
    }
    std::vector<const XmlElement*> chunks;
    if (root.name == "document") chunks = root.childrenNamed("chunk");
    if (root.name == "chunk") chunks.push_back(&root);
    if (chunks.empty())
        throw CameraFileError("'" + path + "' is XML but not a Metashape camera file (no <document> with a <chunk>); "
                              "give a Metashape camera XML (File > Export > Export Cameras)");
    CameraImport out;
    out.format = "Metashape camera XML";
    for (const XmlElement* chunk : chunks) {
        if (isDisabled(*chunk)) continue;
        readChunk(*chunk, path, out);
    }
    if (out.cameras.empty())
        throw CameraFileError("'" + path + "' has no aligned, enabled camera (" + std::to_string(out.skipped.size()) +
                              " skipped); align the photographs in Metashape before exporting the cameras");
    return out;
}

}  // namespace rad
