#include "radiance_fit_plugin.h"

RadianceFitPlugin::RadianceFitPlugin() {
    addFilter(radml::makeFitFromRastersFilter());
    addFilter(radml::makeCreateAnalyticRadianceFilter());
    addFilter(radml::makeRadianceToVertexColorFilter());
    addFilter(radml::makeImportCamerasFilter());
    addFilter(radml::makeExportGltfFilter());
    addFilter(radml::makeTransferGaussianSplatsFilter());
}

MESHLAB_PLUGIN_NAME_EXPORTER(RadianceFitPlugin)
