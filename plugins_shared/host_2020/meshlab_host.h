// Compatibility header for MeshLab 2020.09 (Debian's meshlab, meshlabserver): the few API calls that
// differ between the two MeshLab hosts, under one set of names. Its twin for MeshLab 2025.07
// (pymeshlab) is host_2025/meshlab_host.h; CMake puts exactly one of the two folders on a target's
// include path, so no code outside these folders needs an #ifdef.
#pragma once

#include <common/interfaces.h>
#include <common/meshmodel.h>

#include <QDir>
#include <QFileInfo>
#include <Eigen/Core>

#include <cmath>
#include <vector>

#define RADML_FILTER_PLUGIN_IID MESH_FILTER_INTERFACE_IID
#define RADML_FILTER_INTERFACE MeshFilterInterface
#define RADML_IO_PLUGIN_IID MESH_IO_INTERFACE_IID
#define RADML_IO_INTERFACE MeshIOInterface

namespace radml {

constexpr int kMeshLabHostYear = 2020;
constexpr const char* kMeshLabHostName = "MeshLab 2020.09";

inline std::vector<MeshModel*> documentMeshes(MeshDocument& md) {
    return std::vector<MeshModel*>(md.meshList.begin(), md.meshList.end());
}
inline std::vector<RasterModel*> documentRasters(MeshDocument& md) {
    return std::vector<RasterModel*>(md.rasterList.begin(), md.rasterList.end());
}
// Enables the optional per-element data named by vcg::tri::io::Mask bits (what a reader loaded).
inline void enableLoadedData(MeshModel& m, int ioMask) { m.Enable(ioMask); }
// Bounding box and normals after the geometry changed.
inline void updateBoxAndNormals(MeshModel& m) { m.UpdateBoxAndNormals(); }

// Makes the image file `file` the layer's only texture. MeshLab 2020.09 keeps only the name and
// loads the image when it draws the layer, relative to its working directory (which it moves to the
// folder of the mesh it opens): the file name alone when the map is there, the absolute path
// otherwise; a saved mesh refers to that name.
inline void setLayerTexture(MeshModel& m, const std::string& file) {
    const QFileInfo info(QString::fromStdString(file));
    const bool here = info.absolutePath() == QDir::current().absolutePath();
    m.cm.textures.clear();
    m.cm.textures.push_back((here ? info.fileName() : info.absoluteFilePath()).toStdString());
}

// Gives layer `to` the textures of layer `from` (MeshLab 2020.09 keeps their file names only).
inline void copyLayerTextures(const MeshModel& from, MeshModel& to) { to.cm.textures = from.cm.textures; }

// A numeric parameter's value is finite (floats, percentages, dynamic floats, points); true for the
// other kinds.
inline bool parameterValueIsFinite(const RichParameter& p) {
    const Value& v = p.value();
    if (v.isFloat()) return std::isfinite(v.getFloat());
    if (v.isAbsPerc()) return std::isfinite(v.getAbsPerc());
    if (v.isDynamicFloat()) return std::isfinite(v.getDynamicFloat());
    if (v.isPoint3f()) {
        const vcg::Point3f q = v.getPoint3f();
        return std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]);
    }
    return true;
}
// For an enum parameter: its chosen index and its choices (false for other parameters).
inline bool enumChoice(const RichParameter& p, int& index, QStringList& choices) {
    const auto* e = dynamic_cast<const RichEnum*>(&p);
    if (e == nullptr) return false;
    index = p.value().getEnum();
    choices = e->enumvalues;
    return true;
}

// The image plane of a raster layer.
using RasterImagePlane = Plane;
inline bool rasterIsVisible(const RasterModel& raster) { return raster.visible; }

// A new raster layer showing `image` (already decoded: it is not read again), which the layer
// records as coming from `path`; its camera is the caller's to set. It becomes the current raster.
inline RasterModel* addRasterLayer(MeshDocument& md, const QString& label, const QImage& image, const QString& path) {
    RasterModel* raster = md.addNewRaster();
    raster->setLabel(label);
    Plane* plane = new Plane(QString(), Plane::RGBA);  // an empty path: nothing is decoded here
    plane->fullPathFileName = path;
    plane->image = image;
    raster->addPlane(plane);
    return raster;
}

// A new layer of the document; it becomes the current one only in a document that had none (an
// empty document, where filters like the out-of-core simplification create the first layer).
inline MeshModel* addLayer(MeshDocument& md, const QString& label) { return md.addNewMesh("", label, md.mm() == nullptr); }
// Removes a layer a refused filter added (runFilter: a refusal leaves the layers as they were).
inline void removeLayer(MeshDocument& md, MeshModel* m) { md.delMesh(m); }
// Makes `m` the current layer again (after removeLayer changed it).
inline void makeCurrentLayer(MeshDocument& md, MeshModel* m) { md.setCurrentMesh(m->id()); }

// A parameter naming one of the document's layers.
inline void addMeshParameter(RichParameterList& par, const QString& name, const MeshDocument& md,
                             const MeshModel* initial, const QString& label, const QString& help) {
    par.addParam(RichMesh(name, const_cast<MeshModel*>(initial), const_cast<MeshDocument*>(&md), label, help));
}
inline MeshModel* meshParameter(const RichParameterList& par, MeshDocument&, const QString& name) {
    return par.getMesh(name);
}

// A point in space (MeshLab 2020 has no separate position / direction types).
inline void addPointParameter(RichParameterList& par, const QString& name, const Eigen::Vector3d& initial,
                              const QString& label, const QString& help) {
    par.addParam(RichPoint3f(name, vcg::Point3f(float(initial.x()), float(initial.y()), float(initial.z())), label, help));
}
inline void addDirectionParameter(RichParameterList& par, const QString& name, const Eigen::Vector3d& initial,
                                  const QString& label, const QString& help) {
    addPointParameter(par, name, initial, label, help);
}
inline Eigen::Vector3d pointParameter(const RichParameterList& par, const QString& name) {
    const vcg::Point3f p = par.getPoint3f(name);
    return Eigen::Vector3d(p[0], p[1], p[2]);
}

// An absolute value that the dialog also shows as a percentage of [minimum, maximum].
inline void addAbsoluteOrPercentParameter(RichParameterList& par, const QString& name, double initial,
                                          double minimum, double maximum, const QString& label,
                                          const QString& help) {
    par.addParam(RichAbsPerc(name, float(initial), float(minimum), float(maximum), label, help));
}
inline double absoluteOrPercentParameter(const RichParameterList& par, const QString& name) {
    return par.getAbsPerc(name);
}

inline void addOpenFileParameter(RichParameterList& par, const QString& name, const QString& initial,
                                 const QStringList& extensions, const QString& label, const QString& help) {
    par.addParam(RichOpenFile(name, initial, extensions, label, help));
}
inline void addDynamicFloatParameter(RichParameterList& par, const QString& name, double initial, double minimum,
                                     double maximum, const QString& label, const QString& help) {
    par.addParam(RichDynamicFloat(name, float(initial), float(minimum), float(maximum), label, help));
}

}  // namespace radml
