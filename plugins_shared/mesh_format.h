// One mesh file format, described once for both hosts (MeshLab 2020.09 and 2025.07): the host IO
// plugin classes (host_20xx/io_plugin_base.h) turn it into MeshLab's IO interface. `read` and
// `write` throw (radml::Refusal or any std::exception) with a message naming the file, what is
// wrong and how to fix it; a failed read leaves no half-built layer, a failed write no file.
#pragma once

#include "filter.h"

namespace radml {

class MeshFormat {
public:
    virtual ~MeshFormat() = default;
    virtual QString description() const = 0;
    virtual QString extension() const = 0;  // upper case, without the dot
    virtual int exportCapability() const = 0;  // vcg::tri::io::Mask bits
    // Fills `mesh` from the file; `mask` receives the vcg::tri::io::Mask bits of what was loaded.
    virtual void read(const QString& fileName, MeshModel& mesh, int& mask, FilterProgress& progress,
                      const std::function<void(const std::string&)>& log,
                      const std::function<void(const std::string&)>& warning) const = 0;
    // `warning` says what a successful save could not keep (it must never be dropped silently).
    virtual void write(const QString& fileName, MeshModel& mesh, int mask, FilterProgress& progress,
                       const std::function<void(const std::string&)>& log,
                       const std::function<void(const std::string&)>& warning) const = 0;
};

}  // namespace radml
