#include "out_of_core_plugin.h"

MESHLAB_PLUGIN_NAME_EXPORTER(OutOfCorePlugin)
