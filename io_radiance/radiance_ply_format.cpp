#include "radiance_ply_format.h"

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
    progress(100, "Done");
}

void RadiancePlyFormat::write(const QString& fileName, MeshModel& m, int mask, FilterProgress& progress,
                              const std::function<void(const std::string&)>& log) const {
    using vcg::tri::io::Mask;
    ExportChoice choice;
    choice.normals = (mask & Mask::IOM_VERTNORMAL) != 0;
    choice.colors = (mask & Mask::IOM_VERTCOLOR) != 0;
    choice.quality = (mask & Mask::IOM_VERTQUALITY) != 0;
    progress(5, "Collecting mesh data");
    rad::RadianceMesh plain;
    std::string why;
    if (!exportPlainMesh(m.cm, choice, plain, why))
        throw Refusal("Cannot save " + fileName.toStdString() + ": " + why);
    progress(40, "Writing radiance PLY");
    try {
        rad::writeRadiancePly(fileName.toStdString(), plain);
    } catch (const std::exception& e) {
        throw Refusal("Cannot save " + fileName.toStdString() + ": " + e.what());
    }
    if (!plain.radiance) log("Saved " + fileName.toStdString() + " without radiance data (the mesh has none)");
    if (!plain.extraBlocks.empty()) log("Saved the PRT transfer vectors with " + fileName.toStdString());
    progress(100, "Done");
}

}  // namespace radml
