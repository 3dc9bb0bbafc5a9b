#include "radiance_fit_plugin.h"

RadianceFitPlugin::RadianceFitPlugin() {
    addFilter(radml::makeFitFromRastersFilter());
    addFilter(radml::makeCreateAnalyticRadianceFilter());
    addFilter(radml::makeRadianceToVertexColorFilter());
}

MESHLAB_PLUGIN_NAME_EXPORTER(RadianceFitPlugin)
