// CMeshO, the mesh type of a MeshLab 2025.07 layer (double in pymeshlab's build).
#pragma once

#include <common/ml_document/cmesh.h>
