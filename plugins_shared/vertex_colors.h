// Per-vertex data between a MeshLab layer and the cores' flat arrays: positions and normals of the
// live vertices out, linear RGB back in as sRGB-encoded vertex colours, values back as vertex quality.
#pragma once

#include "meshlab_host.h"

#include <cstdint>
#include <vector>

namespace radml {

// Positions and normals of the live vertices (deleted ones skipped), 3 floats each.
struct VertexArrays {
    std::vector<float> positions;
    std::vector<float> normals;
    std::vector<std::uint32_t> faces;  // live faces, indices into the live vertices
    std::size_t count() const { return positions.size() / 3; }
};
// Throws radml::Refusal when the layer has no vertices.
VertexArrays collectVertexArrays(const CMeshO& mesh);

// Vertex colours of the live vertices from linear RGB (3 floats per live vertex), sRGB-encoded.
void setVertexColorsFromLinear(MeshModel& m, const std::vector<float>& linearRgb);

// Vertex quality of the live vertices (one value per live vertex).
void setVertexQuality(MeshModel& m, const std::vector<float>& values);

// A colour parameter (the dialog shows sRGB) as linear RGB in [0, 1].
std::array<float, 3> linearColorParameter(const RichParameterList& par, const QString& name);

}  // namespace radml
