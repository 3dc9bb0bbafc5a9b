#include "decorate_radiance.h"
#include "irradiance_grid_decoration.h"
#include "layer_files.h"

#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include "gl_capabilities.h"
#include "normal_map_gl_renderer.h"
#include "radiance_gl_renderer.h"

#include "bake/bake_description.h"
#include "bake/lean_maps.h"
#include "lod/pop_buffer.h"
#include "lod/texcoord_correction.h"

#include "image/rgb_image.h"
#include "lighting/environment_map.h"
#include "prt/prt_lighting.h"
#include "render/tone_mapping.h"

#include <GL/glew.h>

#include <common/GLExtensionsManager.h>
#include <meshlab/glarea.h>
#include <wrap/gl/math.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <QDir>
#include <QElapsedTimer>
#include <QFileInfo>
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

const char* const kNormalShading = "MeshLab::Decoration::NormalMapShading";
const char* const kNormalShininess = "MeshLab::Decoration::NormalMapShininess";
const char* const kNormalLight = "MeshLab::Decoration::NormalMapLightDirection";
const char* const kNormalSpecular = "MeshLab::Decoration::NormalMapSpecular";
const char* const kNormalAlbedo = "MeshLab::Decoration::NormalMapAlbedo";
const char* const kNormalLod = "MeshLab::Decoration::NormalMapLevelOfDetail";
const char* const kNormalLodLevel = "MeshLab::Decoration::NormalMapLevelOfDetailLevel";
const char* const kNormalLodTolerance = "MeshLab::Decoration::NormalMapLevelOfDetailTolerance";
const char* const kNormalLodCorrection = "MeshLab::Decoration::NormalMapLevelOfDetailCorrection";
enum { kLodOff = 0, kLodAutomatic = 1, kLodForced = 2 };

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

// What to do when a layer has neither radiance functions nor PRT transfer.
std::string missingDataAdvice() {
    return radml::missingRadianceAdvice() +
           " (or compute PRT transfer with 'Radiance: Compute PRT Transfer' for the relighting mode)";
}

// RADIANCE_DECORATE_MAX_GL=2.1 pretends the context is older (to see the fallback in the GUI).
void applyGlCap(radgl::GlCapabilities& caps) { radgl::capGlVersionFromEnvironment(caps); }


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

struct DecorateRadiancePlugin::NormalMapView {
    std::unique_ptr<radgl::NormalMapGlRenderer> renderer;
    Fingerprint fingerprint;
    rad::BakeDescription description;
    std::set<std::string> reported;
    // POP buffer (Limper et al. 2013): its box, for the per-frame level, and the last level logged.
    rad::PopBuffer pop;
    int loggedLevel = -1;
};

DecorateRadiancePlugin::DecorateRadiancePlugin() {
    typeList << DP_RADIANCE_FIELD << DP_NORMAL_MAP << DP_IRRADIANCE_GRID;
    for (FilterIDType tt : types()) {
        QAction* action = new QAction(decorationName(tt), this);
        action->setCheckable(true);
        action->setShortcut(QKeySequence(Qt::CTRL + Qt::ALT +
                                          (tt == DP_NORMAL_MAP ? Qt::Key_N : tt == DP_IRRADIANCE_GRID ? Qt::Key_I : Qt::Key_R)));
        // MeshLab lists a decoration on its toolbar only when it has an icon: a small drawn one.
        QPixmap pixmap(32, 32);
        pixmap.fill(Qt::transparent);
        QPainter painter(&pixmap);
        painter.setRenderHint(QPainter::Antialiasing);
        QRadialGradient gradient(QPointF(12, 11), 16);
        gradient.setColorAt(0.0, QColor(255, 255, 240));
        const QColor middle = tt == DP_NORMAL_MAP ? QColor(128, 128, 255) : tt == DP_IRRADIANCE_GRID ? QColor(120, 200, 120) : QColor(230, 120, 60);
        const QColor edge = tt == DP_NORMAL_MAP ? QColor(30, 30, 110) : tt == DP_IRRADIANCE_GRID ? QColor(20, 80, 30) : QColor(90, 30, 20);
        gradient.setColorAt(0.35, middle);
        gradient.setColorAt(1.0, edge);
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
    for (auto& entry : normalViews_) entry.second->renderer.release();
    for (auto& entry : gridViews_) entry.second->renderer.release();
}

QString DecorateRadiancePlugin::decorationName(FilterIDType id) const {
    switch (id) {
        case DP_RADIANCE_FIELD: return "Radiance Field";
        case DP_NORMAL_MAP: return "Baked Normal Map";
        case DP_IRRADIANCE_GRID: return "Irradiance Vector Grid";
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
        case DP_NORMAL_MAP:
            return "Draws the layer with the normal map made by 'Bake Normal Map' (its texture and the "
                   "&lt;base&gt;_bake.txt beside it) under one directional light that follows the camera "
                   "(Tools &gt; Options &gt; Decoration: 'Normal map shading').<br><b>Vertex normals</b>: "
                   "Blinn-Phong with the interpolated vertex normals, what the simplified mesh alone shows. "
                   "<b>Normal map</b>: Blinn-Phong with the mip-mapped normal map. <b>LEAN</b>: the specular "
                   "lobe is a Gaussian whose covariance is the spread of the scan's normals under the pixel, "
                   "read from the LEAN moments (MIP levels 1..K, scaled by the level below 1), so distant "
                   "highlights widen and dim instead of aliasing: <i>T. Weber, M. Stamminger</i>, "
                   "<b>Stateless Level of Detail Lighting for Automotive Visualization</b>, Alg. 3-4 and sec. "
                   "3.5, after <i>Olano and Baker</i>, LEAN Mapping, I3D 2010. Needs OpenGL 3.2 / GLSL 1.50. "
                   "Shortcut Ctrl+Alt+N.";
        case DP_IRRADIANCE_GRID: return raddecorate::irradianceGridInfo();
    }
    return {};
}

bool DecorateRadiancePlugin::isDecorationApplicable(QAction* action, const MeshModel& m, QString& message) const {
    if (ID(action) == DP_IRRADIANCE_GRID) {
        // Whether a grid exists and reads is said in the log when the decoration starts.
        if (m.cm.fn > 0) return true;
        message = "the layer has no faces (a point cloud): the decoration draws triangles";
        return false;
    }
    if (ID(action) == DP_NORMAL_MAP) {
        std::string why;
        if (raddecorate::bakedMapOf(m, why).empty()) {
            message = QString::fromStdString(why);
            return false;
        }
        return true;
    }
    CMeshO& mesh = const_cast<CMeshO&>(m.cm);
    if (radml::hasRadiance(mesh) || radml::hasTransfer(mesh)) return true;
    message = QString::fromStdString(missingDataAdvice());
    return false;
}

void DecorateRadiancePlugin::initGlobalParameterSet(QAction* action, RichParameterList& par) {
    if (ID(action) == DP_IRRADIANCE_GRID) {
        raddecorate::addIrradianceGridParameters(par);
        return;
    }
    if (ID(action) == DP_NORMAL_MAP) {
        par.addParam(RichEnum(kNormalShading, 2,
                              QStringList() << "Vertex normals (Blinn-Phong)" << "Normal map (Blinn-Phong)"
                                            << "Normal map with LEAN specular (Weber and Stamminger)",
                              "Normal map shading",
                              "How the Baked Normal Map decoration shades the layer: the simplified mesh's own "
                              "normals, the baked normal map, or the normal map with the LEAN Gaussian lobe whose "
                              "width follows the normals' spread under each pixel."));
        par.addParam(RichFloat(kNormalShininess, 100.0f, "Normal map shininess",
                               "Blinn-Phong exponent s (the LEAN lobe has covariance 1/s at close range)."));
        par.addParam(RichFloat(kNormalSpecular, 0.6f, "Normal map specular", "Specular reflectance (grey)."));
        par.addParam(RichColor(kNormalAlbedo, QColor(150, 150, 150), "Normal map albedo", "Diffuse colour."));
        par.addParam(RichPoint3f(kNormalLight, vcg::Point3f(0.4f, 0.5f, 1.0f), "Normal map light direction",
                                 "Direction toward the light in camera coordinates (x right, y up, z toward you): "
                                 "the light follows the camera."));
        par.addParam(RichEnum(kNormalLod, kLodOff,
                              QStringList() << "Off (the whole mesh)" << "Automatic (from the projected size)"
                                            << "Forced level",
                              "Level of detail (POP buffer)",
                              "Draws the layer as a POP buffer (Limper et al. 2013): positions snapped in the vertex "
                              "shader to a grid of 2^L cells per axis over the bounding box, only the triangles that "
                              "stay non-degenerate drawn (a prefix of one buffer, no state between frames). "
                              "Automatic: the coarsest level whose snapping moves no vertex by more than the "
                              "tolerance, from the bounding box's size on screen; forced: the level below."));
        par.addParam(RichInt(kNormalLodLevel, 8, "Level of detail: forced level",
                             "The POP-buffer level drawn when the level is forced, 1 (2 cells per axis) to 16."));
        par.addParam(RichFloat(kNormalLodTolerance, 1.0f, "Level of detail: tolerance (pixels)",
                               "Automatic level: how far, in pixels, snapping may move a vertex on screen."));
        par.addParam(RichBool(kNormalLodCorrection, true, "Level of detail: correct texture coordinates",
                              "Shift the texture coordinates of snapped vertices by the inverse of their averaged "
                              "tangent space times their move (Weber & Stamminger, Alg. 1), so the normal map stays "
                              "in place instead of sliding."));
        return;
    }
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

bool DecorateRadiancePlugin::startDecorate(QAction* action, MeshModel& m, const RichParameterList* par, GLArea* gla) {
    if (!gla || !par) return false;
    if (ID(action) == DP_NORMAL_MAP) return startNormalMap(m, par, gla);
    if (ID(action) == DP_IRRADIANCE_GRID) {
        const Key key(gla, m.id());
        gridViews_.erase(key);
        if (!GLExtensionsManager::initializeGLextensions_notThrowing()) {
            Log(GLLogStream::WARNING, "Irradiance Vector Grid: OpenGL extensions could not be initialised; nothing drawn.");
            return false;
        }
        std::string startLine, why;
        std::unique_ptr<raddecorate::IrradianceGridView> view = raddecorate::startIrradianceGrid(m, *par, startLine, why);
        if (!view) {
            Log(GLLogStream::WARNING, "Irradiance Vector Grid: not started on layer '%s': %s", qUtf8Printable(m.label()),
                why.c_str());
            return false;
        }
        Log("Irradiance Vector Grid: layer '%s', %s", qUtf8Printable(m.label()), startLine.c_str());
        gridViews_[key] = std::move(view);
        return true;
    }
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

void DecorateRadiancePlugin::endDecorate(QAction* action, MeshModel& m, const RichParameterList*, GLArea* gla) {
    if (ID(action) == DP_IRRADIANCE_GRID) {
        auto grid = gridViews_.find(Key(gla, m.id()));
        if (grid == gridViews_.end()) return;
        if (gla) gla->makeCurrent();
        gridViews_.erase(grid);
        return;
    }
    if (ID(action) == DP_NORMAL_MAP) {
        auto normal = normalViews_.find(Key(gla, m.id()));
        if (normal == normalViews_.end()) return;
        if (gla) gla->makeCurrent();
        normalViews_.erase(normal);
        return;
    }
    auto it = views_.find(Key(gla, m.id()));
    if (it == views_.end()) return;
    if (gla) gla->makeCurrent();  // the buffers belong to this view's context
    views_.erase(it);
}

void DecorateRadiancePlugin::decorateMesh(QAction* action, MeshModel& m, const RichParameterList* par, GLArea* gla,
                                          QPainter*, GLLogStream& log) {
    if (ID(action) == DP_NORMAL_MAP) {
        decorateNormalMap(m, par, gla, log);
        return;
    }
    if (ID(action) == DP_IRRADIANCE_GRID) {
        auto grid = gridViews_.find(Key(gla, m.id()));
        if (grid != gridViews_.end() && par) raddecorate::drawIrradianceGrid(*grid->second, m, *par, log);
        return;
    }
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
                // The one PRT lighting of the decoration and the relighting filter; the core validates.
                rad::PrtLightingSettings settings;
                settings.source = light.kind == kEnvironment ? rad::PrtLightSource::EnvironmentMap
                                                             : rad::PrtLightSource::Directional;
                settings.upAxis = static_cast<rad::UpAxis>(light.upAxis);
                settings.rotationDegrees = light.rotation;
                settings.intensity = light.intensity;
                settings.direction = Eigen::Vector3d(light.direction[0], light.direction[1], light.direction[2]);
                settings.degree = degree;
                if (light.kind == kEnvironment) {
                    if (light.map.isEmpty()) throw std::runtime_error("choose an environment map (.exr or .hdr) in the options");
                    if (light.map != view.loadedMapPath) {
                        view.map = rad::readEnvironmentMap(light.map.toStdString());
                        view.loadedMapPath = light.map;
                    }
                    lighting = rad::prtLightingSH(settings, &view.map);
                } else {
                    lighting = rad::prtLightingSH(settings);
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

bool DecorateRadiancePlugin::startNormalMap(MeshModel& m, const RichParameterList* par, GLArea* gla) {
    if (!GLExtensionsManager::initializeGLextensions_notThrowing()) {
        Log(GLLogStream::WARNING, "Baked Normal Map: OpenGL extensions could not be initialised; nothing drawn.");
        return false;
    }
    QElapsedTimer timer;
    timer.start();
    const Key key(gla, m.id());
    normalViews_.erase(key);
    const auto refuse = [&](const std::string& why) {
        Log(GLLogStream::WARNING, "Baked Normal Map: not started on layer '%s': %s", qUtf8Printable(m.label()),
            why.c_str());
        return false;
    };
    std::string why;
    const std::string descriptionPath = raddecorate::bakedMapOf(m, why);
    if (descriptionPath.empty()) return refuse(why);
    auto view = std::make_unique<NormalMapView>();
    radgl::GlCapabilities caps = radgl::queryGlCapabilities();
    applyGlCap(caps);
    std::string leanNote;
    try {
        view->description = rad::readBakeDescription(descriptionPath);
        const QDir folder = QFileInfo(QString::fromStdString(descriptionPath)).absoluteDir();
        const auto beside = [&](const std::string& file) {
            return folder.filePath(QString::fromStdString(file)).toStdString();
        };
        int width = 0, height = 0;
        const std::vector<float> normals = rad::readNormalMap(beside(view->description.normalMap), width, height);
        radml::ExportChoice choice;
        choice.colors = choice.quality = choice.radiance = choice.transfer = false;
        rad::RadianceMesh plain;
        if (!radml::exportPlainMesh(m.cm, choice, plain, why)) return refuse(why);
        const std::vector<float> wedgeUv = radml::exportWedgeTexCoords(m.cm);
        view->renderer = std::make_unique<radgl::NormalMapGlRenderer>(caps);
        // The layer is uploaded as a POP buffer once; drawing the whole mesh (level 0) reads the same
        // buffer, so switching the level of detail on or off needs no new upload.
        const rad::TriangleMesh triangles{plain.positions, {}, plain.faces};
        view->pop = rad::buildPopBuffer(triangles);
        const rad::TexCoordDerivatives derivatives = rad::computeTexCoordDerivatives(triangles, wedgeUv);
        std::string problem = view->renderer->setPopMesh(plain.positions.data(), plain.normals.data(),
                                                         plain.vertexCount(), plain.faces.data(), plain.faceCount(),
                                                         wedgeUv.data(), view->pop, &derivatives);
        if (problem.empty())
            problem = view->renderer->setNormalMap(rad::buildNormalPyramid(normals.data(), width, height),
                                                   view->description.space == rad::NormalSpace::Tangent,
                                                   view->description.tangentFrame);
        if (!problem.empty()) return refuse(problem);
        if (!view->description.leanMoments.empty()) {
            const std::string leanProblem =
                view->renderer->setLeanMoments(rad::readLeanMoments(beside(view->description.leanMoments)));
            if (!leanProblem.empty()) leanNote = "; LEAN unavailable: " + leanProblem;
        } else {
            leanNote = "; no LEAN moments (tangent-space bake, or baked without them): the LEAN mode draws the "
                       "normal map with Blinn-Phong";
        }
    } catch (const std::exception& e) {
        return refuse(e.what());
    }
    view->fingerprint = fingerprintOf(m.cm);
    Log("Baked Normal Map: layer '%s', %s-space %dx%d map%s, LEAN %s, set up in %.2f s; %s", qUtf8Printable(m.label()),
        view->description.space == rad::NormalSpace::Object ? "object"
        : view->description.tangentFrame == rad::TangentFrame::MikkTSpace ? "tangent (MikkTSpace, Mikkelsen 2008)"
                                                                          : "tangent (per-face dP/du)",
        view->description.size,
        view->description.size, leanNote.c_str(), view->renderer->hasLeanMoments() ? "on" : "off",
        timer.elapsed() / 1000.0, caps.describe().c_str());
    const std::string errors = view->renderer->takeGlErrors();
    if (!errors.empty()) Log(GLLogStream::WARNING, "Baked Normal Map: %s", errors.c_str());
    normalViews_[key] = std::move(view);
    return true;
}

void DecorateRadiancePlugin::decorateNormalMap(MeshModel& m, const RichParameterList* par, GLArea* gla,
                                               GLLogStream& log) {
    auto it = normalViews_.find(Key(gla, m.id()));
    if (it == normalViews_.end() || !par) return;
    NormalMapView& view = *it->second;
    auto reportOnce = [&](int level, const std::string& message) {
        if (view.reported.insert(message).second) log.Log(level, "Baked Normal Map: " + message);
    };
    if (fingerprintOf(m.cm) != view.fingerprint) {
        reportOnce(GLLogStream::WARNING, "the layer changed since the decoration started: switch it off and on");
        return;
    }
    const int choice = par->getEnum(kNormalShading);
    radgl::NormalMapShading mode = choice == 0   ? radgl::NormalMapShading::VertexNormals
                                   : choice == 1 ? radgl::NormalMapShading::NormalMap
                                                 : radgl::NormalMapShading::Lean;
    if (mode == radgl::NormalMapShading::Lean && !view.renderer->hasLeanMoments()) {
        reportOnce(GLLogStream::WARNING, "no LEAN moments for this map: drawing the normal map with Blinn-Phong");
        mode = radgl::NormalMapShading::NormalMap;
    }
    glPushMatrix();
    vcg::glMultMatrix(m.cm.Tr);
    GLdouble modelview[16];
    glGetDoublev(GL_MODELVIEW_MATRIX, modelview);
    const Eigen::Map<const Eigen::Matrix4d> mv(modelview);
    const Eigen::Matrix4d inverse = mv.inverse();
    const Eigen::Vector4d eye = inverse * Eigen::Vector4d(0, 0, 0, 1);
    const vcg::Point3f light = par->getPoint3f(kNormalLight);
    radgl::NormalMapLighting lighting;
    // The light is given in camera coordinates; directions transform with the inverse modelview.
    lighting.lightDirection = (inverse * Eigen::Vector4d(light[0], light[1], light[2], 0.0)).head<3>().normalized();
    const QColor albedo = par->getColor(kNormalAlbedo);
    const auto linear = [](int code) { return double(rad::srgbToLinear(static_cast<std::uint8_t>(code))); };
    lighting.albedo = Eigen::Vector3d(linear(albedo.red()), linear(albedo.green()), linear(albedo.blue()));
    lighting.specular = Eigen::Vector3d::Constant(std::max(0.0f, par->getFloat(kNormalSpecular)));
    lighting.shininess = std::max(1.0f, par->getFloat(kNormalShininess));
    lighting.ambient = Eigen::Vector3d::Constant(0.05);
    const int lod = par->getEnum(kNormalLod);
    int level = 0;
    if (lod == kLodForced) {
        level = std::clamp(par->getInt(kNormalLodLevel), rad::kPopMinLevel, rad::kPopMaxLevel);
    } else if (lod == kLodAutomatic) {
        // The bounding box's size on screen: the largest distance between its projected corners.
        GLdouble projection[16];
        GLint viewport[4];
        glGetDoublev(GL_PROJECTION_MATRIX, projection);
        glGetIntegerv(GL_VIEWPORT, viewport);
        const Eigen::Map<const Eigen::Matrix4d> pr(projection);
        std::vector<Eigen::Vector2d> corners;
        bool behind = false;
        for (int c = 0; c < 8; ++c) {
            Eigen::Vector4d p(1, 1, 1, 1);
            for (int a = 0; a < 3; ++a) p[a] = view.pop.boxMin[a] + ((c >> a) & 1) * view.pop.boxExtent[a];
            const Eigen::Vector4d clip = pr * (mv * p);
            if (clip.w() <= 0) behind = true;
            else corners.emplace_back((clip.x() / clip.w() + 1) * 0.5 * viewport[2], (clip.y() / clip.w() + 1) * 0.5 * viewport[3]);
        }
        double pixels = 0;
        for (const auto& a : corners)
            for (const auto& b : corners) pixels = std::max(pixels, (a - b).norm());
        // A corner behind the eye: the object fills the view, draw the finest level.
        level = behind ? rad::kPopMaxLevel
                       : rad::popLevelForScreenSize(pixels, std::max(0.05, double(par->getFloat(kNormalLodTolerance))));
    }
    const std::string levelProblem = view.renderer->setPopLevel(level, par->getBool(kNormalLodCorrection));
    if (!levelProblem.empty()) reportOnce(GLLogStream::WARNING, levelProblem);
    if (level > 0) {
        // MeshLab has drawn the layer at full resolution: hide it under its background, or it would
        // show through wherever the level's snapped surface lies behind it.
        const vcg::Color4b top = gla->glas.backgroundTopColor, bottom = gla->glas.backgroundBotColor;
        const std::string eraseProblem = view.renderer->eraseFullMesh(
            Eigen::Vector3f(top[0], top[1], top[2]) / 255.0f, Eigen::Vector3f(bottom[0], bottom[1], bottom[2]) / 255.0f);
        if (!eraseProblem.empty()) reportOnce(GLLogStream::WARNING, eraseProblem);
    }
    const std::string problem = view.renderer->draw(mode, lighting, rad::ToneMapping(), eye.head<3>() / eye[3]);
    glPopMatrix();
    if (level != view.loggedLevel) {
        // Logged when the level changes, not every frame.
        view.loggedLevel = level;
        if (level > 0)
            log.Logf(GLLogStream::FILTER, "Baked Normal Map: POP level %d (%s%s): %zu of %zu triangles", level,
                     lod == kLodForced ? "forced" : "automatic",
                     par->getBool(kNormalLodCorrection) ? ", texture coordinates corrected" : "",
                     view.renderer->drawnFaceCount(), view.pop.faceCount());
        else
            log.Logf(GLLogStream::FILTER, "Baked Normal Map: the whole mesh, %zu triangles", view.pop.faceCount());
    }
    if (level > 0)  // MeshLab's real-time info panel of the view, as its own decorations report
        RealTimeLog("POP Level of Detail", m.label(), "level %d: %zu / %zu triangles", level,
                    view.renderer->drawnFaceCount(), view.pop.faceCount());
    if (!problem.empty()) reportOnce(GLLogStream::WARNING, problem);
    const std::string errors = view.renderer->takeGlErrors();
    if (!errors.empty()) reportOnce(GLLogStream::WARNING, errors);
}

MESHLAB_PLUGIN_NAME_EXPORTER(DecorateRadiancePlugin)
