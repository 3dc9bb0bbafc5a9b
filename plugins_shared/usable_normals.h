// The normals a filter computes with, made usable for real scans (geometry/normal_repair.h): zero,
// tiny or non-finite vertex normals are repaired in the filter's own copy (the layer's normals are
// left as they are) and the repair is counted in the log. Refused only when there is nothing to
// take a normal from: no vertex has one and there are no faces (a point cloud without normals).
#pragma once

#include "filter.h"

#include <cstdint>
#include <string>
#include <vector>

namespace radml {

// `layer` (may be empty) names the layer in the log line when a filter reads several.
void makeNormalsUsable(FilterContext& context, const std::vector<float>& positions,
                       const std::vector<std::uint32_t>& faces, std::vector<float>& normals,
                       const std::string& layer = {});

}  // namespace radml
