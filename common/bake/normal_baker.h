// Baking the full scan's normals (and colours) into a texture of the simplified mesh, as Granier et
// al. 2007 keep a simplified scan's appearance: per covered texel (texel_coverage.h), the nearer
// source hit along the target's interpolated normal, either way (Embree), gives the source's
// interpolated vertex normal (and colour); the closest source point when no ray hits (counted). The
// normals are stored in object space or in tangent space, MikkTSpace (Mikkelsen 2008, the frame
// Blender, glTF 2.0, Unity and Unreal decode with; the default) or the old per-face dP/du frame, both
// "+Y up"; always a unit vector. A stop request makes the bake throw OperationCancelled.
// Details: docs/normal-map-baking.md, "What the filter does" (step 4) and "Conventions".
#pragma once
#include "progress/progress_callback.h"
#include "geometry/triangle_mesh.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <vector>

namespace rad {

enum class NormalSpace { Object, Tangent };
enum class TangentFrame { MikkTSpace, PerFaceUvDerivative };

struct NormalBakeOptions {
    int width = 1024, height = 1024;
    NormalSpace space = NormalSpace::Object;
    TangentFrame tangentFrame = TangentFrame::MikkTSpace;  // for NormalSpace::Tangent
    float maxRayDistance = 0.0f;       // <= 0: automaticRayDistance(target, source)
    bool bakeColor = false;            // needs sourceColors
    // Also fill `mikkTSpaceNormals` (a MikkTSpace tangent-space map next to the requested one: the
    // glTF export of an object-space bake needs both).
    bool alsoMikkTSpace = false;
    // Fill `tangents` (LEAN needs them). Off, the array stays empty: 12 bytes per texel neither
    // allocated nor written (a tangent-space bake without LEAN has no use for them).
    bool keepTangents = true;
    // progress/progress_callback.h, called from the calling thread (LoopProgress). A stop request
    // makes the bake throw OperationCancelled.
    ProgressCallback progress;
};

struct NormalBakeResult {
    int width = 0, height = 0;
    std::vector<float> normals;        // 3 per texel, unit, in the requested space; 0 where not valid
    std::vector<float> tangents;       // 3 per texel, object-space unit T of the frame above (LEAN needs it); 0 where not valid; empty without keepTangents
    std::vector<float> colors;         // 3 per texel when bakeColor (source colour units), else empty
    std::vector<float> mikkTSpaceNormals;  // 3 per texel when alsoMikkTSpace, else empty
    // MikkTSpace bakes (and alsoMikkTSpace): the per-corner tangents used (4 per corner: x, y, z,
    // sign; geometry/mikktspace_tangents.h, completed), which a renderer must be given with the map.
    std::vector<float> cornerTangents;
    std::vector<std::uint8_t> chart;   // 1 where the coverage has a face (the texel belongs to a chart)
    std::vector<std::uint8_t> valid;   // 1 where a value was baked (chart texels whose source normal was usable)
    float maxRayDistance = 0.0f;       // the distance used
    std::size_t chartTexels = 0, rayHits = 0, closestPointFallbacks = 0, invalidTexels = 0;
    // MikkTSpace bakes: corners whose tangent had to be made up (no triangle around them has UV
    // derivatives, or dP/du along the normal; mikktspace_tangents.h completeTangents).
    std::size_t madeUpTangentCorners = 0;
    double seconds = 0.0;
    // Parts of `seconds` (wall clock): rasterising the layout, building the source's ray scene
    // (and the automatic ray distance), casting the rays and writing the texels.
    double coverageSeconds = 0.0, sceneSeconds = 0.0, raySeconds = 0.0;
};

// Target: the simplified mesh (positions, unit vertex normals required, faces) with its wedge UVs
// (texture_atlas.h). Source: the full scan; vertex normals used when present, else area-weighted
// ones are computed. sourceColors: 3 floats per source vertex or nullptr. Throws BakeInputError
// for empty meshes, missing target normals, mismatched arrays, NaN positions; OperationCancelled.
// Parallel (OpenMP) over texel rows.
NormalBakeResult bakeNormalMap(const TriangleMesh& target, const float* targetWedgeUv, const TriangleMesh& source,
                               const float* sourceColors, const NormalBakeOptions& options);

// The default ray length: twice the largest distance from the target's vertices and face
// centroids to the source (closest point), and at least 0.5 % of the source's bounding-box
// diagonal, so that every target point finds the surface it was simplified from.
float automaticRayDistance(const TriangleMesh& target, const TriangleMesh& source);

// Unit normal component in [-1, 1] -> code. 8 bit: round((x + 1) / 2 * 255); 16 bit: * 65535.
std::uint8_t encodeNormal8(float component);
std::uint16_t encodeNormal16(float component);
float decodeNormal8(std::uint8_t code);
float decodeNormal16(std::uint16_t code);

}  // namespace rad
