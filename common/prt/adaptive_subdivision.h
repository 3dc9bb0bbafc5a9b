// Adaptive subdivision of a mesh with per-vertex PRT transfer vectors under a triangle budget,
// Křivánek et al. 2004 sec. 3.2, Fig. 2 and Fig. 3: the worst triangle (by transfer_error_estimate.h)
// is split 1-to-4 at its edge midpoints until the budget is reached, the new vertices' transfer
// ray-cast through the oracle (never interpolated); refinement stays 1-irregular and T-vertices are
// removed afterwards, so the output is conforming and never exceeds the budget. Edges are matched by
// position, so attribute seams leave no T-junction; midpoints are exact averages, so every output
// face lies inside one input face (originFace), which the evaluation relies on.
// Details: docs/prt-subdivision.md, "Refinement rules", "Budget" and "Seams".
#pragma once

#include "progress/progress_callback.h"
#include "prt/transfer_error_estimate.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

// Transfer vectors of new vertices: positions and normals 3 floats each, `count` points; writes
// count * width floats to out. Called with small batches (the new vertices of one split operation)
// during the adaptive loop and with one large batch by the uniform subdivision; never with count 0
// (an operation that creates no vertex, e.g. splitting a triangle whose three edges are already
// split, does not call it).
using TransferOracle =
    std::function<void(const float* positions, const float* normals, std::size_t count, float* out)>;

// A mesh with unit per-vertex normals and `width` transfer floats per vertex.
struct PrtMesh {
    std::vector<float> positions;       // 3 per vertex
    std::vector<float> normals;         // 3 per vertex, unit
    std::vector<std::uint32_t> faces;   // 3 per triangle, counter-clockwise
    int width = 0;                      // floats per vertex in transfer
    std::vector<float> transfer;        // width per vertex

    std::size_t vertexCount() const { return positions.size() / 3; }
    std::size_t faceCount() const { return faces.size() / 3; }
};

struct AdaptiveSubdivisionOptions {
    TransferErrorMeasure measure = TransferErrorMeasure::ProbedRelative;  // the winner (README, PRT figures)
    double alpha = kDefaultNormalDivergenceAlpha;  // eq. 4 only
    // Triangles at or below it never enter the queue (a forced split, done to keep a finer neighbour
    // 1-irregular, may still split one).
    double threshold = 0.0;
    std::size_t triangleBudget = 0;                // max output faces (after T-vertex removal)
    // Fraction done = faces created / budget (progress/progress_callback.h; a stop request throws
    // OperationCancelled). May be empty.
    ProgressCallback progress;
};

enum class SubdivisionStop { BudgetReached, QueueEmpty };

struct SubdivisionResult {
    PrtMesh mesh;
    std::vector<float> faceError;              // per output face: its error estimate (same measure)
    std::vector<std::uint32_t> originFace;     // per output face: the input face containing it
    std::size_t regularSplits = 0;             // 1-to-4 splits (forced ones included)
    std::size_t forcedSplits = 0;              // of which done to keep neighbours 1-irregular
    std::size_t tVertexFixes = 0;              // triangles split by the Fig. 3b post-process
    std::size_t newVertices = 0;
    std::size_t probes = 0;                    // probed measures: midpoints ray-cast to estimate errors
    SubdivisionStop stop = SubdivisionStop::QueueEmpty;
    double largestRemainingError = 0.0;        // top of the queue when stopped (0 if empty)
};

// Throws std::invalid_argument when the mesh is invalid (sizes, indices, non-finite values, no
// faces), width < 1, the budget is below the input face count or above 2^30, the threshold/alpha is
// negative or not finite, or the oracle is empty. Input triangles must be non-degenerate and
// edge-manifold (checked by the caller, see checkPrtSubdivisionInput); the two cases that would
// break the refinement (a face with two corners at the same position, a position-edge of more than
// two faces) also throw std::invalid_argument. Zero-area faces with distinct corners are refined
// like any other.
SubdivisionResult subdivideAdaptively(const PrtMesh& input, const TransferOracle& oracle,
                                      const AdaptiveSubdivisionOptions& options);

// Baseline: regular 1-to-4 subdivision of EVERY triangle, as many levels L as fit the budget
// (faces * 4^L <= budget, L >= 0), new vertices ray-cast through the oracle, normals
// normalize(n_a + n_b) at midpoints. faceError filled with the same measure/alpha for comparison.
// Edges are matched by position as in the adaptive case. Throws like subdivideAdaptively (a budget
// below the input face count included); stop is BudgetReached. The oracle is not called when L = 0.
SubdivisionResult subdivideUniformly(const PrtMesh& input, const TransferOracle& oracle, std::size_t triangleBudget,
                                     TransferErrorMeasure measure = TransferErrorMeasure::NormalDivergence,
                                     double alpha = kDefaultNormalDivergenceAlpha);

// Empty string when the mesh can be subdivided; otherwise a sentence saying what is wrong and how
// to fix it in MeshLab: no faces, zero-area or repeated-vertex faces, non-manifold edges (an
// undirected position-edge used by more than two faces), missing or zero normals, non-finite
// values, transfer width mismatch.
std::string checkPrtSubdivisionInput(const PrtMesh& mesh);

}  // namespace rad
