// "Compute Irradiance Vector Grid": the indirect light of the visible layers cached in an
// irradiance vector grid (Granier et al. 2007), written as an .ivg file for the decoration. A thin
// adapter: the visible layers merged with their vertex colours as albedo, the lights from the
// parameters, a call into common/lighting (irradiance_vector_grid_compute.h), the file, the log.
// The layers are never changed.
//
// Output convention shared with the decoration: an empty output path means
// "<current layer's file without extension>.ivg" beside it; refused when the layer has no file.
#include "irradiance_grid_plugin.h"

#include "citations.h"

#include "image/rgb_image.h"
#include "lighting/environment_map.h"
#include "lighting/irradiance_vector_grid.h"
#include "lighting/irradiance_vector_grid_compute.h"

#include <QDir>
#include <QFileInfo>

#include <cmath>
#include <memory>
#include <vector>

namespace radml {
namespace {

enum LightChoice { kEnvironmentMap = 0, kDirectional = 1 };

// The visible layers (the current one always) merged: positions, faces, albedo from the vertex
// colours (sRGB codes decoded to linear reflectance) or the default grey.
void collectScene(MeshDocument& md, MeshModel& current, rad::TriangleMesh& scene, std::vector<float>& albedo,
                  int& layers, int& coloured) {
    layers = coloured = 0;
    for (MeshModel* layer : documentMeshes(md)) {
        if (layer != &current && !layer->isVisible()) continue;
        CMeshO& m = layer->cm;
        const bool colours = layer->hasDataMask(MeshModel::MM_VERTCOLOR);
        std::vector<std::uint32_t> index(m.vert.size(), 0);
        auto next = static_cast<std::uint32_t>(scene.vertexCount());
        for (std::size_t i = 0; i < m.vert.size(); ++i) {
            if (m.vert[i].IsD()) continue;
            index[i] = next++;
            for (int k = 0; k < 3; ++k) scene.positions.push_back(float(m.vert[i].cP()[k]));
            for (int k = 0; k < 3; ++k)
                albedo.push_back(colours ? rad::srgbToLinear(m.vert[i].cC()[k]) : rad::kDefaultIndirectAlbedo);
        }
        for (const CFaceO& f : m.face) {
            if (f.IsD()) continue;
            for (int k = 0; k < 3; ++k) scene.faces.push_back(index[vcg::tri::Index(m, f.cV(k))]);
        }
        ++layers;
        if (colours) ++coloured;
    }
}

class ComputeIrradianceVectorGridFilter : public Filter {
public:
    QString name() const override { return "Compute Irradiance Vector Grid"; }
    QString pythonName() const override { return "compute_irradiance_vector_grid"; }
    QString description() const override;
    // Measure ("Quality Measure and Computations"): it computes, writes a file, changes no layer.
    int filterClass() const override { return 0x10000; /* Measure */ }
    int postconditions() const override { return 0; }
    bool readsOtherLayers() const override { return true; }

    RichParameterList parameters(const MeshDocument&, const MeshModel&) const override {
        RichParameterList par;
        par.addParam(RichInt("resolution", 16, "Grid resolution",
                             "Cells along the longest side of the visible layers' bounding box (padded by 2 %); the "
                             "other sides get as many cubic cells as they need. 1 to 512; Granier et al. 2007 use "
                             "10 to 20. Memory: 54 floats per grid vertex (17^3 vertices = 1 MB)."));
        par.addParam(RichInt("bounces", 1, "Bounces",
                             "Diffuse bounces of the direct light the grid holds: 1 = light reflected once by the "
                             "scene; more adds the light reflected again (1 to 16)."));
        par.addParam(RichInt("rays", 256, "Rays per vertex and direction",
                             "Monte Carlo rays per grid vertex for each of the six directions (1 to 1048576)."));
        par.addParam(RichEnum("lightSource", kEnvironmentMap, QStringList() << "Environment map" << "Directional light",
                              "Direct light",
                              "Environment map: an HDR map (.exr or .hdr, equirectangular, +Z up) as median-cut "
                              "directional lights (Debevec 2005) with shadow rays. Directional light: one light from "
                              "the given direction."));
        par.addParam(RichString("envMap", "", "Environment map file",
                                "Path of the HDR environment map (.exr or .hdr) for 'Environment map' lighting."));
        par.addParam(RichInt("lightCount", 64, "Environment lights",
                             "Median-cut lights the map is split into (rounded up to a power of two, 1 to 4096)."));
        par.addParam(RichFloat("envScale", 1.0f, "Environment intensity", "Multiplies the map's radiance (> 0)."));
        addDirectionParameter(par, "lightDirection", Eigen::Vector3d(0.3, 0.2, 1.0), "Light direction",
                              "Toward the directional light (need not be unit length).");
        par.addParam(RichFloat("lightIrradiance", 1.0f, "Light irradiance",
                               "Irradiance of the directional light on a surface facing it (>= 0)."));
        par.addParam(RichString("outputFile", "", "Output file (.ivg)",
                                "Where the grid is written; empty = beside the current layer's file, with its name "
                                "and the extension .ivg (the 'Radiance Field' decoration looks there)."));
        return par;
    }

    std::string outOfMemoryAdvice() const override { return "choose a smaller grid resolution"; }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        MeshModel& current = ctx.mesh();
        // Output path first: a refusal costs nothing.
        QString output = par.getString("outputFile").trimmed();
        if (output.isEmpty()) {
            const QString file = current.fullName();
            if (file.isEmpty())
                throw Refusal("The current layer '" + current.label().toStdString() +
                              "' has no file to write the grid beside: save the layer first, or give an output file.");
            const QFileInfo info(file);
            output = info.absoluteDir().filePath(info.completeBaseName() + ".ivg");
        }
        if (QFileInfo(output).isDir()) throw Refusal("The output path '" + output.toStdString() + "' is a folder: give a file name ending in .ivg.");

        rad::IrradianceGridOptions options;
        options.resolution = par.getInt("resolution");
        options.light.bounces = par.getInt("bounces");
        options.raysPerDirection = par.getInt("rays");

        rad::AnalyticLighting lights;
        QString lightText;
        if (par.getEnum("lightSource") == kEnvironmentMap) {
            const QString path = par.getString("envMap").trimmed();
            if (path.isEmpty())
                throw Refusal("No environment map given: choose an .exr or .hdr file, or 'Directional light' as the direct light.");
            const rad::EnvironmentMap map = rad::readEnvironmentMap(path.toStdString());
            lights = rad::environmentLights(map, par.getInt("lightCount"), par.getFloat("envScale"));
            lightText = QString("%1 median-cut lights of %2").arg(lights.directional.size()).arg(QFileInfo(path).fileName());
        } else {
            rad::DirectionalLight sun;
            sun.direction = pointParameter(par, "lightDirection");
            const double e = par.getFloat("lightIrradiance");
            if (!(sun.direction.norm() > 0.0) || !std::isfinite(sun.direction.norm()))
                throw Refusal("The light direction is zero or not finite: give the direction toward the light, e.g. (0, 0, 1).");
            if (!(e >= 0.0) || !std::isfinite(e)) throw Refusal("The light irradiance must be a number >= 0.");
            sun.irradiance = rad::Rgb::Constant(e);
            lights.directional.push_back(sun);
            lightText = QString("a directional light");
        }

        rad::TriangleMesh scene;
        std::vector<float> albedo;
        int layers = 0, coloured = 0;
        collectScene(ctx.document, current, scene, albedo, layers, coloured);
        if (scene.faceCount() == 0)
            throw Refusal("The visible layers have no faces: the grid needs surfaces for the light to bounce on; open or "
                          "show a mesh with faces.");

        ctx.progress.setPhase(0, 100, "Computing the irradiance vector grid");
        rad::IrradianceGridReport report;
        const rad::IrradianceVectorGrid grid =
            rad::computeIrradianceVectorGrid(scene, albedo, lights, options, ctx.progress.forCore(), &report);
        if (!rad::irradianceVectorsFinite(grid)) {
            // The light, not the file, is the cause: name the parameter that sets it.
            const bool map = par.getEnum("lightSource") == kEnvironmentMap;
            throw Refusal(formatLine("The indirect light overflowed single precision (%s): lower the parameter '%s' "
                                     "(now %g) to a physical value, e.g. 1. No file was written.",
                                     "a grid value is infinite", map ? "Environment intensity" : "Light irradiance",
                                     double(par.getFloat(map ? "envScale" : "lightIrradiance"))));
        }
        rad::writeIrradianceVectorGrid(output.toStdString(), grid);

        ctx.log(formatLine("Compute Irradiance Vector Grid: %d layer(s) (%zu faces, albedo from the vertex colours of %d, "
                           "grey %.2f elsewhere), %s, %d bounce(s)",
                           layers, scene.faceCount(), coloured, double(rad::kDefaultIndirectAlbedo),
                           qUtf8Printable(lightText), options.light.bounces));
        ctx.log(formatLine("Compute Irradiance Vector Grid: %d x %d x %d cells, %zu grid vertices, %.2f MB (54 floats per "
                           "vertex)", grid.cells[0], grid.cells[1], grid.cells[2], report.vertices,
                           report.memoryBytes / 1e6));
        ctx.log(formatLine("Compute Irradiance Vector Grid: %.2f M samples (%d rays per vertex and direction), %.2f M rays "
                           "in all, %.2f s (%.3f s per million samples)",
                           report.samples / 1e6, options.raysPerDirection, report.rays / 1e6, report.totalSeconds,
                           report.secondsPerMillionSamples()));
        ctx.log(formatLine("Compute Irradiance Vector Grid: %zu grid vertices inside objects or behind walls, %zu repaired "
                           "from their neighbours, %zu left zero",
                           report.invalidVertices, report.repairedVertices, report.unreachableVertices));
        ctx.log(formatLine("Compute Irradiance Vector Grid: wrote %s", qUtf8Printable(output)));
    }
};

QString ComputeIrradianceVectorGridFilter::description() const {
    return QString(
               "Computes the indirect light of the visible layers (a statue in a room, a scan on its plinth) and "
               "stores it in an irradiance vector grid: at every vertex of an axis-aligned grid, for each of the six "
               "directions +x, -x, +y, -y, +z, -z, one irradiance vector per colour channel, the integral over that "
               "hemisphere of the incoming INDIRECT radiance times its direction. The direct light (an HDR "
               "environment map as median-cut lights, or a directional light) reaches the surfaces with shadow rays; "
               "the light they reflect diffusely (albedo = vertex colour, grey 0.5 without colours), bounced up to the "
               "given number of times, is what the grid holds; rays that escape to the sky count zero. Rays are "
               "cast with Embree. Grid vertices inside closed objects or behind walls (their rays reach back faces) "
               "are filled from their valid neighbours (extrapolated along each direction), so that no dark value "
               "leaks onto nearby surfaces. The grid is written as an .ivg file (docs/irradiance-vector-grid.md), beside the current "
               "layer's file unless a path is given; the layers are not changed. A surface point p with normal n is "
               "then shaded with rho / pi &lt;I_n(p), n&gt;, the vectors interpolated trilinearly and by the squared "
               "normal components (the 'Radiance Field' decoration).") +
           kCiteGranier2007Ivg;
}

}  // namespace

std::unique_ptr<Filter> makeComputeIrradianceVectorGridFilter() {
    return std::make_unique<ComputeIrradianceVectorGridFilter>();
}

}  // namespace radml
