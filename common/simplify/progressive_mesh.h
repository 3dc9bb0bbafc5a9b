// Progressive meshes (Hoppe 1996; Vanhoey et al. 2015, sec. 4.5): the original radiance
// mesh plus the ordered list of collapses the simplifier applied, so that any level of detail
// between the original and the coarsest mesh can be extracted afterwards without simplifying again.
//
// Replay: after the first k steps, every original vertex stands for the survivor it was collapsed
// into (following removed -> survivor links); a face is kept when its three vertices still stand
// for three distinct vertices. For edge collapses this gives exactly the mesh the simplifier had
// after k steps (a face dies precisely when it contained both ends of a collapsed edge, and the
// link condition forbids duplicates). For full collapses the survivor's position, frame and RF
// coefficients after each step are recorded with the step (half-edge collapses never change them).
//
// File (docs/progressive-mesh-format.md): a text header then little-endian binary records, next to
// a radiance PLY holding the original mesh.
#pragma once

#include "errors/error_categories.h"

#include "io/atomic_file.h"
#include "io/radiance_mesh.h"
#include "simplify/edge_collapse.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rad {

class ProgressiveMeshError : public FileError {
public:
    using FileError::FileError;
};

struct ProgressiveRadianceMesh {
    RadianceMesh base;  // the original
    CollapseKind kind = CollapseKind::HalfEdge;
    std::vector<CollapseStep> steps;
    std::vector<std::uint32_t> faceCountAfter;  // alive faces after each step
    // Full collapses with radiance data: per step, the survivor's frame (6 floats) then its
    // coefficients (3 K floats); empty otherwise.
    std::vector<float> survivorRows;

    int rowFloats() const;  // 6 + 3 K for full collapses on a mesh with radiance, else 0
    std::size_t baseFaceCount() const { return base.faceCount(); }
    // The smallest step count whose mesh has at most `faces` faces (all steps when none has).
    std::size_t stepsForFaceCount(std::size_t faces) const;
    // The mesh after the first `stepCount` steps (clamped to steps.size()), compacted: per-vertex
    // arrays (normals, colours, quality, radiance, extra blocks) follow the surviving vertices.
    // For full collapses the survivor's normal is its RF normal (or, without radiance, unchanged).
    RadianceMesh extract(std::size_t stepCount) const;
};

// Records the steps of a simplification of `base`: pass the recorder as simplifyByEdgeCollapse's
// onStep. `field` is the RadianceField the metric updates (full collapses), or null; each step copies
// the survivor's row of it, and takes the face count from the step.
class ProgressiveRecorder {
public:
    ProgressiveRecorder(ProgressiveRadianceMesh& target, const RadianceField* field);
    void operator()(const CollapseStep& step);

private:
    ProgressiveRadianceMesh& target_;
    const RadianceField* field_;
};

// Writes `path` (the progressive records) and the original mesh as the radiance PLY `basePath`
// (stored in the header relative to path's folder when it lies in the same folder, else as given),
// with the hash of the base's bytes in the header: both files or neither (io/atomic_file.h), and a
// refusal (a name with white space, a folder in the way) before anything is written.
// Throws ProgressiveMeshError / RadiancePlyError on failure.
void writeProgressiveMesh(const std::string& path, const std::string& basePath, const ProgressiveRadianceMesh& mesh);
// The same, written to temporaries of `files` only: the caller commits them (with its other
// outputs) or drops them.
void stageProgressiveMesh(const std::string& path, const std::string& basePath, const ProgressiveRadianceMesh& mesh,
                          AtomicFileSet& files);
// Reads a progressive mesh and its base; throws ProgressiveMeshError with a message naming the
// problem: bad header, a size that does not match the records (overflow-safe), indices out of
// range, a position that is not finite or beyond kMaxCoordinateMagnitude, face counts that the
// replay of the collapses on the base does not give, and (format version 2) records or a base whose
// hash differs from the header's. Version 1 files (no hashes) are read with every other check.
ProgressiveRadianceMesh readProgressiveMesh(const std::string& path);

}  // namespace rad
