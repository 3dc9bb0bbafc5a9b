// The PRT transfer vectors of a MeshLab layer (CMeshO): one contiguous rad::TransferField per mesh
// plus a row per vertex (row_indexed_attribute.h), with the settings they were computed with (the
// adaptive subdivision ray-casts new vertices with the same settings). Saved and loaded by the
// radiance PLY IO plugin as the extra vertex block "prt" (docs/radiance-ply-format.md).
#pragma once

#include "io/radiance_mesh.h"
#include "prt/transfer_vectors.h"

#include "meshlab_mesh.h"

#include <optional>
#include <string>

namespace radml {

// How the transfer was computed; stored next to the field and in the file's block metadata.
struct StoredTransfer {
    rad::TransferField field;
    int rayCount = rad::kDefaultTransferRayCount;
    double relativeRayOffset = 1e-4;
    bool allVisibleLayers = false;   // occluders: all visible layers, or the mesh alone
};

inline constexpr const char* kTransferBlockPrefix = "prt";

bool hasTransfer(CMeshO& mesh);
// Rows in the order of the live vertices. Precondition: field.vertexCount() == mesh.vn.
void attachTransfer(CMeshO& mesh, StoredTransfer transfer);
void removeTransfer(CMeshO& mesh);
// The stored field (rows may not match the live vertices: use gatherTransfer), nullptr when none.
const rad::TransferField* storedTransferField(CMeshO& mesh);
// The transfer of the live vertices in vertex-vector order. False with `why` (a sentence for the
// log) when there is none or some vertex has none (created by another filter afterwards).
bool gatherTransfer(CMeshO& mesh, StoredTransfer& out, std::string& why);

// File block <-> stored transfer. blockFromTransfer writes the metadata keys kind, sh_degree,
// channels, rays, ray_offset, occluders. transferFromBlock returns nullopt with `why` when the
// block's width or metadata do not describe a transfer field.
rad::NamedVertexBlock blockFromTransfer(const StoredTransfer& transfer);
std::optional<StoredTransfer> transferFromBlock(const rad::NamedVertexBlock& block, std::string& why);

std::string missingTransferAdvice();

}  // namespace radml
