// MeshLab 2025.07's IO interface over one radml::MeshFormat (mesh_format.h).
#pragma once

#include "mesh_format.h"

#include <QObject>

#include <memory>

namespace radml {

class IoPluginBase : public QObject, public IOPlugin {
public:
    QString vendor() const override { return "radiance-tools"; }
    std::list<FileFormat> importFormats() const override;
    std::list<FileFormat> exportFormats() const override;
    void exportMaskCapability(const QString& format, int& capability, int& defaultBits) const override;
    using IOPlugin::open;
    void open(const QString& format, const QString& fileName, MeshModel& m, int& mask,
              const RichParameterList& par, vcg::CallBackPos* cb = nullptr) override;
    void save(const QString& format, const QString& fileName, MeshModel& m, const int mask,
              const RichParameterList& par, vcg::CallBackPos* cb = nullptr) override;

protected:
    explicit IoPluginBase(std::unique_ptr<MeshFormat> format) : format_(std::move(format)) {}

private:
    // The format's log and warning lines as this host shows them (host_operations.h), for open and save.
    void logLine(const std::string& line);
    void warningLine(const std::string& line);
    std::unique_ptr<MeshFormat> format_;
};

}  // namespace radml
