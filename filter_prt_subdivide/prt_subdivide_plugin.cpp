#include "prt_subdivide_plugin.h"

PrtSubdividePlugin::PrtSubdividePlugin() {
    addFilter(radml::makeComputePrtTransferFilter());
    addFilter(radml::makeAdaptivePrtSubdivisionFilter());
    addFilter(radml::makeUniformPrtSubdivisionFilter());
    addFilter(radml::makePrtRelightingFilter());
}

MESHLAB_PLUGIN_NAME_EXPORTER(PrtSubdividePlugin)
