// Normal-map baking from the full scan onto a simplified mesh (Granier et al. 2007), with LEAN
// covariance maps (Weber and Stamminger), and the out-of-core simplification with its streamed normal
// map (Granier et al. 2007, Lindstrom 2000). This class only registers the filters.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makeBakeNormalMapFilter();
std::unique_ptr<Filter> makeOutOfCoreSimplificationFilter();
}  // namespace radml

class NormalBakePlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    NormalBakePlugin() {
        addFilter(radml::makeBakeNormalMapFilter());
        addFilter(radml::makeOutOfCoreSimplificationFilter());
    }
    QString pluginName() const override { return "FilterNormalBake"; }
};
