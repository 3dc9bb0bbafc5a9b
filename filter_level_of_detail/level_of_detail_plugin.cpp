#include "level_of_detail_plugin.h"

MESHLAB_PLUGIN_NAME_EXPORTER(LevelOfDetailPlugin)
