#include "extra_blocks_attribute.h"

#include "row_indexed_attribute.h"

#include <algorithm>

namespace radml {
namespace {
using Blocks = std::vector<rad::NamedVertexBlock>;
const RowIndexedAttribute<Blocks> kBlocksAttribute("extra_vertex_blocks", "extra_vertex_blocks_row");

std::string prefixList(const Blocks& blocks) {
    std::string names;
    for (const auto& b : blocks) names += (names.empty() ? "'" : ", '") + b.prefix + "'";
    return names;
}
}  // namespace

bool hasExtraBlocks(CMeshO& mesh) { return kBlocksAttribute.present(mesh); }

void attachExtraBlocks(CMeshO& mesh, Blocks blocks) { kBlocksAttribute.attach(mesh, std::move(blocks)); }

void removeExtraBlocks(CMeshO& mesh) { kBlocksAttribute.remove(mesh); }

std::vector<std::string> extraBlockPrefixes(CMeshO& mesh) {
    std::vector<std::string> prefixes;
    if (const Blocks* stored = kBlocksAttribute.stored(mesh))
        for (const auto& b : *stored) prefixes.push_back(b.prefix);
    return prefixes;
}

bool gatherExtraBlocks(CMeshO& mesh, Blocks& out, std::string& why) {
    out.clear();
    const Blocks* stored = kBlocksAttribute.stored(mesh);
    if (stored == nullptr || stored->empty()) return true;
    const std::size_t n = static_cast<std::size_t>(mesh.vn);
    std::size_t storedRows = 0;
    if (stored->front().width > 0) storedRows = stored->front().values.size() / static_cast<std::size_t>(stored->front().width);
    Blocks blocks = *stored;
    for (auto& b : blocks) b.values.assign(n * static_cast<std::size_t>(b.width), 0.0f);
    const long long missing = kBlocksAttribute.forEachLiveRow(mesh, storedRows, [&](std::size_t row, std::size_t live) {
        for (std::size_t i = 0; i < blocks.size(); ++i) {
            const std::size_t w = static_cast<std::size_t>(blocks[i].width);
            std::copy_n((*stored)[i].values.data() + row * w, w, blocks[i].values.data() + live * w);
        }
    });
    if (missing > 0) {
        why = "the extra vertex block" + std::string(blocks.size() == 1 ? " " : "s ") + prefixList(blocks) +
              " of the opened file cannot be saved: " + std::to_string(missing) + " of " + std::to_string(n) +
              " vertices were created after the file was opened (by a filter that adds vertices) and have no "
              "values in " + (blocks.size() == 1 ? "it" : "them") +
              ". Save the layer before that filter to keep " + (blocks.size() == 1 ? "the block" : "the blocks") +
              ", or recompute them on the new mesh";
        return false;
    }
    out = std::move(blocks);
    return true;
}

}  // namespace radml
