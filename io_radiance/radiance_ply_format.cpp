#include "radiance_ply_format.h"

#include "extra_blocks_attribute.h"
#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include <wrap/io_trimesh/io_mask.h>

#include <cstdio>

namespace radml {

int RadiancePlyFormat::exportCapability() const {
    using vcg::tri::io::Mask;
    return Mask::IOM_VERTCOORD | Mask::IOM_FACEINDEX | Mask::IOM_VERTNORMAL | Mask::IOM_VERTCOLOR |
           Mask::IOM_VERTQUALITY;
}

void RadiancePlyFormat::read(const QString& fileName, MeshModel& m, int& mask, FilterProgress& progress,
                             const std::function<void(const std::string&)>& log,
                             const std::function<void(const std::string&)>& warning) const {
    progress(5, "Reading radiance PLY");
    const rad::RadianceMesh plain = rad::readRadiancePly(fileName.toStdString());
    progress(60, "Building the mesh");
    std::string transferWarning;
    mask = importPlainMesh(plain, m.cm, &transferWarning);
    enableLoadedData(m, mask);
    char line[256];
    if (plain.radiance) {
        std::snprintf(line, sizeof line, "Loaded %zu vertices with %s radiance functions%s", plain.vertexCount(),
                      plain.radiance->basis.name().c_str(), plain.radiance->reflected ? " (reflected)" : "");
        log(line);
    }
    if (const rad::TransferField* transfer = storedTransferField(m.cm)) {
        std::snprintf(line, sizeof line, "Loaded PRT transfer vectors: SH degree %d (%d coefficients), %d channel(s)",
                      transfer->degree, transfer->coefficientCount(), transfer->channels);
        log(line);
    }
    if (!transferWarning.empty()) warning(transferWarning);
    const std::vector<std::string> kept = extraBlockPrefixes(m.cm);
    if (!kept.empty()) {
        std::string names;
        for (const auto& p : kept) names += (names.empty() ? "'" : ", '") + p + "'";
        log("Kept the extra vertex block" + std::string(kept.size() == 1 ? " " : "s ") + names +
            " of the file as they are (saving as .rply writes them back)");
    }
    // What the format does not know is not loaded, so a save cannot write it: say so.
    for (const auto& skipped : plain.skippedOnRead) warning("Not loaded from " + fileName.toStdString() + ": " + skipped + ".");
    progress(100, "Done");
}

void RadiancePlyFormat::write(const QString& fileName, MeshModel& m, int mask, FilterProgress& progress,
                              const std::function<void(const std::string&)>& log,
                              const std::function<void(const std::string&)>& warning) const {
    using vcg::tri::io::Mask;
    ExportChoice choice;
    choice.normals = (mask & Mask::IOM_VERTNORMAL) != 0;
    choice.colors = (mask & Mask::IOM_VERTCOLOR) != 0;
    choice.quality = (mask & Mask::IOM_VERTQUALITY) != 0;
    choice.extraBlocks = true;
    progress(5, "Collecting mesh data");
    rad::RadianceMesh plain;
    std::string why;
    std::vector<std::string> leftOut;
    if (!exportPlainMesh(m.cm, choice, plain, why, &leftOut))
        throw Refusal("Cannot save " + fileName.toStdString() + ": " + why);
    progress(40, "Writing radiance PLY");
    try {
        rad::writeRadiancePly(fileName.toStdString(), plain);
    } catch (const std::exception& e) {
        throw Refusal("Cannot save " + fileName.toStdString() + ": " + e.what());
    }
    if (!plain.radiance) log("Saved " + fileName.toStdString() + " without radiance data (the mesh has none)");
    for (const auto& b : plain.extraBlocks)
        log(b.prefix == kTransferBlockPrefix && hasTransfer(m.cm)
                ? "Saved the PRT transfer vectors with " + fileName.toStdString()
                : "Saved the extra vertex block '" + b.prefix + "' with " + fileName.toStdString());
    for (const auto& line : leftOut) warning("Saved " + fileName.toStdString() + " without some data: " + line);
    progress(100, "Done");
}

}  // namespace radml
