// Out-of-core simplification of a scan read from disk, with the normal map streamed from its points
// (Lindstrom 2000, Granier et al. 2007). This class only registers the filter.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makeOutOfCoreSimplificationFilter();
}  // namespace radml

class OutOfCorePlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    OutOfCorePlugin() { addFilter(radml::makeOutOfCoreSimplificationFilter()); }
    QString pluginName() const override { return "FilterOutOfCore"; }
};
