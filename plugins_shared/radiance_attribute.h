// The radiance data of a MeshLab layer (CMeshO), shared by every plugin of ours.
//
// The coefficients live in one contiguous rad::RadianceField held by a per-mesh attribute; each
// vertex carries its row in that field (row_indexed_attribute.h: MeshLab's own delete/compact
// filters keep the association; vertices created by other filters have no radiance).
#pragma once

#include "radiance/radiance_field.h"

#include "meshlab_mesh.h"

#include <cstdint>
#include <memory>
#include <string>

namespace radml {

inline constexpr const char* kRadianceFieldAttributeName = "radiance_field";
inline constexpr const char* kRadianceRowAttributeName = "radiance_row";

// Whether the mesh carries radiance data at all.
bool hasRadiance(CMeshO& mesh);

// Attaches `field` (rows in the order of the mesh's live vertices, i.e. skipping deleted ones) to the
// mesh, replacing any previous radiance data. Precondition: field.vertexCount() == mesh.vn.
void attachRadiance(CMeshO& mesh, rad::RadianceField field);

// The radiance of the live vertices in vertex-vector order (deleted vertices skipped), as a new
// contiguous field. Returns false and sets `why` (a sentence for MeshLab's log) when the mesh has no
// radiance data or some vertex has none (created after the data was made).
bool gatherRadiance(CMeshO& mesh, rad::RadianceField& out, std::string& why);

// Direct read access to the stored field and a vertex's row (-1 when none), for adapters that
// only read a few vertices; nullptr when the mesh has no radiance.
const rad::RadianceField* storedRadiance(CMeshO& mesh);
std::int32_t radianceRow(CMeshO& mesh, const CVertexO& vertex);

void removeRadiance(CMeshO& mesh);

// Message used by every filter that needs radiance data on a mesh without it.
std::string missingRadianceAdvice();

}  // namespace radml
