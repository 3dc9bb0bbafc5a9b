// Baking the full scan's normals (and colours) into a texture of the simplified mesh.
//
// Granier et al. 2007: a simplified mesh plus normal maps baked from the full-resolution
// scan keeps the object's appearance. Per covered texel (texel_coverage.h), the point p and the
// interpolated normal n of the target at the texel centre cast two rays, p + t n and p - t n for
// t in [0, maxRayDistance] (Embree); the nearer hit gives the source point, and the source's
// interpolated vertex normal (and colour) there is what is baked. When neither ray hits, the
// closest point of the source to p is used instead (counted as a fallback).
//
// Normal spaces:
//  - Object: the unit normal in the mesh's coordinates.
//  - Tangent, TangentFrame::MikkTSpace (the default): the frame every common tool decodes with
//    (Blender, glTF 2.0, Unity, Unreal, three.js; Mikkelsen 2008): per-corner tangents T_k and
//    bitangent signs s from geometry/mikktspace_tangents.h (target positions, vertex normals,
//    wedge UVs), interpolated per texel without renormalisation, T = sum b_k T_k and
//    N = sum b_k N_k; B = s (N x T). A renderer reconstructs n = normalize(t.x T + t.y B + t.z N),
//    so the bake stores the exact inverse: t = normalize([T B N]^-1 n), as Blender's baker does.
//  - Tangent, TangentFrame::PerFaceUvDerivative (the old frame, for maps made before): N = the
//    interpolated normal (unit), T = the face's dP/du made orthogonal to N (Gram-Schmidt) and
//    unit, B = s (N x T) with s = +1 when (dP/du, dP/dv, face normal) is right-handed and -1
//    otherwise (mirrored UVs). dP/du is constant per face, which is also what a fragment shader
//    gets from dFdx/dFdy of position and UV.
//  Both: "+Y up" (OpenGL, glTF, Blender): B points to increasing v.
// Either way a unit vector is stored; encodeNormal8/16 map [-1, 1] to the code range.
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
