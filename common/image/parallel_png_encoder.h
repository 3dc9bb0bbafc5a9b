// A PNG encoder that deflates on every thread: the filtered rows are cut into bands of about 1 MB,
// each band is compressed on its own (zlib raw deflate, the first band after the zlib header, every
// band but the last ended by a sync flush so that the bands concatenate into one valid stream, as
// pigz does), and the bands' Adler-32 sums are combined into the stream's. The output does not
// depend on the number of threads (the bands are fixed by the row size). Every row uses PNG's "up"
// filter: baked maps are smooth, alike from row to row, and one fixed filter avoids libpng's
// per-row trial of all five.
#pragma once
#include <cstdint>
#include <vector>

namespace rad {

// Deflate's match search: full (zlib's default strategy) or run lengths only (Z_RLE: matches at
// distance 1). After the "up" filter a smooth map is long runs of equal bytes, which run lengths
// catch; the low bytes of a real scan's 16-bit normals are noise, where the full search spends
// its time finding nothing (figures: README, "Side by side with Blender's Cycles baker").
enum class PngCompression { Full, RunLength };

// 8- or 16-bit samples (bitDepth 8: `samples` points to std::uint8_t, 16: to std::uint16_t in the
// machine's byte order), 1 to 4 channels (grey, grey + alpha, RGB, RGBA), rows top to bottom,
// channels interleaved. zlibLevel 1 (fastest) to 9. Returns the whole file's bytes; throws
// std::invalid_argument for a bad size, depth, channel count or level, std::runtime_error when
// zlib fails.
std::vector<unsigned char> encodePngParallel(const void* samples, int width, int height, int channels, int bitDepth,
                                             int zlibLevel = 1, PngCompression compression = PngCompression::Full);

}  // namespace rad
