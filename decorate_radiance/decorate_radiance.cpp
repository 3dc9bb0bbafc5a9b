#include "decorate_radiance.h"

#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include "gl_capabilities.h"
#include "radiance_gl_renderer.h"

#include "lighting/environment_map.h"
#include "prt/prt_lighting.h"
#include "render/tone_mapping.h"

#include <GL/glew.h>

#include <common/GLExtensionsManager.h>
#include <meshlab/glarea.h>
#include <wrap/gl/math.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <QElapsedTimer>
#include <QPainter>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>

namespace {

const char* const kShading = "MeshLab::Decoration::RadianceShading";
const char* const kExposure = "MeshLab::Decoration::RadianceExposure";
const char* const kToneMap = "MeshLab::Decoration::RadianceToneMap";
const char* const kPrtLight = "MeshLab::Decoration::RadiancePrtLight";
const char* const kPrtDirection = "MeshLab::Decoration::RadiancePrtDirection";
const char* const kPrtIntensity = "MeshLab::Decoration::RadiancePrtIntensity";
const char* const kPrtMap = "MeshLab::Decoration::RadiancePrtMap";
const char* const kPrtRotation = "MeshLab::Decoration::RadiancePrtRotation";
const char* const kPrtUpAxis = "MeshLab::Decoration::RadiancePrtUpAxis";

enum ShadingChoice { kPerVertex = 0, kPerFragment = 1, kPrtRelighting = 2 };
enum LightChoice { kDirectional = 0, kEnvironment = 1 };

const char* shadingName(radgl::GlShading s, bool cpu) {
    if (cpu) return "cpu-per-vertex";
    switch (s) {
        case radgl::GlShading::PerVertex: return "per-vertex";
        case radgl::GlShading::PerFragment: return "per-fragment";
        case radgl::GlShading::VertexColors: return "prt";
    }
    return "?";
}

// What the uploaded buffers were made from; any change (a filter that replaced the vertex vector,
// new radiance or transfer data) triggers a new upload. startDecorate is also called again by
// MeshLab after every filter, which catches edits in place.
struct Fingerprint {
    int vn = -1, fn = -1;
    const void* vertices = nullptr;
    const void* faces = nullptr;
    const void* radiance = nullptr;
    std::size_t radianceFloats = 0;
    const void* transfer = nullptr;
    std::size_t transferFloats = 0;
    bool operator==(const Fingerprint& o) const {
        return vn == o.vn && fn == o.fn && vertices == o.vertices && faces == o.faces && radiance == o.radiance &&
               radianceFloats == o.radianceFloats && transfer == o.transfer && transferFloats == o.transferFloats;
    }
    bool operator!=(const Fingerprint& o) const { return !(*this == o); }
};

Fingerprint fingerprintOf(CMeshO& mesh) {
    Fingerprint f;
    f.vn = mesh.vn;
    f.fn = mesh.fn;
    f.vertices = mesh.vert.empty() ? nullptr : &mesh.vert[0];
    f.faces = mesh.face.empty() ? nullptr : &mesh.face[0];
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

// The light of the PRT mode, as set in the parameters.
struct LightSetting {
    int kind = kDirectional;
    QString map;
    float rotation = 0, intensity = 1;
    vcg::Point3f direction{0, 1, 1};
    int upAxis = 1;
    bool operator==(const LightSetting& o) const {
        return kind == o.kind && map == o.map && rotation == o.rotation && intensity == o.intensity &&
               direction == o.direction && upAxis == o.upAxis;
    }
};

LightSetting lightSetting(const RichParameterList& par) {
    LightSetting s;
    s.kind = par.getEnum(kPrtLight);
    s.map = par.getOpenFileName(kPrtMap).trimmed();
    s.rotation = par.getDynamicFloat(kPrtRotation);
    s.intensity = par.getFloat(kPrtIntensity);
    s.direction = par.getPoint3f(kPrtDirection);
    s.upAxis = par.getEnum(kPrtUpAxis);
    return s;
}

rad::ToneMapping toneMapping(const RichParameterList& par) {
    rad::ToneMapping tm;
    const float stops = par.getFloat(kExposure);
    tm.exposureStops = std::isfinite(stops) ? stops : 0.0;
    tm.curve = par.getEnum(kToneMap) == 1 ? rad::ToneCurve::Reinhard : rad::ToneCurve::Clamp;
    return tm;
}

Eigen::Vector3d axisVector(int upAxis) { return Eigen::Vector3d::Unit(upAxis < 0 || upAxis > 2 ? 1 : upAxis); }

// What to do when a layer has neither radiance functions nor PRT transfer.
std::string missingDataAdvice() {
    return radml::missingRadianceAdvice() +
           " (or compute PRT transfer with 'Radiance: Compute PRT Transfer' for the relighting mode)";
}

// RADIANCE_DECORATE_MAX_GL=2.1 pretends the context is older (to see the fallback in the GUI).
void applyGlCap(radgl::GlCapabilities& caps) {
    const char* cap = std::getenv("RADIANCE_DECORATE_MAX_GL");
    int major = 0, minor = 0;
    if (cap && std::sscanf(cap, "%d.%d", &major, &minor) == 2) radgl::capGlVersion(caps, major, minor);
}

}  // namespace

struct DecorateRadiancePlugin::MeshView {
    std::unique_ptr<radgl::RadianceGlRenderer> renderer;
    radgl::GlCapabilities caps;
    Fingerprint fingerprint;
    bool radiance = false;
    rad::BasisSpec basis;
    std::string gpuProblem;  // why the GPU modes are off, empty when they are on
    bool transfer = false;
    radml::StoredTransfer stored;
    bool coloursValid = false;
    LightSetting colourLight;
    QString loadedMapPath;
    rad::EnvironmentMap map;
    std::set<std::string> reported;  // messages already logged (once each, not every frame)
    long long frame = 0;
};

DecorateRadiancePlugin::DecorateRadiancePlugin() {
    typeList << DP_RADIANCE_FIELD;
    for (FilterIDType tt : types()) {
        QAction* action = new QAction(decorationName(tt), this);
        action->setCheckable(true);
        action->setShortcut(QKeySequence(Qt::CTRL + Qt::ALT + Qt::Key_R));
        // MeshLab lists a decoration on its toolbar only when it has an icon: a small drawn one.
        QPixmap pixmap(32, 32);
        pixmap.fill(Qt::transparent);
        QPainter painter(&pixmap);
        painter.setRenderHint(QPainter::Antialiasing);
        QRadialGradient gradient(QPointF(12, 11), 16);
        gradient.setColorAt(0.0, QColor(255, 255, 240));
        gradient.setColorAt(0.35, QColor(230, 120, 60));
        gradient.setColorAt(1.0, QColor(90, 30, 20));
        painter.setBrush(gradient);
        painter.setPen(Qt::NoPen);
        painter.drawEllipse(QRectF(3, 3, 26, 26));
        painter.end();
        action->setIcon(QIcon(pixmap));
        actionList << action;
    }
}

DecorateRadiancePlugin::~DecorateRadiancePlugin() {
    // GL objects cannot be released without their context here; MeshLab calls endDecorate for every
    // active decoration before closing its views. Whatever is left goes with the context.
    for (auto& entry : views_) entry.second->renderer.release();
}

QString DecorateRadiancePlugin::decorationName(FilterIDType id) const {
    switch (id) {
        case DP_RADIANCE_FIELD: return "Radiance Field";
    }
    return {};
}

QString DecorateRadiancePlugin::decorationInfo(FilterIDType id) const {
    switch (id) {
        case DP_RADIANCE_FIELD:
            return "Draws the layer's radiance functions (view-dependent colour) toward MeshLab's camera, or its "
                   "PRT transfer relit by a light (Tools > Options > Decoration: 'Radiance shading').<br>"
                   "<b>Per vertex</b>: each vertex's function evaluated toward the eye and the colours "
                   "interpolated (highlights inside large triangles fade). <b>Per fragment</b>: the three "
                   "<i>reflected</i> functions of the triangle interpolated at every pixel around the "
                   "interpolated normal, eq. (8) of Vanhoey, Sauvage, Kraemer, Larue, Dischler, "
                   "<i>Simplification of meshes with digitized radiance</i>, The Visual Computer 31 (2015), "
                   "sec. 5 (Fig. 6); below a vertex's hemisphere the function takes its border value (sec. 7). "
                   "<b>PRT relighting</b>: L = &lt;t, l&gt; per vertex (Sloan et al. 2002) under a directional "
                   "light or an HDR map, rotatable about the up axis.<br>Exposure in stops, clamp or Reinhard "
                   "tone curve, sRGB output. Needs OpenGL 3.2 / GLSL 1.50 for the shaded modes; otherwise the "
                   "colours are evaluated per vertex on the CPU. Shortcut Ctrl+Alt+R.";
    }
    return {};
}

bool DecorateRadiancePlugin::isDecorationApplicable(QAction*, const MeshModel& m, QString& message) const {
    CMeshO& mesh = const_cast<CMeshO&>(m.cm);
    if (radml::hasRadiance(mesh) || radml::hasTransfer(mesh)) return true;
    message = QString::fromStdString(missingDataAdvice());
    return false;
}

void DecorateRadiancePlugin::initGlobalParameterSet(QAction*, RichParameterList& par) {
    par.addParam(RichEnum(kShading, kPerFragment,
                          QStringList() << "Per vertex (evaluate at vertices, interpolate colours)"
                                        << "Per fragment (interpolate reflected functions, eq. 8)"
                                        << "PRT relighting (per vertex)",
                          "Radiance shading",
                          "How the Radiance Field decoration shades the layer: per-vertex evaluation (Gouraud-like), "
                          "per-fragment interpolation of the reflected radiance functions (paper eq. 8, keeps "
                          "highlights inside large triangles), or PRT transfer relit by the light below."));
    par.addParam(RichFloat(kExposure, 0.0f, "Radiance exposure (stops)",
                           "Displayed colour = tone curve(2^stops x radiance), then sRGB."));
    par.addParam(RichEnum(kToneMap, 0, QStringList() << "Clamp" << "Reinhard x/(1+x)", "Radiance tone curve",
                          "Clamp: values above 1 saturate. Reinhard: x/(1+x) per channel, keeps detail in highlights."));
    par.addParam(RichEnum(kPrtLight, kDirectional, QStringList() << "Directional light" << "HDR environment map",
                          "PRT light", "The light of the PRT relighting mode."));
    par.addParam(RichPoint3f(kPrtDirection, vcg::Point3f(0, 1, 1), "PRT light direction",
                             "Direction toward the directional light, in the layer's coordinates (before the rotation "
                             "below)."));
    par.addParam(RichFloat(kPrtIntensity, 1.0f, "PRT light intensity", "Scale of the light (directional or map)."));
    par.addParam(RichOpenFile(kPrtMap, "", QStringList() << "*.exr" << "*.hdr", "PRT environment map",
                              "Latitude-longitude HDR map (.exr or .hdr) for the PRT mode."));
    par.addParam(RichDynamicFloat(kPrtRotation, 0.0f, 0.0f, 360.0f, "PRT light rotation (degrees)",
                                  "Turns the light (map or direction) about the up axis."));
    par.addParam(RichEnum(kPrtUpAxis, 1, QStringList() << "X" << "Y" << "Z", "PRT up axis",
                          "The world axis the map's zenith goes to, and the axis of the rotation."));
}

namespace {
// Uploads the layer into the view's renderer. Returns false with `why` when nothing can be drawn.
bool uploadLayer(DecorateRadiancePlugin::MeshView& view, CMeshO& mesh, std::string& why) {
    radml::ExportChoice choice;
    choice.normals = choice.colors = choice.quality = choice.transfer = false;
    choice.radiance = radml::hasRadiance(mesh);
    rad::RadianceMesh plain;
    if (!radml::exportPlainMesh(mesh, choice, plain, why)) return false;
    if (plain.faceCount() == 0) {
        why = "the layer has no faces (a point cloud): the decoration draws triangles";
        return false;
    }
    try {
        view.renderer->setMesh(plain.positions.data(), plain.vertexCount(), plain.faces.data(), plain.faceCount());
        view.radiance = plain.radiance.has_value();
        view.gpuProblem.clear();
        if (view.radiance) {
            view.basis = plain.radiance->basis;
            view.gpuProblem = view.renderer->setRadiance(*plain.radiance);
        }
    } catch (const std::exception& e) {
        why = e.what();
        return false;
    }
    view.transfer = false;
    view.coloursValid = false;
    if (radml::hasTransfer(mesh)) {
        std::string transferWhy;
        view.transfer = radml::gatherTransfer(mesh, view.stored, transferWhy) &&
                        view.stored.field.vertexCount() == plain.vertexCount();
    }
    view.fingerprint = fingerprintOf(mesh);
    return view.radiance || view.transfer;
}
}  // namespace

bool DecorateRadiancePlugin::startDecorate(QAction*, MeshModel& m, const RichParameterList* par, GLArea* gla) {
    if (!gla || !par) return false;
    if (!GLExtensionsManager::initializeGLextensions_notThrowing()) {
        Log(GLLogStream::WARNING, "Radiance Field: OpenGL extensions could not be initialised; nothing drawn.");
        return false;
    }
    QElapsedTimer timer;
    timer.start();
    const Key key(gla, m.id());
    views_.erase(key);  // a new start after a filter: rebuild from the layer as it is now
    auto view = std::make_unique<MeshView>();
    view->caps = radgl::queryGlCapabilities();
    applyGlCap(view->caps);
    view->renderer = std::make_unique<radgl::RadianceGlRenderer>(view->caps);
    std::string why;
    if (!uploadLayer(*view, m.cm, why)) {
        if (why.empty()) why = missingDataAdvice();
        Log(GLLogStream::WARNING, "Radiance Field: not started on layer '%s': %s", qUtf8Printable(m.label()), why.c_str());
        return false;
    }
    const int shading = par->getEnum(kShading);
    QString data;
    if (view->radiance) data += QString("%1 radiance functions").arg(QString::fromStdString(view->basis.name()));
    if (view->transfer)
        data += QString("%1PRT transfer of order %2").arg(data.isEmpty() ? "" : ", ").arg(view->stored.field.degree + 1);
    Log("Radiance Field: %s shading of layer '%s' (%s), %zu vertices, %zu faces, %.1f MB uploaded in %.2f s; %s",
        shading == kPerVertex ? "per-vertex" : shading == kPerFragment ? "per-fragment (eq. 8)" : "PRT relighting",
        qUtf8Printable(m.label()), qUtf8Printable(data), view->renderer->vertexCount(), view->renderer->faceCount(),
        view->renderer->gpuBytes() / 1048576.0, timer.elapsed() / 1000.0, view->caps.describe().c_str());
    if (view->radiance && !view->gpuProblem.empty())
        Log(GLLogStream::WARNING,
            "Radiance Field: GPU shading unavailable (%s): falling back to per-vertex colours evaluated on the CPU; "
            "the per-fragment mode needs OpenGL 3.2 and GLSL 1.50.",
            view->gpuProblem.c_str());
    const std::string errors = view->renderer->takeGlErrors();
    if (!errors.empty()) Log(GLLogStream::WARNING, "Radiance Field: %s", errors.c_str());
    views_[key] = std::move(view);
    return true;
}

void DecorateRadiancePlugin::endDecorate(QAction*, MeshModel& m, const RichParameterList*, GLArea* gla) {
    auto it = views_.find(Key(gla, m.id()));
    if (it == views_.end()) return;
    if (gla) gla->makeCurrent();  // the buffers belong to this view's context
    views_.erase(it);
}

void DecorateRadiancePlugin::decorateMesh(QAction*, MeshModel& m, const RichParameterList* par, GLArea* gla,
                                          QPainter*, GLLogStream& log) {
    auto it = views_.find(Key(gla, m.id()));
    if (it == views_.end() || !par) return;
    MeshView& view = *it->second;
    auto reportOnce = [&](int level, const std::string& message) {
        if (view.reported.insert(message).second) log.Log(level, "Radiance Field: " + message);
    };

    if (fingerprintOf(m.cm) != view.fingerprint) {
        std::string why;
        if (!uploadLayer(view, m.cm, why)) {
            reportOnce(GLLogStream::WARNING, "the layer changed and can no longer be drawn: " +
                                                 (why.empty() ? missingDataAdvice() : why));
            return;
        }
    }

    const int choice = par->getEnum(kShading);
    radgl::GlShading shading = choice == kPerVertex ? radgl::GlShading::PerVertex
                               : choice == kPerFragment ? radgl::GlShading::PerFragment
                                                        : radgl::GlShading::VertexColors;
    if (shading == radgl::GlShading::VertexColors) {
        if (!view.transfer) {
            reportOnce(GLLogStream::WARNING, "the PRT relighting mode needs transfer vectors on the layer: " +
                                                 radml::missingTransferAdvice());
            return;
        }
        const LightSetting light = lightSetting(*par);
        if (!view.coloursValid || !(light == view.colourLight)) {
            const int degree = view.stored.field.degree;
            std::vector<double> lighting;
            try {
                const double radians = light.rotation * M_PI / 180.0;
                if (light.kind == kEnvironment) {
                    if (light.map.isEmpty()) throw std::runtime_error("choose an environment map (.exr or .hdr) in the options");
                    if (light.map != view.loadedMapPath) {
                        view.map = rad::readEnvironmentMap(light.map.toStdString());
                        view.loadedMapPath = light.map;
                    }
                    lighting = rad::environmentLightSH(view.map, degree, radians);
                    rad::rotateLighting(lighting, degree, rad::zenithToAxis(light.upAxis));
                    for (double& c : lighting) c *= light.intensity;
                } else {
                    const Eigen::Vector3d d(light.direction[0], light.direction[1], light.direction[2]);
                    const Eigen::Vector3d turned = Eigen::AngleAxisd(radians, axisVector(light.upAxis)) * d;
                    lighting = rad::directionalLightSH(degree, turned, Eigen::Vector3d::Constant(light.intensity));
                }
            } catch (const std::exception& e) {
                reportOnce(GLLogStream::WARNING, std::string("cannot set the PRT light: ") + e.what());
                return;
            }
            const std::vector<float> rgb =
                rad::relightVertices(view.stored.field.values.data(), view.stored.field.vertexCount(), degree,
                                     view.stored.field.channels, lighting, degree);
            view.renderer->setVertexColors(rgb.data());
            view.colourLight = light;
            view.coloursValid = true;
        }
    } else if (!view.radiance) {
        reportOnce(GLLogStream::WARNING, "this layer has no radiance functions to shade: " + radml::missingRadianceAdvice() +
                                             " (its PRT transfer can be shown with the PRT relighting mode)");
        return;
    } else if (shading == radgl::GlShading::PerFragment && !view.renderer->gpuRadiance()) {
        reportOnce(GLLogStream::WARNING, "per-fragment shading unavailable (" + view.gpuProblem +
                                             "): drawing per-vertex colours evaluated on the CPU");
    }

    glPushMatrix();
    vcg::glMultMatrix(m.cm.Tr);
    GLdouble modelview[16], projection[16];
    GLint viewport[4];
    glGetDoublev(GL_MODELVIEW_MATRIX, modelview);
    glGetDoublev(GL_PROJECTION_MATRIX, projection);
    glGetIntegerv(GL_VIEWPORT, viewport);
    const Eigen::Map<const Eigen::Matrix4d> mv(modelview);  // column-major, as GL returns it
    const Eigen::Vector4d eye = mv.inverse() * Eigen::Vector4d(0, 0, 0, 1);
    const rad::ToneMapping tm = toneMapping(*par);
    view.renderer->draw(shading, tm, eye.head<3>() / eye[3]);
    glPopMatrix();
    const std::string errors = view.renderer->takeGlErrors();
    if (!errors.empty()) reportOnce(GLLogStream::WARNING, errors);
    ++view.frame;

    // The view file (docs/decorate-radiance.md): what this frame was drawn with, for the GUI test and
    // for reproducing the picture on the CPU. Written to a temporary file, then renamed: a reader
    // never sees half a file.
    if (const char* path = std::getenv("RADIANCE_DECORATE_VIEW_FILE")) {
        const std::string target = path, temporary = target + ".tmp";
        std::ofstream out(temporary);
        const QPoint origin = gla->mapToGlobal(QPoint(0, 0));
        out.precision(17);
        out << "radiance-decoration-view 1\nframe " << view.frame << "\nmode "
            << shadingName(view.renderer->activeShading(shading),
                           shading != radgl::GlShading::VertexColors && !view.renderer->gpuRadiance())
            << "\nviewport " << viewport[0] << ' ' << viewport[1] << ' ' << viewport[2] << ' ' << viewport[3]
            << "\nwidget_origin " << origin.x() << ' ' << origin.y() << "\nwidget_size " << gla->width() << ' '
            << gla->height() << "\ndevice_pixel_ratio " << gla->devicePixelRatioF() << "\nmodelview";
        for (double v : modelview) out << ' ' << v;
        out << "\nprojection";
        for (double v : projection) out << ' ' << v;
        out << "\nexposure " << tm.exposureStops << "\ntonemap "
            << (tm.curve == rad::ToneCurve::Reinhard ? "reinhard" : "clamp") << '\n';
        out.close();
        std::rename(temporary.c_str(), target.c_str());
    }
}

MESHLAB_PLUGIN_NAME_EXPORTER(DecorateRadiancePlugin)
