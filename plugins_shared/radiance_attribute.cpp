#include "radiance_attribute.h"

#include <vcg/complex/allocate.h>

namespace radml {
namespace {
using FieldPtr = std::shared_ptr<rad::RadianceField>;
using FieldHandle = CMeshO::PerMeshAttributeHandle<FieldPtr>;
using RowHandle = CMeshO::PerVertexAttributeHandle<RadianceRow>;

bool findHandles(CMeshO& mesh, FieldHandle& field, RowHandle& rows) {
    if (!vcg::tri::HasPerMeshAttribute(mesh, kRadianceFieldAttributeName) ||
        !vcg::tri::HasPerVertexAttribute(mesh, kRadianceRowAttributeName))
        return false;
    field = vcg::tri::Allocator<CMeshO>::FindPerMeshAttribute<FieldPtr>(mesh, kRadianceFieldAttributeName);
    rows = vcg::tri::Allocator<CMeshO>::FindPerVertexAttribute<RadianceRow>(mesh, kRadianceRowAttributeName);
    return vcg::tri::Allocator<CMeshO>::IsValidHandle(mesh, field) &&
           vcg::tri::Allocator<CMeshO>::IsValidHandle(mesh, rows) && field() != nullptr;
}
}  // namespace

bool hasRadiance(CMeshO& mesh) {
    FieldHandle field;
    RowHandle rows;
    return findHandles(mesh, field, rows);
}

void removeRadiance(CMeshO& mesh) {
    if (vcg::tri::HasPerMeshAttribute(mesh, kRadianceFieldAttributeName))
        vcg::tri::Allocator<CMeshO>::DeletePerMeshAttribute(mesh, kRadianceFieldAttributeName);
    if (vcg::tri::HasPerVertexAttribute(mesh, kRadianceRowAttributeName))
        vcg::tri::Allocator<CMeshO>::DeletePerVertexAttribute(mesh, kRadianceRowAttributeName);
}

void attachRadiance(CMeshO& mesh, rad::RadianceField field) {
    removeRadiance(mesh);
    auto fieldHandle = vcg::tri::Allocator<CMeshO>::AddPerMeshAttribute<FieldPtr>(mesh, kRadianceFieldAttributeName);
    auto rowHandle = vcg::tri::Allocator<CMeshO>::AddPerVertexAttribute<RadianceRow>(mesh, kRadianceRowAttributeName);
    std::int32_t row = 0;
    for (auto vi = mesh.vert.begin(); vi != mesh.vert.end(); ++vi)
        rowHandle[vi].row = vi->IsD() ? -1 : row++;
    fieldHandle() = std::make_shared<rad::RadianceField>(std::move(field));
}

const rad::RadianceField* storedRadiance(CMeshO& mesh) {
    FieldHandle field;
    RowHandle rows;
    return findHandles(mesh, field, rows) ? field().get() : nullptr;
}

std::int32_t radianceRow(CMeshO& mesh, const CVertexO& vertex) {
    FieldHandle field;
    RowHandle rows;
    if (!findHandles(mesh, field, rows)) return -1;
    return rows[vcg::tri::Index(mesh, &vertex)].row;
}

bool gatherRadiance(CMeshO& mesh, rad::RadianceField& out, std::string& why) {
    FieldHandle fieldHandle;
    RowHandle rows;
    if (!findHandles(mesh, fieldHandle, rows)) {
        why = missingRadianceAdvice();
        return false;
    }
    const rad::RadianceField& stored = *fieldHandle();
    const std::size_t perVertex = stored.coefficientsPerVertex();
    const std::int32_t storedRows = static_cast<std::int32_t>(stored.vertexCount());
    out = rad::RadianceField(stored.basis, static_cast<std::size_t>(mesh.vn), stored.reflected);
    std::size_t live = 0, missing = 0;
    for (auto vi = mesh.vert.begin(); vi != mesh.vert.end(); ++vi) {
        if (vi->IsD()) continue;
        const std::int32_t row = rows[vi].row;
        if (row < 0 || row >= storedRows) {
            ++missing;
            ++live;
            continue;
        }
        std::copy_n(stored.vertexCoefficients(row), perVertex, out.vertexCoefficients(live));
        std::copy_n(stored.frame(row), 6, out.frame(live));
        ++live;
    }
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
