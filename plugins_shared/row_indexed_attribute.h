// Per-vertex data of a MeshLab layer (CMeshO) kept as ONE contiguous field per mesh plus a
// per-vertex row index: vcg keeps per-vertex attributes in step with the vertex vector (compaction,
// deletion, append), so any MeshLab filter that deletes or reorders vertices keeps the association
// right, and a vertex created by another filter (e.g. a subdivision) gets row -1, "no data", which
// gather() reports instead of inventing values. Used for the radiance functions
// (radiance_attribute.h) and the PRT transfer vectors (transfer_attribute.h).
#pragma once

#include "meshlab_mesh.h"
#include <vcg/complex/allocate.h>

#include <cstdint>
#include <memory>
#include <string>

namespace radml {

// Per-vertex attribute value; the default (-1) is what vertices created by other filters get.
struct VertexRow {
    std::int32_t row = -1;
};

template <class Field>
class RowIndexedAttribute {
public:
    RowIndexedAttribute(const char* fieldName, const char* rowName) : fieldName_(fieldName), rowName_(rowName) {}

    bool present(CMeshO& mesh) const {
        FieldHandle field;
        RowHandle rows;
        return find(mesh, field, rows);
    }

    void remove(CMeshO& mesh) const {
        if (vcg::tri::HasPerMeshAttribute(mesh, fieldName_))
            vcg::tri::Allocator<CMeshO>::DeletePerMeshAttribute(mesh, fieldName_);
        if (vcg::tri::HasPerVertexAttribute(mesh, rowName_))
            vcg::tri::Allocator<CMeshO>::DeletePerVertexAttribute(mesh, rowName_);
    }

    // Rows of `field` in the order of the live vertices (deleted ones skipped). Replaces old data.
    void attach(CMeshO& mesh, Field field) const {
        remove(mesh);
        auto fieldHandle = vcg::tri::Allocator<CMeshO>::template AddPerMeshAttribute<FieldPtr>(mesh, fieldName_);
        auto rowHandle = vcg::tri::Allocator<CMeshO>::template AddPerVertexAttribute<VertexRow>(mesh, rowName_);
        std::int32_t row = 0;
        for (auto vi = mesh.vert.begin(); vi != mesh.vert.end(); ++vi) rowHandle[vi].row = vi->IsD() ? -1 : row++;
        fieldHandle() = std::make_shared<Field>(std::move(field));
    }

    const Field* stored(CMeshO& mesh) const {
        FieldHandle field;
        RowHandle rows;
        return find(mesh, field, rows) ? field().get() : nullptr;
    }

    std::int32_t rowOf(CMeshO& mesh, const CVertexO& vertex) const {
        FieldHandle field;
        RowHandle rows;
        if (!find(mesh, field, rows)) return -1;
        return rows[vcg::tri::Index(mesh, &vertex)].row;
    }

    // Visits the live vertices in vertex-vector order: copyRow(storedRow, liveIndex) for each vertex
    // with data. Returns the number of live vertices without data (row -1 or out of range), or -1
    // when the mesh has no such attribute at all.
    template <class CopyRow>
    long long forEachLiveRow(CMeshO& mesh, std::size_t storedRows, CopyRow copyRow) const {
        FieldHandle field;
        RowHandle rows;
        if (!find(mesh, field, rows)) return -1;
        long long missing = 0;
        std::size_t live = 0;
        for (auto vi = mesh.vert.begin(); vi != mesh.vert.end(); ++vi) {
            if (vi->IsD()) continue;
            const std::int32_t row = rows[vi].row;
            if (row < 0 || static_cast<std::size_t>(row) >= storedRows)
                ++missing;
            else
                copyRow(static_cast<std::size_t>(row), live);
            ++live;
        }
        return missing;
    }

private:
    using FieldPtr = std::shared_ptr<Field>;
    using FieldHandle = typename CMeshO::template PerMeshAttributeHandle<FieldPtr>;
    using RowHandle = typename CMeshO::template PerVertexAttributeHandle<VertexRow>;

    bool find(CMeshO& mesh, FieldHandle& field, RowHandle& rows) const {
        if (!vcg::tri::HasPerMeshAttribute(mesh, fieldName_) || !vcg::tri::HasPerVertexAttribute(mesh, rowName_))
            return false;
        field = vcg::tri::Allocator<CMeshO>::template FindPerMeshAttribute<FieldPtr>(mesh, fieldName_);
        rows = vcg::tri::Allocator<CMeshO>::template FindPerVertexAttribute<VertexRow>(mesh, rowName_);
        return vcg::tri::Allocator<CMeshO>::IsValidHandle(mesh, field) &&
               vcg::tri::Allocator<CMeshO>::IsValidHandle(mesh, rows) && field() != nullptr;
    }

    const char* fieldName_;
    const char* rowName_;
};

}  // namespace radml
