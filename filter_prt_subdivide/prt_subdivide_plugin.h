// Precomputed radiance transfer on a layer: shadowed diffuse transfer vectors ray-cast with Embree
// (Sloan et al. 2002), adaptive subdivision under a triangle budget and its uniform baseline
// (Křivánek et al. 2004), and relighting as vertex colours under an HDR environment map or a
// directional light. One filter per file; this class only registers them with the host.
#pragma once

#include "filter_plugin_base.h"

namespace radml {
std::unique_ptr<Filter> makeComputePrtTransferFilter();
std::unique_ptr<Filter> makeAdaptivePrtSubdivisionFilter();
std::unique_ptr<Filter> makeUniformPrtSubdivisionFilter();
std::unique_ptr<Filter> makePrtRelightingFilter();
}  // namespace radml

class PrtSubdividePlugin : public radml::FilterPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_FILTER_PLUGIN_IID)
    Q_INTERFACES(RADML_FILTER_INTERFACE)

public:
    PrtSubdividePlugin();
    QString pluginName() const override { return "FilterPrtSubdivide"; }
};
