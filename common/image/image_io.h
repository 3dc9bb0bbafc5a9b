// Reading and writing 8-bit images: JPEG and PNG in (any size, grey/RGB/RGBA, converted to RGB),
// PNG out. Uses stb_image / stb_image_write (Debian's libstb-dev): small, well-kept readers made
// for exactly this, with no further dependency.
//
// 16-bit PNG (normal maps: 8 bits quantise a unit normal's components in steps of 2/255, up to
// ~0.45 degrees; 16 bits in steps of 2/65535): read with stb_image's 16-bit loader, written by
// our encoder on zlib (image/parallel_png_encoder.h), because stb_image_write has no 16-bit PNG
// writer.
#pragma once

#include "errors/error_categories.h"
#include "image/rgb_image.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct ImageFileError : FileError {
    using FileError::FileError;
};

// Throws ImageFileError with the file name and the decoder's reason when the file is missing,
// truncated or not a supported image.
Image8 readImage8(const std::string& path);
// The size of an image file (JPEG or PNG) from its header, without decoding it. Throws
// ImageFileError with the file name and the reason when it is missing or not a supported image.
void readImageSize(const std::string& path, int& width, int& height);
// Throws ImageFileError when the file cannot be written.
void writePng(const std::string& path, const Image8& image);

// An 8-bit RGB image encoded as PNG in memory (for files that embed images, e.g. glTF's .glb).
// Throws ImageFileError for a size that does not match.
std::vector<unsigned char> encodePng(const Image8& image);

// Writes a 16-bit PNG: `samples` holds width * height * channels values, row-major, rows top to
// bottom, channels interleaved (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), in native byte order.
// Throws ImageFileError (naming the file) for bad sizes or channel counts and any write failure.
void writePng16(const std::string& path, int width, int height, int channels, const std::uint16_t* samples);

// Reads a PNG (8- or 16-bit; 8-bit samples are scaled to 16 bits exactly: code * 257, so that
// code / 255 == code16 / 65535) or any other image readImage8 reads, keeping its channel count
// (1 to 4, returned in `channels`). Layout as writePng16. Throws ImageFileError with the file name
// and the decoder's reason when the file is missing, truncated or not a supported image.
std::vector<std::uint16_t> readPng16(const std::string& path, int& width, int& height, int& channels);

}  // namespace rad
