#include "normal_bake_plugin.h"

MESHLAB_PLUGIN_NAME_EXPORTER(NormalBakePlugin)
