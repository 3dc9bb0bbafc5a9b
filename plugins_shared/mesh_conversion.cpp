#include "mesh_conversion.h"

#include "extra_blocks_attribute.h"
#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include <vcg/complex/allocate.h>
#include <wrap/io_trimesh/io_mask.h>

#include <algorithm>
#include <vector>

namespace radml {

bool exportPlainMesh(CMeshO& mesh, const ExportChoice& choice, rad::RadianceMesh& out, std::string& why,
                     std::vector<std::string>* leftOut) {
    out = rad::RadianceMesh{};
    std::vector<std::uint32_t> compactIndex(mesh.vert.size(), 0);
    const std::size_t n = static_cast<std::size_t>(mesh.vn);
    out.positions.reserve(3 * n);
    if (choice.normals) out.normals.reserve(3 * n);
    if (choice.colors) out.colors.reserve(4 * n);
    if (choice.quality) out.quality.reserve(n);
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < mesh.vert.size(); ++i) {
        const CVertexO& v = mesh.vert[i];
        if (v.IsD()) continue;
        compactIndex[i] = next++;
        for (int k = 0; k < 3; ++k) out.positions.push_back(v.cP()[k]);
        if (choice.normals)
            for (int k = 0; k < 3; ++k) out.normals.push_back(v.cN()[k]);
        if (choice.colors)
            for (int k = 0; k < 4; ++k) out.colors.push_back(v.cC()[k]);
        if (choice.quality) out.quality.push_back(v.cQ());
    }
    out.faces.reserve(3 * static_cast<std::size_t>(mesh.fn));
    for (const CFaceO& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k)
            out.faces.push_back(compactIndex[vcg::tri::Index(mesh, f.cV(k))]);
    }
    if (choice.radiance && hasRadiance(mesh)) {
        rad::RadianceField field;
        if (!gatherRadiance(mesh, field, why)) return false;
        // The file stores the radiance frame normal as the vertex normal (docs/radiance-ply-format.md).
        out.normals.resize(3 * n);
        for (std::size_t v = 0; v < n; ++v)
            for (int k = 0; k < 3; ++k) out.normals[3 * v + k] = field.frame(v)[3 + k];
        out.radiance = std::move(field);
    }
    if (choice.transfer && hasTransfer(mesh)) {
        StoredTransfer transfer;
        if (!gatherTransfer(mesh, transfer, why)) return false;
        out.extraBlocks.push_back(blockFromTransfer(transfer));
    }
    if (choice.extraBlocks && hasExtraBlocks(mesh)) {
        std::vector<rad::NamedVertexBlock> kept;
        std::string problem;
        if (!gatherExtraBlocks(mesh, kept, problem) && leftOut) leftOut->push_back(problem + ".");
        for (auto& block : kept) {
            const bool taken = std::any_of(out.extraBlocks.begin(), out.extraBlocks.end(),
                                           [&](const rad::NamedVertexBlock& b) { return b.prefix == block.prefix; });
            if (taken) {
                // Only "prt" can collide: a transfer computed since the file was opened replaces the
                // file's block that did not describe a transfer field.
                if (leftOut)
                    leftOut->push_back("The block '" + block.prefix + "' of the opened file was replaced by the PRT "
                                       "transfer vectors computed since.");
                continue;
            }
            out.extraBlocks.push_back(std::move(block));
        }
    }
    return true;
}

int importPlainMesh(const rad::RadianceMesh& in, CMeshO& mesh, std::string* warning) {
    mesh.Clear();
    const std::size_t n = in.vertexCount();
    int mask = vcg::tri::io::Mask::IOM_VERTCOORD | vcg::tri::io::Mask::IOM_FACEINDEX;
    auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(mesh, n);
    for (std::size_t v = 0; v < n; ++v, ++vi) {
        vi->P() = CMeshO::CoordType(in.positions[3 * v], in.positions[3 * v + 1], in.positions[3 * v + 2]);
        if (!in.normals.empty())
            vi->N() = CMeshO::CoordType(in.normals[3 * v], in.normals[3 * v + 1], in.normals[3 * v + 2]);
        if (!in.colors.empty())
            vi->C() = vcg::Color4b(in.colors[4 * v], in.colors[4 * v + 1], in.colors[4 * v + 2], in.colors[4 * v + 3]);
        else
            vi->C() = vcg::Color4b::White;
        vi->Q() = in.quality.empty() ? 0.0f : in.quality[v];
    }
    if (!in.normals.empty()) mask |= vcg::tri::io::Mask::IOM_VERTNORMAL;
    if (!in.colors.empty()) mask |= vcg::tri::io::Mask::IOM_VERTCOLOR;
    if (!in.quality.empty()) mask |= vcg::tri::io::Mask::IOM_VERTQUALITY;
    const std::size_t faceCount = in.faces.size() / 3;
    auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(mesh, faceCount);
    for (std::size_t f = 0; f < faceCount; ++f, ++fi)
        for (int k = 0; k < 3; ++k) fi->V(k) = &mesh.vert[in.faces[3 * f + k]];
    // Clear() keeps vcg's attributes: drop the old data unless `in` brings its own.
    if (in.radiance)
        attachRadiance(mesh, *in.radiance);
    else
        removeRadiance(mesh);
    removeTransfer(mesh);
    removeExtraBlocks(mesh);
    std::vector<rad::NamedVertexBlock> kept;  // carried as they are, so that a save writes them back
    for (const rad::NamedVertexBlock& block : in.extraBlocks) {
        if (block.prefix != kTransferBlockPrefix) {
            kept.push_back(block);
            continue;
        }
        std::string why;
        if (auto transfer = transferFromBlock(block, why)) {
            attachTransfer(mesh, std::move(*transfer));
        } else {
            kept.push_back(block);
            if (warning)
                *warning = "The PRT transfer vectors were not loaded: " + why +
                           ". The block is kept as it is and saved again unchanged; fix its metadata in the file "
                           "(or run 'Radiance: Compute PRT Transfer', which replaces it) to use it for relighting.";
        }
    }
    if (!kept.empty()) attachExtraBlocks(mesh, std::move(kept));
    return mask;
}

std::vector<float> exportWedgeTexCoords(const CMeshO& mesh) {
    std::vector<float> uv;
    uv.reserve(6 * std::size_t(mesh.fn));
    for (const CFaceO& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) {
            uv.push_back(f.cWT(k).U());
            uv.push_back(f.cWT(k).V());
        }
    }
    return uv;
}

std::vector<float> exportVertexTexCoordsAsWedges(const CMeshO& mesh) {
    std::vector<float> uv;
    uv.reserve(6 * std::size_t(mesh.fn));
    for (const CFaceO& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) {
            uv.push_back(f.cV(k)->cT().U());
            uv.push_back(f.cV(k)->cT().V());
        }
    }
    return uv;
}

}  // namespace radml
