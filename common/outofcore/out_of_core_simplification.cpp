#include "outofcore/out_of_core_simplification.h"

#include "bake/bake_description.h"
#include "bake/normal_map_bake.h"
#include "bake/texture_atlas.h"
#include "geometry/coordinate_range.h"
#include "io/atomic_file.h"
#include "outofcore/streamed_normal_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>

namespace rad {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The atlas is made with gutter + 1 (texture_atlas.h counts the texel distance between charts, the
// request the empty texels between them). Refused in the request's own terms, with what would fit.
void checkAtlasCapacity(std::size_t triangles, const OutOfCoreRequest& request, const char* whose) {
    const std::size_t capacity = perTriangleAtlasCapacity(request.textureSize, request.gutterTexels + 1);
    if (triangles <= capacity) return;
    int size = request.textureSize;
    while (size < 16384 && perTriangleAtlasCapacity(size, request.gutterTexels + 1) < triangles) size *= 2;
    int gutter = request.gutterTexels;
    while (gutter > 0 && perTriangleAtlasCapacity(request.textureSize, gutter + 1) < triangles) --gutter;
    std::ostringstream s;
    s << "A " << request.textureSize << " x " << request.textureSize << " map holds at most " << capacity
      << " triangles in the per-triangle atlas with a " << request.gutterTexels << "-texel gutter, and "
      << triangles << " are needed (" << whose << "); ";
    if (perTriangleAtlasCapacity(size, request.gutterTexels + 1) >= triangles)
        s << "use a texture of " << size << " x " << size;
    else
        s << "even 16384 x 16384 is too small: lower the target";
    if (perTriangleAtlasCapacity(request.textureSize, gutter + 1) >= triangles)
        s << ", or a gutter of " << gutter;
    s << ", or a target of at most " << capacity * 4 / 5;
    throw BakeInputError(s.str());
}

// The box of the vertices some triangle uses (flag 1 in `used`).
void usedBox(const std::vector<float>& positions, const std::vector<std::uint8_t>& used, double lo[3], double hi[3]) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<double>::infinity();
        hi[a] = -std::numeric_limits<double>::infinity();
    }
    for (std::size_t v = 0; v < used.size(); ++v)
        if (used[v])
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], double(positions[3 * v + a]));
                hi[a] = std::max(hi[a], double(positions[3 * v + a]));
            }
}

}  // namespace

void checkOutOfCoreRequest(const OutOfCoreRequest& request) {
    const std::string sizeProblem = textureSizeProblem(request.textureSize);
    if (!sizeProblem.empty()) throw BakeInputError(sizeProblem);
    if (request.bits != 8 && request.bits != 16)
        throw BakeInputError("The normal map is written with 8 or 16 bits per channel, not " + std::to_string(request.bits) + ".");
    if (request.gutterTexels < 0 || request.gutterTexels > 64)
        throw BakeInputError("The gutter must be 0 to 64 texels wide (4 keeps two MIP levels clean; 0 packs the "
                             "triangles edge to edge, about twice as many as 1).");
    if (!(request.cellSize >= 0.0) || !std::isfinite(request.cellSize))
        throw BakeInputError("The cell size must be 0 (use the target triangle count) or a positive distance.");
    if (request.cellSize == 0.0 && request.targetTriangles < 4)
        throw BakeInputError("The target triangle count must be at least 4 (or give a cell size).");
    if (request.outputBase.empty())
        throw BakeInputError("No output file name: give the base name of the normal map (e.g. /some/folder/scan, "
                             "which writes scan_normal.png and scan_bake.txt).");
    if (std::string problem = outputPathProblem(request.outputBase + "_normal.png"); !problem.empty())
        throw BakeInputError(problem);
    if (request.plyPath.empty()) throw BakeInputError("No PLY file given: choose the scan's .ply file.");
    PlyStreamReader reader(request.plyPath);
    if (reader.info().faceCount == 0)
        throw BakeInputError(request.plyPath + " has no faces: the out-of-core simplification needs a triangle mesh "
                             "(reconstruct a surface from the point cloud first).");
    // The atlas must fit the map for the mesh the target gives (up to 25 % more triangles than asked
    // for: refused now rather than after a pass over the whole file).
    if (request.cellSize == 0.0) checkAtlasCapacity(request.targetTriangles + request.targetTriangles / 4, request,
                                                     "the target plus up to 25 %");
}

OutOfCoreReport simplifyOutOfCore(const OutOfCoreRequest& request) {
    const Clock::time_point start = Clock::now();
    checkOutOfCoreRequest(request);
    OutOfCoreReport report;
    PlyStreamReader reader(request.plyPath);
    report.file = reader.info();
    report.normalsFromFile = report.file.hasNormals;

    // Pass 1: positions kept (12 bytes per vertex), triangles streamed into the grid's quadrics.
    // Which vertices the triangles use is only known at the end of the pass: when unused ones
    // stretch the box the grid was placed on, the pass is run again on the used ones alone.
    Clock::time_point phase = Clock::now();
    const std::size_t vertexCount = std::size_t(report.file.vertexCount);
    std::vector<std::uint8_t> referenced(vertexCount, 0);
    std::vector<float> accumulatedNormals;
    std::unique_ptr<VertexClustering> clustering;
    for (int attempt = 0; attempt < 2; ++attempt) {
        ClusteringOptions options;
        options.targetTriangles = request.targetTriangles;
        options.cellSize = request.cellSize;
        if (attempt == 1) options.referenced = &referenced;
        clustering = std::make_unique<VertexClustering>(options);
        clustering->reserveVertices(vertexCount);
        accumulatedNormals.clear();
        if (!report.normalsFromFile) accumulatedNormals.assign(3 * vertexCount, 0.0f);
        const double progressEnd = attempt == 0 ? 0.45 : 0.5;
        report.read = reader.read(
            [&](const PlyVertexChunk& chunk) { clustering->addVertices(chunk.positions, chunk.count); },
            [&](const PlyTriangleChunk& chunk) {
                if (attempt == 0)
                    for (std::size_t i = 0; i < 3 * chunk.count; ++i) referenced[chunk.indices[i]] = 1;
                clustering->addTriangles(chunk.indices, chunk.count,
                                         accumulatedNormals.empty() ? nullptr : accumulatedNormals.data());
            },
            false, progressRange(request.progress, attempt == 0 ? 0.0 : 0.45, progressEnd));
        if (attempt == 1) break;
        const std::vector<float>& positions = clustering->positions();
        double allLo[3], allHi[3], usedLo[3], usedHi[3];
        if (!referencedBox(positions.data(), vertexCount, nullptr, 0, allLo, allHi)) break;
        usedBox(positions, referenced, usedLo, usedHi);
        // Far beyond kMaxCoordinateMagnitude or too small: refused before any file is written
        // (the map lost every point at 1e20 and put all of them in one texel at 1e-30).
        if (std::string problem = coordinateRangeProblem(positions.data(), vertexCount); !problem.empty())
            throw BakeInputError(problem);
        if (std::string problem = boxScaleProblem(usedLo, usedHi, "The scan"); !problem.empty())
            throw BakeInputError(problem);
        bool sameBox = true;
        for (int a = 0; a < 3; ++a) sameBox = sameBox && allLo[a] == usedLo[a] && allHi[a] == usedHi[a];
        if (sameBox) break;
    }
    report.mesh = clustering->finish();
    report.clustering = clustering->stats();
    report.clusteringSeconds = secondsSince(phase);
    if (report.mesh.faceCount() == 0) {
        std::ostringstream why;
        why << "Nothing is left of the mesh at this resolution: every triangle fell into fewer than three grid cells "
               "of " << report.clustering.cellSize << " (the grid spans the box of the triangles, "
            << report.clustering.gridCells[0] << " x " << report.clustering.gridCells[1] << " x "
            << report.clustering.gridCells[2] << " cells). If a few triangles lie far from the rest, they stretch the "
               "grid: delete them (e.g. MeshLab's \"Remove Isolated pieces (wrt Diameter)\") and export again; "
               "otherwise raise the target triangle count or lower the cell size.";
        throw BakeInputError(why.str());
    }
    reportProgress(request.progress, 0.5, "laying out the texture");

    checkAtlasCapacity(report.mesh.faceCount(), request, "the simplified mesh");
    PerTriangleAtlas atlas = makePerTriangleAtlas(report.mesh.faceCount(), request.textureSize, request.gutterTexels + 1);
    report.wedgeUv = std::move(atlas.wedgeUv);

    // Pass 2: the original points through the simplified mesh's hierarchy.
    phase = Clock::now();
    NormalSplatter splatter(report.mesh, report.wedgeUv, request.textureSize);
    const ProgressCallback splatProgress = progressRange(request.progress, 0.5, 0.9);
    std::vector<float>& positions = clustering->positions();
    // Points no triangle uses are not part of the surface: left out of the map.
    std::vector<float> usedPositions, usedNormals;
    const auto splatUsed = [&](std::uint64_t first, const float* p, const float* n, std::size_t count) {
        usedPositions.clear();
        usedNormals.clear();
        for (std::size_t i = 0; i < count; ++i) {
            if (!referenced[std::size_t(first) + i]) continue;
            usedPositions.insert(usedPositions.end(), p + 3 * i, p + 3 * i + 3);
            usedNormals.insert(usedNormals.end(), n + 3 * i, n + 3 * i + 3);
        }
        splatter.splat(usedPositions.data(), usedNormals.data(), usedPositions.size() / 3);
    };
    if (report.normalsFromFile) {
        positions = {};  // the file gives them again with the normals
        reader.read([&](const PlyVertexChunk& chunk) { splatUsed(chunk.firstIndex, chunk.positions, chunk.normals, chunk.count); },
                    {}, true, splatProgress);
    } else {
        // Normalised in the splatter; the accumulated sums are area-weighted normals.
        const std::size_t n = positions.size() / 3, block = 1 << 18;
        for (std::size_t first = 0; first < n; first += block) {
            splatUsed(first, &positions[3 * first], &accumulatedNormals[3 * first], std::min(block, n - first));
            reportProgress(splatProgress, double(first + block) / double(n), "streaming the points into the map");
        }
    }
    positions = {};
    accumulatedNormals = {};
    report.splatSeconds = secondsSince(phase);
    reportProgress(request.progress, 0.9, "filling the map");
    phase = Clock::now();
    StreamedNormalMap map = splatter.finish(request.gutterTexels);
    report.fillSeconds = secondsSince(phase);
    report.pointsSplatted = map.pointsSplatted;
    report.pointsWithoutNormal = map.pointsWithoutNormal;
    report.chartTexels = map.chartTexels;
    report.texelsWithPoints = map.texelsWithPoints;
    report.chartTexelsFilled = map.chartTexelsFilled;
    reportProgress(request.progress, 0.95, "writing the map");

    // Written as an in-core bake's files, under temporary names renamed together at the end.
    phase = Clock::now();
    report.normalMapFile = request.outputBase + "_normal.png";
    report.descriptionFile = request.outputBase + "_bake.txt";
    // Unique temporaries (two runs to the same base never share one), put in place together.
    AtomicFileSet files;
    const std::string mapPart = files.add(report.normalMapFile), descriptionPart = files.add(report.descriptionFile);
    {
        writeNormalMapPng(mapPart, map.normals, map.size, map.size, request.bits);
        writeBakeDescription(
            descriptionPart,
            {{"space", "object"},
             {"size", std::to_string(map.size)},
             {"bits", std::to_string(request.bits)},
             {"encoding", request.bits == 16 ? "(x + 1) / 2 * 65535" : "(x + 1) / 2 * 255"},
             {"uv", "per-triangle atlas"},
             {"gutter_texels", std::to_string(request.gutterTexels)},
             {"normal_map", std::filesystem::path(report.normalMapFile).filename().string()},
             {"method", "out-of-core: vertex clustering (Lindstrom 2000), original points splatted into the texel of "
                        "their nearest simplified triangle, pull-push filled (Granier et al. 2007)"},
             {"source_vertices", std::to_string(report.file.vertexCount)},
             {"source_triangles", std::to_string(report.read.trianglesEmitted)},
             {"source_normals", report.normalsFromFile ? "file" : "area-weighted from the faces"},
             {"chart_texels", std::to_string(map.chartTexels)},
             {"texels_with_points", std::to_string(map.texelsWithPoints)},
             {"holes_filled", std::to_string(map.chartTexelsFilled)}});
        files.commit();
    }
    report.writeSeconds = secondsSince(phase);
    report.totalSeconds = secondsSince(start);
    if (request.progress) request.progress(1.0, "done");
    return report;
}

}  // namespace rad
