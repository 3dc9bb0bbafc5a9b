#include "io_radiance.h"

#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include <wrap/io_trimesh/io_mask.h>

#include <cstdio>

namespace {
const char* kExtension = "RPLY";
const char* kDescription = "Radiance PLY (per-vertex radiance functions)";
// The GUI shows errorMessage in a dialog, but meshlabserver's -i/-o paths drop it: say it on
// stderr too, so batch users learn what is wrong with their file.
void reportError(const QString& message) {
    std::fprintf(stderr, "%s\n", qUtf8Printable(message));
}
}  // namespace

QList<MeshIOInterface::Format> RadianceIOPlugin::importFormats() const {
    return {Format(kDescription, kExtension)};
}

QList<MeshIOInterface::Format> RadianceIOPlugin::exportFormats() const {
    return {Format(kDescription, kExtension)};
}

void RadianceIOPlugin::GetExportMaskCapability(QString& format, int& capability, int& defaultBits) const {
    capability = defaultBits = 0;
    if (format.toUpper() != kExtension) return;
    using vcg::tri::io::Mask;
    capability = Mask::IOM_VERTCOORD | Mask::IOM_FACEINDEX | Mask::IOM_VERTNORMAL | Mask::IOM_VERTCOLOR |
                 Mask::IOM_VERTQUALITY;
    defaultBits = capability;
}

bool RadianceIOPlugin::open(const QString& format, const QString& fileName, MeshModel& m, int& mask,
                            const RichParameterList&, vcg::CallBackPos* cb, QWidget*) {
    if (format.toUpper() != kExtension) {
        errorMessage = "The radiance IO plugin only reads ." + QString(kExtension).toLower() + " files.";
        return false;
    }
    try {
        if (cb) cb(5, "Reading radiance PLY");
        const rad::RadianceMesh plain = rad::readRadiancePly(fileName.toStdString());
        if (cb) cb(60, "Building the mesh");
        std::string transferWarning;
        mask = radml::importPlainMesh(plain, m.cm, &transferWarning);
        m.Enable(mask);
        if (plain.radiance)
            Log("Loaded %zu vertices with %s radiance functions%s", plain.vertexCount(),
                plain.radiance->basis.name().c_str(), plain.radiance->reflected ? " (reflected)" : "");
        if (const rad::TransferField* transfer = radml::storedTransferField(m.cm))
            Log("Loaded PRT transfer vectors: SH degree %d (%d coefficients), %d channel(s)", transfer->degree,
                transfer->coefficientCount(), transfer->channels);
        if (!transferWarning.empty()) {
            Log(GLLogStream::WARNING, "%s", transferWarning.c_str());
            std::fprintf(stderr, "%s\n", transferWarning.c_str());
        }
        if (cb) cb(100, "Done");
        return true;
    } catch (const std::exception& e) {
        // MeshLab discards the half-built layer of a failed open; the user's other layers are untouched.
        m.cm.Clear();
        errorMessage = QString::fromUtf8(e.what());  // names the file and says what is wrong
        reportError(errorMessage);
        return false;
    }
}

bool RadianceIOPlugin::save(const QString& format, const QString& fileName, MeshModel& m, const int mask,
                            const RichParameterList&, vcg::CallBackPos* cb, QWidget*) {
    if (format.toUpper() != kExtension) {
        errorMessage = "The radiance IO plugin only writes ." + QString(kExtension).toLower() + " files.";
        return false;
    }
    using vcg::tri::io::Mask;
    radml::ExportChoice choice;
    choice.normals = (mask & Mask::IOM_VERTNORMAL) != 0;
    choice.colors = (mask & Mask::IOM_VERTCOLOR) != 0;
    choice.quality = (mask & Mask::IOM_VERTQUALITY) != 0;
    try {
        if (cb) cb(5, "Collecting mesh data");
        rad::RadianceMesh plain;
        std::string why;
        if (!radml::exportPlainMesh(m.cm, choice, plain, why)) {
            errorMessage = QString("Cannot save %1: %2").arg(fileName, QString::fromStdString(why));
            reportError(errorMessage);
            return false;
        }
        if (cb) cb(40, "Writing radiance PLY");
        rad::writeRadiancePly(fileName.toStdString(), plain);
        if (!plain.radiance)
            Log("Saved %s without radiance data (the mesh has none)", qUtf8Printable(fileName));
        if (!plain.extraBlocks.empty())
            Log("Saved the PRT transfer vectors with %s", qUtf8Printable(fileName));
        if (cb) cb(100, "Done");
        return true;
    } catch (const std::exception& e) {
        errorMessage = QString("Cannot save %1: %2").arg(fileName, e.what());
        reportError(errorMessage);
        return false;
    }
}

MESHLAB_PLUGIN_NAME_EXPORTER(RadianceIOPlugin)
