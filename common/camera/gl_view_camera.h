// The camera of an OpenGL view (GL_VIEWPORT, GL_MODELVIEW_MATRIX, GL_PROJECTION_MATRIX, as MeshLab's
// GLArea leaves them when a decoration draws) as a PinholeCamera, and the view file the "Radiance
// Field" decoration writes every frame (docs/decorate-radiance.md, "View file"), so that a CPU
// reference rendering (render/radiance_renderer.h) can be made of exactly what is on screen. With
// MV = [s R | t] (a uniform scale s > 0 allowed) and a perspective P, the image is the viewport with
// row 0 at its TOP: fx = W/2 P00, cx = W/2 (1 - P02), fy = H/2 P11, cy = H/2 (1 + P12),
// rotation = diag(1, -1, -1) R, center = -R^T t / s, in the modelview's object space.
// Details: docs/decorate-radiance.md, "`common/camera/gl_view_camera.h`: how it works".
#pragma once

#include "camera/pinhole_camera.h"

#include <array>
#include <string>

namespace rad {

// As glGetDoublev returns them: viewport (X, Y, W, H) in device pixels, origin at the bottom-left of
// the GL surface; matrices COLUMN-major (element (row i, column j) at index 4 j + i).
struct GlView {
    std::array<double, 4> viewport{};
    std::array<double, 16> modelview{};
    std::array<double, 16> projection{};
};

// The camera described in the file comment. Throws std::invalid_argument, with a sentence saying
// which condition failed, when
//  - the viewport is degenerate (W or H not a positive integer, non-finite values);
//  - a matrix has non-finite values, or the modelview's last row is not (0 0 0 1);
//  - the modelview's 3x3 part is not a positive uniform scale times a rotation (non-uniform scale,
//    shear or mirror, relative tolerance 1e-4 after dividing by s = cbrt(det));
//  - the projection is not a perspective one (last row not (0 0 -w 0) with w > 0, e.g. MeshLab's
//    orthographic mode when its field of view is below 5 degrees), is skewed (P01, P10 != 0),
//    translates in clip space (P03, P13 != 0) or mirrors (P00 or P11 <= 0).
// The last row (0 0 -w 0) is normalised to w = 1 (homogeneous coordinates: same projection).
PinholeCamera cameraFromGlView(const GlView& view);

// The whole view file (docs/decorate-radiance.md):
//   radiance-decoration-view 1
//   frame N
//   mode per-vertex|per-fragment|prt|cpu-per-vertex
//   viewport X Y W H
//   widget_origin GX GY          (global screen coordinates of the GL widget's top-left, logical px)
//   widget_size W H              (logical px)
//   device_pixel_ratio R
//   modelview m0 ... m15         (column-major)
//   projection p0 ... p15        (column-major)
//   exposure STOPS
//   tonemap clamp|reinhard
struct DecorationViewFile {
    int version = 1;
    long long frame = 0;
    std::string mode;  // one of the four words above
    GlView view;
    std::array<double, 2> widgetOrigin{};
    std::array<double, 2> widgetSize{};
    double devicePixelRatio = 1.0;
    double exposureStops = 0.0;
    std::string toneMap;  // "clamp" or "reinhard"
};

// Reads the file. Every line is "key values..."; text after '#' and blank lines are ignored; keys
// may come in any order after the first line. Strict otherwise: throws std::runtime_error naming
// the file and the line (or the missing key) for a missing file, a wrong first line or version,
// an unknown or repeated key, a wrong number of values, a value that is not a finite number (or
// not an integer for frame), an unknown mode or tone curve, a non-positive widget size or device
// pixel ratio, or a missing key. The camera itself is checked by cameraFromGlView, not here.
DecorationViewFile readDecorationViewFile(const std::string& path);

// Where the viewport's pixels are in a capture of the whole screen (`import -window root`): device
// pixels, origin at the screen's top-left, rows downwards. The widget's top-left corner is at
// round(widget_origin * R) and its height round(widget_size.H * R) device pixels (R the device pixel
// ratio); GL counts the viewport's Y from the widget's BOTTOM, so its top row in the widget is
// widget_height - (Y + H):
//   x = round(GX R) + X,   y = round(GY R) + round(WH R) - (Y + H),   width = W,  height = H.
// Row r of the PinholeCamera image of cameraFromGlView is row y + r of the capture.
// Throws std::invalid_argument when the viewport's values are not whole numbers or W, H <= 0.
struct ScreenRect {
    int x = 0, y = 0, width = 0, height = 0;
};
ScreenRect viewportInScreen(const DecorationViewFile& file);

}  // namespace rad
