// EXIF orientation: the tag read from hand-built JPEG headers (both TIFF byte orders, after an
// APP0 segment), the eight orientations applied to a 3 x 2 image against layouts written by hand.
#include "image/exif_orientation.h"

#include <gtest/gtest.h>

#include <vector>

namespace {

// FFD8, an APP0 (JFIF) segment, an APP1 Exif segment whose IFD0 holds two entries (the
// orientation second), then a start of scan.
std::vector<unsigned char> jpegHeader(bool littleEndian, unsigned orientation) {
    std::vector<unsigned char> tiff;
    const auto put16 = [&](unsigned v) {
        if (littleEndian) { tiff.push_back(v & 0xFF); tiff.push_back(v >> 8); }
        else { tiff.push_back(v >> 8); tiff.push_back(v & 0xFF); }
    };
    const auto put32 = [&](unsigned v) {
        if (littleEndian) { put16(v & 0xFFFF); put16(v >> 16); }
        else { put16(v >> 16); put16(v & 0xFFFF); }
    };
    tiff.push_back(littleEndian ? 'I' : 'M');
    tiff.push_back(littleEndian ? 'I' : 'M');
    put16(42);
    put32(8);
    put16(2);                                           // two entries
    put16(0x010F); put16(2); put32(4); put32(0x41424300);  // Make, ASCII "ABC" inline
    put16(0x0112); put16(3); put32(1); put16(orientation); put16(0);
    put32(0);                                           // no next IFD
    std::vector<unsigned char> out = {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x07, 'J', 'F', 'I', 'F', 0};
    const std::size_t length = 2 + 6 + tiff.size();
    out.insert(out.end(), {0xFF, 0xE1, static_cast<unsigned char>(length >> 8), static_cast<unsigned char>(length & 0xFF),
                           'E', 'x', 'i', 'f', 0, 0});
    out.insert(out.end(), tiff.begin(), tiff.end());
    out.insert(out.end(), {0xFF, 0xDA, 0x00, 0x02});
    return out;
}

TEST(ExifOrientation, ReadsTheTagInBothByteOrders) {
    for (bool little : {true, false})
        for (unsigned o = 1; o <= 8; ++o) {
            const std::vector<unsigned char> bytes = jpegHeader(little, o);
            EXPECT_EQ(rad::exifOrientationOfJpeg(bytes.data(), bytes.size()), int(o)) << little << " " << o;
        }
    const std::vector<unsigned char> odd = jpegHeader(true, 9);
    EXPECT_EQ(rad::exifOrientationOfJpeg(odd.data(), odd.size()), 1);
    const unsigned char noExif[] = {0xFF, 0xD8, 0xFF, 0xDA, 0x00, 0x02};
    EXPECT_EQ(rad::exifOrientationOfJpeg(noExif, sizeof noExif), 1);
    const unsigned char png[] = {0x89, 'P', 'N', 'G', 13, 10, 26, 10};
    EXPECT_EQ(rad::exifOrientationOfJpeg(png, sizeof png), 1);
    EXPECT_EQ(rad::readExifOrientation("/nonexistent/photo.jpg"), 1);
}

TEST(ExifOrientation, TheEightOrientationsShowTheImageAsViewersDo) {
    // Stored:  a b c
    //          d e f      (one grey value per pixel: a = 1 ... f = 6)
    rad::Image8 stored(3, 2);
    for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 3; ++c) stored.rgb[3 * i + c] = std::uint8_t(i + 1);
    const std::vector<std::vector<int>> expected[9] = {
        {}, {{1, 2, 3}, {4, 5, 6}}, {{3, 2, 1}, {6, 5, 4}}, {{6, 5, 4}, {3, 2, 1}}, {{4, 5, 6}, {1, 2, 3}},
        {{1, 4}, {2, 5}, {3, 6}},   // 5: transposed
        {{4, 1}, {5, 2}, {6, 3}},   // 6: turned clockwise
        {{6, 3}, {5, 2}, {4, 1}},   // 7: transverse
        {{3, 6}, {2, 5}, {1, 4}}};  // 8: turned counter-clockwise
    for (int o = 1; o <= 8; ++o) {
        const rad::Image8 shown = rad::applyExifOrientation(stored, o);
        ASSERT_EQ(shown.height, int(expected[o].size())) << o;
        ASSERT_EQ(shown.width, int(expected[o][0].size())) << o;
        EXPECT_EQ(rad::orientationSwapsAxes(o), o >= 5);
        for (int y = 0; y < shown.height; ++y)
            for (int x = 0; x < shown.width; ++x)
                EXPECT_EQ(shown.rgb[(std::size_t(y) * shown.width + x) * 3 + 1], expected[o][y][x]) << o << " " << x << " " << y;
    }
}

}  // namespace
