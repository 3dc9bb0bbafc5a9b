#include "radiance_field_decoration.h"

#include "decoration_support.h"

#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include "gl_capabilities.h"
#include "radiance_gl_renderer.h"

#include "lighting/environment_map.h"
#include "prt/prt_lighting.h"

#include <GL/glew.h>

#include <meshlab/glarea.h>

#include <Eigen/Geometry>

#include <QElapsedTimer>

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace raddecorate {
namespace {

const char* const kName = "Radiance Field";
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

radgl::GlShading shadingOf(const RichParameterList& par) {
    const int choice = par.getEnum(kShading);
    return choice == kPerVertex     ? radgl::GlShading::PerVertex
           : choice == kPerFragment ? radgl::GlShading::PerFragment
                                    : radgl::GlShading::VertexColors;
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

// What to do when a layer has neither radiance functions nor PRT transfer.
std::string missingDataAdvice() {
    return radml::missingRadianceAdvice() +
           " (or compute PRT transfer with 'Radiance: Compute PRT Transfer' for the relighting mode)";
}

// MeshLab's matrices and viewport when the frame was drawn (the view file reports them).
struct FrameCamera {
    LayerEye layer;
    GLdouble projection[16];
    GLint viewport[4];
};

// The state per (view, layer): the GL renderer and what it was built from.
struct View {
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
    OnceLog reported{kName};  // messages already logged (once each, not every frame)
    long long frame = 0;
};

// Uploads the layer into the view's renderer. Returns false with `why` when nothing can be drawn.
bool uploadLayer(View& view, CMeshO& mesh, std::string& why) {
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

// Logs the start line (data, sizes, upload time, GL) and the fallback when the GPU modes are off.
void logStart(const View& view, const MeshModel& m, const RichParameterList& par, const QElapsedTimer& timer,
              MeshLabInterface& pluginLog) {
    const int shading = par.getEnum(kShading);
    QString data;
    if (view.radiance) data += QString("%1 radiance functions").arg(QString::fromStdString(view.basis.name()));
    if (view.transfer)
        data += QString("%1PRT transfer of order %2").arg(data.isEmpty() ? "" : ", ").arg(view.stored.field.degree + 1);
    pluginLog.Log("Radiance Field: %s shading of layer '%s' (%s), %zu vertices, %zu faces, %.1f MB uploaded in %.2f s; %s",
                  shading == kPerVertex ? "per-vertex" : shading == kPerFragment ? "per-fragment (eq. 8)" : "PRT relighting",
                  qUtf8Printable(m.label()), qUtf8Printable(data), view.renderer->vertexCount(),
                  view.renderer->faceCount(), view.renderer->gpuBytes() / 1048576.0, timer.elapsed() / 1000.0,
                  view.caps.describe().c_str());
    if (view.radiance && !view.gpuProblem.empty())
        pluginLog.Log(GLLogStream::WARNING,
                      "Radiance Field: GPU shading unavailable (%s): falling back to per-vertex colours evaluated on the "
                      "CPU; the per-fragment mode needs OpenGL 3.2 and GLSL 1.50.",
                      view.gpuProblem.c_str());
}

// The PRT lighting vector of `light` (the one PRT lighting of the decoration and the relighting
// filter; the core validates). Loads the environment map when it changed; throws with the reason.
std::vector<double> prtLighting(View& view, const LightSetting& light) {
    rad::PrtLightingSettings settings;
    settings.source = light.kind == kEnvironment ? rad::PrtLightSource::EnvironmentMap : rad::PrtLightSource::Directional;
    settings.upAxis = static_cast<rad::UpAxis>(light.upAxis);
    settings.rotationDegrees = light.rotation;
    settings.intensity = light.intensity;
    settings.direction = Eigen::Vector3d(light.direction[0], light.direction[1], light.direction[2]);
    settings.degree = view.stored.field.degree;
    if (light.kind != kEnvironment) return rad::prtLightingSH(settings);
    if (light.map.isEmpty()) throw std::runtime_error("choose an environment map (.exr or .hdr) in the options");
    if (light.map != view.loadedMapPath) {
        view.map = rad::readEnvironmentMap(light.map.toStdString());
        view.loadedMapPath = light.map;
    }
    return rad::prtLightingSH(settings, &view.map);
}

// PRT mode: relights the vertex colours when the light changed. False (logged) when nothing can be drawn.
bool relightIfNeeded(View& view, const RichParameterList& par, GLLogStream& log) {
    if (!view.transfer) {
        view.reported.report(log, GLLogStream::WARNING,
                             "the PRT relighting mode needs transfer vectors on the layer: " + radml::missingTransferAdvice());
        return false;
    }
    const LightSetting light = lightSetting(par);
    if (view.coloursValid && light == view.colourLight) return true;
    std::vector<double> lighting;
    try {
        lighting = prtLighting(view, light);
    } catch (const std::exception& e) {
        view.reported.report(log, GLLogStream::WARNING, std::string("cannot set the PRT light: ") + e.what());
        return false;
    }
    const int degree = view.stored.field.degree;
    const std::vector<float> rgb = rad::relightVertices(view.stored.field.values.data(), view.stored.field.vertexCount(),
                                                        degree, view.stored.field.channels, lighting, degree);
    view.renderer->setVertexColors(rgb.data());
    view.colourLight = light;
    view.coloursValid = true;
    return true;
}

// Whether the frame can be drawn in `shading`; logs the problem or the CPU fallback once.
bool readyToShade(View& view, radgl::GlShading shading, const RichParameterList& par, GLLogStream& log) {
    if (shading == radgl::GlShading::VertexColors) return relightIfNeeded(view, par, log);
    if (!view.radiance) {
        view.reported.report(log, GLLogStream::WARNING,
                             "this layer has no radiance functions to shade: " + radml::missingRadianceAdvice() +
                                 " (its PRT transfer can be shown with the PRT relighting mode)");
        return false;
    }
    if (shading == radgl::GlShading::PerFragment && !view.renderer->gpuRadiance())
        view.reported.report(log, GLLogStream::WARNING,
                             "per-fragment shading unavailable (" + view.gpuProblem +
                                 "): drawing per-vertex colours evaluated on the CPU");
    return true;
}

// The view file (docs/decorate-radiance.md): what this frame was drawn with, for the GUI test and
// for reproducing the picture on the CPU. Written to a temporary file, then renamed: a reader
// never sees half a file.
void writeViewFile(const std::string& target, const View& view, radgl::GlShading shading, const FrameCamera& camera,
                   const rad::ToneMapping& tm, const GLArea& gla) {
    const std::string temporary = target + ".tmp";
    std::ofstream out(temporary);
    const QPoint origin = gla.mapToGlobal(QPoint(0, 0));
    out.precision(17);
    out << "radiance-decoration-view 1\nframe " << view.frame << "\nmode "
        << shadingName(view.renderer->activeShading(shading),
                       shading != radgl::GlShading::VertexColors && !view.renderer->gpuRadiance())
        << "\nviewport " << camera.viewport[0] << ' ' << camera.viewport[1] << ' ' << camera.viewport[2] << ' '
        << camera.viewport[3] << "\nwidget_origin " << origin.x() << ' ' << origin.y() << "\nwidget_size "
        << gla.width() << ' ' << gla.height() << "\ndevice_pixel_ratio " << gla.devicePixelRatioF() << "\nmodelview";
    for (int i = 0; i < 16; ++i) out << ' ' << camera.layer.modelview.data()[i];
    out << "\nprojection";
    for (double v : camera.projection) out << ' ' << v;
    out << "\nexposure " << tm.exposureStops << "\ntonemap " << (tm.curve == rad::ToneCurve::Reinhard ? "reinhard" : "clamp")
        << '\n';
    out.close();
    std::rename(temporary.c_str(), target.c_str());
}

class RadianceFieldDecoration : public Decoration {
public:
    QString name() const override { return kName; }
    QString info() const override;
    ActionLook look() const override;
    bool isApplicable(const MeshModel& m, QString& message) const override;
    void addParameters(RichParameterList& par) const override;
    bool start(MeshModel& m, const RichParameterList& par, GLArea& gla, MeshLabInterface& pluginLog) override;
    void draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
              MeshLabInterface& pluginLog) override;
    void end(MeshModel& m, GLArea* gla) override { views_.end(gla, m); }

private:
    LayerViews<View> views_;
};

QString RadianceFieldDecoration::info() const {
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

ActionLook RadianceFieldDecoration::look() const { return {Qt::Key_R, QColor(230, 120, 60), QColor(90, 30, 20)}; }

bool RadianceFieldDecoration::isApplicable(const MeshModel& m, QString& message) const {
    CMeshO& mesh = const_cast<CMeshO&>(m.cm);
    if (radml::hasRadiance(mesh) || radml::hasTransfer(mesh)) return true;
    message = QString::fromStdString(missingDataAdvice());
    return false;
}

void RadianceFieldDecoration::addParameters(RichParameterList& par) const {
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
    QStringList axes;  // one axis list, in the core's order, shared with the relighting filter
    for (const char* axis : rad::kUpAxisNames) axes << axis;
    par.addParam(RichEnum(kPrtUpAxis, static_cast<int>(rad::UpAxis::Y), axes, "PRT up axis",
                          "The world axis the map's zenith goes to, and the axis of the rotation."));
}

bool RadianceFieldDecoration::start(MeshModel& m, const RichParameterList& par, GLArea& gla,
                                    MeshLabInterface& pluginLog) {
    if (!glExtensionsReady(kName, pluginLog)) return false;
    QElapsedTimer timer;
    timer.start();
    views_.erase(&gla, m);  // a new start after a filter: rebuild from the layer as it is now
    auto view = std::make_unique<View>();
    view->caps = radgl::queryGlCapabilities();
    // RADIANCE_DECORATE_MAX_GL=2.1 pretends the context is older (to see the fallback in the GUI).
    radgl::capGlVersionFromEnvironment(view->caps);
    view->renderer = std::make_unique<radgl::RadianceGlRenderer>(view->caps);
    std::string why;
    if (!uploadLayer(*view, m.cm, why)) return refuseStart(kName, m, why.empty() ? missingDataAdvice() : why, pluginLog);
    logStart(*view, m, par, timer, pluginLog);
    const std::string errors = view->renderer->takeGlErrors();
    if (!errors.empty()) pluginLog.Log(GLLogStream::WARNING, "Radiance Field: %s", errors.c_str());
    views_.put(&gla, m, std::move(view));
    return true;
}

void RadianceFieldDecoration::draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
                                   MeshLabInterface&) {
    View* found = views_.find(gla, m);
    if (!found) return;
    View& view = *found;
    if (fingerprintOf(m.cm) != view.fingerprint) {
        std::string why;
        if (!uploadLayer(view, m.cm, why)) {
            view.reported.report(log, GLLogStream::WARNING, "the layer changed and can no longer be drawn: " +
                                                                (why.empty() ? missingDataAdvice() : why));
            return;
        }
    }
    const radgl::GlShading shading = shadingOf(par);
    if (!readyToShade(view, shading, par, log)) return;

    FrameCamera camera;
    camera.layer = enterLayerSpace(m.cm);
    glGetDoublev(GL_PROJECTION_MATRIX, camera.projection);
    glGetIntegerv(GL_VIEWPORT, camera.viewport);
    const rad::ToneMapping tm = toneMappingOf(par, kExposure, kToneMap);
    view.renderer->draw(shading, tm, camera.layer.eye);
    glPopMatrix();
    view.reported.warnIfAny(log, view.renderer->takeGlErrors());
    ++view.frame;
    if (const char* path = std::getenv("RADIANCE_DECORATE_VIEW_FILE")) writeViewFile(path, view, shading, camera, tm, *gla);
}

}  // namespace

std::unique_ptr<Decoration> makeRadianceFieldDecoration() { return std::make_unique<RadianceFieldDecoration>(); }

}  // namespace raddecorate
