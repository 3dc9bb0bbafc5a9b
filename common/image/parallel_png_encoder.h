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

// 8- or 16-bit samples (bitDepth 8: `samples` points to std::uint8_t, 16: to std::uint16_t in the
// machine's byte order), 1 to 4 channels (grey, grey + alpha, RGB, RGBA), rows top to bottom,
// channels interleaved. zlibLevel 1 (fastest) to 9. Returns the whole file's bytes; throws
// std::invalid_argument for a bad size, depth, channel count or level, std::runtime_error when
// zlib fails.
std::vector<unsigned char> encodePngParallel(const void* samples, int width, int height, int channels, int bitDepth,
                                             int zlibLevel = 1);

}  // namespace rad
