#include "geometry/mesh_bounds.h"

#include <algorithm>

namespace rad {

MeshBounds meshBounds(const std::vector<float>& positions) {
    MeshBounds bounds;
    bounds.box.setEmpty();
    const std::size_t n = positions.size() / 3;
    const auto position = [&](std::size_t v) {
        return Eigen::Vector3d(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
    };
    for (std::size_t v = 0; v < n; ++v) bounds.box.extend(position(v));
    for (std::size_t v = 0; v < n; ++v)
        bounds.farthestFromCentre = std::max(bounds.farthestFromCentre, (position(v) - bounds.box.center()).norm());
    return bounds;
}

}  // namespace rad
