// Stateless level of detail: the POP buffer (Limper et al. 2013) with the texture-coordinate
// correction of Weber & Stamminger. This class only registers the filters.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makePopBufferLevelsFilter();
}  // namespace radml

class LevelOfDetailPlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    LevelOfDetailPlugin() { addFilter(radml::makePopBufferLevelsFilter()); }
    QString pluginName() const override { return "FilterLevelOfDetail"; }
};
