#include "irradiance_grid_decoration.h"

#include "decoration_support.h"

#include "layer_files.h"
#include "mesh_conversion.h"

#include "gl_capabilities.h"
#include "normal_map_gl_renderer.h"

#include "bake/bake_description.h"
#include "bake/lean_maps.h"
#include "image/image_io.h"
#include "image/rgb_image.h"
#include "lighting/irradiance_vector_grid.h"
#include "render/tone_mapping.h"

#include <GL/glew.h>

#include <QDir>
#include <QElapsedTimer>
#include <QFileInfo>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace raddecorate {
namespace {

const char* const kName = "Irradiance Vector Grid";
const char* const kFile = "MeshLab::Decoration::IrradianceGridFile";
const char* const kLight = "MeshLab::Decoration::IrradianceGridLight";
const char* const kNormals = "MeshLab::Decoration::IrradianceGridNormals";
const char* const kAlbedo = "MeshLab::Decoration::IrradianceGridAlbedo";
const char* const kDirection = "MeshLab::Decoration::IrradianceGridLightDirection";
const char* const kIntensity = "MeshLab::Decoration::IrradianceGridLightIntensity";
const char* const kExposure = "MeshLab::Decoration::IrradianceGridExposure";
const char* const kToneMap = "MeshLab::Decoration::IrradianceGridToneMap";
const char* const kWeights = "MeshLab::Decoration::IrradianceGridDirectionalWeights";
enum { kIndirectOnly = 0, kDirectAndIndirect = 1 };
enum { kMappedNormals = 0, kVertexNormals = 1 };

double linearOf(int code) { return double(rad::srgbToLinear(static_cast<std::uint8_t>(std::clamp(code, 0, 255)))); }

// The state per (view, layer): the renderer, its grid and the uploaded layer.
struct View {
    std::unique_ptr<radgl::NormalMapGlRenderer> renderer;
    std::string gridPath;        // the grid drawn
    std::string failedPath;      // a grid named in the options that could not be read (not retried every frame)
    bool normalMap = false;      // the layer's baked normal map is uploaded
    LayerGeometry geometry;      // what was uploaded (a filter that changes the layer stops the drawing)
    OnceLog reported{kName};     // messages logged once
};

// Reads and uploads the grid at `path`; returns the reason on failure (the reader's message names
// the file and the problem), else empty, with `note` from the upload.
std::string loadGrid(View& view, const std::string& path, std::string& note, rad::IrradianceVectorGrid* out,
                     const std::vector<float>& positions) {
    try {
        rad::IrradianceVectorGrid grid = rad::readIrradianceVectorGrid(path);
        // A grid that does not cover the layer (another scene's, or a near-zero cell) would light it
        // with one flat extrapolated colour: refused, saying why.
        if (std::string coverage = rad::gridCoverageProblem(grid, positions.data(), positions.size() / 3);
            !coverage.empty())
            return "'" + path + "' does not fit the layer: " + coverage;
        const std::string problem = view.renderer->setIrradianceGrid(grid, note);
        if (!problem.empty()) return "cannot draw the grid '" + path + "' with this OpenGL: " + problem;
        view.gridPath = path;
        if (out) *out = std::move(grid);
        return {};
    } catch (const std::bad_alloc&) {
        return "not enough memory to read the grid '" + path + "': compute a grid of lower resolution";
    } catch (const std::exception& e) {
        return e.what();
    }
}

// The layer's diffuse colour rho and the normal the grid is evaluated with: the diffuse map and the
// normal map of the layer's bake when there is one (and the options ask for mapped normals), else
// the vertex colours (sRGB decoded) when it has some, else the albedo option (set per frame).
// `mapNote` and `colourNote` say which, for the start line. Throws on an unreadable bake description.
void uploadAppearance(View& view, MeshModel& m, const RichParameterList& par, const rad::RadianceMesh& plain,
                      const std::string& description, std::string& mapNote, std::string& colourNote) {
    std::string problem;
    bool diffuse = false;
    if (!description.empty()) {
        const rad::BakeDescription bake = rad::readBakeDescription(description);
        const QDir folder = QFileInfo(QString::fromStdString(description)).absoluteDir();
        if (!bake.diffuseMap.empty()) {
            const std::string file = folder.filePath(QString::fromStdString(bake.diffuseMap)).toStdString();
            try {
                problem = view.renderer->setDiffuseMap(rad::readImage8(file));
            } catch (const std::exception& e) {
                problem = e.what();
            }
            diffuse = problem.empty();
            colourNote = diffuse ? "albedo from the baked diffuse map" : "diffuse map refused (" + problem + ")";
        }
    }
    if (!description.empty() && par.getEnum(kNormals) == kMappedNormals) {
        const rad::BakeDescription bake = rad::readBakeDescription(description);
        const QDir folder = QFileInfo(QString::fromStdString(description)).absoluteDir();
        int width = 0, height = 0;
        const std::vector<float> normals =
            rad::readNormalMap(folder.filePath(QString::fromStdString(bake.normalMap)).toStdString(), width, height);
        problem = view.renderer->setNormalMap(rad::buildNormalPyramid(normals.data(), width, height),
                                              bake.space == rad::NormalSpace::Tangent, bake.tangentFrame);
        if (problem.empty()) {
            view.normalMap = true;
            mapNote = "the baked " + std::to_string(width) + "x" + std::to_string(height) + " normal map";
        } else {
            mapNote = "vertex normals (normal map refused: " + problem + ")";
        }
    }
    if (!diffuse && m.hasDataMask(MeshModel::MM_VERTCOLOR) && plain.colors.size() == 4 * plain.vertexCount()) {
        std::vector<float> rho(3 * plain.vertexCount());
        for (std::size_t v = 0; v < plain.vertexCount(); ++v)
            for (int c = 0; c < 3; ++c) rho[3 * v + c] = static_cast<float>(linearOf(plain.colors[4 * v + c]));
        problem = view.renderer->setVertexColors(rho.data(), plain.vertexCount());
        colourNote = problem.empty() ? "albedo from the vertex colours" : "albedo from the options (" + problem + ")";
    }
}

// Uploads the layer's mesh, appearance and the grid at `path` into the view's new renderer. Returns
// false with `why` when it cannot be drawn, else true with `startLine` for the log. Throws on
// unreadable files.
bool uploadLayer(View& view, MeshModel& m, const RichParameterList& par, const std::string& path,
                 const radgl::GlCapabilities& caps, const QElapsedTimer& timer, std::string& startLine, std::string& why) {
    view.renderer = std::make_unique<radgl::NormalMapGlRenderer>(caps);
    if (!view.renderer->shaderProblem().empty()) {
        why = "no shaders: " + view.renderer->shaderProblem();
        return false;
    }
    radml::ExportChoice choice;
    choice.quality = choice.radiance = choice.transfer = false;
    rad::RadianceMesh plain;
    if (!radml::exportPlainMesh(m.cm, choice, plain, why)) return false;
    std::string mapWhy;
    const std::string description = bakedMapOf(m, mapWhy);  // normal map and diffuse map of a bake
    std::vector<float> wedgeUv = description.empty() ? std::vector<float>(6 * plain.faceCount(), 0.0f)
                                                     : radml::exportWedgeTexCoords(m.cm);
    std::string problem = view.renderer->setMesh(plain.positions.data(), plain.normals.data(), plain.vertexCount(),
                                                 plain.faces.data(), plain.faceCount(), wedgeUv.data());
    if (!problem.empty()) {
        why = problem;
        return false;
    }
    std::string mapNote = "vertex normals", colourNote = "albedo from the options";
    uploadAppearance(view, m, par, plain, description, mapNote, colourNote);
    std::string note;
    rad::IrradianceVectorGrid grid;
    problem = loadGrid(view, path, note, &grid, plain.positions);
    if (!problem.empty()) {
        why = problem;
        return false;
    }
    char line[1024];
    std::snprintf(line, sizeof line,
                  "grid '%s', %d x %d x %d cells, %d bounce(s), %.1f MB of 3D textures (12 x RGB16F); %s, %s; set up "
                  "in %.2f s; %s%s%s",
                  path.c_str(), grid.cells[0], grid.cells[1], grid.cells[2], grid.bounces,
                  view.renderer->irradianceGridBytes() / 1048576.0, mapNote.c_str(), colourNote.c_str(),
                  timer.elapsed() / 1000.0, caps.describe().c_str(), note.empty() ? "" : "; ", note.c_str());
    startLine = line;
    return true;
}

// Sets the layer up (mesh, albedo, normal map, grid). Returns null with `why` (no grid file, a bad
// file with the reader's reason, GL limits, no faces); else the view, with `startLine` for the log.
std::unique_ptr<View> setUpLayer(MeshModel& m, const RichParameterList& par, std::string& startLine, std::string& why) {
    QElapsedTimer timer;
    timer.start();
    if (m.cm.fn == 0) {
        why = "the layer has no faces (a point cloud): the decoration draws triangles";
        return nullptr;
    }
    const std::string path = irradianceGridPathOf(m, par.getOpenFileName(kFile).trimmed().toStdString(), why);
    if (path.empty()) return nullptr;
    if (!QFileInfo::exists(QString::fromStdString(path))) {
        why = "no irradiance vector grid '" + path + "': compute one with 'Compute Irradiance Vector Grid' (it saves "
              "it beside the layer's file), or name a grid file in Tools > Options > Decoration";
        return nullptr;
    }
    radgl::GlCapabilities caps = radgl::queryGlCapabilities();
    radgl::capGlVersionFromEnvironment(caps);  // RADIANCE_DECORATE_MAX_GL, as the other decorations
    auto view = std::make_unique<View>();
    try {
        if (!uploadLayer(*view, m, par, path, caps, timer, startLine, why)) return nullptr;
    } catch (const std::bad_alloc&) {
        why = "not enough memory to set the layer and its grid up: close other layers or programs";
        return nullptr;
    } catch (const std::exception& e) {
        why = e.what();
        return nullptr;
    }
    view->geometry = geometryOf(m.cm);
    const std::string errors = view->renderer->takeGlErrors();
    if (!errors.empty()) startLine += "; " + errors;
    return view;
}

// A grid file chosen in the options while the decoration is on: loaded once (a failure is not
// retried every frame). False (logged) when there is nothing to draw.
bool followGridFile(View& view, MeshModel& m, const RichParameterList& par, GLLogStream& log) {
    std::string why;
    const std::string path = irradianceGridPathOf(m, par.getOpenFileName(kFile).trimmed().toStdString(), why);
    if (path.empty()) {
        view.reported.report(log, GLLogStream::WARNING, why);
        return false;
    }
    if (path == view.gridPath) return true;
    if (path == view.failedPath) return false;
    std::string note;
    std::vector<float> positions;
    for (const CVertexO& v : m.cm.vert)
        if (!v.IsD()) positions.insert(positions.end(), {v.cP()[0], v.cP()[1], v.cP()[2]});
    const std::string problem = loadGrid(view, path, note, nullptr, positions);
    if (!problem.empty()) {
        view.failedPath = path;
        view.reported.report(log, GLLogStream::WARNING, problem + "; nothing drawn");
        return false;
    }
    view.failedPath.clear();
    view.reported.report(log, GLLogStream::FILTER, "now drawing the grid '" + path + "'" + (note.empty() ? "" : "; " + note));
    return true;
}

// The lights and albedo of the parameters; the direct light, given in camera coordinates, turned
// into the layer's with the inverse modelview (directions transform with it).
radgl::NormalMapLighting lightingOf(const RichParameterList& par, const Eigen::Matrix4d& inverseModelview) {
    const vcg::Point3f light = par.getPoint3f(kDirection);
    radgl::NormalMapLighting lighting;
    lighting.indirect = par.getEnum(kLight) == kDirectAndIndirect ? radgl::IndirectLight::DirectAndIndirect
                                                                  : radgl::IndirectLight::Indirect;
    const Eigen::Vector3d l = (inverseModelview * Eigen::Vector4d(light[0], light[1], light[2], 0.0)).head<3>();
    lighting.lightDirection = l.norm() > 0 ? l.normalized() : Eigen::Vector3d(0, 0, 1);
    const float intensity = par.getFloat(kIntensity);
    lighting.lightColor = Eigen::Vector3d::Constant(std::isfinite(intensity) ? std::max(0.0f, intensity) : 1.0);
    const QColor albedo = par.getColor(kAlbedo);
    lighting.albedo = Eigen::Vector3d(linearOf(albedo.red()), linearOf(albedo.green()), linearOf(albedo.blue()));
    lighting.gridAbsoluteWeights = par.getEnum(kWeights) == 1;
    lighting.specular.setZero();  // the grid's surfaces are diffuse (L = rho / pi <I, n>); so is the direct light
    lighting.ambient.setZero();
    return lighting;
}

class IrradianceGridDecoration : public Decoration {
public:
    QString name() const override { return kName; }
    QString info() const override;
    ActionLook look() const override;
    bool isApplicable(const MeshModel& m, QString& message) const override;
    void addParameters(RichParameterList& par) const override;
    // Sets the layer up (mesh, albedo, normal map, grid); refuses (logged) when there is no grid file,
    // a bad file (with the reader's reason), GL limits, no faces.
    bool start(MeshModel& m, const RichParameterList& par, GLArea& gla, MeshLabInterface& pluginLog) override;
    void draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
              MeshLabInterface& pluginLog) override;
    void end(MeshModel& m, GLArea* gla) override { views_.end(gla, m); }

private:
    LayerViews<View> views_;
};

QString IrradianceGridDecoration::info() const {
    return "Draws the layer lit by the indirect light stored in an irradiance vector grid: <i>P. Granier, R. "
           "Pacanowski, C. Schlick</i>, <b>Managing Geometry Complexity for Illumination Computation of Cultural "
           "Heritage Scenes</b> (2007). Per fragment: the paper's six irradiance vectors per grid vertex, "
           "compressed to a colour and a direction in twelve 16-bit 3D textures, interpolated trilinearly, "
           "weighted by the squared components of the normal (or their absolute values), L = rho / pi &lt;I_n, n&gt;; alone or with one "
           "directional light (no shadows). The grid is the layer's file with the extension .ivg, or the file "
           "named in Tools &gt; Options &gt; Decoration. With a normal map baked by 'Bake Normal Map' the grid "
           "is evaluated with the mapped normal. Needs OpenGL 3.2 / GLSL 1.50 and 14 texture units. Shortcut "
           "Ctrl+Alt+I.";
}

ActionLook IrradianceGridDecoration::look() const { return {Qt::Key_I, QColor(120, 200, 120), QColor(20, 80, 30)}; }

bool IrradianceGridDecoration::isApplicable(const MeshModel& m, QString& message) const {
    // Whether a grid exists and reads is said in the log when the decoration starts.
    if (m.cm.fn > 0) return true;
    message = "the layer has no faces (a point cloud): the decoration draws triangles";
    return false;
}

void IrradianceGridDecoration::addParameters(RichParameterList& par) const {
    par.addParam(RichOpenFile(kFile, "", QStringList() << "*.ivg", "Irradiance vector grid file",
                              "The grid to draw. Empty: the layer's file with the extension .ivg, as 'Compute "
                              "Irradiance Vector Grid' saves it. A relative name is taken beside the layer's file."));
    par.addParam(RichEnum(kLight, kIndirectOnly,
                          QStringList() << "Indirect light only" << "Direct + indirect light (direct: no shadows)",
                          "Irradiance grid light",
                          "Indirect only: rho / pi <I_n, n> from the grid. Direct + indirect: plus one directional "
                          "light that follows the camera (Lambert; the direct light casts no shadows)."));
    par.addParam(RichEnum(kNormals, kMappedNormals,
                          QStringList() << "Baked normal map when the layer has one" << "Vertex normals",
                          "Irradiance grid normals",
                          "The normal the grid is evaluated with: the normal map baked by 'Bake Normal Map' (the "
                          "scan's detail on a simplified mesh, Granier et al. 2007), or the mesh's vertex normals."));
    par.addParam(RichEnum(kWeights, 0,
                          QStringList() << "n_a^2 (Granier et al. 2007)" << "|n_a| (exact under uniform light)",
                          "Irradiance grid directional weights",
                          "How the three vectors chosen by the normal's signs are blended. The paper's squared "
                          "components n_a^2 are exact on the axes but give 1/sqrt(3) of the light under a uniform "
                          "sky on a diagonal normal; |n_a| is exact under uniform light for every normal and equal "
                          "on the axes (README: the image error of both)."));
    par.addParam(RichColor(kAlbedo, QColor(200, 200, 200), "Irradiance grid albedo",
                           "Diffuse colour rho of a layer without vertex colours (a layer with colours uses them)."));
    par.addParam(RichPoint3f(kDirection, vcg::Point3f(0.4f, 0.5f, 1.0f), "Irradiance grid direct light direction",
                             "Direction toward the direct light in camera coordinates (x right, y up, z toward you)."));
    par.addParam(RichFloat(kIntensity, 1.0f, "Irradiance grid direct light intensity",
                           "Irradiance of the direct light (white): L = rho max(n.l, 0) x intensity."));
    par.addParam(RichFloat(kExposure, 0.0f, "Irradiance grid exposure (stops)",
                           "Displayed colour = tone curve(2^stops x radiance), then sRGB."));
    par.addParam(RichEnum(kToneMap, 0, QStringList() << "Clamp" << "Reinhard x/(1+x)", "Irradiance grid tone curve",
                          "Clamp: values above 1 saturate. Reinhard: x/(1+x) per channel."));
}

bool IrradianceGridDecoration::start(MeshModel& m, const RichParameterList& par, GLArea& gla,
                                     MeshLabInterface& pluginLog) {
    views_.erase(&gla, m);
    if (!glExtensionsReady(kName, pluginLog)) return false;
    std::string startLine, why;
    std::unique_ptr<View> view = setUpLayer(m, par, startLine, why);
    if (!view) return refuseStart(kName, m, why, pluginLog);
    pluginLog.Log("Irradiance Vector Grid: layer '%s', %s", qUtf8Printable(m.label()), startLine.c_str());
    views_.put(&gla, m, std::move(view));
    return true;
}

void IrradianceGridDecoration::draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
                                    MeshLabInterface&) {
    View* found = views_.find(gla, m);
    if (!found) return;
    View& view = *found;
    if (geometryOf(m.cm) != view.geometry) {
        view.reported.report(log, GLLogStream::WARNING, "the layer changed since the decoration started: switch it off and on");
        return;
    }
    if (!followGridFile(view, m, par, log)) return;

    const LayerEye layer = enterLayerSpace(m.cm);
    const radgl::NormalMapLighting lighting = lightingOf(par, layer.inverse);
    const rad::ToneMapping tm = toneMappingOf(par, kExposure, kToneMap);
    const radgl::NormalMapShading mode = view.normalMap ? radgl::NormalMapShading::NormalMap : radgl::NormalMapShading::VertexNormals;
    const std::string problem = view.renderer->draw(mode, lighting, tm, layer.eye);
    glPopMatrix();
    view.reported.warnIfAny(log, problem);
    view.reported.warnIfAny(log, view.renderer->takeGlErrors());
}

}  // namespace

std::unique_ptr<Decoration> makeIrradianceGridDecoration() { return std::make_unique<IrradianceGridDecoration>(); }

}  // namespace raddecorate
