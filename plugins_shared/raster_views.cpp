#include "raster_views.h"

#include "shot_conversion.h"

namespace radml {

namespace {

// A view on a 32-bit QImage: Qt stores Format_RGB32 / ARGB32 pixels as 0xAARRGGBB words, i.e.
// bytes B, G, R, A in memory on little-endian machines (and A, R, G, B on big-endian ones).
rad::ImageView8 viewOf(const QImage& image) {
    rad::ImageView8 view;
    view.data = image.constBits();
    view.width = image.width();
    view.height = image.height();
    view.rowStride = image.bytesPerLine();
    view.pixelStride = 4;
    if (Q_BYTE_ORDER == Q_LITTLE_ENDIAN) {
        view.channelOffset[0] = 2;
        view.channelOffset[1] = 1;
        view.channelOffset[2] = 0;
    } else {
        view.channelOffset[0] = 1;
        view.channelOffset[1] = 2;
        view.channelOffset[2] = 3;
    }
    return view;
}

bool isWordRgbFormat(QImage::Format f) {
    return f == QImage::Format_RGB32 || f == QImage::Format_ARGB32 || f == QImage::Format_ARGB32_Premultiplied;
}

}  // namespace

RasterViews collectRasterViews(MeshDocument& md, bool visibleOnly) {
    RasterViews out;
    // First pass: which rasters, and their converted images (kept in `converted` before any view
    // points into it, so that growing the vector cannot move an image a view already uses).
    std::vector<RasterModel*> chosen;
    for (RasterModel* raster : documentRasters(md))
        if (raster != nullptr && (!visibleOnly || rasterIsVisible(*raster))) chosen.push_back(raster);
    out.rasterCount = chosen.size();
    out.converted.reserve(chosen.size());
    for (RasterModel* raster : chosen) {
        const QString label = raster->label();
        const RasterImagePlane* plane = raster->currentPlane;
        if (plane == nullptr || plane->image.isNull()) {
            const QString file = plane ? plane->fullPathFileName : QString("(none)");
            out.warnings.push_back(("raster '" + label + "' skipped: its image '" + file +
                                    "' could not be read (missing or not an image file); fix the path in the project")
                                       .toStdString());
            continue;
        }
        rad::PinholeCamera camera;
        const std::string problem = pinholeFromShot(raster->shot, camera);
        if (!problem.empty()) {
            out.warnings.push_back("raster '" + label.toStdString() + "' skipped: " + problem);
            continue;
        }
        if (camera.width != plane->image.width() || camera.height != plane->image.height()) {
            out.warnings.push_back("raster '" + label.toStdString() + "' skipped: its camera is for a " +
                                   std::to_string(camera.width) + " x " + std::to_string(camera.height) +
                                   " image but the image is " + std::to_string(plane->image.width()) + " x " +
                                   std::to_string(plane->image.height()));
            continue;
        }
        rad::CalibratedView view;
        view.camera = camera;
        if (isWordRgbFormat(plane->image.format())) {
            view.image = viewOf(plane->image);
        } else {
            out.converted.push_back(plane->image.convertToFormat(QImage::Format_RGB32));
            view.image = viewOf(out.converted.back());
        }
        out.views.push_back(view);
        out.labels.push_back(label);
    }
    return out;
}

}  // namespace radml
