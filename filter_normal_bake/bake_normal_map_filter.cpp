// "Bake Normal Map": the full scan's normals (and colours) baked into a texture of the simplified
// mesh (Granier et al. 2007), with LEAN covariance maps for filtered specular highlights (Weber and
// Stamminger). A thin adapter: parameters in, a call into common/bake (normal_map_bake.h), the texture
// coordinates and the texture attached to the layer, log out.
#include "normal_bake_plugin.h"

#include "citations.h"
#include "mesh_conversion.h"
#include "output_naming.h"
#include "usable_normals.h"

#include "bake/normal_map_bake.h"
#include "bake/texture_atlas.h"

#include <QDir>
#include <QFileInfo>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace radml {
namespace {

enum SpaceChoice { kObjectSpace = 0, kTangentSpace = 1 };
enum TangentFrameChoice { kMikkTSpace = 0, kPerFaceFrame = 1 };
enum BitsChoice { kBits16 = 0, kBits8 = 1 };
enum AssignChoice { kAssignNormal = 0, kAssignDiffuse = 1 };

// The layer with the most faces other than the current one: the full scan, usually.
const MeshModel* defaultSource(const MeshDocument& md) {
    const MeshModel* best = nullptr;
    for (const MeshModel* layer : documentMeshes(const_cast<MeshDocument&>(md)))
        if (layer != md.mm() && (!best || layer->cm.fn > best->cm.fn)) best = layer;
    return best ? best : md.mm();
}

// The layer's own texture coordinates as wedge coordinates of the live faces (in the order
// exportPlainMesh writes the faces): its wedge coordinates, else its per-vertex ones; empty when it
// has none (or all are zero, as MeshLab leaves them when it enables the attribute without a
// parametrisation). `kind` says which were used, for the log.
std::vector<float> layerTexCoords(MeshModel& m, const char*& kind) {
    const auto allZero = [](const std::vector<float>& uv) {
        return std::all_of(uv.begin(), uv.end(), [](float c) { return c == 0.0f; });
    };
    if (m.hasDataMask(MeshModel::MM_WEDGTEXCOORD)) {
        std::vector<float> uv = exportWedgeTexCoords(m.cm);
        if (!allZero(uv)) {
            kind = "the target's wedge texture coordinates";
            return uv;
        }
    }
    if (m.hasDataMask(MeshModel::MM_VERTTEXCOORD)) {
        std::vector<float> uv = exportVertexTexCoordsAsWedges(m.cm);
        if (!allZero(uv)) {
            kind = "the target's per-vertex texture coordinates";
            return uv;
        }
    }
    return {};
}

// Output base: the parameter when given (output_naming.h; a folder receives maps named after the
// target), else the target's file name without extension, beside it; the source's directory when the
// target was never saved.
QString outputBase(const QString& given, MeshModel& target, MeshModel& source) {
    QString label = QFileInfo(target.label()).completeBaseName();
    if (label.isEmpty()) label = "baked";
    if (const QString base = outputBaseFromParameter(given, label); !base.isEmpty()) return base;
    const QString targetFile = target.fullName();
    const QString directory = !targetFile.isEmpty() ? QFileInfo(targetFile).absolutePath()
                              : !source.fullName().isEmpty() ? QFileInfo(source.fullName()).absolutePath()
                                                              : QString();
    if (directory.isEmpty()) return QString();
    return QDir(directory).filePath(label);
}

class BakeNormalMapFilter : public Filter {
public:
    QString name() const override { return "Bake Normal Map"; }
    QString pythonName() const override { return "bake_normal_map"; }
    QString description() const override;
    // Texture: MeshLab's GUI (re)loads the layer's textures after the filter.
    int filterClass() const override { return 0x02000; /* Texture */ }
    int postconditions() const override { return MeshModel::MM_WEDGTEXCOORD; }
    bool readsOtherLayers() const override { return true; }

    RichParameterList parameters(const MeshDocument& md, const MeshModel&) const override {
        RichParameterList par;
    const MeshModel* source = defaultSource(md);
        const double diagonal = source ? double(source->cm.bbox.Diag()) : 1.0;
        addMeshParameter(par, "sourceMesh", md, source, "Source mesh (full scan)",
                         "The full-resolution mesh whose normals and colours are baked. The target is the current "
                         "layer.");
        par.addParam(RichInt("textureSize", 2048, "Texture size",
                             "Width and height of the maps in texels: a power of two from 16 to 16384."));
        par.addParam(RichEnum("space", kObjectSpace, QStringList() << "Object space" << "Tangent space", "Normal space",
                              "Object space: the normal in the mesh's coordinates (needed for LEAN maps). Tangent space: "
                              "in the texel's (T, B, N) frame (see 'Tangent frame'), '+Y up' as glTF 2.0 and Blender "
                              "expect."));
        par.addParam(RichEnum("tangentFrame", kMikkTSpace,
                              QStringList() << "MikkTSpace (Blender, glTF, Unity, Unreal)" << "Per-face dP/du (old)",
                              "Tangent frame",
                              "Tangent-space maps only. MikkTSpace (Mikkelsen 2008): the per-vertex tangents and "
                              "bitangent signs every common tool decodes with, interpolated across the triangle, so "
                              "the map shows the scan's shading in Blender, glTF viewers, Unity and Unreal. Per-face "
                              "dP/du: the frame this filter used before (T = dP/du of each face made orthogonal to the "
                              "normal), for maps that must match earlier bakes."));
        par.addParam(RichEnum("bits", kBits16, QStringList() << "16 bit" << "8 bit", "Bits per channel",
                              "16-bit PNG keeps the quantisation error far below a tenth of a degree; 8 bit is about "
                              "0.2 degrees."));
        addAbsoluteOrPercentParameter(par, "maxDistance", 0.0, 0.0, diagonal, "Max ray distance",
                                      "How far the rays search the scan from the target's surface. 0 = automatic: twice "
                                      "the largest distance from the target's vertices and face centres to the scan.");
        par.addParam(RichInt("gutter", 4, "Gutter (texels)",
                             "Empty texels between any two triangles of a generated atlas (at least this many), filled by dilation of each triangle's border."));
        par.addParam(RichBool("newAtlas", false, "Make a per-triangle atlas",
                              "Replace the target's texture coordinates (wedge or per-vertex) by a per-triangle "
                              "atlas; done anyway when the target has none. The atlas cuts every triangle apart: "
                              "for a chart-based layout, parametrize first with MeshLab's own filters."));
        par.addParam(RichBool("diffuse", true, "Bake the vertex colours too",
                              "Write the scan's vertex colours at the same points into a diffuse map (when the scan has "
                              "vertex colours)."));
        par.addParam(RichBool("lean", true, "Write LEAN maps",
                              "Second moments of the normals about the averaged normal per MIP level 1..K (object-space "
                              "maps only)."));
        par.addParam(RichBool("gltf", false, "Also write a glTF 2.0 file (.glb)",
                              "Write <base>.glb beside the maps: the target with its texture coordinates, normals and "
                              "MikkTSpace tangents (Mikkelsen 2008), the tangent-space normal map (baked in MikkTSpace "
                              "whatever the space chosen above), the diffuse map, and with LEAN maps a metallic-roughness "
                              "texture whose roughness grows with the spread of the scan's normals (Toksvig 2005, from "
                              "the LEAN moments of Olano and Baker 2010). Opens in Blender, three.js, Unity, Unreal."));
        par.addParam(RichFloat("gltfRoughness", 0.5f, "glTF base roughness",
                               "glTF perceptual roughness of a surface whose normals do not vary (0 mirror, 1 matte); "
                               "the LEAN spread adds to it."));
        par.addParam(RichEnum("assign", kAssignNormal, QStringList() << "Normal map" << "Diffuse map",
                              "Layer texture", "Which map becomes the layer's texture."));
        par.addParam(RichString("outputFile", "", "Output file (optional)",
                                "Path of the normal map (…_normal.png), or an existing folder to write the maps into "
                                "(named after the target); empty = beside the target mesh, named after it."));
        return par;
    }

    std::string outOfMemoryAdvice() const override { return "choose a smaller texture size"; }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        MeshDocument& md = ctx.document;
        MeshModel* target = md.mm();
        MeshModel* source = meshParameter(par, md, "sourceMesh");
        if (!target || !source) throw Refusal("Open the simplified mesh (current layer) and the full scan (source) first.");
        if (target == source)
            throw rad::BakeInputError("The source and the target are the same layer: choose the full-resolution scan "
                                      "as the source, with the simplified mesh as the current layer.");
        if (target->cm.fn == 0)
            throw rad::BakeInputError("The target layer '" + target->label().toStdString() +
                                      "' has no faces: a normal map is baked onto triangles.");

        ExportChoice geometryOnly;
        geometryOnly.colors = geometryOnly.quality = geometryOnly.radiance = geometryOnly.transfer = false;
        rad::RadianceMesh targetPlain, sourcePlain;
        std::string why;
        if (!exportPlainMesh(target->cm, geometryOnly, targetPlain, why) ||
            !exportPlainMesh(source->cm, geometryOnly, sourcePlain, why))
            throw rad::BakeInputError(why);
        makeNormalsUsable(ctx, targetPlain.positions, targetPlain.faces, targetPlain.normals,
                          target->label().toStdString());
        if (!sourcePlain.normals.empty())  // (none: the core computes them from the faces)
            makeNormalsUsable(ctx, sourcePlain.positions, sourcePlain.faces, sourcePlain.normals,
                              source->label().toStdString());
        rad::TriangleMesh targetMesh{targetPlain.positions, targetPlain.normals, targetPlain.faces};
        rad::TriangleMesh sourceMesh{sourcePlain.positions, sourcePlain.normals, sourcePlain.faces};

        std::vector<float> sourceColors;
        const bool sourceHasColors = source->hasDataMask(MeshModel::MM_VERTCOLOR);
        if (par.getBool("diffuse") && sourceHasColors) {
            sourceColors.reserve(3 * sourceMesh.vertexCount());
            for (const CVertexO& v : source->cm.vert)
                if (!v.IsD())
                    for (int k = 0; k < 3; ++k) sourceColors.push_back(v.cC()[k] / 255.0f);
        }
        const char* uvKind = "";
        std::vector<float> existingUv = par.getBool("newAtlas") ? std::vector<float>() : layerTexCoords(*target, uvKind);

        rad::NormalMapBakeRequest request;
        request.target = &targetMesh;
        request.targetWedgeUv = &existingUv;
        request.source = &sourceMesh;
        request.sourceColors = sourceColors.empty() ? nullptr : &sourceColors;
        request.textureSize = par.getInt("textureSize");
        request.space = par.getEnum("space") == kTangentSpace ? rad::NormalSpace::Tangent : rad::NormalSpace::Object;
        request.tangentFrame = par.getEnum("tangentFrame") == kPerFaceFrame ? rad::TangentFrame::PerFaceUvDerivative
                                                                            : rad::TangentFrame::MikkTSpace;
        request.bits = par.getEnum("bits") == kBits8 ? 8 : 16;
        request.maxRayDistance = absoluteOrPercentParameter(par, "maxDistance");
        request.gutterTexels = par.getInt("gutter");
        request.bakeDiffuse = par.getBool("diffuse");
        request.writeLean = par.getBool("lean");
        request.writeGltf = par.getBool("gltf");
        request.gltfBaseRoughness = float(par.getFloat("gltfRoughness"));
        request.outputBase = outputBase(par.getString("outputFile"), *target, *source).toStdString();
        ctx.progress.setPhase(0, 100, "Baking normal map");
        request.progress = ctx.progress.forCore();

        const rad::NormalMapBakeReport report = rad::bakeNormalMapFiles(request);

        // Everything is written: only now is the layer changed.
        target->updateDataMask(MeshModel::MM_WEDGTEXCOORD);
        std::size_t face = 0;
        for (CFaceO& f : target->cm.face) {
            if (f.IsD()) continue;
            for (int k = 0; k < 3; ++k) {
                f.WT(k).U() = report.wedgeUv[6 * face + 2 * k];
                f.WT(k).V() = report.wedgeUv[6 * face + 2 * k + 1];
                f.WT(k).N() = 0;
            }
            ++face;
        }
        const bool assignDiffuse = par.getEnum("assign") == kAssignDiffuse && !report.diffuseMapFile.empty();
        const std::string& assigned = assignDiffuse ? report.diffuseMapFile : report.normalMapFile;
        setLayerTexture(*target, assigned);

        const rad::NormalBakeResult& stats = report.bake;
        const double chart = std::max<double>(1.0, double(stats.chartTexels));
        ctx.log(formatLine("Bake Normal Map: %s %dx%d, %d bit, %s, from '%s' (%zu faces) onto '%s' (%zu faces) in %.2f s "
            "(bake %.2f: coverage %.2f, scene %.2f, rays %.2f; fill %.2f, LEAN %.2f, write %.2f; processor time %.2f s)",
            request.space == rad::NormalSpace::Object ? "object space"
            : request.tangentFrame == rad::TangentFrame::MikkTSpace ? "tangent space (MikkTSpace, Mikkelsen 2008, +Y up)"
                                                                    : "tangent space (per-face dP/du frame, +Y up)",
            request.textureSize,
            request.textureSize, request.bits,
            report.atlasGenerated ? qUtf8Printable(QString("per-triangle atlas (cells of %1 texels)").arg(report.atlasCellSize))
                                  : uvKind,
            qUtf8Printable(source->label()), sourceMesh.faceCount(), qUtf8Printable(target->label()),
            targetMesh.faceCount(), report.totalSeconds, report.bakeSeconds, report.bake.coverageSeconds,
            report.bake.sceneSeconds, report.bake.raySeconds, report.fillSeconds, report.leanSeconds,
            report.writeSeconds, report.cpuSeconds));
        ctx.log(formatLine("Bake Normal Map: %zu chart texels: %.2f %% ray hits, %.2f %% closest-point fallbacks, %zu holes filled by "
            "pull-push; %zu gutter texels dilated; max ray distance %g",
            stats.chartTexels, 100.0 * stats.rayHits / chart, 100.0 * stats.closestPointFallbacks / chart,
            report.holesFilled, report.gutterTexelsDilated, double(stats.maxRayDistance)));
        const double hit = double(stats.rayHits) / chart;
        if (hit < 0.5)
            ctx.warning(formatLine("Bake Normal Map: only %.1f %% of the texels' rays met the source; the others "
                                   "took the closest point or were filled. Check that the scan covers the whole "
                                   "target at the same place and scale, or raise the maximum distance.",
                                   100.0 * hit));
        ctx.log(formatLine("Bake Normal Map: wrote %s%s%s%s", report.normalMapFile.c_str(),
            report.diffuseMapFile.empty() ? "" : (", " + report.diffuseMapFile).c_str(),
            report.leanFile.empty() ? "" : (", " + report.leanFile).c_str(),
            (", " + report.descriptionFile).c_str()));
        if (!report.gltfFile.empty())
            ctx.log(formatLine("Bake Normal Map: wrote %s (glTF 2.0: %zu vertices after splitting at UV seams, MikkTSpace "
                               "tangent-space normal map%s%s)", report.gltfFile.c_str(), report.gltfVertices,
                               report.diffuseMapFile.empty() ? "" : ", diffuse map",
                               report.leanFile.empty() ? "" : ", roughness from the LEAN moments (Toksvig 2005)"));
        if (request.space == rad::NormalSpace::Tangent && stats.madeUpTangentCorners > 0)
            ctx.log(formatLine("Bake Normal Map: %zu triangle corners have no UV derivative around them (zero-area UV "
                               "triangles); they got a tangent orthogonal to the normal, which other tools will not "
                               "reproduce there.", stats.madeUpTangentCorners));
        if (par.getBool("diffuse") && !sourceHasColors)
            ctx.log(formatLine("Bake Normal Map: the source has no vertex colours, so no diffuse map was written."));
        if (par.getBool("lean") && request.space == rad::NormalSpace::Tangent)
            ctx.log(formatLine("Bake Normal Map: LEAN maps filter object-space normals (Weber and Stamminger); bake in object space to get them."));
}
};

QString BakeNormalMapFilter::description() const {
    return QString(
               "Bakes the normals of a full-resolution scan (the source layer) into a normal map of the current, "
               "simplified layer (the target), so that the simplified mesh keeps the scan's shading. If the target "
               "has no texture coordinates (or you ask for it), a per-triangle atlas is made: faces in pairs in the "
               "square cells of a grid, as 'Parametrization: Trivial Per-Triangle' does, with a gutter of at least "
               "the given number of empty texels between any two triangles. This atlas cuts every triangle apart (no "
               "charts): for a layout with charts, run one of MeshLab's parametrization filters (for example "
               "'Parametrization: Voronoi Atlas') or use the scan's own UVs; wedge and per-vertex coordinates are "
               "kept. Existing coordinates must lie in [0, 1] and must not overlap. For every texel, the nearer "
               "hit on the scan along the target's interpolated normal, forward or backward within the maximum "
               "distance (Embree: one ray over the whole segment settles most texels, two from the surface point "
               "the others), gives the interpolated scan normal, and when nothing is hit the closest point of the "
               "scan does. Object-space maps store the normal; tangent-space maps store it in the texel's "
               "frame: by default MikkTSpace (Mikkelsen 2008), the frame Blender, glTF 2.0, Unity and Unreal decode "
               "with (per-vertex tangents and bitangent signs computed from the mesh's UVs, interpolated; "
               "B = sign N x T, negative for mirrored UVs), stored as the exact inverse of n = normalize(x T + y B + z N); "
               "or the older per-face frame (T = dP/du of the face made orthogonal to N). Both are '+Y up' (OpenGL, "
               "glTF, Blender: green grows with v); the _bake.txt file says which frame was used. Encoding (x + 1) / 2 in 8 or 16 bits. "
               "Texels the bake could not fill are filled by pull-push diffusion, the gutters by dilation of the "
               "charts' border texels, and the rest of the texture too, so mip-mapping never mixes in an empty "
               "texel. Also written: the scan's vertex colours as a diffuse map, and LEAN second moments for MIP "
               "levels 1 and up (object space only) in an OpenEXR file. Files: &lt;base&gt;_normal.png, "
               "_diffuse.png, _lean.exr, _bake.txt (and &lt;base&gt;.glb on request: glTF 2.0 with the MikkTSpace "
               "tangents and maps), beside the target mesh unless a file is given. The map is "
               "assigned as the layer's texture; the 'Radiance Field' decoration shows it with Blinn-Phong or LEAN "
               "shading.") +
           kCiteGranier2007WeberStamminger + kCiteMikkelsen2008;
}

}  // namespace

std::unique_ptr<Filter> makeBakeNormalMapFilter() { return std::make_unique<BakeNormalMapFilter>(); }

}  // namespace radml
