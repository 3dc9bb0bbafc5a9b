// Agisoft Metashape camera XML (File > Export > Export Cameras, "Agisoft XML"), as Metashape's user
// manual (appendix "Camera models") and the file itself describe it:
//  - per <sensor>: the <calibration> (the adjusted one when there is one) with f, cx, cy, b1, b2,
//    k1..k4, p1, p2 in pixels / dimensionless; cx, cy are OFFSETS of the principal point from the
//    image centre; pixel coordinates start at the image's top-left corner (first pixel's centre at
//    (0.5, 0.5)): u = w / 2 + cx + x' (f + b1) + y' b2, v = h / 2 + cy + y' f; the tangential terms
//    have P1 and P2 swapped with respect to OpenCV (x' += P1 (r^2 + 2 x^2) + 2 P2 x y);
//    type "frame" or "fisheye" (equidistant, then the same polynomials);
//  - per <camera>: a 4 x 4 camera-to-chunk <transform> (camera axes x right, y down, z forward);
//    a camera without one was not aligned, one with enabled="false" is disabled: both are skipped
//    and counted;
//  - per <chunk>: an optional chunk <transform> (rotation, translation, scale) from chunk to world
//    coordinates, and per <component> (Metashape 1.6 and later) a transform of the same form for the
//    cameras of its partition; the import places the cameras in world coordinates: the mesh must be
//    exported in the same (Metashape exports models in world coordinates).
#pragma once

#include "cameras/imported_camera.h"

#include <string>

namespace rad {

// Throws CameraFileError naming the file, the line, the sensor or camera, and what to do.
CameraImport readMetashapeXml(const std::string& path);

}  // namespace rad
