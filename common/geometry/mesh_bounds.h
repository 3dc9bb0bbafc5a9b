// The bounding box of a set of positions and the largest distance of a position from its centre
// (the "bounding radius" the sample scene's lights and the shared fit's light distance are measured in).
#pragma once

#include <Eigen/Geometry>

#include <vector>

namespace rad {

struct MeshBounds {
    Eigen::AlignedBox3d box;          // empty for no positions
    double farthestFromCentre = 0.0;  // max |p - box.center()|
};

// positions: 3 floats per point.
MeshBounds meshBounds(const std::vector<float>& positions);

}  // namespace rad
