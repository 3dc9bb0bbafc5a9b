// Radiance data onto a layer (Vanhoey et al. 2015): fitted from calibrated photographs (raster
// layers), created from an analytic material, and evaluated toward a viewpoint as vertex colours;
// the calibrated photographs themselves, imported from COLMAP, Metashape or nerfstudio; the
// view-dependent colour of a 3D Gaussian Splatting scene, transferred onto the vertices; and the
// radiance exported as glTF for other programs.
// One filter per file; this class only registers them with the host.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makeFitFromRastersFilter();
std::unique_ptr<Filter> makeCreateAnalyticRadianceFilter();
std::unique_ptr<Filter> makeRadianceToVertexColorFilter();
std::unique_ptr<Filter> makeImportCamerasFilter();
std::unique_ptr<Filter> makeExportGltfFilter();
std::unique_ptr<Filter> makeTransferGaussianSplatsFilter();
}  // namespace radml

class RadianceFitPlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    RadianceFitPlugin();
    QString pluginName() const override { return "FilterRadianceFit"; }
};
