// Per-photograph exposure / white-balance compensation for "Fit Radiance Functions from Rasters".
//
// Real acquisitions rarely keep one exposure and one white balance: a camera in automatic mode
// scales each photograph's linear values by its own gain per colour channel. Fitted as they are,
// those gains become fake view dependence (a vertex looks brighter "from" the views that happened
// to be exposed longer). Model: the linear value of point p in view i, channel c, is
//     y_pic = g_ic x_pc,
// x_pc the point's colour (its view dependence is left to the per-vertex fit and treated here as
// noise), g_ic the view's gain. In the log domain, log y = log g + log x is linear; we solve it by
// alternating weighted means over the points seen by at least two views:
//     log x_pc = mean_i (log y_pic - log g_ic),   log g_ic = mean_p (log y_pic - log x_pc),
// then normalise every channel to a geometric mean of the gains of 1 (the model only fixes gains up
// to a common factor; this keeps the overall brightness of the photographs). The alternation is
// block coordinate descent on a convex quadratic, so it converges; a Huber reweighting (MAD scale of
// the log residuals) keeps highlights and misregistered samples from biasing the gains. Samples
// too dark for a meaningful logarithm or at saturation are left out (a clipped value says nothing
// about the gain). Views that share no usable point with any other view keep gain 1.
// This is the usual gain compensation of image stitching and multi-view texturing (e.g. Brown and
// Lowe's panorama gain compensation), here per channel in the log domain; our own recipe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rad {

// One observation: point `point` seen in view `view` with linear RGB `rgb` and weight `weight` (> 0).
struct ExposureSample {
    std::uint32_t point;
    std::uint32_t view;
    float rgb[3];
    float weight;
};

struct ExposureOptions {
    double darkLevel = 0.005;        // linear values below this are too dark to use (log noise)
    double saturationLevel = 0.955;  // linear values at or above this are clipped (sRGB code 250)
    int maxIterations = 200;         // alternations (each is cheap: two passes over the samples)
    double tolerance = 1e-7;         // stop when no log gain moves more than this
    int robustPasses = 2;            // Huber reweightings after the first convergence (0: plain L2)
    double huberThreshold = 1.345;   // in units of the MAD scale of the log residuals

    std::string validate() const;
};

struct ExposureGains {
    // 3 per view (channel-major within a view): divide a view's linear values by them.
    std::vector<double> gains;
    std::vector<std::uint8_t> constrained;  // per view: 1 when its gains were estimated, 0 when left 1
    std::size_t samplesUsed = 0;            // samples of points seen by >= 2 views, usable in every channel
    std::size_t pointsUsed = 0;
    int iterations = 0;
};

// Throws std::invalid_argument on invalid options, or a sample whose view is >= viewCount.
ExposureGains solveExposureGains(const std::vector<ExposureSample>& samples, std::size_t viewCount,
                                 const ExposureOptions& options = {});

}  // namespace rad
