#include "normal_map_decoration.h"

#include "decoration_support.h"

#include "layer_files.h"

#include "mesh_conversion.h"

#include "gl_capabilities.h"
#include "normal_map_gl_renderer.h"

#include "bake/bake_description.h"
#include "bake/lean_maps.h"
#include "image/rgb_image.h"
#include "lod/pop_buffer.h"
#include "lod/texcoord_correction.h"

#include <GL/glew.h>

#include <meshlab/glarea.h>

#include <Eigen/Geometry>

#include <QDir>
#include <QElapsedTimer>
#include <QFileInfo>

#include <algorithm>

namespace raddecorate {
namespace {

const char* const kName = "Baked Normal Map";
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

// The state per (view, layer): the normal-map renderer.
struct View {
    std::unique_ptr<radgl::NormalMapGlRenderer> renderer;
    Fingerprint fingerprint;
    rad::BakeDescription description;
    OnceLog reported{kName};
    // POP buffer (Limper et al. 2013): its box, for the per-frame level, and the last level logged.
    rad::PopBuffer pop;
    int loggedLevel = -1;
};

// Uploads the layer (as a POP buffer), its normal map and its LEAN moments described by the bake
// description at `descriptionPath`. Returns why it cannot be drawn, else empty with `leanNote` for
// the start line. Throws on unreadable files.
std::string uploadBake(View& view, MeshModel& m, const std::string& descriptionPath, const radgl::GlCapabilities& caps,
                       std::string& leanNote) {
    view.description = rad::readBakeDescription(descriptionPath);
    const QDir folder = QFileInfo(QString::fromStdString(descriptionPath)).absoluteDir();
    const auto beside = [&](const std::string& file) { return folder.filePath(QString::fromStdString(file)).toStdString(); };
    int width = 0, height = 0;
    const std::vector<float> normals = rad::readNormalMap(beside(view.description.normalMap), width, height);
    radml::ExportChoice choice;
    choice.colors = choice.quality = choice.radiance = choice.transfer = false;
    rad::RadianceMesh plain;
    std::string why;
    if (!radml::exportPlainMesh(m.cm, choice, plain, why)) return why;
    const std::vector<float> wedgeUv = radml::exportWedgeTexCoords(m.cm);
    view.renderer = std::make_unique<radgl::NormalMapGlRenderer>(caps);
    // The layer is uploaded as a POP buffer once; drawing the whole mesh (level 0) reads the same
    // buffer, so switching the level of detail on or off needs no new upload.
    const rad::TriangleMesh triangles{plain.positions, {}, plain.faces};
    view.pop = rad::buildPopBuffer(triangles);
    const rad::TexCoordDerivatives derivatives = rad::computeTexCoordDerivatives(triangles, wedgeUv);
    std::string problem =
        view.renderer->setPopMesh(plain.positions.data(), plain.normals.data(), plain.vertexCount(), plain.faces.data(),
                                  plain.faceCount(), wedgeUv.data(), view.pop, &derivatives);
    if (problem.empty())
        problem = view.renderer->setNormalMap(rad::buildNormalPyramid(normals.data(), width, height),
                                              view.description.space == rad::NormalSpace::Tangent,
                                              view.description.tangentFrame);
    if (!problem.empty()) return problem;
    if (!view.description.leanMoments.empty()) {
        const std::string leanProblem =
            view.renderer->setLeanMoments(rad::readLeanMoments(beside(view.description.leanMoments)));
        if (!leanProblem.empty()) leanNote = "; LEAN unavailable: " + leanProblem;
    } else {
        leanNote = "; no LEAN moments (tangent-space bake, or baked without them): the LEAN mode draws the "
                   "normal map with Blinn-Phong";
    }
    return {};
}

radgl::NormalMapShading shadingOf(const RichParameterList& par) {
    const int choice = par.getEnum(kNormalShading);
    return choice == 0   ? radgl::NormalMapShading::VertexNormals
           : choice == 1 ? radgl::NormalMapShading::NormalMap
                         : radgl::NormalMapShading::Lean;
}

// The light and material of the parameters; the light, given in camera coordinates, turned into the
// layer's with the inverse modelview (directions transform with it).
radgl::NormalMapLighting lightingOf(const RichParameterList& par, const Eigen::Matrix4d& inverseModelview) {
    const vcg::Point3f light = par.getPoint3f(kNormalLight);
    radgl::NormalMapLighting lighting;
    lighting.lightDirection =
        (inverseModelview * Eigen::Vector4d(light[0], light[1], light[2], 0.0)).head<3>().normalized();
    const QColor albedo = par.getColor(kNormalAlbedo);
    const auto linear = [](int code) { return double(rad::srgbToLinear(static_cast<std::uint8_t>(code))); };
    lighting.albedo = Eigen::Vector3d(linear(albedo.red()), linear(albedo.green()), linear(albedo.blue()));
    lighting.specular = Eigen::Vector3d::Constant(std::max(0.0f, par.getFloat(kNormalSpecular)));
    lighting.shininess = std::max(1.0f, par.getFloat(kNormalShininess));
    lighting.ambient = Eigen::Vector3d::Constant(0.05);
    return lighting;
}

// The automatic POP level: from the bounding box's size on screen, the largest distance between its
// projected corners.
int automaticLevel(const rad::PopBuffer& pop, const Eigen::Matrix4d& modelview, const RichParameterList& par) {
    GLdouble projection[16];
    GLint viewport[4];
    glGetDoublev(GL_PROJECTION_MATRIX, projection);
    glGetIntegerv(GL_VIEWPORT, viewport);
    const Eigen::Map<const Eigen::Matrix4d> pr(projection);
    std::vector<Eigen::Vector2d> corners;
    bool behind = false;
    for (int c = 0; c < 8; ++c) {
        Eigen::Vector4d p(1, 1, 1, 1);
        for (int a = 0; a < 3; ++a) p[a] = pop.boxMin[a] + ((c >> a) & 1) * pop.boxExtent[a];
        const Eigen::Vector4d clip = pr * (modelview * p);
        if (clip.w() <= 0) behind = true;
        else corners.emplace_back((clip.x() / clip.w() + 1) * 0.5 * viewport[2], (clip.y() / clip.w() + 1) * 0.5 * viewport[3]);
    }
    double pixels = 0;
    for (const auto& a : corners)
        for (const auto& b : corners) pixels = std::max(pixels, (a - b).norm());
    // A corner behind the eye: the object fills the view, draw the finest level.
    return behind ? rad::kPopMaxLevel
                  : rad::popLevelForScreenSize(pixels, std::max(0.05, double(par.getFloat(kNormalLodTolerance))));
}

// The POP level to draw: 0 (the whole mesh) when the level of detail is off.
int levelOf(const rad::PopBuffer& pop, const Eigen::Matrix4d& modelview, const RichParameterList& par) {
    const int lod = par.getEnum(kNormalLod);
    if (lod == kLodForced) return std::clamp(par.getInt(kNormalLodLevel), rad::kPopMinLevel, rad::kPopMaxLevel);
    if (lod == kLodAutomatic) return automaticLevel(pop, modelview, par);
    return 0;
}

// MeshLab has drawn the layer at full resolution: hide it under its background, or it would
// show through wherever the level's snapped surface lies behind it.
void hideFullMesh(View& view, const GLArea& gla, GLLogStream& log) {
    const vcg::Color4b top = gla.glas.backgroundTopColor, bottom = gla.glas.backgroundBotColor;
    view.reported.warnIfAny(log, view.renderer->eraseFullMesh(Eigen::Vector3f(top[0], top[1], top[2]) / 255.0f,
                                                              Eigen::Vector3f(bottom[0], bottom[1], bottom[2]) / 255.0f));
}

// The level in the log when it changes (not every frame), and in MeshLab's real-time info panel of
// the view, as its own decorations report.
void reportLevel(View& view, int level, const MeshModel& m, const RichParameterList& par, GLLogStream& log,
                 MeshLabInterface& pluginLog) {
    if (level != view.loggedLevel) {
        view.loggedLevel = level;
        if (level > 0)
            log.Logf(GLLogStream::FILTER, "Baked Normal Map: POP level %d (%s%s): %zu of %zu triangles", level,
                     par.getEnum(kNormalLod) == kLodForced ? "forced" : "automatic",
                     par.getBool(kNormalLodCorrection) ? ", texture coordinates corrected" : "",
                     view.renderer->drawnFaceCount(), view.pop.faceCount());
        else
            log.Logf(GLLogStream::FILTER, "Baked Normal Map: the whole mesh, %zu triangles", view.pop.faceCount());
    }
    if (level > 0)
        pluginLog.RealTimeLog("POP Level of Detail", m.label(), "level %d: %zu / %zu triangles", level,
                              view.renderer->drawnFaceCount(), view.pop.faceCount());
}

class NormalMapDecoration : public Decoration {
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

QString NormalMapDecoration::info() const {
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
}

ActionLook NormalMapDecoration::look() const { return {Qt::Key_N, QColor(128, 128, 255), QColor(30, 30, 110)}; }

bool NormalMapDecoration::isApplicable(const MeshModel& m, QString& message) const {
    std::string why;
    if (bakedMapOf(m, why).empty()) {
        message = QString::fromStdString(why);
        return false;
    }
    return true;
}

void NormalMapDecoration::addParameters(RichParameterList& par) const {
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
}

bool NormalMapDecoration::start(MeshModel& m, const RichParameterList&, GLArea& gla, MeshLabInterface& pluginLog) {
    if (!glExtensionsReady(kName, pluginLog)) return false;
    QElapsedTimer timer;
    timer.start();
    views_.erase(&gla, m);
    std::string why;
    const std::string descriptionPath = bakedMapOf(m, why);
    if (descriptionPath.empty()) return refuseStart(kName, m, why, pluginLog);
    auto view = std::make_unique<View>();
    radgl::GlCapabilities caps = radgl::queryGlCapabilities();
    // RADIANCE_DECORATE_MAX_GL=2.1 pretends the context is older (to see the fallback in the GUI).
    radgl::capGlVersionFromEnvironment(caps);
    std::string leanNote;
    try {
        const std::string problem = uploadBake(*view, m, descriptionPath, caps, leanNote);
        if (!problem.empty()) return refuseStart(kName, m, problem, pluginLog);
    } catch (const std::exception& e) {
        return refuseStart(kName, m, e.what(), pluginLog);
    }
    view->fingerprint = fingerprintOf(m.cm);
    pluginLog.Log("Baked Normal Map: layer '%s', %s-space %dx%d map%s, LEAN %s, set up in %.2f s; %s",
                  qUtf8Printable(m.label()),
                  view->description.space == rad::NormalSpace::Object ? "object"
                  : view->description.tangentFrame == rad::TangentFrame::MikkTSpace
                      ? "tangent (MikkTSpace, Mikkelsen 2008)"
                      : "tangent (per-face dP/du)",
                  view->description.size, view->description.size, leanNote.c_str(),
                  view->renderer->hasLeanMoments() ? "on" : "off", timer.elapsed() / 1000.0, caps.describe().c_str());
    const std::string errors = view->renderer->takeGlErrors();
    if (!errors.empty()) pluginLog.Log(GLLogStream::WARNING, "Baked Normal Map: %s", errors.c_str());
    views_.put(&gla, m, std::move(view));
    return true;
}

void NormalMapDecoration::draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
                               MeshLabInterface& pluginLog) {
    View* found = views_.find(gla, m);
    if (!found) return;
    View& view = *found;
    if (fingerprintOf(m.cm) != view.fingerprint) {
        view.reported.report(log, GLLogStream::WARNING, "the layer changed since the decoration started: switch it off and on");
        return;
    }
    radgl::NormalMapShading mode = shadingOf(par);
    if (mode == radgl::NormalMapShading::Lean && !view.renderer->hasLeanMoments()) {
        view.reported.report(log, GLLogStream::WARNING, "no LEAN moments for this map: drawing the normal map with Blinn-Phong");
        mode = radgl::NormalMapShading::NormalMap;
    }
    const LayerEye layer = enterLayerSpace(m.cm);
    const radgl::NormalMapLighting lighting = lightingOf(par, layer.inverse);
    const int level = levelOf(view.pop, layer.modelview, par);
    view.reported.warnIfAny(log, view.renderer->setPopLevel(level, par.getBool(kNormalLodCorrection)));
    if (level > 0) hideFullMesh(view, *gla, log);
    const std::string problem = view.renderer->draw(mode, lighting, rad::ToneMapping(), layer.eye);
    glPopMatrix();
    reportLevel(view, level, m, par, log, pluginLog);
    view.reported.warnIfAny(log, problem);
    view.reported.warnIfAny(log, view.renderer->takeGlErrors());
}

}  // namespace

std::unique_ptr<Decoration> makeNormalMapDecoration() { return std::make_unique<NormalMapDecoration>(); }

}  // namespace raddecorate
