#include "usable_normals.h"

#include "geometry/normal_repair.h"

namespace radml {

void makeNormalsUsable(FilterContext& context, const std::vector<float>& positions,
                       const std::vector<std::uint32_t>& faces, std::vector<float>& normals,
                       const std::string& layer) {
    const rad::NormalRepairCounts counts = rad::repairVertexNormals(positions, faces, normals);
    const std::size_t n = positions.size() / 3;
    if (n > 0 && counts.defaulted == n)
        throw Refusal((layer.empty() ? std::string() : "Layer '" + layer + "': ") +
                      formatLine("None of the %zu vertices has a usable normal and there are no faces to compute "
                                 "them from: compute normals first (Filters > Normals, Curvatures and Orientation > "
                                 "Compute normals for point sets).",
                                 n));
    if (counts.repaired() > 0)
        context.log((layer.empty() ? std::string() : "Layer '" + layer + "': ") + counts.describe() +
                    " for this filter (the layer's own normals are unchanged)");
}

}  // namespace radml
