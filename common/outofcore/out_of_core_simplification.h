// The whole out-of-core job of Granier et al. 2007 behind the MeshLab filter and
// tools/simplify_out_of_core: a PLY scan of any size is simplified by vertex clustering while it
// streams from disk (vertex_clustering.h, Lindstrom 2000), the simplified mesh gets a per-triangle
// texture atlas (bake/texture_atlas.h), and the ORIGINAL points are streamed through the simplified
// mesh's hierarchy into an object-space normal map (streamed_normal_map.h), written as an in-core
// bake writes it (bake/normal_map_bake.h: B_normal.png, B_bake.txt; docs/normal-map-baking.md).
// Memory and passes: docs/out-of-core.md.
#pragma once

#include "geometry/triangle_mesh.h"
#include "io/ply_stream_reader.h"
#include "outofcore/vertex_clustering.h"
#include "progress/progress_callback.h"

#include <cstddef>
#include <string>
#include <vector>

namespace rad {

struct OutOfCoreRequest {
    std::string plyPath;
    std::size_t targetTriangles = 100000;   // used when cellSize <= 0
    double cellSize = 0.0;                  // > 0: the grid's cell edge, in model units
    int textureSize = 4096;                 // power of two in [16, 16384]
    int bits = 16;                          // 8 or 16
    int gutterTexels = 4;                   // empty texels between charts of the atlas (0 to 64; 0: no texel shared, none empty)
    std::string outputBase;                 // B: writes B_normal.png and B_bake.txt
    ProgressCallback progress;
};

struct OutOfCoreReport {
    TriangleMesh mesh;                      // the simplified mesh, unit vertex normals
    std::vector<float> wedgeUv;             // 6 per face: the per-triangle atlas the map is laid out in
    PlyStreamInfo file;
    PlyStreamStats read;
    ClusteringStats clustering;
    bool normalsFromFile = false;           // else area-weighted normals of the original faces
    std::size_t pointsSplatted = 0, pointsWithoutNormal = 0;
    std::size_t chartTexels = 0, texelsWithPoints = 0, chartTexelsFilled = 0;
    std::string normalMapFile, descriptionFile;
    double clusteringSeconds = 0, splatSeconds = 0, fillSeconds = 0, writeSeconds = 0, totalSeconds = 0;  // splat: pass 2; fill: averaging and filling
};

// Cheap checks before anything is read beyond the header (the filter runs them first): throws
// BakeInputError (bake/texture_atlas.h) for a texture size, bits, gutter, target or output base
// that cannot work, and PlyStreamError for a file that cannot be read (its header is parsed).
void checkOutOfCoreRequest(const OutOfCoreRequest& request);

// Runs the job. Throws as checkOutOfCoreRequest, PlyStreamError while reading, BakeInputError when
// the target is so small that nothing survives the clustering (with the fix), OperationCancelled,
// std::runtime_error when a file cannot be written. The files are written under temporary names and
// renamed at the end: an error or a cancel leaves no file.
OutOfCoreReport simplifyOutOfCore(const OutOfCoreRequest& request);

}  // namespace rad
