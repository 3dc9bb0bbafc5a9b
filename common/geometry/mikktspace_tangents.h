// Per-corner tangent frames in the MikkTSpace convention (Mikkelsen 2008), the tangent space that
// Blender, Unity, Unreal, three.js and glTF 2.0 use to decode tangent-space normal maps. A map baked
// with other tangents shows seams and shading errors in those tools, so the bake, the glTF export
// and the tests all take their tangents from here. Our implementation of the published algorithm,
// with the behaviour of the implementation Blender ships (what users see), including its defaults
// for corners no tangent reaches. The input is triangles.
// Details: docs/gltf-export.md, "`common/geometry/mikktspace_tangents.h`: how it works".
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
