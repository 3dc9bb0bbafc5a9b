// "Virtually acquired photographs" (Vanhoey et al. 2015 sec. 7): a VirtualScene (virtual_scene.h) seen
// through a PinholeCamera (camera/pinhole_camera.h), rendered by ray casting.
//
// For every pixel (column c, row r from the top), NxN primary rays go through the sub-pixel
// centres (c + (i + 0.5) / N, r + (j + 0.5) / N) of the pinhole image coordinates (N = 1: the
// pixel centre); the pixel is their average (a box filter, so silhouettes are antialiased as the
// sensor of a real camera integrates over the pixel). At a hit (face, barycentrics a), the point
// is sum a_k p_k (on the flat triangle) and the shading normal normalize(sum a_k n_k) (interpolated
// vertex normals, Phong); the sample is scene.radiance(point, normal, -ray direction), with cast
// shadows. A miss gives the background colour. Values are LINEAR radiance (no tone mapping);
// writePhotographPng encodes them with the sRGB curve into 8 bits, as a camera JPEG/PNG would be,
// which is what the fitting decodes (image/rgb_image.h).
#pragma once

#include "acquisition/virtual_scene.h"
#include "camera/pinhole_camera.h"
#include "image/rgb_image.h"

#include <string>

namespace rad {

struct PhotographOptions {
    int supersampling = 2;              // N: N x N rays per pixel, 1..16
    Rgb background = Rgb::Zero();       // linear radiance of pixels (or samples) that miss the mesh
};

// Parallel over rows (OpenMP). Throws std::invalid_argument when the camera is invalid
// (PinholeCamera::validate) or an option is out of range.
ImageF renderPhotograph(const VirtualScene& scene, const PinholeCamera& camera, const PhotographOptions& options = {});

// Writes exposure * image as an 8-bit sRGB PNG (encodeToSrgb8). Throws ImageFileError.
void writePhotographPng(const std::string& path, const ImageF& image, float exposure = 1.0f);

}  // namespace rad
