// The extra blocks kept on a CMeshO (plugins_shared/extra_blocks_attribute.h) and their way through
// importPlainMesh / exportPlainMesh, with vcglib's own delete, compact and append doing the edits.
#include "extra_blocks_attribute.h"
#include "mesh_conversion.h"
#include "transfer_attribute.h"

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/allocate.h>

#include <gtest/gtest.h>

namespace {

// A strip of n vertices (x = v) and n - 2 triangles, with a block 'curvature' (values 10 v, 10 v + 1)
// and a 'prt' block whose metadata do not describe a transfer field.
rad::RadianceMesh strip(std::size_t n) {
    rad::RadianceMesh m;
    for (std::size_t v = 0; v < n; ++v) m.positions.insert(m.positions.end(), {float(v), 0.0f, 0.0f});
    for (std::size_t f = 0; f + 2 < n; ++f)
        m.faces.insert(m.faces.end(), {std::uint32_t(f), std::uint32_t(f + 1), std::uint32_t(f + 2)});
    rad::NamedVertexBlock curvature;
    curvature.prefix = "curvature";
    curvature.width = 2;
    for (std::size_t v = 0; v < n; ++v) curvature.values.insert(curvature.values.end(), {10.0f * v, 10.0f * v + 1});
    curvature.metadata["unit"] = "1/m";
    rad::NamedVertexBlock prt;
    prt.prefix = "prt";
    prt.width = 3;
    prt.values.assign(3 * n, 0.5f);
    prt.metadata["kind"] = "not a transfer";
    m.extraBlocks = {prt, curvature};
    return m;
}

}  // namespace

TEST(ExtraBlocksAttribute, ImportKeepsEveryUninterpretedBlockAndExportWritesItBack) {
    CMeshO mesh;
    std::string warning;
    radml::importPlainMesh(strip(5), mesh, &warning);
    EXPECT_NE(warning.find("The block is kept as it is and saved again unchanged"), std::string::npos) << warning;
    EXPECT_FALSE(radml::hasTransfer(mesh));
    EXPECT_EQ(radml::extraBlockPrefixes(mesh), (std::vector<std::string>{"prt", "curvature"}));

    radml::ExportChoice choice;
    choice.extraBlocks = true;
    rad::RadianceMesh out;
    std::string why;
    std::vector<std::string> leftOut;
    ASSERT_TRUE(radml::exportPlainMesh(mesh, choice, out, why, &leftOut)) << why;
    EXPECT_TRUE(leftOut.empty());
    ASSERT_EQ(out.extraBlocks.size(), 2u);
    EXPECT_EQ(out.extraBlocks[0].prefix, "prt");
    EXPECT_EQ(out.extraBlocks[1].values, (std::vector<float>{0, 1, 10, 11, 20, 21, 30, 31, 40, 41}));
    EXPECT_EQ(out.extraBlocks[1].metadata.at("unit"), "1/m");

    // Filters export without them unless they ask.
    ASSERT_TRUE(radml::exportPlainMesh(mesh, radml::ExportChoice{}, out, why));
    EXPECT_TRUE(out.extraBlocks.empty());
}

TEST(ExtraBlocksAttribute, RowsFollowVcgDeleteAndCompact) {
    CMeshO mesh;
    radml::importPlainMesh(strip(5), mesh);
    // Delete vertex 1 and the faces using it, then compact, as MeshLab's filters do.
    for (auto& f : mesh.face)
        if (!f.IsD() && (f.V(0) == &mesh.vert[1] || f.V(1) == &mesh.vert[1] || f.V(2) == &mesh.vert[1]))
            vcg::tri::Allocator<CMeshO>::DeleteFace(mesh, f);
    vcg::tri::Allocator<CMeshO>::DeleteVertex(mesh, mesh.vert[1]);
    vcg::tri::Allocator<CMeshO>::CompactEveryVector(mesh);
    ASSERT_EQ(mesh.vn, 4);

    radml::ExportChoice choice;
    choice.extraBlocks = true;
    rad::RadianceMesh out;
    std::string why;
    ASSERT_TRUE(radml::exportPlainMesh(mesh, choice, out, why)) << why;
    ASSERT_EQ(out.extraBlocks.size(), 2u);
    // Vertices 0, 2, 3, 4 of the strip, in that order.
    EXPECT_EQ(out.extraBlocks[1].values, (std::vector<float>{0, 1, 20, 21, 30, 31, 40, 41}));
}

TEST(ExtraBlocksAttribute, NewVerticesLeaveTheBlocksOutWithASentence) {
    CMeshO mesh;
    radml::importPlainMesh(strip(5), mesh);
    vcg::tri::Allocator<CMeshO>::AddVertices(mesh, 2);

    radml::ExportChoice choice;
    choice.extraBlocks = true;
    rad::RadianceMesh out;
    std::string why;
    std::vector<std::string> leftOut;
    ASSERT_TRUE(radml::exportPlainMesh(mesh, choice, out, why, &leftOut)) << why;
    EXPECT_TRUE(out.extraBlocks.empty());
    ASSERT_EQ(leftOut.size(), 1u);
    EXPECT_NE(leftOut[0].find("the extra vertex blocks 'prt', 'curvature' of the opened file cannot be saved: 2 of 7 "
                              "vertices were created after the file was opened"),
              std::string::npos)
        << leftOut[0];
}

TEST(ExtraBlocksAttribute, ANewImportReplacesTheOldBlocks) {
    CMeshO mesh;
    radml::importPlainMesh(strip(5), mesh);
    rad::RadianceMesh plain = strip(3);
    plain.extraBlocks.clear();
    radml::importPlainMesh(plain, mesh);
    EXPECT_FALSE(radml::hasExtraBlocks(mesh));
    EXPECT_TRUE(radml::extraBlockPrefixes(mesh).empty());
}
