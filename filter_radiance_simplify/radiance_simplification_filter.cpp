// "Radiance: Radiance-Aware Simplification": the adapter between a MeshLab layer and the
// simplification core (common/simplify/radiance_simplification.h). The layer is exported, simplified
// aside as a progressive mesh, and replaced only when everything succeeded; extra levels of detail
// are extracted from the same recording into new layers.
#include "radiance_simplify_plugin.h"

#include "citations.h"
#include "extra_blocks_attribute.h"

#include "mesh_conversion.h"
#include "radiance_attribute.h"

#include "simplify/progressive_mesh.h"
#include "simplify/radiance_simplification.h"

#include <QElapsedTimer>
#include <QFileInfo>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace radml {
namespace {

// Indices are part of the scripts' interface (pymeshlab and .mlx pass them): new metrics go at the end.
enum MetricChoice { kMetricRadiance = 0, kMetricLightField2010 = 1, kMetricColor = 2, kMetricGeometry = 3, kMetricRadianceQuadric = 4 };

// "0.5 0.25, 0.1" -> ratios in (0, 1), largest first; throws Refusal otherwise.
std::vector<double> parseRatios(const QString& text) {
    std::vector<double> ratios;
    QString cleaned = text;
    cleaned.replace(',', ' ').replace(';', ' ');
    for (const QString& item : cleaned.split(QChar(' '), Qt::SkipEmptyParts)) {
        bool ok = false;
        double r = item.toDouble(&ok);
        if (ok && item.endsWith('%')) ok = false;
        if (!ok || !(r > 0.0 && r < 1.0))
            throw Refusal(QString("Level-of-detail ratio '%1' is not a number in (0, 1): write e.g. '0.5 0.25 0.1'.").arg(item));
        ratios.push_back(r);
    }
    std::sort(ratios.begin(), ratios.end(), std::greater<double>());
    ratios.erase(std::unique(ratios.begin(), ratios.end()), ratios.end());
    return ratios;
}

class RadianceSimplificationFilter : public Filter {
public:
    QString name() const override { return "Radiance: Radiance-Aware Simplification"; }
    QString pythonName() const override { return "radiance_radiance_aware_simplification"; }
    QString description() const override;
    int filterClass() const override { return 0x00004; /* Remeshing */ }
    int postconditions() const override { return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE; }

    RichParameterList parameters(const MeshDocument&, const MeshModel& m) const override {
        RichParameterList par;
        const rad::EdgeCollapseOptions defaults;
        par.addParam(RichEnum("metric", kMetricRadianceQuadric,
                              QStringList() << "Radiance error (Vanhoey et al. 2015, eq. 7)"
                                            << "Light-field quadric (Vanhoey et al. 2010)"
                                            << "Colour QEM on the mean colour (Garland-Heckbert 1998)"
                                            << "Geometry only (memoryless QEM)"
                                            << "Radiance quadric (Hoppe 1999; default)",
                              "Metric",
                              "What a collapse costs. Default: the accumulating radiance quadric (Hoppe 1999, Garland and "
                              "Heckbert 1998): distances to every original face's plane plus the L2 distance between "
                              "radiance functions, summed over all the original faces a vertex stands for; it places the "
                              "new vertex and its radiance function optimally. The references: the radiance error of "
                              "Vanhoey et al. 2015 (eq. 7, memoryless: area-weighted L2 distance over the hemisphere "
                              "between the functions before and after), its 2010 precursor (quadric on the "
                              "coefficients), the extended colour QEM on each function's mean colour, or geometry alone."));
        par.addParam(RichEnum("collapse", 1, QStringList() << "Half-edge collapse (Vanhoey et al. 2015, sec. 4.1)" << "Full edge collapse (sec. 4.3; default)",
                              "Collapse",
                              "Half-edge: a vertex merges into a neighbour, positions and functions are never "
                              "interpolated. Full: the new vertex goes to the optimal position and gets a new radiance "
                              "function (radiance quadric: the quadric's optimum; eq. 7: interpolated along the edge, "
                              "spherical harmonics only)."));
        const int faces = m.cm.fn;
        par.addParam(RichInt("targetFaces", std::max(faces / 2, 0), "Target number of faces",
                             "The face count of the simplified layer (used when the percentage is 0)."));
        par.addParam(RichFloat("targetPercentage", 0.0f, "Target percentage (0..1)",
                               "If non-zero, the target as a fraction of the current face count."));
        par.addParam(RichString("lodLevels", "", "Extra levels of detail",
                                "Fractions of the face count, e.g. '0.5 0.25 0.1': each becomes a new layer "
                                "'<name>_LOD<percent>' extracted from the same run (progressive mesh, Vanhoey et al. 2015, sec. 4.5). Empty: "
                                "none."));
        par.addParam(RichFloat("geometryWeight", float(defaults.geometryWeight), "Geometry weight",
                               "Weight of the geometric error: the memoryless QEM for the eq. 7, 2010 and colour metrics "
                               "(Vanhoey et al. 2015, sec. 4.4: 1 % geometry, 99 % radiance); the radiance quadric's "
                               "plane terms (scale-free: positions normalised by the bounding box)."));
        par.addParam(RichFloat("attributeWeight", float(defaults.attributeWeight), "Metric weight",
                               "Weight of the chosen metric (lambda of the 2010 light-field metric). For the radiance "
                               "quadric, its radiance term (normalised by the field's RMS radiance) weighs "
                               "attributeWeight x 1.5e-6 against geometryWeight: at the defaults, 0.015 % of the geometry's, "
                               "the balance measured best in images (docs/design-notes.md)."));
        par.addParam(RichBool("preserveBoundary", defaults.preserveBoundary, "Preserve boundary",
                              "Keep the mesh's boundary (holes, a scan's open base) where it is. Off: boundary "
                              "vertices move and disappear like the others."));
        par.addParam(RichBool("collapseAlongBoundary", defaults.collapseAlongBoundary, "Collapse along the boundary",
                              "With 'Preserve boundary' and the radiance quadric's full collapses: boundary vertices "
                              "may still merge with a neighbour along the boundary, the survivor taking the boundary "
                              "vertex's place, priced by boundary planes (Garland & Heckbert 1997), so that a long "
                              "boundary does not keep its full resolution at coarse levels. Off, and for the other "
                              "metrics: a boundary vertex never moves or disappears."));
        par.addParam(RichInt("minValence", 0, "Minimum valence", "Forbid collapses leaving a vertex with fewer neighbours (0: no bound; Vanhoey et al. 2010 use 4)."));
        par.addParam(RichInt("maxValence", 0, "Maximum valence", "Forbid collapses leaving a vertex with more neighbours (0: no bound; Vanhoey et al. 2010 use 11)."));
        par.addParam(RichFloat("maxNormalChange", float(defaults.maxNormalDeviationDegrees), "Maximum normal change (degrees)",
                               "A collapse may not turn any remaining face's normal by more than this."));
        par.addParam(RichBool("lazy", defaults.lazyRepricing, "Lazy queue updates",
                              "Re-price vertices touched by a collapse only when they reach the front of the queue "
                              "(several times faster; slightly different order)."));
        par.addParam(RichString("progressiveFile", "", "Progressive mesh file",
                                "If set (a path ending in .rpm), the collapse sequence is written there, with the "
                                "original mesh beside it as <name>_base.rply (docs/progressive-mesh-format.md)."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        MeshDocument& md = ctx.document;
        MeshModel& m = ctx.mesh();
        QElapsedTimer timer;
        timer.start();
        rad::RadianceSimplificationOptions options;
        switch (par.getEnum("metric")) {
            case kMetricRadiance: options.metric = rad::SimplificationMetric::Radiance; break;
            case kMetricLightField2010: options.metric = rad::SimplificationMetric::LightField2010; break;
            case kMetricColor: options.metric = rad::SimplificationMetric::ColorQuadric; break;
            case kMetricRadianceQuadric: options.metric = rad::SimplificationMetric::RadianceQuadric; break;
            default: options.metric = rad::SimplificationMetric::GeometryOnly; break;
        }
        options.collapse.kind = par.getEnum("collapse") == 1 ? rad::CollapseKind::Full : rad::CollapseKind::HalfEdge;
        options.collapse.geometryWeight = par.getFloat("geometryWeight");
        options.collapse.attributeWeight = par.getFloat("attributeWeight");
        options.collapse.preserveBoundary = par.getBool("preserveBoundary");
        options.collapse.collapseAlongBoundary = par.getBool("collapseAlongBoundary");
        options.collapse.minValence = par.getInt("minValence");
        options.collapse.maxValence = par.getInt("maxValence");
        options.collapse.maxNormalDeviationDegrees = par.getFloat("maxNormalChange");
        options.collapse.lazyRepricing = par.getBool("lazy");
        // (The core validates the options: simplifyRadianceMesh refuses them with a sentence.)
        const std::vector<double> lodRatios = parseRatios(par.getString("lodLevels"));
        const QString progressivePath = par.getString("progressiveFile").trimmed();
        if (!progressivePath.isEmpty() && !progressivePath.endsWith(".rpm", Qt::CaseInsensitive)) {
            throw Refusal("The progressive mesh file must end in .rpm.");
        }

        rad::RadianceMesh plain;
        std::string problem;
        ExportChoice choice;
        choice.transfer = false;  // not used here (and not required to cover every vertex)
        choice.radiance = hasRadiance(m.cm);
        choice.extraBlocks = true;  // the blocks kept from a .rply follow their vertices through the collapses
        std::vector<std::string> leftOut;
        if (!exportPlainMesh(m.cm, choice, plain, problem, &leftOut)) {
            throw Refusal(QString::fromStdString(problem));
        }
        for (const std::string& line : leftOut) ctx.warning("The simplified mesh goes without some data: " + line);
        if (!choice.radiance && options.metric != rad::SimplificationMetric::GeometryOnly) {
            throw Refusal(QString::fromStdString(missingRadianceAdvice()) +
                           " Or choose the geometry-only metric.");
        }
        const std::size_t faces = plain.faceCount();
        const double percentage = par.getFloat("targetPercentage");
        if (!(percentage >= 0.0 && percentage < 1.0)) {
            throw Refusal(formatLine("The target percentage must lie in [0, 1), got %g.", percentage));
        }
        const long long targetFaces =
            percentage > 0.0 ? static_cast<long long>(std::floor(percentage * faces)) : par.getInt("targetFaces");
        // (A layer without faces is refused by the core's input check, with a message saying so.)
        if (faces > 0 && (targetFaces < 0 || static_cast<std::size_t>(targetFaces) >= faces)) {
            throw Refusal(QString("The target of %1 faces is not below the layer's %2 faces: choose a smaller target.")
                               .arg(targetFaces)
                               .arg(faces));
        }
        std::size_t coarsest = static_cast<std::size_t>(targetFaces);
        for (double r : lodRatios) coarsest = std::min(coarsest, static_cast<std::size_t>(std::floor(r * faces)));
        options.collapse.targetFaceCount = coarsest;
        ctx.progress.setPhase(0, 95, "Radiance-aware simplification");
        options.collapse.progress = ctx.progress.forCore();

        // Everything is computed aside; the layers change only once the simplification succeeded. The
        // core checks the input first (manifold, duplicates, degenerate faces...) and throws
        // SimplificationError with a message for the log.
        const rad::RadianceSimplificationResult result = rad::simplifyRadianceMesh(std::move(plain), options);
        const rad::ProgressiveRadianceMesh& progressive = result.progressive;
        const std::size_t targetSteps = progressive.stepsForFaceCount(targetFaces);
        const rad::RadianceMesh target = progressive.extract(targetSteps);
        const double targetCost = targetSteps > 0 ? progressive.steps[targetSteps - 1].cost : 0.0;
        std::vector<std::pair<double, rad::RadianceMesh>> levels;
        for (double r : lodRatios)
            levels.emplace_back(r, progressive.extract(progressive.stepsForFaceCount(std::floor(r * faces))));
        // Order of the changes, so that a failure leaves the document and the folder as they were:
        // the .rpm and its base staged under temporary names, the LOD layers added (runFilter removes
        // them on a failure), the files put in place together, and the current layer replaced last.
        rad::AtomicFileSet progressiveFiles;
        if (!progressivePath.isEmpty()) {
            const QString base = progressivePath.left(progressivePath.size() - 4) + "_base.rply";
            // A failure (AtomicFileError, naming the file) reaches the user through runFilter.
            rad::stageProgressiveMesh(progressivePath.toStdString(), base.toStdString(), progressive, progressiveFiles);
        }

        ctx.progress.setPhase(97, 100, "Updating layers");
        const QString label = QFileInfo(m.label()).completeBaseName();
        for (const auto& [ratio, level] : levels) {
            MeshModel* layer = addLayer(md, QString("%1_LOD%2").arg(label).arg(100.0 * ratio));
            enableLoadedData(*layer, importPlainMesh(level, layer->cm));
            updateBoxAndNormals(*layer);
            ctx.log(formatLine("Level of detail %.4g %%: %zu vertices, %zu faces (layer '%s')", 100.0 * ratio, level.vertexCount(),
                level.faceCount(), qUtf8Printable(layer->label())));
        }
        progressiveFiles.commit();
        const int mask = importPlainMesh(target, m.cm);
        enableLoadedData(m, mask);
        updateBoxAndNormals(m);
        ctx.progress(100, "Done");
        if (result.facesRepeatingAVertexRemoved > 0 || result.duplicateFacesRemoved > 0 || result.zeroAreaFaces > 0)
            ctx.log(formatLine("Input defects handled: %zu faces repeating a vertex removed, %zu duplicate faces "
                               "removed (later copies of a triangle), %zu zero-area faces simplified like the others",
                               result.facesRepeatingAVertexRemoved, result.duplicateFacesRemoved, result.zeroAreaFaces));
        if (result.nonManifoldEdges > 0)
            ctx.log(formatLine("Non-manifold edges: %zu (more than two faces), kept as they are with their vertices",
                               result.nonManifoldEdges));
        if (result.boundaryEdges > 0)
            ctx.log(formatLine("Open mesh: %zu boundary edges, %s", result.boundaryEdges,
                               !options.collapse.preserveBoundary     ? "free to move like the other edges"
                               : result.collapse.collapsedAlongBoundary ? "kept in place, their vertices merged along the boundary"
                                                                        : "kept in place with all their vertices"));
        const rad::EdgeCollapseResult& r = result.collapse;
        ctx.log(formatLine("Simplified %zu -> %zu faces (%zu vertices) with the %s metric, %s collapse: %zu collapses in %.2f s "
            "(%zu to this layer), cost of its last collapse %.4g; coarsest level %zu faces, last cost %.4g (%s)%s",
            faces, target.faceCount(), target.vertexCount(), rad::describe(options.metric).c_str(),
            options.collapse.kind == rad::CollapseKind::Full ? "full edge" : "half-edge", r.collapses, result.seconds,
            targetSteps, targetCost, r.finalFaceCount, r.lastCost, rad::describe(r.stop).c_str(),
            progressivePath.isEmpty() ? "" : qUtf8Printable(", progressive mesh written to " + progressivePath)));
        if (target.faceCount() > static_cast<std::size_t>(targetFaces))
            ctx.warning(formatLine("Stopped at %zu faces above the target of %lld: %s (boundary, valence or normal "
                                      "constraints forbid further collapses).",
                target.faceCount(), targetFaces, rad::describe(r.stop).c_str()));
        ctx.log(formatLine("Total time %.2f s", timer.elapsed() / 1000.0));
}
};

QString RadianceSimplificationFilter::description() const {
    return QString(
               "Simplifies the current mesh by iterative edge collapse so that what is rendered stays close "
               "to the original (Vanhoey et al. 2015, sec. 4). Default metric: the accumulating radiance "
               "quadric (Hoppe 1999; Garland and Heckbert 1998): each vertex carries the sum, over the original "
               "faces it stands for, of their squared plane distances and of the squared L2 distance between "
               "radiance functions (coefficients in the basis's orthonormalised L2 space, interpolated over "
               "each face), so error accumulated by earlier collapses is never forgotten; a full collapse puts "
               "the new vertex at the planes' optimum and gives it the quadric's optimal radiance function "
               "(PB and SH alike). With the paper's own metric (eq. 7), a collapse costs w_G E_G + w_R E, with E_G the "
               "memoryless quadric error (planes of the faces around the edge) and E the radiance error of "
               "eq. 7 of Vanhoey et al. 2015: for a half-edge collapse v0 -> v1, the sum over the new triangles of their area times "
               "the squared L2 distance, over v0's hemisphere, between v0's reflected radiance function and "
               "the function the triangle extrapolates to v0's position (eq. 4-6); for a full edge collapse "
               "the new vertex sits at the QEM-optimal position with its function interpolated along the "
               "edge, and the error is summed at both old positions (sec. 4.3; spherical harmonics only). "
               "Default weights 1 % / 99 % as in sec. 4.4. Baselines in the same engine: the 2010 "
               "light-field quadric (Vanhoey et al. 2010), the extended colour QEM of Garland and Heckbert (1998) on "
               "the functions' mean colours, and geometry alone.<br>"
               "Collapses keep the surface a 2-manifold (link condition), never flip a face, optionally "
               "keep the boundary and valences within bounds. The whole collapse sequence is recorded "
               "(progressive mesh, sec. 4.5): extra levels of detail become new layers, and the sequence "
               "can be saved as a .rpm file and replayed with the simplify_radiance tool. The mesh must be "
               "a 2-manifold triangle mesh (no edge shared by more than two faces; the filter says which "
               "cleaning filter to run otherwise); faces repeating a vertex and repeated triangles are removed, "
               "zero-area faces are simplified like the others, and the log counts them.") +
           kCiteVanhoey2015;
}

}  // namespace

std::unique_ptr<Filter> makeRadianceSimplificationFilter() { return std::make_unique<RadianceSimplificationFilter>(); }

}  // namespace radml
