// MeshLab 2020.09's IO interface over one radml::MeshFormat (mesh_format.h).
#pragma once

#include "mesh_format.h"

#include <QObject>

#include <memory>

namespace radml {

class IoPluginBase : public QObject, public MeshIOInterface {
public:
    QList<Format> importFormats() const override;
    QList<Format> exportFormats() const override;
    void GetExportMaskCapability(QString& format, int& capability, int& defaultBits) const override;
    bool open(const QString& format, const QString& fileName, MeshModel& m, int& mask,
              const RichParameterList& par, vcg::CallBackPos* cb = nullptr, QWidget* parent = nullptr) override;
    bool save(const QString& format, const QString& fileName, MeshModel& m, const int mask,
              const RichParameterList& par, vcg::CallBackPos* cb = nullptr, QWidget* parent = nullptr) override;

protected:
    explicit IoPluginBase(std::unique_ptr<MeshFormat> format) : format_(std::move(format)) {}

private:
    bool refuse(const std::string& message);
    // The format's log and warning lines as this host shows them (host_operations.h), for open and save.
    void logLine(const std::string& line);
    void warningLine(const std::string& line);
    std::unique_ptr<MeshFormat> format_;
};

}  // namespace radml
