// IO plugin for the radiance PLY format (.rply, docs/radiance-ply-format.md): Debian's PLY reader
// drops unknown vertex properties, so per-vertex radiance coefficients need a reader of their own.
// The plugin only converts between the file (common/io/radiance_ply) and the CMeshO layer.
#pragma once

#include <QObject>
#include <common/interfaces.h>

class RadianceIOPlugin : public QObject, public MeshIOInterface {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_IO_INTERFACE_IID)
    Q_INTERFACES(MeshIOInterface)

public:
    QString pluginName() const override { return "IORadiance"; }
    QList<Format> importFormats() const override;
    QList<Format> exportFormats() const override;
    void GetExportMaskCapability(QString& format, int& capability, int& defaultBits) const override;
    bool open(const QString& format, const QString& fileName, MeshModel& m, int& mask,
              const RichParameterList& par, vcg::CallBackPos* cb = nullptr, QWidget* parent = nullptr) override;
    bool save(const QString& format, const QString& fileName, MeshModel& m, const int mask,
              const RichParameterList& par, vcg::CallBackPos* cb = nullptr, QWidget* parent = nullptr) override;
};
