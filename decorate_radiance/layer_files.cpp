#include "layer_files.h"

#include "bake/bake_description.h"

#include <QDir>
#include <QFileInfo>

namespace raddecorate {

std::string bakedMapOf(const MeshModel& m, std::string& why) {
    const std::string advice = "run 'Bake Normal Map' (Filters > Texture) with this layer as the target first";
    if (m.cm.fn == 0 || !m.hasDataMask(MeshModel::MM_WEDGTEXCOORD) || m.cm.textures.empty()) {
        why = "the layer has no texture coordinates and texture: " + advice;
        return {};
    }
    const QString name = QString::fromStdString(m.cm.textures.front());
    QStringList candidates;
    if (QFileInfo(name).isAbsolute()) candidates << name;
    else {
        if (!m.fullName().isEmpty()) candidates << QFileInfo(m.fullName()).absoluteDir().filePath(name);
        candidates << QFileInfo(name).absoluteFilePath();
    }
    for (const QString& candidate : candidates) {
        const std::string description = rad::bakeDescriptionPathFor(candidate.toStdString());
        if (!description.empty() && QFileInfo::exists(QString::fromStdString(description))) return description;
    }
    why = "the layer's texture '" + name.toStdString() + "' has no bake description (…_bake.txt) beside it: " + advice;
    return {};
}

std::string irradianceGridPathOf(const MeshModel& m, const std::string& explicitFile, std::string& why) {
    const QString layerFile = m.fullName();
    if (!explicitFile.empty()) {
        const QString name = QString::fromStdString(explicitFile);
        if (QFileInfo(name).isAbsolute() || layerFile.isEmpty()) return QFileInfo(name).absoluteFilePath().toStdString();
        return QFileInfo(layerFile).absoluteDir().filePath(name).toStdString();
    }
    if (layerFile.isEmpty()) {
        why = "the layer has no file, so no grid beside it: save the layer, or name the grid file in Tools > Options > "
              "Decoration ('Irradiance vector grid file')";
        return {};
    }
    const QFileInfo info(layerFile);
    return info.absoluteDir().filePath(info.completeBaseName() + ".ivg").toStdString();
}

}  // namespace raddecorate
