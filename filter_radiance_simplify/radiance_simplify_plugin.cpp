#include "radiance_simplify_plugin.h"

MESHLAB_PLUGIN_NAME_EXPORTER(RadianceSimplifyPlugin)
