// The exact radiance of a virtual scene (virtual_scene.h) at every vertex, projected onto a basis:
// radiance data with known ground truth and no photographs, for the simplification benchmarks and
// the main job (Vanhoey et al. 2015 Fig. 7-8 compare simplifications of such fields).
#pragma once

#include "acquisition/virtual_scene.h"
#include "progress/progress_callback.h"
#include "radiance/radiance_field.h"

#include <functional>

namespace rad {

// One RF per scene vertex: the L2 projection (radiance_projection.h, FunctionProjector) of
// w -> scene.radiance(p_v, n_v, w), with the vertex frame frameFromNormal(n_v). Cast shadows are
// included when the scene has them (each evaluation then casts one shadow ray per light).
// Parallel over vertices (OpenMP); progress as in progress/progress_callback.h (may be empty).
RadianceField sceneRadianceField(const VirtualScene& scene, const BasisSpec& basis, bool reflected,
                                 const ProgressCallback& progress = {});

}  // namespace rad
