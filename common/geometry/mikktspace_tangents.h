// Per-corner tangent frames in the MikkTSpace convention (Mikkelsen 2008, "Simulation of wrinkled
// surfaces revisited"), the tangent space that Blender, Unity, Unreal, three.js and the glTF 2.0
// specification use to decode tangent-space normal maps. A map baked with other tangents shows
// seams and shading errors in those tools, so the bake, the glTF export and the tests all take
// their tangents from here.
//
// What is computed (our implementation of the published algorithm, with the behaviour of the
// implementation Blender ships, which is what users see; see docs/normal-map-baking.md):
//  1. Corners with bit-identical position, normal and UV are one "vertex" (welding).
//  2. A triangle is degenerate when two of its corners have the same position; it takes, per
//     corner, the frame of the first good corner of the same vertex.
//  3. Per good triangle: dP/ds from the UV derivatives (eq. 18 of the reference code), made unit
//     and multiplied by the sign of the UV area; the triangle is orientation preserving when the
//     UV area is > 0. A triangle whose UV area, dP/ds or dP/dt is zero (below FLT_MIN) has no
//     usable derivative: it contributes nothing, never starts a group, and takes the orientation
//     of the first group that reaches it.
//  4. Around each vertex, the triangles reachable through edges that contain it (vertex ids after
//     welding, so UV seams and normal creases cut) and that have the same orientation form a
//     group; the group's tangent is the sum of its triangles' dP/ds projected on the vertex
//     normal's plane and made unit, weighted by the triangle's angle at the corner (measured in
//     that plane), normalised. (The original reference code could split a group further by an
//     angle threshold; with its default of 180 degrees it does not, and Blender has no split.)
//  5. Bitangent sign = +1 for an orientation-preserving group, -1 otherwise (mirrored UVs).
//  A corner that no group reaches (every triangle around it lacks UV derivatives) gets Blender's
//  default T = (1, 0, 0), sign -1, flagged in `reached`.
// A renderer decodes a tangent-space normal t as normalize(t.x T + t.y B + t.z N) with
// B = sign * cross(N, T), T and N interpolated across the triangle (not renormalised): "+Y up"
// with v growing upwards in the image, the convention glTF 2.0 and Blender expect.
//
// Quads are not split here: the input is triangles (the reference splits quads along a diagonal
// of its own choosing; a triangulated mesh gives the same result in every tool).
#pragma once

#include "errors/error_categories.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace rad {

// Whether an attribute array holds one value per vertex or one per face corner (3 per face, in
// the order of the face's vertex indices: MeshLab's "wedge" attributes).
enum class AttributeRate { PerVertex, PerCorner };

struct TangentSpaceInput {
    const float* positions = nullptr;   // 3 per vertex
    std::size_t vertexCount = 0;
    const std::uint32_t* faces = nullptr;  // 3 vertex indices per triangle
    std::size_t faceCount = 0;
    const float* normals = nullptr;     // 3 per vertex or per corner, unit
    AttributeRate normalRate = AttributeRate::PerVertex;
    const float* uv = nullptr;          // 2 per vertex or per corner
    AttributeRate uvRate = AttributeRate::PerCorner;
};

struct CornerTangents {
    // 4 per corner (corner c = 3 * face + k): unit tangent x, y, z and the bitangent sign (+1 or
    // -1), exactly as Blender computes them (including its defaults, see above).
    std::vector<float> tangents;
    std::vector<std::uint8_t> reached;    // per corner: 0 where the default frame was written
    std::size_t degenerateTriangles = 0;  // two corners at the same position
    std::size_t zeroUvAreaTriangles = 0;  // non-degenerate, but no usable UV derivative
    std::size_t defaultFrameCorners = 0;  // corners no group reached (default frame)
    std::size_t zeroTangentCorners = 0;   // reached, but the sum was zero (dP/ds along the normal)
};

struct TangentSpaceInputError : InputError {
    using InputError::InputError;
};

// Throws TangentSpaceInputError for missing arrays or a vertex index out of range.
CornerTangents computeMikkTSpaceTangents(const TangentSpaceInput& input);

// Replaces each default frame and each zero or non-finite tangent by a unit vector orthogonal to
// the corner's normal (a fixed choice) with sign +1, so that consumers needing a unit tangent
// orthogonal to the normal (glTF, a baker) always get one; returns how many were replaced.
// `input` is the one the tangents were computed from.
std::size_t completeTangents(CornerTangents& result, const TangentSpaceInput& input);

}  // namespace rad
