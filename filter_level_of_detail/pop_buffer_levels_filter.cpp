// "Extract Level of Detail (POP Buffer)": levels of the POP buffer (Limper et al. 2013) of the current
// layer written as new layers, texture coordinates corrected by Alg. 1 of Weber & Stamminger, so the
// stateless LOD can be saved and used outside MeshLab. A thin adapter: parameters in, common/lod
// (pop_buffer.h, texcoord_correction.h, pop_level.h), new layers and log out.
#include "level_of_detail_plugin.h"

#include "citations.h"
#include "mesh_conversion.h"

#include "lod/pop_buffer.h"
#include "lod/pop_level.h"
#include "lod/texcoord_correction.h"

#include <QFileInfo>
#include <QRegularExpression>

#include <algorithm>
#include <memory>
#include <set>
#include <vector>

namespace radml {
namespace {

enum class UvKind { None, Wedge, PerVertex };

bool allZero(const std::vector<float>& uv) {
    return std::all_of(uv.begin(), uv.end(), [](float c) { return c == 0.0f; });
}

// The layer's texture coordinates as wedges of its live faces (wedge ones first, else per-vertex);
// none when MeshLab merely enabled the attribute (all zero).
std::vector<float> layerTexCoords(MeshModel& m, UvKind& kind) {
    kind = UvKind::None;
    if (m.hasDataMask(MeshModel::MM_WEDGTEXCOORD)) {
        std::vector<float> uv = exportWedgeTexCoords(m.cm);
        if (!allZero(uv)) {
            kind = UvKind::Wedge;
            return uv;
        }
    }
    if (m.hasDataMask(MeshModel::MM_VERTTEXCOORD)) {
        std::vector<float> uv = exportVertexTexCoordsAsWedges(m.cm);
        if (!allZero(uv)) {
            kind = UvKind::PerVertex;
            return uv;
        }
    }
    return {};
}

// "8", "4,6,8", "4 6 8", "4-8" or a mix: the sorted distinct levels.
std::vector<int> parseLevels(const QString& text) {
    const QString trimmed = text.trimmed();
    const QString fix = QString(" Give levels from %1 to %2 as '8', '4,6,8' or '4-8'.").arg(rad::kPopMinLevel).arg(rad::kPopMaxLevel);
    if (trimmed.isEmpty()) throw Refusal("No level given." + fix);
    std::set<int> levels;
    for (const QString& part : trimmed.split(QRegularExpression("[,;\\s]+"), Qt::SkipEmptyParts)) {
        const QStringList ends = part.split('-');
        bool ok1 = false, ok2 = false;
        const int a = ends.value(0).toInt(&ok1);
        const int b = ends.size() == 2 ? ends[1].toInt(&ok2) : a;
        if (ends.size() > 2 || !ok1 || (ends.size() == 2 && !ok2) || b < a)
            throw Refusal("'" + part + "' is not a level nor a range of levels." + fix);
        if (a < rad::kPopMinLevel || b > rad::kPopMaxLevel)
            throw Refusal(QString("Level %1 does not exist: POP-buffer levels are %2 to %3 (the grid of level L has 2^L "
                                  "cells per axis).").arg(a < rad::kPopMinLevel ? a : b).arg(rad::kPopMinLevel).arg(rad::kPopMaxLevel) + fix);
        for (int l = a; l <= b; ++l) levels.insert(l);
    }
    return std::vector<int>(levels.begin(), levels.end());
}

class PopBufferLevelsFilter : public Filter {
public:
    QString name() const override { return "Extract Level of Detail (POP Buffer)"; }
    QString pythonName() const override { return "extract_level_of_detail_pop_buffer"; }
    QString description() const override;
    int filterClass() const override { return 0x00004; /* Remeshing */ }
    int postconditions() const override { return MeshModel::MM_NONE; }

    RichParameterList parameters(const MeshDocument&, const MeshModel&) const override {
        RichParameterList par;
        par.addParam(RichString("levels", "8", "Levels",
                                "The POP-buffer levels to write, each as a new layer: one level ('8'), a list "
                                "('4,6,8') or a range ('4-8'), from 1 (2 cells per axis) to 16 (65536 cells per axis)."));
        par.addParam(RichBool("correction", true, "Correct texture coordinates",
                              "Shift each snapped vertex's texture coordinates by the inverse of its averaged tangent "
                              "space times its move (Weber & Stamminger, Alg. 1), so the texture stays in place "
                              "instead of sliding with the vertex. Needs wedge or per-vertex texture coordinates."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        MeshDocument& md = ctx.document;
        MeshModel& layer = ctx.mesh();
        const std::vector<int> levels = parseLevels(ctx.parameters.getString("levels"));
        const bool correct = ctx.parameters.getBool("correction");

        ExportChoice choice;
        choice.normals = choice.quality = choice.radiance = choice.transfer = false;
        choice.colors = layer.hasDataMask(MeshModel::MM_VERTCOLOR);
        rad::RadianceMesh plain;
        std::string why;
        if (!exportPlainMesh(layer.cm, choice, plain, why)) throw Refusal(why);
        rad::TriangleMesh mesh{plain.positions, {}, plain.faces};
        UvKind kind = UvKind::None;
        const std::vector<float> uv = layerTexCoords(layer, kind);
        if (correct && kind == UvKind::None)
            throw Refusal("The layer '" + layer.label() + "' has no texture coordinates to correct: parametrize it "
                          "first (e.g. 'Parametrization: Trivial Per-Triangle'), or turn off 'Correct texture "
                          "coordinates'. The layers are unchanged.");
        // Texture index of every live face (wedge coordinates) or vertex (per-vertex ones), kept on copy.
        std::vector<short> faceTexture, vertexTexture;
        for (const CFaceO& f : layer.cm.face)
            if (!f.IsD()) faceTexture.push_back(kind == UvKind::Wedge ? f.cWT(0).N() : 0);
        for (const CVertexO& v : layer.cm.vert)
            if (!v.IsD()) vertexTexture.push_back(kind == UvKind::PerVertex ? v.cT().N() : 0);

        // Everything is computed before any layer is added: a refusal leaves the document as it was.
        ctx.progress.setPhase(0, 40, "Ordering triangles (POP buffer)");
        const rad::PopBuffer pop = rad::buildPopBuffer(mesh, ctx.progress.forCore());
        rad::TexCoordDerivatives derivatives;
        if (correct) {
            ctx.progress.setPhase(40, 70, "Tangent spaces");
            derivatives = rad::computeTexCoordDerivatives(mesh, uv, ctx.progress.forCore());
        }
        ctx.progress.setPhase(70, 90, "Evaluating levels");
        std::vector<rad::PopLevelMesh> results;
        for (int level : levels) {
            rad::PopLevelRequest request;
            request.mesh = &mesh;
            request.pop = &pop;
            request.level = level;
            request.wedgeUv = kind == UvKind::None ? nullptr : &uv;
            request.correction = correct ? &derivatives : nullptr;
            results.push_back(rad::evaluatePopLevel(request));
            if (results.back().mesh.faceCount() == 0)
                ctx.warning(formatLine("Level %d has no triangle: every triangle of '%s' collapses on a grid of %u cells "
                                       "per axis; choose a finer level.", level, qUtf8Printable(layer.label()), 1u << level));
        }

        ctx.progress.setPhase(90, 100, "Adding layers");
        const QString base = QFileInfo(layer.label()).completeBaseName();
        for (std::size_t i = 0; i < results.size(); ++i) {
            const rad::PopLevelMesh& lod = results[i];
            rad::RadianceMesh out;
            out.positions = lod.mesh.positions;
            out.faces = lod.mesh.faces;
            if (!plain.colors.empty())
                for (std::uint32_t s : lod.sourceVertex)
                    out.colors.insert(out.colors.end(), plain.colors.begin() + 4 * s, plain.colors.begin() + 4 * s + 4);
            MeshModel* added = addLayer(md, QString("%1_pop%2").arg(base).arg(levels[i]));
            enableLoadedData(*added, importPlainMesh(out, added->cm));
            if (kind == UvKind::Wedge) {
                added->updateDataMask(MeshModel::MM_WEDGTEXCOORD);
                std::size_t f = 0;
                for (CFaceO& face : added->cm.face) {
                    for (int k = 0; k < 3; ++k) {
                        face.WT(k).U() = lod.wedgeUv[6 * f + 2 * k];
                        face.WT(k).V() = lod.wedgeUv[6 * f + 2 * k + 1];
                        face.WT(k).N() = faceTexture[lod.sourceFace[f]];
                    }
                    ++f;
                }
            } else if (kind == UvKind::PerVertex) {
                // Per-vertex coordinates: every corner of a vertex is the same texture vertex, so any
                // corner gives the vertex's corrected coordinates.
                added->updateDataMask(MeshModel::MM_VERTTEXCOORD);
                std::size_t c = 0;
                for (CFaceO& face : added->cm.face)
                    for (int k = 0; k < 3; ++k, ++c) {
                        CVertexO* v = face.V(k);
                        v->T().U() = lod.wedgeUv[2 * c];
                        v->T().V() = lod.wedgeUv[2 * c + 1];
                        v->T().N() = vertexTexture[lod.sourceVertex[lod.mesh.faces[c]]];
                    }
            }
            if (kind != UvKind::None) copyLayerTextures(layer, *added);
            updateBoxAndNormals(*added);
            ctx.log(formatLine("Extract Level of Detail (POP Buffer): level %d (grid of %u cells per axis) -> layer '%s': "
                               "%zu of %zu triangles, %zu vertices, %zu moved (at most %.4g), texture coordinates %s",
                               levels[i], 1u << levels[i], qUtf8Printable(added->label()), lod.mesh.faceCount(),
                               mesh.faceCount(), lod.mesh.vertexCount(), lod.movedVertices, lod.maxDisplacement,
                               kind == UvKind::None ? "none (the layer has none)"
                               : correct ? (kind == UvKind::Wedge ? "(wedge) corrected" : "(per vertex) corrected")
                                         : (kind == UvKind::Wedge ? "(wedge) copied" : "(per vertex) copied")));
        }
        const std::size_t never = pop.levelEnd[rad::kPopNeverDrawn] - pop.levelEnd[rad::kPopMaxLevel];
        if (never > 0)
            ctx.log(formatLine("Extract Level of Detail (POP Buffer): %zu triangles collapse even at level 16 (two corners "
                               "in the same 1/65536 of the bounding box) and appear in no level.", never));
        if (correct && derivatives.withoutTangentSpace > 0)
            ctx.warning(formatLine("Extract Level of Detail (POP Buffer): %zu of %zu texture vertices have only triangles "
                                   "degenerate in space or in texture space; their coordinates are not corrected.",
                                   derivatives.withoutTangentSpace, derivatives.textureVertices));
        ctx.progress(100, "Done");
    }
};

QString PopBufferLevelsFilter::description() const {
    return QString(
               "Writes levels of detail of the current layer as new layers, as a POP buffer (Limper et al. 2013) "
               "draws them: at level L every vertex is snapped to the centre of its cell in a grid of 2^L cells per "
               "axis over the bounding box, and a triangle is kept when its three vertices are in three different "
               "cells (it has collapsed otherwise). The triangles kept at level L are the first ones of the "
               "POP-buffer order, so a renderer needs no state between frames. Snapping slides the texture along "
               "the surface; with the correction on, each vertex's texture coordinates move by the inverse of its "
               "tangent space, averaged over its triangles of the same texture chart, times its move (Weber & "
               "Stamminger, eq. 1-3 and Alg. 1): exact on a plane mapped linearly. Wedge or per-vertex texture "
               "coordinates are written as the layer has them; vertex colours and textures are kept. The vertices "
               "of a cell are not merged, since their corrected texture coordinates differ. Layers are "
               "named &lt;layer&gt;_pop&lt;L&gt;; the current layer is not changed.") +
           kCiteLimper2013WeberStamminger;
}

}  // namespace

std::unique_ptr<Filter> makePopBufferLevelsFilter() { return std::make_unique<PopBufferLevelsFilter>(); }

}  // namespace radml
