// The lens of a calibrated photograph, as the tools that calibrate real captures describe it
// (COLMAP, Agisoft Metashape, nerfstudio): focal lengths, principal point and skew in pixels, and a
// distortion that maps a point of the ideal pinhole image plane (x, y) = (X/Z, Y/Z), camera axes
// x right, y down, z forward, to where the lens actually images it.
//
// One model covers them all, applied in this order:
//  1. fisheye (equidistant): (x, y) *= atan(r) / r, r = |(x, y)| (COLMAP's *_FISHEYE models,
//     OpenCV's fisheye module);
//  2. FOV (Devernay and Faugeras 2001), when omega > 0: (x, y) *= atan(2 r tan(omega / 2)) / (omega r);
//  3. radial, rational: (x, y) *= (1 + k1 r^2 + k2 r^4 + k3 r^6 + k4 r^8) / (1 + d1 r^2 + d2 r^4 + d3 r^6),
//     with r the radius after steps 1-2;
//  4. tangential (Brown-Conrady, OpenCV's order): x += 2 p1 x y + p2 (r^2 + 2 x^2),
//     y += p1 (r^2 + 2 y^2) + 2 p2 x y;  thin prism: x += s1 r^2 + s2 r^4, y += s3 r^2 + s4 r^4;
//  5. pixels: u = fx x + skew y + cx, v = fy y + cy.
// Pixel coordinates as camera/pinhole_camera.h: continuous, origin at the image's top-left CORNER,
// pixel (c, r) centred at (c + 0.5, r + 0.5) (COLMAP's and Metashape's convention as well).
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
