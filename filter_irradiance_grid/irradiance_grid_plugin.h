// Indirect light cached in an irradiance vector grid (Granier et al. 2007). This class only
// registers the filters.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makeComputeIrradianceVectorGridFilter();
}  // namespace radml

class IrradianceGridPlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    IrradianceGridPlugin() { addFilter(radml::makeComputeIrradianceVectorGridFilter()); }
    QString pluginName() const override { return "FilterIrradianceGrid"; }
};
