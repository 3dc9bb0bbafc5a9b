// CMeshO, the mesh type of a MeshLab 2020.09 layer (float).
#pragma once

#include <common/ml_mesh_type.h>
