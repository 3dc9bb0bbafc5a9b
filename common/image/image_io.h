// Reading and writing 8-bit images: JPEG and PNG in (any size, grey/RGB/RGBA, converted to RGB),
// PNG out. Uses stb_image / stb_image_write (Debian's libstb-dev): small, well-kept readers made
// for exactly this, with no further dependency.
#pragma once
#include "image/rgb_image.h"

#include <stdexcept>
#include <string>

namespace rad {

struct ImageFileError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Throws ImageFileError with the file name and the decoder's reason when the file is missing,
// truncated or not a supported image.
Image8 readImage8(const std::string& path);
// Throws ImageFileError when the file cannot be written.
void writePng(const std::string& path, const Image8& image);

}  // namespace rad
