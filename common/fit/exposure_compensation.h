// Per-photograph exposure / white-balance compensation for "Fit Radiance Functions from Rasters". A
// camera in automatic mode scales each photograph's linear values by its own gain per channel;
// fitted as they are, those gains become fake view dependence. The gains are estimated in the log
// domain by weighted least squares over the points seen by at least two views, solved exactly (the
// points eliminated, a small linear system over the views; Huber-reweighted, dark and saturated
// samples left out), normalised to a geometric mean of 1 per channel, and divided out of the samples. The usual gain compensation of image stitching (e.g. Brown and Lowe's
// panoramas), per channel; the recipe is our own.
// Details: docs/fitting.md, "`common/fit/exposure_compensation.h`: how it works".
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
    int solves = 0;                         // weighted least-squares solves: 1 + the robust passes
};

// Throws std::invalid_argument on invalid options, or a sample whose view is >= viewCount.
ExposureGains solveExposureGains(const std::vector<ExposureSample>& samples, std::size_t viewCount,
                                 const ExposureOptions& options = {});

}  // namespace rad
