// EXIF orientation (tag 0x0112 of a JPEG's APP1 "Exif" segment, TIFF 6.0 / EXIF 2.3): how a camera
// that stored the pixels as the sensor read them asks viewers to show the photograph. Cameras held
// upright portrait write 6 or 8 instead of turning the pixels; a calibration made on the upright
// image needs the same turn applied.
//
// Values: 1 as stored; 2 mirrored left-right; 3 turned 180 degrees; 4 mirrored top-bottom;
// 5 transposed (mirror about the main diagonal); 6 turned 90 degrees clockwise; 7 transverse
// (mirror about the anti-diagonal); 8 turned 90 degrees counter-clockwise.
#pragma once

#include "image/rgb_image.h"

#include <string>

namespace rad {

// The orientation (1..8) a JPEG file asks for; 1 when the file is not a JPEG, has no EXIF
// orientation or holds a value outside 1..8. Reads only the markers before the image data.
int readExifOrientation(const std::string& path);
// The same for a file's bytes in memory.
int exifOrientationOfJpeg(const unsigned char* bytes, std::size_t size);

// Whether the orientation swaps width and height (5 to 8).
inline bool orientationSwapsAxes(int orientation) { return orientation >= 5 && orientation <= 8; }

// The image as a viewer shows it under `orientation`.
Image8 applyExifOrientation(const Image8& stored, int orientation);

}  // namespace rad
