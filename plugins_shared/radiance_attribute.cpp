#include "radiance_attribute.h"

#include "row_indexed_attribute.h"

namespace radml {
namespace {
const RowIndexedAttribute<rad::RadianceField> kRadianceAttribute(kRadianceFieldAttributeName,
                                                                 kRadianceRowAttributeName);
}  // namespace

bool hasRadiance(CMeshO& mesh) { return kRadianceAttribute.present(mesh); }

void removeRadiance(CMeshO& mesh) { kRadianceAttribute.remove(mesh); }

void attachRadiance(CMeshO& mesh, rad::RadianceField field) { kRadianceAttribute.attach(mesh, std::move(field)); }

const rad::RadianceField* storedRadiance(CMeshO& mesh) { return kRadianceAttribute.stored(mesh); }

std::int32_t radianceRow(CMeshO& mesh, const CVertexO& vertex) { return kRadianceAttribute.rowOf(mesh, vertex); }

bool gatherRadiance(CMeshO& mesh, rad::RadianceField& out, std::string& why) {
    const rad::RadianceField* stored = kRadianceAttribute.stored(mesh);
    if (stored == nullptr) {
        why = missingRadianceAdvice();
        return false;
    }
    const std::size_t perVertex = stored->coefficientsPerVertex();
    out = rad::RadianceField(stored->basis, static_cast<std::size_t>(mesh.vn), stored->reflected);
    const long long missing =
        kRadianceAttribute.forEachLiveRow(mesh, stored->vertexCount(), [&](std::size_t row, std::size_t live) {
            std::copy_n(stored->vertexCoefficients(row), perVertex, out.vertexCoefficients(live));
            std::copy_n(stored->frame(row), 6, out.frame(live));
        });
    if (missing > 0) {
        why = std::to_string(missing) + " of " + std::to_string(mesh.vn) +
              " vertices have no radiance function (they were created after the radiance data was "
              "made, e.g. by a subdivision or a merge). Recreate the radiance data on this mesh, or "
              "apply the geometry filter before creating it.";
        return false;
    }
    return true;
}

std::string missingRadianceAdvice() {
    return "The current mesh has no radiance data. Open a radiance PLY (.rply), or create data with "
           "'Radiance: Create Radiance Data from Analytic Material' (Filters > Color Creation and "
           "Processing), then run this filter again.";
}

}  // namespace radml
