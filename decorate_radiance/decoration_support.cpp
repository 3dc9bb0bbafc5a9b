#include "decoration_support.h"

#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include <GL/glew.h>

#include <common/GLExtensionsManager.h>
#include <meshlab/glarea.h>
#include <wrap/gl/math.h>

#include <Eigen/LU>

#include <cmath>

namespace raddecorate {

void makeContextCurrent(GLArea& gla) { gla.makeCurrent(); }

LayerGeometry geometryOf(const CMeshO& mesh) {
    LayerGeometry g;
    g.vn = mesh.vn;
    g.fn = mesh.fn;
    g.vertices = mesh.vert.empty() ? nullptr : &mesh.vert[0];
    g.faces = mesh.face.empty() ? nullptr : &mesh.face[0];
    return g;
}

Fingerprint fingerprintOf(CMeshO& mesh) {
    Fingerprint f;
    f.geometry = geometryOf(mesh);
    if (const rad::RadianceField* field = radml::storedRadiance(mesh)) {
        f.radiance = field->coefficients.data();
        f.radianceFloats = field->coefficients.size();
    }
    if (const rad::TransferField* transfer = radml::storedTransferField(mesh)) {
        f.transfer = transfer->values.data();
        f.transferFloats = transfer->values.size();
    }
    return f;
}

LayerEye enterLayerSpace(const CMeshO& mesh) {
    glPushMatrix();
    vcg::glMultMatrix(mesh.Tr);
    GLdouble modelview[16];
    glGetDoublev(GL_MODELVIEW_MATRIX, modelview);
    LayerEye e;
    e.modelview = Eigen::Map<const Eigen::Matrix4d>(modelview);  // column-major, as GL returns it
    e.inverse = e.modelview.inverse();
    const Eigen::Vector4d eye = e.inverse * Eigen::Vector4d(0, 0, 0, 1);
    e.eye = eye.head<3>() / eye[3];
    return e;
}

rad::ToneMapping toneMappingOf(const RichParameterList& par, const char* exposureKey, const char* toneCurveKey) {
    rad::ToneMapping tm;
    const float stops = par.getFloat(exposureKey);
    tm.exposureStops = std::isfinite(stops) ? stops : 0.0;
    tm.curve = par.getEnum(toneCurveKey) == 1 ? rad::ToneCurve::Reinhard : rad::ToneCurve::Clamp;
    return tm;
}

void OnceLog::report(GLLogStream& log, int level, const std::string& message) {
    if (reported_.insert(message).second) log.Log(level, prefix_ + message);
}

bool glExtensionsReady(const char* decoration, MeshLabInterface& pluginLog) {
    if (GLExtensionsManager::initializeGLextensions_notThrowing()) return true;
    pluginLog.Log(GLLogStream::WARNING, "%s: OpenGL extensions could not be initialised; nothing drawn.", decoration);
    return false;
}

bool refuseStart(const char* decoration, const MeshModel& m, const std::string& why, MeshLabInterface& pluginLog) {
    pluginLog.Log(GLLogStream::WARNING, "%s: not started on layer '%s': %s", decoration, qUtf8Printable(m.label()),
                  why.c_str());
    return false;
}

}  // namespace raddecorate
