// The extra per-vertex blocks of a radiance PLY file that no plugin of ours interprets (anything but
// the PRT transfer "prt", e.g. a curvature or a user's own data), kept on the MeshLab layer so that
// opening and saving a .rply keeps them (docs/radiance-ply-format.md). Stored like the radiance and the
// transfer (row_indexed_attribute.h): MeshLab's own delete/compact filters keep the rows right, and
// vertices created by other filters have no row, which gatherExtraBlocks reports.
#pragma once

#include "io/radiance_mesh.h"

#include "meshlab_mesh.h"

#include <string>
#include <vector>

namespace radml {

bool hasExtraBlocks(CMeshO& mesh);
// Rows in the order of the live vertices. Precondition: every block has mesh.vn rows.
void attachExtraBlocks(CMeshO& mesh, std::vector<rad::NamedVertexBlock> blocks);
void removeExtraBlocks(CMeshO& mesh);
// The stored blocks (rows may not match the live vertices), empty when none.
std::vector<std::string> extraBlockPrefixes(CMeshO& mesh);

// The blocks for the live vertices in vertex-vector order. False with `why` (a sentence for the log
// naming the blocks, what happened and what to do) when some live vertex has no row (created by
// another filter after the file was opened); `out` is then empty.
bool gatherExtraBlocks(CMeshO& mesh, std::vector<rad::NamedVertexBlock>& out, std::string& why);

}  // namespace radml
