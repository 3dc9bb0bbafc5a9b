// MeshLab raster layers -> calibrated views for the cores (common/fit/view_sampling.h): each
// raster's vcg::Shot becomes a rad::PinholeCamera (shot_conversion.h) and its current plane's
// QImage is viewed in place (no copy) as an ImageView8.
//
// A raster that cannot be used is skipped with a warning naming it: no image (file missing or
// unreadable when the project was opened), a camera we cannot convert, or a camera whose viewport
// is not the image's size. Whether anything usable remains is the caller's decision.
#pragma once

#include "fit/view_sampling.h"

#include <QImage>
#include "meshlab_host.h"

#include <string>
#include <vector>

namespace radml {

struct RasterViews {
    std::vector<rad::CalibratedView> views;
    std::vector<QString> labels;         // labels[i]: the raster behind views[i]
    std::vector<std::string> warnings;   // one sentence per skipped raster
    std::size_t rasterCount = 0;         // rasters considered (all, or only the visible ones)
    // Images converted to a 32-bit format when the raster's was not; the views point into them.
    std::vector<QImage> converted;
};

RasterViews collectRasterViews(MeshDocument& md, bool visibleOnly);

}  // namespace radml
