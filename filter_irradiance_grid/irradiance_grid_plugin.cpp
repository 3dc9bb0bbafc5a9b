#include "irradiance_grid_plugin.h"

MESHLAB_PLUGIN_NAME_EXPORTER(IrradianceGridPlugin)
