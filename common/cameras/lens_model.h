// The lens of a calibrated photograph, as the tools that calibrate real captures describe it (COLMAP,
// Agisoft Metashape, nerfstudio): it maps a point (x, y) = (X/Z, Y/Z) of the ideal pinhole image
// plane (x right, y down, z forward) to where the lens images it, in this order: 1. fisheye
// (equidistant); 2. FOV (Devernay and Faugeras 2001); 3. rational radial; 4. tangential
// (Brown-Conrady, OpenCV's order) and thin prism; 5. pixels, with focal lengths, principal point and
// skew. Pixel coordinates as camera/pinhole_camera.h: from the image's top-left CORNER, pixel (c, r)
// centred at (c + 0.5, r + 0.5).
// Details: docs/camera-import.md, "`common/cameras/lens_model.h`: how it works".
#pragma once

#include <Eigen/Core>

#include <string>

namespace rad {

struct LensModel {
    double fx = 1.0, fy = 1.0;   // pixels
    double cx = 0.5, cy = 0.5;   // principal point, pixels from the top-left corner
    double skew = 0.0;           // u += skew * y (Metashape's b2)
    bool fisheye = false;        // step 1
    double fovOmega = 0.0;       // step 2 (radians; 0 = off)
    double k[4] = {0, 0, 0, 0};  // step 3, numerator
    double d[3] = {0, 0, 0};     // step 3, denominator
    double p1 = 0.0, p2 = 0.0;   // step 4, tangential (OpenCV order)
    double s[4] = {0, 0, 0, 0};  // step 4, thin prism

    // Whether any of steps 1-4 or the skew changes a point (else the lens is an exact pinhole).
    bool distorts() const;
    // Step 1-4: the distorted normalised coordinates of the ideal point (x, y).
    Eigen::Vector2d distort(const Eigen::Vector2d& ideal) const;
    // Steps 1-5: the pixel where the lens images the ideal point (x, y).
    Eigen::Vector2d pixelOf(const Eigen::Vector2d& ideal) const;
    // The same lens for the image scaled by (sx, sy) (a resized copy of the photograph: its pixel
    // edges, hence the top-left corner, coincide with the original's).
    LensModel scaled(double sx, double sy) const;
    // Empty when usable (finite values, positive focal lengths); otherwise what is wrong.
    std::string validate() const;
    // The parameters as text with full precision (cache keys, logs).
    std::string describe() const;
};

}  // namespace rad
