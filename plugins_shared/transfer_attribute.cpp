#include "transfer_attribute.h"

#include "row_indexed_attribute.h"

#include "radiance/basis.h"

#include <algorithm>

namespace radml {
namespace {
const RowIndexedAttribute<StoredTransfer> kTransferAttribute("prt_transfer", "prt_transfer_row");

bool parseInt(const std::map<std::string, std::string>& meta, const char* key, int& value) {
    auto it = meta.find(key);
    if (it == meta.end()) return false;
    try {
        std::size_t used = 0;
        value = std::stoi(it->second, &used);
        return used == it->second.size();
    } catch (const std::exception&) {
        return false;
    }
}
}  // namespace

bool hasTransfer(CMeshO& mesh) { return kTransferAttribute.present(mesh); }

void attachTransfer(CMeshO& mesh, StoredTransfer transfer) { kTransferAttribute.attach(mesh, std::move(transfer)); }

void removeTransfer(CMeshO& mesh) { kTransferAttribute.remove(mesh); }

const rad::TransferField* storedTransferField(CMeshO& mesh) {
    const StoredTransfer* stored = kTransferAttribute.stored(mesh);
    return stored ? &stored->field : nullptr;
}

bool gatherTransfer(CMeshO& mesh, StoredTransfer& out, std::string& why) {
    const StoredTransfer* stored = kTransferAttribute.stored(mesh);
    if (stored == nullptr) {
        why = missingTransferAdvice();
        return false;
    }
    out = *stored;
    const std::size_t width = static_cast<std::size_t>(stored->field.width());
    out.field.values.assign(static_cast<std::size_t>(mesh.vn) * width, 0.0f);
    const long long missing = kTransferAttribute.forEachLiveRow(
        mesh, stored->field.vertexCount(), [&](std::size_t row, std::size_t live) {
            std::copy_n(stored->field.vertex(row), width, out.field.vertex(live));
        });
    if (missing > 0) {
        why = std::to_string(missing) + " of " + std::to_string(mesh.vn) +
              " vertices have no PRT transfer vector (they were created by another filter after the transfer "
              "was computed). Run 'Radiance: Compute PRT Transfer' again, or use 'Radiance: Adaptive PRT "
              "Subdivision', which ray-casts the vertices it creates.";
        return false;
    }
    return true;
}

rad::NamedVertexBlock blockFromTransfer(const StoredTransfer& transfer) {
    rad::NamedVertexBlock block;
    block.prefix = kTransferBlockPrefix;
    block.width = transfer.field.width();
    block.values = transfer.field.values;
    block.metadata["kind"] = "sh_transfer_shadowed_diffuse";
    block.metadata["sh_degree"] = std::to_string(transfer.field.degree);
    block.metadata["channels"] = std::to_string(transfer.field.channels);
    block.metadata["rays"] = std::to_string(transfer.rayCount);
    char offset[32];
    std::snprintf(offset, sizeof offset, "%.9g", transfer.relativeRayOffset);
    block.metadata["ray_offset"] = offset;
    block.metadata["occluders"] = transfer.allVisibleLayers ? "visible_layers" : "mesh";
    return block;
}

std::optional<StoredTransfer> transferFromBlock(const rad::NamedVertexBlock& block, std::string& why) {
    StoredTransfer t;
    int degree = -1, channels = 0;
    if (!parseInt(block.metadata, "sh_degree", degree) || degree < 0 || degree > rad::kMaxHarmonicDegree) {
        why = "block 'prt' lacks a valid 'sh_degree' metadata entry (0.." + std::to_string(rad::kMaxHarmonicDegree) + ")";
        return std::nullopt;
    }
    if (!parseInt(block.metadata, "channels", channels) || (channels != 1 && channels != 3)) {
        why = "block 'prt' lacks a valid 'channels' metadata entry (1 or 3)";
        return std::nullopt;
    }
    t.field.degree = degree;
    t.field.channels = channels;
    if (block.width != t.field.width()) {
        why = "block 'prt' has width " + std::to_string(block.width) + " but SH degree " + std::to_string(degree) +
              " with " + std::to_string(channels) + " channel(s) needs " + std::to_string(t.field.width());
        return std::nullopt;
    }
    // The ray settings are reused for the vertices a subdivision adds: values the transfer filter
    // would refuse are refused here too (a file claiming 10^6 rays was used as such).
    if (block.metadata.count("rays") > 0) {
        int rays = 0;
        if (!parseInt(block.metadata, "rays", rays) || rays < 1 || rays > rad::kMaxTransferRayCount) {
            why = "block 'prt' has 'rays' = '" + block.metadata.at("rays") + "', not a ray count in 1.." +
                  std::to_string(rad::kMaxTransferRayCount) + ": compute the transfer again with 'Radiance: "
                  "Compute PRT Transfer'";
            return std::nullopt;
        }
        t.rayCount = rays;
    }
    auto offset = block.metadata.find("ray_offset");
    if (offset != block.metadata.end()) {
        double value = 0.0;
        try {
            value = std::stod(offset->second);
        } catch (const std::exception&) {
            value = 0.0;
        }
        if (!(value > 0.0 && value < rad::kMaxRelativeRayOffset)) {
            why = "block 'prt' has 'ray_offset' = '" + offset->second + "', not a fraction of the diagonal in (0, " +
                  std::to_string(rad::kMaxRelativeRayOffset) + "): compute the transfer again with 'Radiance: "
                  "Compute PRT Transfer'";
            return std::nullopt;
        }
        t.relativeRayOffset = value;
    }
    auto occluders = block.metadata.find("occluders");
    t.allVisibleLayers = occluders != block.metadata.end() && occluders->second == "visible_layers";
    t.field.values = block.values;
    return t;
}

std::string missingTransferAdvice() {
    return "The current mesh has no PRT transfer vectors. Run 'Radiance: Compute PRT Transfer' first (or open a "
           ".rply file saved with them).";
}

}  // namespace radml
