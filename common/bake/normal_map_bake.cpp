#include "bake/normal_map_bake.h"

#include "bake/bake_description.h"
#include "bake/lean_maps.h"
#include "bake/map_filling.h"
#include "bake/texture_atlas.h"
#include "bake/toksvig_roughness.h"
#include "geometry/coordinate_range.h"
#include "image/image_io.h"
#include "io/atomic_file.h"
#include "io/gltf_writer.h"
#include "memory/available_memory.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iomanip>
#include <sstream>

namespace rad {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

bool sameMesh(const TriangleMesh& a, const TriangleMesh& b) {
    return &a == &b || (a.positions == b.positions && a.faces == b.faces);
}

// 8-bit RGB of colours in [0, 1] (clamped; not finite: 0).
Image8 colorImage(const std::vector<float>& colors, int width, int height) {
    Image8 image(width, height);
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        const float c = std::isfinite(colors[i]) ? std::clamp(colors[i], 0.0f, 1.0f) : 0.0f;
        image.rgb[i] = static_cast<std::uint8_t>(std::lround(c * 255.0f));
    }
    return image;
}

std::string preciseText(double value) {
    std::ostringstream text;
    text << std::setprecision(9) << value;
    return text.str();
}

std::string fileName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

}  // namespace

BakedMapFillCounts fillBakedMap(std::vector<float>& values, int width, int height, std::vector<std::uint8_t> valid,
                                const std::vector<std::uint8_t>& chart, int rings) {
    BakedMapFillCounts counts;
    counts.holes = fillByPullPush(values.data(), 3, width, height, valid, chart.data());
    counts.gutter = dilateValidTexels(values.data(), 3, width, height, valid, rings);
    counts.background = fillByPullPush(values.data(), 3, width, height, valid, nullptr);
    return counts;
}

void writeNormalMapPng(const std::string& path, const std::vector<float>& normals, int width, int height, int bits) {
    const std::size_t count = std::size_t(width) * height * 3;
    if (bits == 16) {
        std::vector<std::uint16_t> codes(count);
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(count); ++i) codes[i] = encodeNormal16(normals[i]);
        writePng16(path, width, height, 3, codes.data());
    } else {
        Image8 image(width, height);
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(count); ++i) image.rgb[i] = encodeNormal8(normals[i]);
        writePng(path, image);
    }
}

std::size_t estimatedBakeBytes(const NormalMapBakeRequest& request) {
    const bool withColor = request.bakeDiffuse && request.sourceColors != nullptr;
    const bool withLean = request.writeLean && request.space == NormalSpace::Object;
    const bool gltfNeedsSecondMap = request.writeGltf && !(request.space == NormalSpace::Tangent &&
                                                           request.tangentFrame == TangentFrame::MikkTSpace);
    // glTF: a second normal map (12 bytes per texel) and the PNGs in memory (a few bytes).
    const double perTexel = 39.0 + (withColor ? 12.0 : 0.0) + (withLean ? 20.0 : 0.0) +
                            (request.writeGltf ? 6.0 : 0.0) + (gltfNeedsSecondMap ? 12.0 : 0.0);
    const double texels = double(std::max(request.textureSize, 0)) * double(std::max(request.textureSize, 0));
    return static_cast<std::size_t>(1.1 * perTexel * texels);
}

void checkNormalMapBakeRequest(const NormalMapBakeRequest& request) {
    if (!request.target || request.target->faceCount() == 0)
        throw BakeInputError("The target layer has no faces: a normal map is baked onto the triangles of a (simplified) "
                             "mesh. Select the simplified mesh as the current layer.");
    if (!request.source || request.source->faceCount() == 0)
        throw BakeInputError("The source layer has no faces: bake from the full-resolution scan as a triangle mesh "
                             "(reconstruct a surface from a point cloud first).");
    if (sameMesh(*request.target, *request.source))
        throw BakeInputError("The source and the target are the same mesh: choose the full-resolution scan as the "
                             "source and the simplified mesh as the target (current layer).");
    const std::string targetProblem = request.target->validate();
    if (!targetProblem.empty()) throw BakeInputError("The target mesh is not usable: " + targetProblem);
    const std::string sourceProblem = request.source->validate();
    if (!sourceProblem.empty()) throw BakeInputError("The source mesh is not usable: " + sourceProblem);
    // Rays are cast between the two: both within the range and scale Embree computes with.
    for (const auto& [mesh, what] : {std::make_pair(request.target, "The target layer"),
                                     std::make_pair(request.source, "The source layer")}) {
        const std::string scale = sceneScaleProblem(mesh->positions.data(), mesh->vertexCount(), mesh->faces.data(),
                                                    mesh->faceCount(), what);
        if (!scale.empty()) throw BakeInputError(scale);
    }
    if (!request.target->hasNormals())
        throw BakeInputError("The target has no vertex normals: run {{Re-Compute Vertex Normals}} on it first.");
    std::size_t badNormals = 0;
    for (std::size_t i = 0; i < request.target->faces.size(); ++i) {
        const float* n = &request.target->normals[3 * std::size_t(request.target->faces[i])];
        if (!(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 1e-12f)) ++badNormals;
    }
    if (badNormals > 0)
        throw BakeInputError("The target has zero vertex normals (the rays leave along them): run "
                             "{{Re-Compute Vertex Normals}} on it first.");
    const std::string sizeProblem = textureSizeProblem(request.textureSize);
    if (!sizeProblem.empty()) throw BakeInputError(sizeProblem);
    const std::size_t limit = request.memoryLimitBytes > 0 ? request.memoryLimitBytes : availableMemoryBytes();
    const std::size_t needed = estimatedBakeBytes(request);
    if (limit > 0 && needed > limit) {
        NormalMapBakeRequest smaller = request;
        while (smaller.textureSize > 16 && estimatedBakeBytes(smaller) > limit) smaller.textureSize /= 2;
        throw BakeInputError("A " + std::to_string(request.textureSize) + " x " + std::to_string(request.textureSize) +
                             " bake needs about " + describeBytes(double(needed)) + " of memory and " +
                             describeBytes(double(limit)) + " are available: choose a texture size of " +
                             std::to_string(smaller.textureSize) + " or less (or bake without the LEAN or diffuse "
                             "maps), or close other programs.");
    }
    if (request.bits != 8 && request.bits != 16)
        throw BakeInputError("The normal map is written with 8 or 16 bits per channel, not " +
                             std::to_string(request.bits) + ".");
    if (request.writeGltf && !(request.gltfBaseRoughness >= 0.0f && request.gltfBaseRoughness <= 1.0f))
        throw BakeInputError("The glTF base roughness must lie in [0, 1] (glTF's perceptual roughness); it is " +
                             preciseText(request.gltfBaseRoughness) + ".");
    if (request.gutterTexels < 1 || request.gutterTexels > 64)
        throw BakeInputError("The gutter must be 1 to 64 texels wide (4 keeps two MIP levels clean).");
    if (!std::isfinite(request.maxRayDistance) || request.maxRayDistance < 0.0f)
        throw BakeInputError("The maximum ray distance must be 0 (automatic) or a positive distance; it is " +
                             preciseText(request.maxRayDistance) + ".");
    if (request.outputBase.empty())
        throw BakeInputError("No output file name: the maps are written beside the mesh; save the mesh first or "
                             "give an output file.");
    if (std::string problem = outputPathProblem(request.outputBase + "_normal.png"); !problem.empty())
        throw BakeInputError(problem);
    if (request.sourceColors && request.sourceColors->size() != request.source->positions.size())
        throw BakeInputError("The source colours do not match the source vertices (3 values per vertex expected).");
    if (request.targetWedgeUv && !request.targetWedgeUv->empty()) {
        if (request.targetWedgeUv->size() != 6 * request.target->faceCount())
            throw BakeInputError("The target's texture coordinates do not match its faces (3 per face expected).");
        const std::string layoutProblem =
            checkUvLayout(request.targetWedgeUv->data(), request.target->faceCount(), request.textureSize).problem();
        if (!layoutProblem.empty()) throw BakeInputError(layoutProblem);
    }
}

namespace {

// What the request asks to bake and write besides the normal map.
struct MapsAsked {
    int size = 0;
    bool withColor = false;          // a diffuse map: asked for, and the source has colours
    bool withLean = false;           // the LEAN moments
    bool gltfFromSecondMap = false;  // the glTF needs a MikkTSpace map beside the requested one
};

MapsAsked mapsAskedBy(const NormalMapBakeRequest& request) {
    MapsAsked asked;
    asked.size = request.textureSize;
    asked.withColor = request.bakeDiffuse && request.sourceColors != nullptr;
    // LEAN filters object-space normals (Weber and Stamminger, sec. 3.3): a tangent-space bake writes none.
    asked.withLean = request.writeLean && request.space == NormalSpace::Object;
    asked.gltfFromSecondMap = request.writeGltf && !(request.space == NormalSpace::Tangent &&
                                                     request.tangentFrame == TangentFrame::MikkTSpace);
    return asked;
}

// The target's own texture coordinates, or a per-triangle atlas made for the bake.
void chooseWedgeUv(const NormalMapBakeRequest& request, NormalMapBakeReport& report) {
    if (request.targetWedgeUv && !request.targetWedgeUv->empty()) {
        report.wedgeUv = *request.targetWedgeUv;
        return;
    }
    // gutterTexels counts the EMPTY texels between two charts; the atlas's gutter is the index
    // distance between texels of two charts, one more.
    PerTriangleAtlas atlas = makePerTriangleAtlas(request.target->faceCount(), request.textureSize,
                                                  request.gutterTexels + 1);
    report.wedgeUv = std::move(atlas.wedgeUv);
    report.atlasGenerated = true;
    report.atlasCellSize = atlas.cellSize;
}

NormalBakeOptions rayBakeOptions(const NormalMapBakeRequest& request, const MapsAsked& asked) {
    NormalBakeOptions options;
    options.width = options.height = asked.size;
    options.space = request.space;
    options.tangentFrame = request.tangentFrame;
    options.maxRayDistance = request.maxRayDistance > 0.0f ? request.maxRayDistance : 0.0f;
    options.bakeColor = asked.withColor;
    options.alsoMikkTSpace = asked.gltfFromSecondMap;
    options.keepTangents = asked.withLean;
    options.progress = progressRange(request.progress, 0.0, 0.75);
    return options;
}

// Closest points alone (no ray hit at all) are a far-away or foreign source, not a bake.
void refuseBakeWithoutHits(const NormalBakeResult& baked) {
    if (baked.chartTexels > 0 && baked.rayHits == 0)
        throw BakeInputError("No ray from the target met the source within the ray distance (" +
                             preciseText(baked.maxRayDistance) + "): the two layers do not overlap. The full scan "
                             "and the simplified mesh must be at the same place and scale (check the layers' "
                             "transformations, and apply them with Matrix: Freeze Current Matrix), or raise the "
                             "maximum distance.");
}

// Holes, gutters and background of every baked map filled; the direction maps made unit again.
void fillBakedMaps(const NormalMapBakeRequest& request, const MapsAsked& asked, NormalBakeResult& baked,
                   NormalMapBakeReport& report) {
    const int size = asked.size;
    const BakedMapFillCounts normalFill = fillBakedMap(baked.normals, size, size, baked.valid, baked.chart, request.gutterTexels);
    normalizeTexelVectors(baked.normals.data(), baked.normals.size() / 3);
    report.holesFilled = normalFill.holes;
    report.gutterTexelsDilated = normalFill.gutter;
    report.backgroundTexelsFilled = normalFill.background;
    if (asked.withLean) {
        fillBakedMap(baked.tangents, size, size, baked.valid, baked.chart, request.gutterTexels);
        normalizeTexelVectors(baked.tangents.data(), baked.tangents.size() / 3);
    }
    if (asked.withColor) fillBakedMap(baked.colors, size, size, baked.valid, baked.chart, request.gutterTexels);
    if (asked.gltfFromSecondMap) {
        fillBakedMap(baked.mikkTSpaceNormals, size, size, baked.valid, baked.chart, request.gutterTexels);
        normalizeTexelVectors(baked.mikkTSpaceNormals.data(), baked.mikkTSpaceNormals.size() / 3);
    }
}

// The glTF binary: the target with its MikkTSpace normal map (8 bit), and the diffuse and
// roughness maps when baked. Sets report.gltfVertices.
std::vector<unsigned char> buildBakeGlb(const NormalMapBakeRequest& request, const MapsAsked& asked,
                                        const NormalBakeResult& baked, const LeanMaps& lean,
                                        NormalMapBakeReport& report) {
    const std::vector<float>& tangentMap = asked.gltfFromSecondMap ? baked.mikkTSpaceNormals : baked.normals;
    Image8 normalImage(asked.size, asked.size);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(normalImage.rgb.size()); ++i)
        normalImage.rgb[i] = encodeNormal8(tangentMap[i]);
    GltfMesh mesh;
    mesh.positions = request.target->positions.data();
    mesh.normals = request.target->normals.data();
    mesh.vertexCount = request.target->vertexCount();
    mesh.faces = request.target->faces.data();
    mesh.faceCount = request.target->faceCount();
    mesh.wedgeUv = report.wedgeUv.data();
    mesh.cornerTangents = baked.cornerTangents.data();
    mesh.normalTexturePng = encodePng(normalImage);
    if (asked.withColor) mesh.baseColorTexturePng = encodePng(colorImage(baked.colors, asked.size, asked.size));
    // Roughness from the finest LEAN level (MIP level 1, half the map's size): Toksvig 2005.
    if (asked.withLean && !lean.moments.empty()) {
        mesh.metallicRoughnessTexturePng = encodePng(metallicRoughnessFromLean(lean.moments[0], request.gltfBaseRoughness, 0.0f));
        mesh.roughnessFactor = 1.0f;
    } else {
        mesh.roughnessFactor = request.gltfBaseRoughness;
    }
    mesh.metallicFactor = 0.0f;
    mesh.name = std::filesystem::path(request.outputBase).filename().string();
    mesh.generator = "radiance-tools Bake Normal Map (MikkTSpace, Mikkelsen 2008)";
    std::vector<unsigned char> glb = buildGlb(mesh);
    report.gltfVertices = gltfVertexCount(mesh);
    return glb;
}

void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path);
}

// The lines of <base>_bake.txt: how the maps were made and how to decode them.
std::vector<std::pair<std::string, std::string>> bakeDescriptionLines(const NormalMapBakeRequest& request,
                                                                      const MapsAsked& asked,
                                                                      const NormalBakeResult& baked,
                                                                      const NormalMapBakeReport& report) {
    std::vector<std::pair<std::string, std::string>> lines = {
        {"space", request.space == NormalSpace::Object ? "object" : "tangent"},
        {"size", std::to_string(asked.size)},
        {"bits", std::to_string(request.bits)},
        {"encoding", request.bits == 16 ? "(x + 1) / 2 * 65535" : "(x + 1) / 2 * 255"},
        {"uv", report.atlasGenerated ? "per-triangle atlas" : "target's wedge coordinates"},
        {"gutter_texels", std::to_string(request.gutterTexels)},
        {"max_ray_distance", preciseText(baked.maxRayDistance)},
        {"normal_map", fileName(report.normalMapFile)}};
    if (request.space == NormalSpace::Tangent) {
        if (request.tangentFrame == TangentFrame::MikkTSpace) {
            lines.push_back({"tangent_frame", "mikktspace"});
            lines.push_back({"tangent_frame_note",
                             "MikkTSpace (Mikkelsen 2008) per-corner tangents and signs, interpolated, not "
                             "renormalised; B = sign * cross(N, T); n = normalize(x T + y B + z N): as "
                             "Blender, glTF 2.0, Unity and Unreal decode"});
        } else {
            lines.push_back({"tangent_frame", "per-face-dpdu"});
            lines.push_back({"tangent_frame_note",
                             "per face: T = dP/du orthogonalised against the interpolated unit normal N, "
                             "B = s * cross(N, T), s = -1 for mirrored UVs (not MikkTSpace)"});
        }
        lines.push_back({"green_channel", "+Y up (OpenGL, glTF 2.0, Blender): green grows towards increasing v"});
    }
    if (asked.withColor) lines.push_back({"diffuse_map", fileName(report.diffuseMapFile)});
    if (request.writeGltf) {
        lines.push_back({"gltf", fileName(report.gltfFile)});
        lines.push_back({"gltf_note", "glTF 2.0 binary: normalTexture in MikkTSpace tangent space (8 bit, +Y up), "
                                      "TANGENT per vertex" + std::string(asked.withLean ? ", metallicRoughnessTexture from "
                                      "the LEAN moments of MIP level 1 (Toksvig 2005 style)" : "")});
    }
    if (asked.withLean) {
        lines.push_back({"lean_moments", fileName(report.leanFile)});
        lines.push_back({"lean_levels", std::to_string(report.leanLevels)});
    }
    lines.push_back({"chart_texels", std::to_string(baked.chartTexels)});
    lines.push_back({"ray_hits", std::to_string(baked.rayHits)});
    lines.push_back({"closest_point_fallbacks", std::to_string(baked.closestPointFallbacks)});
    lines.push_back({"holes_filled", std::to_string(report.holesFilled)});
    return lines;
}

// Every file of the bake, written under temporary names and put in place together at the end
// (all or none); their names into the report.
void writeBakeFiles(const NormalMapBakeRequest& request, const MapsAsked& asked, const NormalBakeResult& baked,
                    const LeanMaps& lean, NormalMapBakeReport& report) {
    AtomicFileSet files;
    report.normalMapFile = request.outputBase + "_normal.png";
    // The EXR is compressed on OpenEXR's threads while this one writes the PNG (zlib, one thread).
    std::future<void> leanWritten;
    if (asked.withLean) {
        report.leanFile = request.outputBase + "_lean.exr";
        const std::string leanPath = files.add(report.leanFile);
        leanWritten = std::async(std::launch::async, [&lean, leanPath] { writeLeanMoments(leanPath, lean); });
    }
    writeNormalMapPng(files.add(report.normalMapFile), baked.normals, asked.size, asked.size, request.bits);
    if (asked.withColor) {
        report.diffuseMapFile = request.outputBase + "_diffuse.png";
        writePng(files.add(report.diffuseMapFile), colorImage(baked.colors, asked.size, asked.size));
    }
    if (request.writeGltf) {
        report.gltfFile = request.outputBase + ".glb";
        const std::vector<unsigned char> glb = buildBakeGlb(request, asked, baked, lean, report);
        writeBytes(files.add(report.gltfFile), glb);
    }
    if (leanWritten.valid()) leanWritten.get();  // rethrows a write error
    report.descriptionFile = request.outputBase + "_bake.txt";
    writeBakeDescription(files.add(report.descriptionFile), bakeDescriptionLines(request, asked, baked, report));
    files.commit();
}

// The report keeps the bake's statistics, not its maps.
void dropMaps(NormalBakeResult& baked) {
    baked.normals.clear();
    baked.normals.shrink_to_fit();
    baked.tangents.clear();
    baked.tangents.shrink_to_fit();
    baked.colors.clear();
    baked.colors.shrink_to_fit();
    baked.mikkTSpaceNormals.clear();
    baked.mikkTSpaceNormals.shrink_to_fit();
}

}  // namespace

NormalMapBakeReport bakeNormalMapFiles(const NormalMapBakeRequest& request) {
    const Clock::time_point start = Clock::now();
    const std::clock_t cpuStart = std::clock();
    checkNormalMapBakeRequest(request);
    NormalMapBakeReport report;
    chooseWedgeUv(request, report);
    const MapsAsked asked = mapsAskedBy(request);
    const NormalBakeOptions options = rayBakeOptions(request, asked);

    Clock::time_point phase = Clock::now();
    NormalBakeResult baked = bakeNormalMap(*request.target, report.wedgeUv.data(), *request.source,
                                           asked.withColor ? request.sourceColors->data() : nullptr, options);
    report.bakeSeconds = secondsSince(phase);
    refuseBakeWithoutHits(baked);
    reportProgress(request.progress, 0.75, "filling holes and gutters");

    phase = Clock::now();
    fillBakedMaps(request, asked, baked, report);
    report.fillSeconds = secondsSince(phase);
    reportProgress(request.progress, 0.80, "building the LEAN moment pyramid");

    LeanMaps lean;
    if (asked.withLean) {
        phase = Clock::now();
        lean = buildLeanMaps(baked.normals.data(), baked.tangents.data(), asked.size, asked.size);
        report.leanLevels = static_cast<int>(lean.moments.size());
        report.leanSeconds = secondsSince(phase);
    }
    reportProgress(request.progress, 0.90, "writing the maps");

    phase = Clock::now();
    writeBakeFiles(request, asked, baked, lean, report);
    report.writeSeconds = secondsSince(phase);

    dropMaps(baked);
    report.bake = std::move(baked);
    report.totalSeconds = secondsSince(start);
    report.cpuSeconds = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;
    if (request.progress) request.progress(1.0, "done");
    return report;
}

}  // namespace rad
