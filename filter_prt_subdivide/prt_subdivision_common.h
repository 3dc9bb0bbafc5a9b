// What the PRT filters of this plugin share: the occluders as one triangle soup for Embree, the
// shading written back as vertex colour and quality, and, for the two subdivision filters
// (Křivánek et al. 2004), the budget parameters, the preparation of the layer, the ray-casting
// oracle of new vertices and the write-back of the subdivided mesh.
#pragma once

#include "filter.h"
#include "transfer_attribute.h"

#include "prt/adaptive_subdivision.h"
#include "prt/transfer_vectors.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace radml {

enum OccluderChoice { kOccludersMesh = 0, kOccludersVisibleLayers = 1 };

// The faces of the current layer, or of every visible layer, as one triangle soup.
struct OccluderScene {
    std::vector<float> positions;
    std::vector<std::uint32_t> faces;
    float diagonal = 0.0f;  // of the bounding box of all positions; 0 when empty or a single point
};
OccluderScene collectOccluders(MeshDocument& md, MeshModel& current, bool allVisibleLayers);

// Shading under a constant white sky of unit radiance, L = t_00 sqrt(4 pi) (ambient occlusion),
// 3 linear floats per vertex.
std::vector<float> whiteSkyShading(const rad::TransferField& field);

// Vertex colour := exposure times the linear RGB, sRGB-encoded; vertex quality := its luminance
// (before the exposure). One RGB triple per live vertex.
void setShading(MeshModel& m, const std::vector<float>& linearRgb, float exposure);

// What the PRT filters' users change when memory runs out (Filter::outOfMemoryAdvice).
inline constexpr const char* kPrtOutOfMemoryAdvice = "lower the SH order, the ray count or the triangle budget";

// The budget parameters of both subdivision filters ("budget", "budgetFactor").
void addBudgetParameters(RichParameterList& par, const MeshModel& m);
// The choices of the "measure" parameter (0: eq. 2, 1: eq. 3, 2: eq. 4 of Křivánek et al. 2004,
// 3: probed relative, 4: probed absolute; transfer_error_estimate.h), the estimate and its name.
QStringList measureChoices();
rad::TransferErrorMeasure measureParameter(const RichParameterList& par);
const char* measureCitation(const RichParameterList& par);

// The current layer ready for a subdivision: its stored transfer (one channel), the mesh with unit
// normals, checked by rad::checkPrtSubdivisionInput, and the triangle budget from the parameters.
// Throws Refusal.
struct PrtSubdivisionInput {
    StoredTransfer stored;
    rad::PrtMesh mesh;
    std::size_t faces = 0;
    long long budget = 0;
};
PrtSubdivisionInput prepareSubdivision(FilterContext& ctx);

// Calls `subdivide` with an oracle that ray-casts the transfer of new vertices against the
// occluders and with the settings the stored vectors were computed with (never interpolated).
rad::SubdivisionResult subdivideWithRayCasting(
    FilterContext& ctx, const PrtSubdivisionInput& input,
    const std::function<rad::SubdivisionResult(const rad::TransferOracle&)>& subdivide);

// Replaces the layer by the subdivided mesh, its transfer and white-sky shading; the error
// estimate of every face as face quality and a colour ramp. Logs a warning when the layer's
// radiance functions are dropped.
void replaceWithSubdivision(FilterContext& ctx, const PrtSubdivisionInput& input,
                            const rad::SubdivisionResult& result);

}  // namespace radml
