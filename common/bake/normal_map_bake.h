// The whole "Bake Normal Map" job behind the MeshLab filter and the tools: check the inputs, make or
// check the texture layout, bake (normal_baker.h), fill holes and gutters (map_filling.h), build the
// LEAN covariance maps (lean_maps.h), and write the documented file set (normal map, diffuse map,
// LEAN moments, optional glTF binary, bake description) atomically: every file goes to a temporary
// name first and all are renamed only when complete, so a refusal, an error or a cancel leaves no
// partial file.
// Details: docs/normal-map-baking.md, "What the filter does" and "File set".
#pragma once
#include "bake/normal_baker.h"
#include "bake/texture_atlas.h"  // BakeInputError

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rad {

struct NormalMapBakeRequest {
    const TriangleMesh* target = nullptr;          // simplified mesh, unit vertex normals
    const std::vector<float>* targetWedgeUv = nullptr;  // 6 per face; nullptr or empty: per-triangle atlas
    const TriangleMesh* source = nullptr;          // full scan (normals optional)
    const std::vector<float>* sourceColors = nullptr;   // 3 per source vertex in [0, 1], or nullptr
    int textureSize = 2048;
    NormalSpace space = NormalSpace::Object;
    TangentFrame tangentFrame = TangentFrame::MikkTSpace;  // tangent space only (normal_baker.h)
    int bits = 16;                                 // 8 or 16
    float maxRayDistance = 0.0f;                   // 0: automatic; negative is refused
    int gutterTexels = 4;                          // empty texels between two charts of a generated atlas
    bool bakeDiffuse = true;                       // ignored without sourceColors
    bool writeLean = true;
    // glTF 2.0 binary beside the maps. Its normal texture is always MikkTSpace tangent space (what
    // glTF defines), baked alongside an object-space map when that is the requested space.
    bool writeGltf = false;
    float gltfBaseRoughness = 0.5f;                // glTF perceptual roughness of the flat surface
    std::string outputBase;                        // B above
    ProgressCallback progress;                     // progress/progress_callback.h (OperationCancelled)
    // Memory the bake may take; 0: what the machine has available now (memory/available_memory.h).
    std::size_t memoryLimitBytes = 0;
};

// Peak memory of bakeNormalMapFiles beyond its inputs, from the texture size and the maps written
// (measured through pymeshlab at 2048^2 and 4096^2: ~39 bytes per texel for the normals alone,
// +12 with the diffuse map, +20 with the LEAN moments; a 10 % margin on top).
std::size_t estimatedBakeBytes(const NormalMapBakeRequest& request);

struct NormalMapBakeReport {
    std::vector<float> wedgeUv;                    // the layout baked into (generated or the input's)
    bool atlasGenerated = false;
    int atlasCellSize = 0;
    std::string normalMapFile, diffuseMapFile, leanFile, descriptionFile, gltfFile;  // empty when not written
    std::size_t gltfVertices = 0;                  // after splitting at UV seams and tangent changes
    NormalBakeResult bake;                         // stats of the bake (maps released after writing)
    std::size_t holesFilled = 0, gutterTexelsDilated = 0, backgroundTexelsFilled = 0;
    int leanLevels = 0;
    double bakeSeconds = 0, fillSeconds = 0, leanSeconds = 0, writeSeconds = 0, totalSeconds = 0;
    // Processor time of the whole job, all threads (std::clock): with other programs competing for
    // the cores it varies far less than the wall time.
    double cpuSeconds = 0;
};

// Throws BakeInputError (nothing written) for: no target or no faces, source equal to the target
// (the same arrays, or identical positions and faces), no source faces, target without normals,
// a texture size that is not a power of two in [16, 16384], bits other than 8 / 16, an output
// base that is empty or in a directory that does not exist, a UV layout with a problem
// (texture_atlas.h: out of range, NaN, degenerate or overlapping), an estimated peak memory above
// the limit (with the figures and the largest texture size that fits). OperationCancelled on cancel;
// std::runtime_error when a file cannot be written (temporary files removed).
NormalMapBakeReport bakeNormalMapFiles(const NormalMapBakeRequest& request);

// The filling bakeNormalMapFiles applies to a baked map (3 floats per texel): pull-push inside the
// charts (map_filling.h), `rings` of dilation around them, pull-push for the rest, so every texel
// ends up with a value and the gutter carries each chart's own border values. `valid` is taken by
// value (the caller's stays as baked); `chart` is 1 on texels some face covers.
struct BakedMapFillCounts {
    std::size_t holes = 0, gutter = 0, background = 0;
};
BakedMapFillCounts fillBakedMap(std::vector<float>& values, int width, int height, std::vector<std::uint8_t> valid,
                                const std::vector<std::uint8_t>& chart, int rings);

// B_normal.png as bakeNormalMapFiles writes it: unit vectors, 3 floats per texel, rows top to
// bottom, encoded with encodeNormal8 / encodeNormal16 (bits 8 or 16). Throws on I/O errors.
void writeNormalMapPng(const std::string& path, const std::vector<float>& normals, int width, int height, int bits);

// The checks alone (the filter runs them before touching anything).
void checkNormalMapBakeRequest(const NormalMapBakeRequest& request);

}  // namespace rad
