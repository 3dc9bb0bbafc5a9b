// encodePngParallel: the file is checked by two decoders that are not the code under test: zlib's
// inflate (which verifies the stream's Adler-32) over the IDAT chunks whose CRCs are recomputed
// here, and stb_image's PNG reader for the pixels.
#include "image/parallel_png_encoder.h"

#include <gtest/gtest.h>
#include <omp.h>
#include <stb/stb_image.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

std::uint32_t bigEndian32(const unsigned char* p) {
    return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

// Walks the chunks (checking every CRC), inflates the IDAT data with zlib and returns the
// filtered scanlines; also returns the number of IDAT chunks.
std::vector<unsigned char> inflateIdat(const std::vector<unsigned char>& png, std::size_t expected, int& idatChunks) {
    const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    EXPECT_EQ(0, std::memcmp(png.data(), signature, 8));
    std::vector<unsigned char> stream;
    idatChunks = 0;
    bool ended = false;
    for (std::size_t at = 8; at < png.size();) {
        const std::uint32_t length = bigEndian32(png.data() + at);
        const std::string type(reinterpret_cast<const char*>(png.data() + at + 4), 4);
        const std::uint32_t crc = bigEndian32(png.data() + at + 8 + length);
        EXPECT_EQ(crc, std::uint32_t(crc32(0L, png.data() + at + 4, length + 4))) << type;
        if (type == "IDAT") {
            stream.insert(stream.end(), png.data() + at + 8, png.data() + at + 8 + length);
            ++idatChunks;
        }
        if (type == "IEND") ended = at + 12 + length == png.size();
        at += 12 + length;
    }
    EXPECT_TRUE(ended);
    std::vector<unsigned char> raw(expected + 1);
    uLongf size = static_cast<uLongf>(raw.size());
    EXPECT_EQ(Z_OK, uncompress(raw.data(), &size, stream.data(), static_cast<uLong>(stream.size())));
    raw.resize(size);
    return raw;
}

void checkRoundTrip(int width, int height, int channels, int depth, int level, unsigned seed,
                    rad::PngCompression compression = rad::PngCompression::Full) {
    SCOPED_TRACE(std::to_string(width) + " x " + std::to_string(height) + " x " + std::to_string(channels) + ", " +
                 std::to_string(depth) + " bit, level " + std::to_string(level));
    std::mt19937 random(seed);
    const std::size_t count = std::size_t(width) * height * channels;
    std::vector<std::uint16_t> samples16(count);
    std::vector<std::uint8_t> samples8(count);
    // Smooth rows with noise: what the "up" filter sees in a baked map, and every byte value.
    for (std::size_t i = 0; i < count; ++i) {
        samples16[i] = std::uint16_t((i * 37 + random() % 4096) & 0xffff);
        samples8[i] = std::uint8_t(random() & 0xff);
    }
    const void* samples = depth == 16 ? static_cast<const void*>(samples16.data()) : samples8.data();
    const std::vector<unsigned char> png = rad::encodePngParallel(samples, width, height, channels, depth, level, compression);

    // zlib: the scanlines, each "up"-filtered, undone here.
    const std::size_t rowBytes = std::size_t(width) * channels * (depth / 8);
    int idat = 0;
    const std::vector<unsigned char> raw = inflateIdat(png, (rowBytes + 1) * height, idat);
    ASSERT_EQ(raw.size(), (rowBytes + 1) * height);
    std::vector<unsigned char> previous(rowBytes, 0), row(rowBytes);
    for (int r = 0; r < height; ++r) {
        const unsigned char* line = raw.data() + (rowBytes + 1) * r;
        ASSERT_EQ(line[0], 2) << "row " << r;
        for (std::size_t i = 0; i < rowBytes; ++i) row[i] = static_cast<unsigned char>(line[1 + i] + previous[i]);
        for (std::size_t i = 0; i < std::size_t(width) * channels; ++i) {
            const std::size_t k = std::size_t(r) * width * channels + i;
            if (depth == 16) ASSERT_EQ((row[2 * i] << 8) | row[2 * i + 1], samples16[k]) << "row " << r;
            else ASSERT_EQ(row[i], samples8[k]) << "row " << r;
        }
        previous = row;
    }

    // stb_image: the pixels.
    int w = 0, h = 0, c = 0;
    if (depth == 16) {
        stbi_us* pixels = stbi_load_16_from_memory(png.data(), int(png.size()), &w, &h, &c, 0);
        ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
        EXPECT_EQ(0, std::memcmp(pixels, samples16.data(), count * 2));
        stbi_image_free(pixels);
    } else {
        stbi_uc* pixels = stbi_load_from_memory(png.data(), int(png.size()), &w, &h, &c, 0);
        ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
        EXPECT_EQ(0, std::memcmp(pixels, samples8.data(), count));
        stbi_image_free(pixels);
    }
    EXPECT_EQ(w, width);
    EXPECT_EQ(h, height);
    EXPECT_EQ(c, channels);
}

}  // namespace

TEST(ParallelPngEncoder, ManyBandsDecodeExactlyWithZlibAndStb) {
    // 16-bit RGB rows of 6001 bytes: 174 rows per band, so 700 rows are 5 bands (4 sync-flushed).
    checkRoundTrip(1000, 700, 3, 16, 1, 1);
    checkRoundTrip(1000, 700, 3, 16, 9, 2);
    checkRoundTrip(777, 1500, 4, 8, 6, 3);   // 8-bit RGBA, 2 bands
    checkRoundTrip(513, 2100, 2, 16, 3, 4);  // grey + alpha, 2 bands
    checkRoundTrip(1000, 700, 3, 16, 1, 10, rad::PngCompression::RunLength);
    checkRoundTrip(777, 1500, 4, 8, 1, 11, rad::PngCompression::RunLength);
}

TEST(ParallelPngEncoder, TinyAndSingleBandImages) {
    checkRoundTrip(1, 1, 1, 8, 1, 5);
    checkRoundTrip(1, 1, 3, 16, 1, 6);
    checkRoundTrip(3, 5, 3, 16, 1, 7);
    checkRoundTrip(16, 1, 4, 8, 1, 8);
    // A single row wider than a band's byte budget: one row per band.
    checkRoundTrip(200000, 3, 3, 16, 1, 9);
}

TEST(ParallelPngEncoder, OutputDoesNotDependOnTheThreadCount) {
    std::vector<std::uint16_t> samples(std::size_t(900) * 800 * 3);
    for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = std::uint16_t(i * 2654435761u >> 16);
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const std::vector<unsigned char> one = rad::encodePngParallel(samples.data(), 900, 800, 3, 16, 1);
    omp_set_num_threads(4);
    const std::vector<unsigned char> four = rad::encodePngParallel(samples.data(), 900, 800, 3, 16, 1);
    omp_set_num_threads(threads);
    EXPECT_EQ(one, four);
}

TEST(ParallelPngEncoder, RefusesBadArguments) {
    const std::uint16_t samples[12] = {};
    EXPECT_THROW(rad::encodePngParallel(samples, 0, 2, 3, 16), std::invalid_argument);
    EXPECT_THROW(rad::encodePngParallel(samples, 2, 2, 5, 16), std::invalid_argument);
    EXPECT_THROW(rad::encodePngParallel(samples, 2, 2, 3, 12), std::invalid_argument);
    EXPECT_THROW(rad::encodePngParallel(samples, 2, 2, 3, 16, 0), std::invalid_argument);
    EXPECT_THROW(rad::encodePngParallel(nullptr, 2, 2, 3, 16), std::invalid_argument);
}
