// Compatibility header for MeshLab 2025.07 (the double-precision build inside pymeshlab): the few API
// calls that differ between the two MeshLab hosts, under one set of names. Its twin for MeshLab
// 2020.09 is host_2020/meshlab_host.h; CMake puts exactly one of the two folders on a target's
// include path, so no code outside these folders needs an #ifdef.
#pragma once

#include <common/ml_document/mesh_document.h>
#include <common/mlexception.h>
#include <common/plugins/interfaces/filter_plugin.h>
#include <common/plugins/interfaces/io_plugin.h>

#include <QFileInfo>
#include <Eigen/Core>

#include <cmath>
#include <vector>

#define RADML_FILTER_PLUGIN_IID FILTER_PLUGIN_IID
#define RADML_FILTER_INTERFACE FilterPlugin
#define RADML_IO_PLUGIN_IID IO_PLUGIN_IID
#define RADML_IO_INTERFACE IOPlugin

namespace radml {

constexpr int kMeshLabHostYear = 2025;
constexpr const char* kMeshLabHostName = "MeshLab 2025.07";

inline std::vector<MeshModel*> documentMeshes(MeshDocument& md) {
    std::vector<MeshModel*> out;
    for (MeshModel& m : md.meshIterator()) out.push_back(&m);
    return out;
}
inline std::vector<RasterModel*> documentRasters(MeshDocument& md) {
    std::vector<RasterModel*> out;
    for (RasterModel& r : md.rasterIterator()) out.push_back(&r);
    return out;
}
// Enables the optional per-element data named by vcg::tri::io::Mask bits (what a reader loaded).
inline void enableLoadedData(MeshModel& m, int ioMask) { m.enable(ioMask); }
// Bounding box and normals after the geometry changed.
inline void updateBoxAndNormals(MeshModel& m) { m.updateBoxAndNormals(); }

// Makes the image file `file` the layer's only texture. MeshLab 2025.07 keeps the image in the layer
// and saves it beside a saved mesh under the texture's name, hence the file name alone (a path
// there makes pymeshlab's save_current_mesh(save_textures=True) fail).
inline void setLayerTexture(MeshModel& m, const std::string& file) {
    const QString path = QString::fromStdString(file);
    m.clearTextures();
    m.addTexture(QFileInfo(path).fileName().toStdString(), QImage(path));
}

// Gives layer `to` the textures of layer `from` (MeshLab 2025.07 keeps the images in the layer).
inline void copyLayerTextures(const MeshModel& from, MeshModel& to) {
    to.clearTextures();
    for (const std::string& name : from.cm.textures) to.addTexture(name, from.getTexture(name));
}

// A numeric parameter's value is finite (floats, percentages, dynamic floats, points); true for the
// other kinds.
inline bool parameterValueIsFinite(const RichParameter& p) {
    const Value& v = p.value();
    if (v.isFloat()) return std::isfinite(v.getFloat());  // also percentages and dynamic floats
    if (v.isPoint3()) {
        const Point3m q = v.getPoint3();
        return std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]);
    }
    return true;
}
// For an enum parameter: its chosen index and its choices (false for other parameters).
inline bool enumChoice(const RichParameter& p, int& index, QStringList& choices) {
    const auto* e = dynamic_cast<const RichEnum*>(&p);
    if (e == nullptr) return false;
    index = p.value().getInt();
    choices = e->enumvalues;
    return true;
}

// The image plane of a raster layer.
using RasterImagePlane = RasterPlane;
inline bool rasterIsVisible(const RasterModel& raster) { return raster.isVisible(); }

// A new raster layer showing `image` (already decoded: it is not read again), which the layer
// records as coming from `path`; its camera is the caller's to set. It becomes the current raster.
inline RasterModel* addRasterLayer(MeshDocument& md, const QString& label, const QImage& image, const QString& path) {
    RasterModel* raster = md.addNewRaster();
    raster->setLabel(label);
    raster->addPlane(new RasterPlane(image, path, RasterPlane::RGBA));
    return raster;
}

// A new layer of the document; it becomes the current one only in a document that had none (an
// empty document, where filters like the out-of-core simplification create the first layer).
inline MeshModel* addLayer(MeshDocument& md, const QString& label) { return md.addNewMesh("", label, md.mm() == nullptr); }
// Removes a layer a refused filter added (runFilter: a refusal leaves the layers as they were).
inline void removeLayer(MeshDocument& md, MeshModel* m) { md.delMesh(static_cast<unsigned int>(m->id())); }
// Makes `m` the current layer again (after removeLayer changed it).
inline void makeCurrentLayer(MeshDocument& md, MeshModel* m) { md.setCurrentMesh(m->id()); }

// A parameter naming one of the document's layers (MeshLab 2025 stores the layer's id).
inline void addMeshParameter(RichParameterList& par, const QString& name, const MeshDocument& md,
                             const MeshModel* initial, const QString& label, const QString& help) {
    const unsigned int id = initial != nullptr ? initial->id() : (md.mm() != nullptr ? md.mm()->id() : 0u);
    par.addParam(RichMesh(name, id, &md, label, help));
}
inline MeshModel* meshParameter(const RichParameterList& par, MeshDocument& md, const QString& name) {
    return md.getMesh(par.getMeshId(name));
}

inline void addPointParameter(RichParameterList& par, const QString& name, const Eigen::Vector3d& initial,
                              const QString& label, const QString& help) {
    par.addParam(RichPosition(name, Point3m(initial.x(), initial.y(), initial.z()), label, help));
}
inline void addDirectionParameter(RichParameterList& par, const QString& name, const Eigen::Vector3d& initial,
                                  const QString& label, const QString& help) {
    par.addParam(RichDirection(name, Point3m(initial.x(), initial.y(), initial.z()), label, help));
}
inline Eigen::Vector3d pointParameter(const RichParameterList& par, const QString& name) {
    const Point3m p = par.getPoint3m(name);
    return Eigen::Vector3d(p[0], p[1], p[2]);
}

inline void addAbsoluteOrPercentParameter(RichParameterList& par, const QString& name, double initial,
                                          double minimum, double maximum, const QString& label,
                                          const QString& help) {
    par.addParam(RichPercentage(name, initial, minimum, maximum, label, help));
}
inline double absoluteOrPercentParameter(const RichParameterList& par, const QString& name) {
    return par.getAbsPerc(name);
}

inline void addOpenFileParameter(RichParameterList& par, const QString& name, const QString& initial,
                                 const QStringList& extensions, const QString& label, const QString& help) {
    par.addParam(RichFileOpen(name, initial, extensions, label, help));
}
inline void addDynamicFloatParameter(RichParameterList& par, const QString& name, double initial, double minimum,
                                     double maximum, const QString& label, const QString& help) {
    par.addParam(RichDynamicFloat(name, initial, minimum, maximum, label, help));
}

}  // namespace radml
