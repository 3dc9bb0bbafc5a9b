// "Fit Radiance Functions from Rasters": per-vertex radiance functions (RF) of a whole mesh fitted
// on calibrated photographs (Vanhoey et al. 2015, sec. 7 "Data acquisition and reconstruction").
// The driver the MeshLab filter, the tools and the benchmarks call: it validates everything before
// any work, compensates each photograph's exposure, samples every view per vertex
// (fit/view_sampling.h), fits each vertex (fit/robust_radiance_fit.h) or the shared model
// (fit/shared_radiance_fit.h) in parallel (OpenMP, one sample buffer per thread), and fills the
// vertices no view sees from their neighbours. Unusable views are skipped with a warning; unusable
// input throws FitError (an InputError).
// Details: docs/fitting.md, "`common/fit/radiance_from_views.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include "fit/robust_radiance_fit.h"
#include "fit/shared_radiance_fit.h"
#include "fit/view_sampling.h"
#include "geometry/triangle_mesh.h"
#include "progress/progress_callback.h"
#include "radiance/radiance_field.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

// Thrown when the fit cannot run; what() is a sentence for the user (what is wrong, how to fix it).
struct FitError : InputError {
    using InputError::InputError;
};

// Which fit produces the radiance functions:
//  - PerVertex: each vertex alone (fit/robust_radiance_fit.h), streaming its samples;
//  - Shared: the shared diffuse + reflected-lobe model of fit/shared_radiance_fit.h, converted to
//    the basis with the per-vertex guard against the constant;
//  - Automatic: both are fitted on the training views minus every validationEvery-th one and
//    compared on those left out, VIEW BY VIEW (RMS error in 8-bit sRGB levels of the stored
//    functions at each left-out view's samples): Shared is chosen only when it is better pooled over
//    all left-out samples, better or equal in at least half of the left-out views, and in no
//    left-out view worse than the per-vertex fit by more than it gains pooled (or than maxViewLoss,
//    relative, when that is larger): sharedWinsOnLeftOutViews. Otherwise PerVertex (the safe choice:
//    a fit that wins on average but loses a whole view by more than it wins is not taken).
//    The chosen one is then fitted on every training view. Falls back to PerVertex when there are
//    fewer than 2 * validationEvery usable views. On meshes of more than 16k vertices the two
//    candidates are fitted and compared on patches of the surface (automaticChoiceVertices), about an
//    eighth of it and at least 8k vertices: the choice needs thousands of left-out samples per view,
//    and its cost was half of the automatic fit's.
enum class FitModel : std::uint8_t { PerVertex = 0, Shared = 1, Automatic = 2 };

struct RadianceFromViewsOptions {
    RobustFitOptions fit;           // basis, storage, regularisation, coverage, range guard, validation, IRLS
    FitModel model = FitModel::Automatic;
    SharedFitOptions shared;
    int validationEvery = 5;        // Automatic: every k-th usable view is left out of the comparison fit (>= 2)
    // Shared: vertices where the constant predicts the vertex's own left-out samples clearly better
    // than the shared function (SharedFitOptions::guardStandardErrors) get the per-vertex fit (which validates itself against the constant)
    // instead of the constant mean colour. Off by default: on six of seven Mitsuba captures the
    // constant is as good or better on held-out photographs and the fit takes a quarter less time
    // (docs/design-notes.md, "The vertices the shared fit does not win").
    bool sharedRejectedPerVertex = false;
    // Automatic: the relative loss of Shared in one left-out view always allowed (>= 0); a larger loss
    // is allowed up to Shared's pooled gain (sharedWinsOnLeftOutViews).
    double maxViewLoss = 0.02;
    ViewSamplingOptions sampling;   // depth tolerance, grazing angle, border margin
    bool fillUnseen = true;         // fill unseen vertices from their neighbours
    // Per-raster exposure / white-balance gains (fit/exposure_compensation.h), estimated on at most
    // exposurePoints vertices spread over the mesh, divided out of every sample before the fit.
    bool compensateExposure = true;
    std::size_t exposurePoints = 20000;
    // A sample with a channel at or above saturationLevel (linear; 0.955 = sRGB code 250) is clipped:
    // its value is a lower bound, not a measurement, so its weight is multiplied by saturatedWeight
    // (it keeps a say only where every sample of the vertex is clipped). Detected before the gains.
    double saturationLevel = 0.955;
    double saturatedWeight = 0.01;

    std::string validate() const;  // the fit's and sampling's checks plus these
};

struct RadianceFromViewsResult {
    // One RF per vertex: frames from the vertex normals, `reflected` = options.fit.storeReflected.
    RadianceField field;
    std::vector<float> meanColor;     // 3 per vertex, linear RGB (the diffuse colour)
    std::vector<float> sampleCount;   // per vertex: samples used (0 for unseen / filled)
    std::vector<float> residual;      // per vertex: weighted RMS residual of the samples (0 if none)
    std::vector<std::uint8_t> status; // per vertex: a FitStatus value
    std::size_t fitted = 0;           // status Fitted
    std::size_t poorlySampled = 0;    // status PoorlySampled
    std::size_t unseenFilled = 0;     // status FilledFromNeighbours
    std::size_t unseenLeft = 0;       // status Unseen: zero radiance
    std::size_t guardRetried = 0;     // vertices whose lambda the range guard escalated
    std::size_t constantFallbacks = 0;  // vertices given the constant mean colour (any reason below)
    // Of the seen vertices: a view-dependent function (not the constant); among them, those for
    // which validation chose a larger lambda or a lower degree than the user's.
    std::size_t viewDependent = 0;
    std::size_t regularised = 0;
    // Constant mean colour because validation preferred it (it predicted the vertex's left-out
    // views better), because of fewer than minSamples samples, or because the guard rejected every fit.
    std::size_t validatedConstant = 0;
    std::size_t tooFewSamples = 0;
    std::size_t guardConstant = 0;
    double medianSamples = 0.0;       // median samples per seen vertex
    std::size_t robustDownweighted = 0;  // samples the Huber IRLS gave a weight below 1
    std::size_t saturatedSamples = 0;    // samples at saturation (weight reduced)
    // Exposure compensation: 3 gains per input view (1 for skipped or unconstrained views).
    std::vector<double> viewGains;
    bool exposureCompensated = false;
    std::size_t exposureViews = 0;    // views whose gains were estimated
    std::size_t exposureSamples = 0;  // samples the estimate used
    std::size_t viewsUsed = 0;        // views that passed checkView
    std::vector<std::size_t> samplesPerView;  // per input view (0 for skipped views)
    std::size_t totalSamples = 0;
    std::vector<std::string> warnings;  // sentences for the log (skipped views, unseen parts...)
    double seconds = 0.0;             // wall-clock time of the whole call
    // Which fit was used (Shared or PerVertex) and, for Automatic, the comparison: RMS error in 8-bit
    // sRGB levels of each candidate on the samples of the left-out views (0 when not run).
    FitModel modelUsed = FitModel::PerVertex;
    bool modelValidated = false;
    std::size_t validationViews = 0, validationSamples = 0;
    std::size_t validationVertices = 0;  // vertices the candidates were fitted and compared on (automaticChoiceVertices)
    double validationPerVertex = 0.0, validationShared = 0.0, validationConstant = 0.0;
    // Per left-out view (views with samples only): how many Shared won or tied, and its worst ratio
    // shared / per-vertex RMS.
    std::size_t validationViewsSharedWins = 0, validationViewsCompared = 0;
    double validationWorstViewRatio = 0.0;
    std::size_t sharedVertices = 0;   // Shared: vertices given diffuse + scaled lobe (the others: constant)
    int lobeDegree = 0;               // Shared: SH degree of the reflected lobe
    // Shared: the lights' distance the lobe assumes, in bounding radii (SharedFitOptions::lightDistance;
    // infinity: distant lights).
    double lightDistance = std::numeric_limits<double>::infinity();
};

// mesh: positions, unit (or at least non-zero finite) per-vertex normals, faces (may be empty: a
// point cloud, sampled without visibility test and without filling).
// Throws FitError on unusable input (empty mesh, missing / zero / non-finite normals, non-finite
// positions, bad face indices, invalid options, no view or no usable view, no vertex seen at all);
// OperationCancelled when `progress` asks to stop (progress/progress_callback.h).
RadianceFromViewsResult fitRadianceFromViews(const TriangleMesh& mesh, const std::vector<CalibratedView>& views,
                                             const RadianceFromViewsOptions& options,
                                             const ProgressCallback& progress = {});

// Vertex adjacency over the face edges, compressed: the neighbours of v are
// neighbours[offsets[v] .. offsets[v + 1]), sorted, without duplicates. Faces must be valid.
struct VertexAdjacency {
    std::vector<std::size_t> offsets;
    std::vector<std::uint32_t> neighbours;
};
VertexAdjacency buildVertexAdjacency(const TriangleMesh& mesh);

// 1 for the vertices the automatic choice fits and compares its candidates on: every vertex up to
// 16k vertices; beyond, the vertices in the picked cells of a grid over the bounding box (the
// finest of 32, 16, 8 and 4 cells across with at least 64 vertices per occupied cell; one cell in
// n / max(8192, n / 8), picked by a hash of the cell's coordinates), so that neighbours stay
// together whatever the order of the vertices; every vertex again when the picked cells hold fewer
// than half of the share.
std::vector<std::uint8_t> automaticChoiceVertices(const TriangleMesh& mesh);

// The automatic choice's rule on its left-out comparison (RMS errors in sRGB levels, pooled over the
// left-out samples, and the worst view's ratio shared / per-vertex): true (Shared) when the shared
// fit is better pooled, better or equal in at least half of the views compared, and its worst view
// is not worse than the per-vertex fit's by more than the larger of maxViewLoss and its pooled gain
// (perVertexRms / sharedRms - 1). One view lost by a few per cent vetoes a shared fit that wins
// by less; a shared fit 13 % better pooled may lose one view of twelve by 11 % (a rough metal
// rendered by Cycles, where it also won every held-out view: docs/design-notes.md).
bool sharedWinsOnLeftOutViews(double perVertexRms, double sharedRms, std::size_t sharedWins,
                              std::size_t viewsCompared, double worstViewRatio, double maxViewLoss);
// The largest worst-view ratio shared / per-vertex that rule accepts: 1 + max(maxViewLoss, pooled gain).
double sharedWorstViewBound(double perVertexRms, double sharedRms, double maxViewLoss);

}  // namespace rad
