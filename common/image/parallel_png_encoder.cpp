// PNG encoding with the deflate work shared by the threads (parallel_png_encoder.h). File layout:
// the PNG specification (ISO/IEC 15948): signature, IHDR, IDAT chunks holding one zlib stream
// (RFC 1950: header, raw deflate data of RFC 1951, Adler-32 of the uncompressed bytes), IEND.
#include "image/parallel_png_encoder.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

void appendBigEndian32(std::vector<unsigned char>& out, std::uint32_t value) {
    out.push_back(static_cast<unsigned char>(value >> 24));
    out.push_back(static_cast<unsigned char>(value >> 16));
    out.push_back(static_cast<unsigned char>(value >> 8));
    out.push_back(static_cast<unsigned char>(value));
}

void appendChunk(std::vector<unsigned char>& out, const char type[4], const unsigned char* data, std::size_t size) {
    appendBigEndian32(out, static_cast<std::uint32_t>(size));
    const std::size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data, data + size);
    appendBigEndian32(out, static_cast<std::uint32_t>(crc32(0L, out.data() + start, static_cast<uInt>(size + 4))));
}

// The filtered bytes of rows [row0, row1): per row the filter type 2 ("up") and the byte-wise
// difference to the row above (zero above the first row), 16-bit samples big-endian.
void filterRows(const void* samples, int width, int channels, int bitDepth, int row0, int row1,
                std::vector<unsigned char>& out) {
    const std::size_t values = std::size_t(width) * channels;
    const std::size_t rowBytes = values * (bitDepth / 8);
    out.resize((rowBytes + 1) * std::size_t(row1 - row0));
    unsigned char* o = out.data();
    for (int r = row0; r < row1; ++r) {
        *o++ = 2;
        if (bitDepth == 8) {
            const auto* row = static_cast<const std::uint8_t*>(samples) + values * std::size_t(r);
            if (r == 0) {
                std::memcpy(o, row, values);
            } else {
                const std::uint8_t* above = row - values;
                for (std::size_t i = 0; i < values; ++i) o[i] = static_cast<unsigned char>(row[i] - above[i]);
            }
        } else {
            const auto* row = static_cast<const std::uint16_t*>(samples) + values * std::size_t(r);
            const std::uint16_t* above = r == 0 ? nullptr : row - values;
            for (std::size_t i = 0; i < values; ++i) {
                const unsigned hi = row[i] >> 8, lo = row[i] & 0xffu;
                const unsigned aboveHi = above ? above[i] >> 8 : 0u, aboveLo = above ? above[i] & 0xffu : 0u;
                o[2 * i] = static_cast<unsigned char>(hi - aboveHi);
                o[2 * i + 1] = static_cast<unsigned char>(lo - aboveLo);
            }
        }
        o += rowBytes;
    }
}

// Raw deflate of one band; the last band ends the stream (Z_FINISH), the others end on a byte
// boundary with an empty stored block (Z_SYNC_FLUSH) so that the next band's data can follow.
std::string deflateBand(const std::vector<unsigned char>& in, int level, int strategy, bool last,
                        std::vector<unsigned char>& out) {
    z_stream stream;
    std::memset(&stream, 0, sizeof stream);
    if (deflateInit2(&stream, level, Z_DEFLATED, -15, 8, strategy) != Z_OK) return "deflateInit2 failed";
    out.resize(deflateBound(&stream, static_cast<uLong>(in.size())) + 64);
    stream.next_in = const_cast<unsigned char*>(in.data());
    stream.avail_in = static_cast<uInt>(in.size());
    stream.next_out = out.data();
    stream.avail_out = static_cast<uInt>(out.size());
    const int flush = last ? Z_FINISH : Z_SYNC_FLUSH;
    int status = Z_OK;
    for (;;) {
        status = deflate(&stream, flush);
        if (status == Z_STREAM_ERROR) break;
        if (last ? status == Z_STREAM_END : (stream.avail_in == 0 && stream.avail_out > 0)) break;
        if (stream.avail_out == 0) {  // not expected with deflateBound's size; grow and go on
            const std::size_t used = out.size();
            out.resize(2 * used);
            stream.next_out = out.data() + used;
            stream.avail_out = static_cast<uInt>(out.size() - used);
        }
    }
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return status == Z_STREAM_ERROR ? "deflate failed" : "";
}

}  // namespace

std::vector<unsigned char> encodePngParallel(const void* samples, int width, int height, int channels, int bitDepth,
                                             int zlibLevel, PngCompression compression) {
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || !samples)
        throw std::invalid_argument("PNG encoding: bad image " + std::to_string(width) + " x " + std::to_string(height) +
                                    " x " + std::to_string(channels) + " (1 to 4 channels)");
    if (bitDepth != 8 && bitDepth != 16)
        throw std::invalid_argument("PNG encoding: " + std::to_string(bitDepth) + " bits per sample (8 or 16)");
    if (zlibLevel < 1 || zlibLevel > 9)
        throw std::invalid_argument("PNG encoding: zlib level " + std::to_string(zlibLevel) + " (1 to 9)");
    const std::size_t rowBytes = std::size_t(width) * channels * (bitDepth / 8) + 1;
    if (rowBytes > (1u << 30) || double(rowBytes) * height > 4.0e9)
        throw std::invalid_argument("PNG encoding: the image is too large (" + std::to_string(width) + " x " +
                                    std::to_string(height) + ")");
    const int rowsPerBand = std::max(1, int((std::size_t(1) << 20) / rowBytes));
    const int bands = (height + rowsPerBand - 1) / rowsPerBand;
    const std::size_t bandCount = static_cast<std::size_t>(bands);
    std::vector<std::vector<unsigned char>> compressed(bandCount);
    std::vector<uLong> adler(bandCount), length(bandCount);
    std::vector<std::string> problems(bandCount);
#pragma omp parallel
    {
        std::vector<unsigned char> filtered;
#pragma omp for schedule(dynamic, 1)
        for (int b = 0; b < bands; ++b) {
            const int row0 = b * rowsPerBand, row1 = std::min(height, row0 + rowsPerBand);
            filterRows(samples, width, channels, bitDepth, row0, row1, filtered);
            adler[std::size_t(b)] = adler32(adler32(0L, Z_NULL, 0), filtered.data(), static_cast<uInt>(filtered.size()));
            length[std::size_t(b)] = static_cast<uLong>(filtered.size());
            const int strategy = compression == PngCompression::RunLength ? Z_RLE : Z_DEFAULT_STRATEGY;
            problems[std::size_t(b)] = deflateBand(filtered, zlibLevel, strategy, b == bands - 1, compressed[std::size_t(b)]);
        }
    }
    for (const std::string& problem : problems)
        if (!problem.empty()) throw std::runtime_error("PNG encoding: zlib: " + problem);

    // The zlib stream: header (deflate, 32 KiB window, check bits), the bands, Adler-32.
    std::vector<unsigned char> stream;
    std::size_t total = 6;
    for (const auto& c : compressed) total += c.size();
    stream.reserve(total);
    const unsigned char cmf = 0x78, flevel = zlibLevel == 1 ? 0 : zlibLevel < 6 ? 1 : zlibLevel == 6 ? 2 : 3;
    unsigned char flg = static_cast<unsigned char>(flevel << 6);
    flg = static_cast<unsigned char>(flg + (31 - (cmf * 256u + flg) % 31) % 31);
    stream.push_back(cmf);
    stream.push_back(flg);
    uLong sum = adler[0];
    for (int b = 0; b < bands; ++b) {
        stream.insert(stream.end(), compressed[std::size_t(b)].begin(), compressed[std::size_t(b)].end());
        if (b > 0) sum = adler32_combine(sum, adler[std::size_t(b)], static_cast<z_off_t>(length[std::size_t(b)]));
        std::vector<unsigned char>().swap(compressed[std::size_t(b)]);
    }
    appendBigEndian32(stream, static_cast<std::uint32_t>(sum));

    std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    png.reserve(stream.size() + stream.size() / (1u << 20) * 12 + 64);
    unsigned char header[13];
    const auto put32 = [](unsigned char* p, std::uint32_t v) {
        p[0] = static_cast<unsigned char>(v >> 24);
        p[1] = static_cast<unsigned char>(v >> 16);
        p[2] = static_cast<unsigned char>(v >> 8);
        p[3] = static_cast<unsigned char>(v);
    };
    put32(header, static_cast<std::uint32_t>(width));
    put32(header + 4, static_cast<std::uint32_t>(height));
    header[8] = static_cast<unsigned char>(bitDepth);
    static const unsigned char colorTypes[5] = {0, 0, 4, 2, 6};  // grey, grey + alpha, RGB, RGBA
    header[9] = colorTypes[channels];
    header[10] = header[11] = header[12] = 0;  // deflate, adaptive filtering, no interlace
    appendChunk(png, "IHDR", header, sizeof header);
    constexpr std::size_t kChunk = std::size_t(1) << 20;
    for (std::size_t at = 0; at < stream.size(); at += kChunk)
        appendChunk(png, "IDAT", stream.data() + at, std::min(kChunk, stream.size() - at));
    appendChunk(png, "IEND", nullptr, 0);
    return png;
}

}  // namespace rad
