#include "io_radiance_plugin.h"

#include "radiance_ply_format.h"

RadianceIOPlugin::RadianceIOPlugin() : radml::IoPluginBase(std::make_unique<radml::RadiancePlyFormat>()) {}

MESHLAB_PLUGIN_NAME_EXPORTER(RadianceIOPlugin)
