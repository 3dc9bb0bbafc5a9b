// Normal-map baking from the full scan onto a simplified mesh (Granier et al. 2007), with LEAN
// covariance maps (Weber and Stamminger). This class only registers the filter.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makeBakeNormalMapFilter();
}  // namespace radml

class NormalBakePlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    NormalBakePlugin() {
        addFilter(radml::makeBakeNormalMapFilter());
    }
    QString pluginName() const override { return "FilterNormalBake"; }
};
