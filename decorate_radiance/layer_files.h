// Files that belong to a MeshLab layer, found beside the layer's file: the normal-map bake's
// description (the "Baked Normal Map" decoration) and the irradiance vector grid (the "Irradiance
// Vector Grid" decoration).
#pragma once

#include <common/meshmodel.h>

#include <string>

namespace raddecorate {

// The bake description (<base>_bake.txt) of the layer's texture, resolved like MeshLab resolves
// textures: an absolute name as it is, a relative one beside the layer's file, then in the working
// directory. Empty with `why` when the layer has no baked normal map.
std::string bakedMapOf(const MeshModel& m, std::string& why);

// The layer's irradiance vector grid: `explicitFile` when not empty (a relative name beside the
// layer's file), else the layer's file with its extension replaced by .ivg (the convention of the
// "Compute Irradiance Vector Grid" filter). Empty with `why` when the layer has no file and no
// explicit name is given. Existence is not checked (the reader says why it cannot read).
std::string irradianceGridPathOf(const MeshModel& m, const std::string& explicitFile, std::string& why);

}  // namespace raddecorate
