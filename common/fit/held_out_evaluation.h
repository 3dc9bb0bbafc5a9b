// Held-out photographs as the test of a fit: how well do the radiance functions fitted on some
// photographs predict a photograph they never saw, compared with two simpler answers (the vertex's
// mean colour, and the plain average of the training photographs' colours as MeshLab's colour
// projection blends them)? RMS errors in 8-bit sRGB levels per held-out view, over the vertices it
// sees that a training view saw too; as is and after the best per-channel gain of each prediction,
// since no prediction can know the exposure of a photograph it never saw.
// Details: docs/fitting.md, "`common/fit/held_out_evaluation.h`: how it works".
#pragma once

#include "fit/view_sampling.h"
#include "geometry/triangle_mesh.h"
#include "radiance/radiance_field.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

struct HeldOutViewError {
    std::size_t vertices = 0;  // vertices compared (0: the view sees nothing comparable)
    double fitted = 0.0;       // RMS error, 8-bit sRGB levels
    double constant = 0.0;
    double projection = 0.0;
    // The same after the best per-channel gain of each prediction (see the file comment).
    double fittedMatched = 0.0, constantMatched = 0.0, projectionMatched = 0.0;
};

struct HeldOutEvaluation {
    std::vector<HeldOutViewError> views;  // one per held-out view, in order
    std::size_t viewsCompared = 0;        // views with at least one compared vertex
    std::size_t fittedNotWorseThanConstant = 0;  // of viewsCompared: fitted <= constant
    double meanFitted = 0.0, meanConstant = 0.0, meanProjection = 0.0;  // over viewsCompared
    double meanRatioToProjection = 0.0;   // mean over viewsCompared of fitted / projection
    // The same statistics of the exposure-matched errors.
    std::size_t fittedNotWorseThanConstantMatched = 0;
    double meanFittedMatched = 0.0, meanConstantMatched = 0.0, meanProjectionMatched = 0.0;
    double meanRatioToProjectionMatched = 0.0;
};

// `field` and `meanColor` (3 linear floats per vertex) as fitRadianceFromViews returns them, on the
// same mesh; the views must pass checkView. Throws std::invalid_argument on inconsistent sizes or
// unusable views.
HeldOutEvaluation evaluateHeldOutViews(const TriangleMesh& mesh, const RadianceField& field,
                                       const std::vector<float>& meanColor,
                                       const std::vector<CalibratedView>& training,
                                       const std::vector<CalibratedView>& heldOut,
                                       const ViewSamplingOptions& sampling = {});

// Continuous IEC 61966-2-1 sRGB encoding of a linear value (clamped to [0, 1]) to [0, 255].
double srgbLevel(double linear);

}  // namespace rad
