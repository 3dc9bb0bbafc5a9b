// IO plugin for the Radiance PLY format (.rply, docs/radiance-ply-format.md): Debian's PLY reader
// drops unknown vertex properties, so per-vertex radiance coefficients need a reader of their own.
// The format itself is radiance_ply_format.h; this class only registers it with the host.
#pragma once

#include "io_plugin_base.h"

class RadianceIOPlugin : public radml::IoPluginBase {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(RADML_IO_PLUGIN_IID)
    Q_INTERFACES(RADML_IO_INTERFACE)

public:
    RadianceIOPlugin();
    QString pluginName() const override { return "IORadiance"; }
};
