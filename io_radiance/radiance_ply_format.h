// The Radiance PLY format (.rply) between a file (common/io/radiance_ply.h) and a MeshLab layer.
#pragma once

#include "mesh_format.h"

namespace radml {

class RadiancePlyFormat : public MeshFormat {
public:
    QString description() const override { return "Radiance PLY (per-vertex radiance functions)"; }
    QString extension() const override { return "RPLY"; }
    int exportCapability() const override;
    void read(const QString& fileName, MeshModel& mesh, int& mask, FilterProgress& progress,
              const std::function<void(const std::string&)>& log,
              const std::function<void(const std::string&)>& warning) const override;
    void write(const QString& fileName, MeshModel& mesh, int mask, FilterProgress& progress,
               const std::function<void(const std::string&)>& log,
               const std::function<void(const std::string&)>& warning) const override;
};

}  // namespace radml
