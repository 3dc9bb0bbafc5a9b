// Radiance-aware simplification of meshes carrying radiance functions (Vanhoey et al. 2015), with
// levels of detail from one progressive recording. This class only registers the filter.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makeRadianceSimplificationFilter();
}  // namespace radml

class RadianceSimplifyPlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    RadianceSimplifyPlugin() { addFilter(radml::makeRadianceSimplificationFilter()); }
    QString pluginName() const override { return "FilterRadianceSimplify"; }
};
