// "Out-of-Core Simplification and Normal Map": a PLY scan too large to open is simplified while it
// streams from disk (vertex clustering, Lindstrom 2000) and its points are streamed again into a
// normal map of the simplified mesh (Granier et al. 2007). A thin adapter: parameters in, a call into
// common/outofcore (out_of_core_simplification.h), the simplified mesh added as a new layer with its
// texture coordinates and the map as its texture, log out. The current layer is not read or changed.
#include "out_of_core_plugin.h"

#include "citations.h"
#include "mesh_conversion.h"
#include "output_naming.h"

#include "outofcore/out_of_core_simplification.h"

#include <QDir>
#include <QFileInfo>

#include <memory>

namespace radml {
namespace {

enum BitsChoice { kBits16 = 0, kBits8 = 1 };

// The output base: the parameter when given (output_naming.h), else beside the PLY file, named after
// it + "_ooc".
QString outputBase(const QString& given, const QString& plyPath) {
    const QString label = QFileInfo(plyPath).completeBaseName() + "_ooc";
    if (const QString base = outputBaseFromParameter(given, label); !base.isEmpty()) return base;
    return QDir(QFileInfo(plyPath).absolutePath()).filePath(label);
}

class OutOfCoreSimplificationFilter : public Filter {
public:
    QString name() const override { return "Out-of-Core Simplification and Normal Map"; }
    QString pythonName() const override { return "out_of_core_simplification_and_normal_map"; }
    QString description() const override;
    // MeshLab's "Create New Mesh Layer" class (MeshCreation) alone: the only class whose filters the
    // GUI offers in an empty document, which is where a scan too large to open is simplified.
    int filterClass() const override { return 0x00020; }
    int postconditions() const override { return MeshModel::MM_NONE; }
    bool needsCurrentLayer() const override { return false; }

    RichParameterList parameters(const MeshDocument& md, const MeshModel&) const override {
        return parametersWithoutLayer(md);
    }
    RichParameterList parametersWithoutLayer(const MeshDocument&) const override {
        RichParameterList par;
        addOpenFileParameter(par, "plyFile", "", QStringList() << "*.ply", "PLY scan",
                             "The full-resolution scan, a PLY file (ASCII or binary, triangles or polygons, with or "
                             "without vertex normals). It is read from disk twice at most and never loaded whole: "
                             "it may be larger than the memory.");
        par.addParam(RichInt("targetFaces", 100000, "Target number of triangles",
                             "About how many triangles the simplified mesh has (the clustering grid is chosen for "
                             "it; the result is typically within 20 %)."));
        par.addParam(RichInt("textureSize", 4096, "Texture size",
                             "Width and height of the normal map in texels: a power of two from 16 to 16384."));
        par.addParam(RichInt("gutter", 4, "Gutter (texels)",
                             "Empty texels between any two triangles of the per-triangle atlas (0 to 64; 4 keeps "
                             "two MIP levels from mixing neighbouring triangles). Each triangle needs legs of 2 "
                             "texels plus the gutter: at 4096 x 4096 at most about 1.34 M triangles fit with 0 "
                             "(triangles edge to edge, no texel shared), 684 k with 1, 198 k with 4; the target "
                             "may be at most 80 % of that."));
        par.addParam(RichEnum("bits", kBits16, QStringList() << "16 bit" << "8 bit", "Bits per channel",
                              "16-bit PNG keeps the quantisation error far below a tenth of a degree; 8 bit is about "
                              "0.2 degrees."));
        par.addParam(RichString("outputFile", "", "Output file (optional)",
                                "Path of the normal map (…_normal.png), or an existing folder; empty = beside the PLY "
                                "file, named after it with '_ooc'."));
        return par;
    }

    std::string outOfMemoryAdvice() const override { return "choose a smaller target or texture size"; }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        const QString plyPath = par.getOpenFileName("plyFile").trimmed();
        if (plyPath.isEmpty())
            throw Refusal("Choose the PLY file of the scan (parameter 'PLY scan'). The layers are unchanged.");
        if (QFileInfo(plyPath).isDir())
            throw Refusal("'" + plyPath.toStdString() + "' is a folder, not a PLY file: choose the scan's .ply file "
                          "inside it. The layers are unchanged.");
        if (!QFileInfo(plyPath).isFile())
            throw Refusal("The PLY file " + plyPath.toStdString() +
                          " does not exist: choose an existing file. The layers are unchanged.");
        const int target = par.getInt("targetFaces");
        if (target < 4) throw Refusal("The target number of triangles must be at least 4. The layers are unchanged.");

        rad::OutOfCoreRequest request;
        request.plyPath = plyPath.toStdString();
        request.targetTriangles = std::size_t(target);
        request.textureSize = par.getInt("textureSize");
        request.bits = par.getEnum("bits") == kBits8 ? 8 : 16;
        request.gutterTexels = par.getInt("gutter");
        request.outputBase = outputBase(par.getString("outputFile"), plyPath).toStdString();
        ctx.progress.setPhase(0, 95, "Out-of-core simplification");
        request.progress = ctx.progress.forCore();
        const rad::OutOfCoreReport report = rad::simplifyOutOfCore(request);

        // Everything is written: only now is the document changed.
        ctx.progress.setPhase(95, 100, "Adding the layer");
        rad::RadianceMesh out;
        out.positions = report.mesh.positions;
        out.normals = report.mesh.normals;
        out.faces = report.mesh.faces;
        MeshModel* added = addLayer(ctx.document, QFileInfo(plyPath).completeBaseName() + "_ooc");
        enableLoadedData(*added, importPlainMesh(out, added->cm));
        added->updateDataMask(MeshModel::MM_WEDGTEXCOORD);
        std::size_t f = 0;
        for (CFaceO& face : added->cm.face) {
            for (int k = 0; k < 3; ++k) {
                face.WT(k).U() = report.wedgeUv[6 * f + 2 * k];
                face.WT(k).V() = report.wedgeUv[6 * f + 2 * k + 1];
                face.WT(k).N() = 0;
            }
            ++f;
        }
        setLayerTexture(*added, report.normalMapFile);
        updateBoxAndNormals(*added);

        const rad::ClusteringStats& c = report.clustering;
        ctx.log(formatLine("Out-of-Core Simplification: '%s' (%llu vertices, %llu triangles%s, %s) -> layer '%s': %zu "
                           "triangles, %zu vertices; grid %d x %d x %d cells of %g, %zu occupied; %.2f s (clustering "
                           "%.2f, normal map %.2f, write %.2f)",
                           qUtf8Printable(QFileInfo(plyPath).fileName()), (unsigned long long)report.file.vertexCount,
                           (unsigned long long)report.read.trianglesEmitted,
                           report.read.polygonsTriangulated ? formatLine(", %llu polygons fanned",
                               (unsigned long long)report.read.polygonsTriangulated).c_str() : "",
                           report.normalsFromFile ? "normals from the file" : "area-weighted normals",
                           qUtf8Printable(added->label()), report.mesh.faceCount(), report.mesh.vertexCount(),
                           c.gridCells[0], c.gridCells[1], c.gridCells[2], c.cellSize, c.occupiedCells,
                           report.totalSeconds, report.clusteringSeconds, report.splatSeconds, report.writeSeconds));
        ctx.log(formatLine("Out-of-Core Simplification: normal map %dx%d, %d bit, object space: %zu points splatted, "
                           "%zu of %zu chart texels received points, %zu filled from their triangle; wrote %s, %s",
                           request.textureSize, request.textureSize, request.bits, report.pointsSplatted,
                           report.texelsWithPoints, report.chartTexels, report.chartTexelsFilled,
                           report.normalMapFile.c_str(), report.descriptionFile.c_str()));
        if (report.pointsWithoutNormal > 0)
            ctx.warning(formatLine("Out-of-Core Simplification: %zu points had a zero or invalid normal and were not "
                                   "used in the map.", report.pointsWithoutNormal));
    }
};

QString OutOfCoreSimplificationFilter::description() const {
    return QString(
               "Simplifies a PLY scan that may not fit in memory and bakes its normals into a normal map of the "
               "simplified mesh, without ever loading the scan. Pass 1 streams the file: the vertices' positions "
               "are kept (12 bytes each), and every triangle adds its area-weighted plane quadric to the cells of a "
               "uniform grid that hold its vertices; a triangle whose three vertices fall in three different cells "
               "is kept, and each cell's vertex minimises its quadric (vertex clustering, Lindstrom 2000). The "
               "simplified mesh gets a per-triangle atlas. Pass 2 streams the original points (with the file's "
               "normals, or area-weighted normals of its faces) through a hierarchy of the simplified triangles "
               "(Embree): each point's normal is added to the texel under its nearest simplified point; the texels "
               "average their points, and the empty ones are filled by pull-push diffusion (Granier et al. 2007). "
               "The map is object space, written like 'Bake Normal Map' writes it (&lt;base&gt;_normal.png and "
               "_bake.txt), and the simplified mesh is added as a new layer with the map as its texture. The "
               "current layer, if any, is neither read nor changed: the filter is under Filters > Create New Mesh "
               "Layer and runs in an empty document (or on an empty pymeshlab MeshSet). Malformed "
               "files (truncated, wrong counts, indices out of range, NaN coordinates) are refused with the byte "
               "offset of the problem.") +
           kCiteGranier2007Lindstrom2000;
}

}  // namespace

std::unique_ptr<Filter> makeOutOfCoreSimplificationFilter() { return std::make_unique<OutOfCoreSimplificationFilter>(); }

}  // namespace radml
