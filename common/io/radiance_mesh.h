// A triangle mesh with per-vertex radiance functions, as plain arrays: what the radiance PLY file
// (radiance_ply.h, docs/radiance-ply-format.md) stores and what the plugins convert to and from
// MeshLab's CMeshO.
#pragma once

#include "radiance/radiance_field.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rad {

// A per-vertex float array carried along with the mesh (e.g. PRT transfer vectors).
// Stored in the file as the float vertex properties <prefix>_0 .. <prefix>_<width-1>.
struct NamedVertexBlock {
    std::string prefix;                           // [A-Za-z_][A-Za-z0-9_]*, not "rf" nor "rf_..."
    int width = 0;                                // floats per vertex, >= 1
    std::vector<float> values;                    // values[v * width + i]
    std::map<std::string, std::string> metadata;  // key: no whitespace; value: no control characters
};

struct RadianceMesh {
    std::vector<float> positions;       // 3 per vertex
    std::vector<float> normals;         // 3 per vertex or empty
    std::vector<std::uint8_t> colors;   // 4 per vertex (RGBA) or empty
    std::vector<float> quality;         // 1 per vertex or empty
    std::vector<std::uint32_t> faces;   // 3 per triangle
    std::optional<RadianceField> radiance;
    std::vector<NamedVertexBlock> extraBlocks;
    // Filled by the reader only (the writer ignores it): one sentence per piece of the file it skipped
    // (unknown vertex properties, unknown elements), so that callers can say what a later save drops.
    std::vector<std::string> skippedOnRead;

    std::size_t vertexCount() const { return positions.size() / 3; }
    std::size_t faceCount() const { return faces.size() / 3; }
};

}  // namespace rad
