// "Import Cameras as Raster Layers": photographs calibrated by COLMAP (binary or text model), Agisoft
// Metashape (camera XML) or nerfstudio (transforms.json) become raster layers with exact pinhole
// cameras. The cores read the file (common/cameras/camera_file.h) and undistort the photographs
// (common/cameras/image_undistortion.h); this adapter finds the photographs, decodes them (the
// cores' JPEG / PNG reader, EXIF orientation applied: pymeshlab's Qt has no JPEG plugin), keeps the
// pinhole images in a cache folder, and adds the layers only once every photograph was read and
// made (all or nothing).
#include "radiance_fit_plugin.h"

#include "shot_conversion.h"

#include "cameras/camera_file.h"
#include "cameras/image_undistortion.h"
#include "image/exif_orientation.h"
#include "image/image_io.h"
#include "image/parallel_png_encoder.h"
#include "io/atomic_file.h"

#include <QDateTime>
#include <QDir>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QImage>

#include <algorithm>
#include <type_traits>

namespace radml {
namespace {

// One photograph on its way to a raster layer.
struct PlannedRaster {
    rad::ImportedCamera camera;
    QString photograph;          // the photograph's path
    int orientation = 1;         // the EXIF orientation applied when decoding (1: none)
    bool reoriented = false;     // whether it changes the pixels
    rad::UndistortionPlan plan;  // at the (oriented) photograph's size
    QString shown;               // the file the layer shows: the photograph, or its pinhole image in the cache
    QImage image;                // decoded (step 3)
};

const char* const kImageExtensions[] = {"", ".jpg", ".JPG", ".jpeg", ".JPEG", ".png", ".PNG"};

// The photograph a camera names, in `folder`: the name as written, else with a usual image
// extension (Metashape's camera labels usually have none). Empty when none exists.
QString findPhotograph(const QDir& folder, const std::string& name) {
    for (const char* extension : kImageExtensions) {
        const QString path = folder.filePath(QString::fromStdString(name) + extension);
        if (QFileInfo(path).isFile()) return path;
    }
    return {};
}

// Step 1 for one camera: the photograph found, its size and orientation read (without decoding it),
// the undistortion planned. Empty on success, else what is wrong.
std::string planRaster(const QDir& folder, PlannedRaster& r) {
    r.photograph = findPhotograph(folder, r.camera.imageName);
    if (r.photograph.isEmpty())
        return "image '" + r.camera.imageName + "' is not in the image folder '" + folder.absolutePath().toStdString() + "'";
    const std::string path = r.photograph.toStdString();
    int width = 0, height = 0;
    try {
        rad::readImageSize(path, width, height);
    } catch (const rad::ImageFileError& e) {
        return std::string(e.what()) + " (JPEG and PNG photographs are read)";
    }
    // The calibration describes the photograph as it is shown, EXIF orientation applied; a tool that
    // ignored the orientation (COLMAP reads the stored pixels) calibrated the stored size instead,
    // which tells the two apart when the orientation turns the image by 90 degrees.
    const int orientation = rad::readExifOrientation(path);
    const bool swap = rad::orientationSwapsAxes(orientation);
    const int shownWidth = swap ? height : width, shownHeight = swap ? width : height;
    if (r.camera.sizedByPhotograph()) {  // a field of view only (the original NeRF's camera_angle_x)
        r.camera.takeSizeFromPhotograph(shownWidth, shownHeight);
        if (std::string problem = r.camera.validate(); !problem.empty()) return problem;
    }
    std::string problem = rad::imageSizeProblem(r.camera, shownWidth, shownHeight);
    r.orientation = orientation;
    int usedWidth = shownWidth, usedHeight = shownHeight;
    if (!problem.empty() && swap && rad::imageSizeProblem(r.camera, width, height).empty()) {
        problem.clear();
        r.orientation = 1;
        usedWidth = width;
        usedHeight = height;
    }
    if (!problem.empty()) return problem;
    r.reoriented = r.orientation != 1;
    r.plan = rad::planUndistortion(r.camera, usedWidth, usedHeight);
    return {};
}

// A photograph decoded (once) and turned as its EXIF orientation asks; throws Refusal.
rad::Image8 decodePhotograph(const PlannedRaster& r) {
    rad::Image8 image;
    try {
        image = rad::applyExifOrientation(rad::readImage8(r.photograph.toStdString()), r.orientation);
    } catch (const rad::ImageFileError& e) {
        throw Refusal(std::string(e.what()) + "; replace the file");
    }
    if (image.width != r.plan.target.width || image.height != r.plan.target.height)
        throw Refusal("image '" + r.photograph.toStdString() + "' decodes to another size than its header says; replace the file");
    return image;
}

QImage toQImage(const rad::Image8& image) {
    QImage out(image.width, image.height, QImage::Format_RGB32);
    for (int row = 0; row < image.height; ++row) {
        QRgb* line = reinterpret_cast<QRgb*>(out.scanLine(row));
        const std::uint8_t* in = image.rgb.data() + std::size_t(row) * image.width * 3;
        for (int c = 0; c < image.width; ++c) line[c] = qRgb(in[3 * c], in[3 * c + 1], in[3 * c + 2]);
    }
    return out;
}

class ImportCamerasFilter : public Filter {
public:
    QString name() const override { return "Import Cameras as Raster Layers"; }
    QString pythonName() const override { return "radiance_import_cameras_as_rasters"; }
    QString description() const override {
        return "Adds one raster layer per calibrated photograph of a <b>COLMAP</b> sparse model (binary "
               "<i>cameras.bin</i> + <i>images.bin</i> or text <i>cameras.txt</i> + <i>images.txt</i>; give the folder or "
               "one of its files), an <b>Agisoft Metashape</b> camera XML or a <b>nerfstudio</b> <i>transforms.json</i>. "
               "Photographs with lens distortion are undistorted exactly (the lens model applied to each pixel of the "
               "pinhole image, one bilinear resampling) into a cache folder, so that every filter sees exact pinhole "
               "cameras; images resized from the calibrated size are accepted, EXIF orientation is honoured. Disabled "
               "or unaligned cameras are skipped and counted. Nothing is added unless every photograph is found and "
               "usable. Conventions: docs/design-notes.md, \"Importing cameras\".";
    }
    int filterClass() const override { return 0x40000 | 0x00400; /* Camera | RasterLayer */ }
    int postconditions() const override { return MeshModel::MM_NONE; }
    bool needsCurrentLayer() const override { return false; }
    RichParameterList parameters(const MeshDocument& md, const MeshModel&) const override { return parametersWithoutLayer(md); }
    RichParameterList parametersWithoutLayer(const MeshDocument&) const override {
        RichParameterList par;
        addOpenFileParameter(par, "camerafile", "",
                             QStringList() << "*.bin" << "*.txt" << "*.xml" << "*.json",
                             "Camera file",
                             "A COLMAP model folder or one of its files (cameras.bin, images.bin, cameras.txt, "
                             "images.txt), a Metashape camera XML (File > Export > Export Cameras), or a nerfstudio "
                             "transforms.json.");
        par.addParam(RichString("imagefolder", "", "Image folder",
                                "The folder the camera file's image names are relative to (COLMAP: the images folder "
                                "given to COLMAP). Empty: the camera file's folder."));
        par.addParam(RichString("cachefolder", "", "Undistorted image folder",
                                "Where the undistorted (pinhole) images are kept, named by the image and a hash of its "
                                "calibration, so a changed calibration is never served a stale image. Empty: "
                                "'undistorted' inside the image folder."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        QElapsedTimer timer;
        timer.start();
        const QString cameraFile = ctx.parameters.getOpenFileName("camerafile").trimmed();
        if (cameraFile.trimmed().isEmpty())
            throw Refusal("Camera file: none given; give a COLMAP model folder or file, a Metashape XML or a nerfstudio "
                          "transforms.json.");
        QString imageFolder = ctx.parameters.getString("imagefolder");
        if (imageFolder.trimmed().isEmpty()) {
            const QFileInfo info(cameraFile);
            imageFolder = info.isDir() ? info.absoluteFilePath() : info.absolutePath();
        }
        const QDir images(imageFolder);
        if (!images.exists())
            throw Refusal("Image folder '" + imageFolder.toStdString() + "' does not exist; give the folder that holds the photographs.");
        QString cacheFolder = ctx.parameters.getString("cachefolder");
        if (cacheFolder.trimmed().isEmpty()) cacheFolder = images.filePath("undistorted");

        // 1. The camera file, read and validated whole.
        ctx.progress.setPhase(0, 5, "Reading cameras");
        const rad::CameraImport imported = rad::readCameraFile(cameraFile.toStdString());
        ctx.log(formatLine("%s '%s': %zu cameras usable, %zu skipped.", imported.format.c_str(),
                           cameraFile.toStdString().c_str(), imported.cameras.size(), imported.skipped.size()));
        for (std::size_t i = 0; i < imported.skipped.size() && i < 20; ++i) ctx.log("Skipped: " + imported.skipped[i]);
        if (imported.skipped.size() > 20) ctx.log(formatLine("... and %zu more skipped.", imported.skipped.size() - 20));

        // 2. Every photograph found and its size checked before anything is decoded.
        std::vector<PlannedRaster> rasters(imported.cameras.size());
        std::vector<std::string> problems;
        for (std::size_t i = 0; i < rasters.size(); ++i) {
            rasters[i].camera = imported.cameras[i];
            std::string problem;
            try {
                problem = planRaster(images, rasters[i]);
            } catch (const std::invalid_argument& e) {
                problem = e.what();
            }
            if (!problem.empty()) problems.push_back(problem);
        }
        if (!problems.empty()) {
            std::string list;
            for (std::size_t i = 0; i < problems.size() && i < 5; ++i) list += (i ? "; " : "") + problems[i];
            throw Refusal(formatLine("%zu of the %zu photographs cannot be used, nothing was imported: %s%s. Give the "
                                     "image folder and camera file of the same capture (the photographs the calibration "
                                     "was made with).",
                                     problems.size(), rasters.size(), list.c_str(), problems.size() > 5 ? "; ..." : ""));
        }

        // 3. The pinhole images: taken from the cache when made before, else made and written there.
        const bool anyMade = std::any_of(rasters.begin(), rasters.end(),
                                         [](const PlannedRaster& r) { return r.plan.resample || r.reoriented; });
        if (anyMade && !QDir().mkpath(cacheFolder))
            throw Refusal("Cannot create the undistorted image folder '" + cacheFolder.toStdString() +
                          "'; give a writable folder as 'Undistorted image folder' (cachefolder).");
        std::size_t made = 0, cached = 0, asIs = 0;
        double zoomMax = 1.0;
        for (std::size_t i = 0; i < rasters.size(); ++i) {
            PlannedRaster& r = rasters[i];
            const int begin = 5 + int(95 * i / rasters.size()), end = 5 + int(95 * (i + 1) / rasters.size());
            ctx.progress.setPhase(begin, end, "Undistorting photographs");
            if (!ctx.progress(0)) throw rad::OperationCancelled();
            if (!r.plan.resample && !r.reoriented) {
                r.image = toQImage(decodePhotograph(r));
                r.shown = r.photograph;
                ++asIs;
                continue;
            }
            zoomMax = std::max(zoomMax, r.plan.zoom);
            const QFileInfo source(r.photograph);
            const std::string identity = source.absoluteFilePath().toStdString() + "|" +
                                         std::to_string(source.size()) + "|" +
                                         std::to_string(source.lastModified().toMSecsSinceEpoch()) + "|" +
                                         "orientation " + std::to_string(r.orientation);
            r.shown = QDir(cacheFolder).filePath(
                QString::fromStdString(rad::undistortedFileName(r.camera.imageName, r.plan, identity)));
            if (QFileInfo(r.shown).isFile()) {
                QImage previous(r.shown);
                if (!previous.isNull() && previous.width() == r.plan.target.width &&
                    previous.height() == r.plan.target.height) {
                    r.image = previous.convertToFormat(QImage::Format_RGB32);
                    ++cached;
                    continue;
                }
            }
            rad::Image8 pixels = decodePhotograph(r);
            if (r.plan.resample) pixels = rad::undistortImage(pixels.view(), r.plan, ctx.progress.forCore());
            const std::vector<unsigned char> png = rad::encodePngParallel(pixels.rgb.data(), pixels.width, pixels.height, 3, 8, 1);
            try {
                rad::writeFileAtomically(r.shown.toStdString(), {{png.data(), png.size()}});
            } catch (const rad::AtomicFileError& e) {
                throw Refusal(std::string(e.what()) + " Give a writable 'Undistorted image folder' (cachefolder).");
            }
            r.image = toQImage(pixels);
            ++made;
        }

        // 4. The layers, all at once.
        for (PlannedRaster& r : rasters) {
            RasterModel* raster = addRasterLayer(ctx.document, QString::fromStdString(r.camera.imageName), r.image, r.shown);
            using ShotScalar = typename std::decay_t<decltype(raster->shot)>::ScalarType;
            raster->shot = shotFromPinhole<ShotScalar>(r.plan.target);
        }
        ctx.progress(100, "Done");
        ctx.log(formatLine("Added %zu raster layers in %.2f s: %zu photographs undistorted or reoriented into '%s', %zu "
                           "taken from there (made before for the same calibration), %zu used as they are (pinhole, "
                           "upright)%s.",
                           rasters.size(), timer.elapsed() / 1000.0, made, cacheFolder.toStdString().c_str(), cached, asIs,
                           zoomMax > 1.0 ? formatLine("; focal lengths zoomed by up to %.2f so that the undistorted "
                                                      "images stay inside the photographs", zoomMax).c_str()
                                         : ""));
    }
};

}  // namespace

std::unique_ptr<Filter> makeImportCamerasFilter() { return std::make_unique<ImportCamerasFilter>(); }

}  // namespace radml
