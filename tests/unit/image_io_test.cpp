// Tests of image/image_io.h: PNG round trips (lossless: bit-exact), PNGs of other channel counts
// written by stb_image_write itself, a JPEG written by stb_image_write (lossy: compared with a
// tolerance), and the refusals (missing, empty, truncated, foreign, unwritable) whose messages must
// name the file. 16-bit PNG: exact round trips for 1 to 4 channels, 8-bit files read as code * 257,
// truncated 16-bit files refused naming the file.
#include "image/image_io.h"
#include "test_temporary_directory.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>

#include <sys/resource.h>

#include <stb/stb_image_write.h>  // declarations only: the implementation lives in image/image_io.cpp

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace {

// stb_image_write's JPEG encoder left-shifts negative ints (upstream nothings/stb issue #1433);
// common/CMakeLists.txt compiles image/image_io.cpp (stb's implementation) with
// -fno-sanitize=shift-base in the sanitizer build, so these tests run there too.

std::string tmpPath(const std::string& name) { return std::string(RADIANCE_TEST_TMPDIR) + "/image_io_" + name; }

rad::Image8 randomImage(int w, int h, unsigned seed) {
    rad::Image8 image(w, h);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> code(0, 255);
    for (auto& b : image.rgb) b = static_cast<std::uint8_t>(code(rng));
    return image;
}

// Smooth content (JPEG's 8x8 DCT keeps it well), different per channel.
rad::Image8 smoothImage(int w, int h) {
    rad::Image8 image(w, h);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            std::uint8_t* p = image.pixel(c, r);
            p[0] = static_cast<std::uint8_t>(40 + 150.0 * c / (w - 1));
            p[1] = static_cast<std::uint8_t>(200 - 120.0 * r / (h - 1));
            p[2] = static_cast<std::uint8_t>(128 + 60.0 * std::sin(0.2 * (c + r)));
        }
    return image;
}

// The ImageFileError text of readImage8 ("" when it succeeded).
std::string readError(const std::string& path) {
    try {
        rad::readImage8(path);
    } catch (const rad::ImageFileError& e) {
        return e.what();
    }
    return "";
}

// Copies of `whole` cut from inside the header to just before the end must all be refused, with
// the file named. (Not tested: cuts inside a PNG's final IEND chunk, after all pixel data, are
// accepted by stb, harmlessly.)
void expectTruncationsRefused(const std::string& whole) {
    const std::vector<char> bytes = radtest::readBytes(whole);
    ASSERT_GT(bytes.size(), 100u);
    EXPECT_EQ(readError(whole), "");
    for (const double fraction : {0.02, 0.3, 0.7, 0.98}) {
        const std::size_t keep = static_cast<std::size_t>(fraction * bytes.size());
        const std::string cut = tmpPath("truncated_" + std::to_string(keep) + "_" + whole.substr(whole.rfind('/') + 1));
        radtest::writeBytes(cut, std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(keep)));
        const std::string why = readError(cut);
        EXPECT_NE(why.find(cut), std::string::npos) << "kept " << keep << " of " << bytes.size() << ": '" << why << "'";
    }
}

TEST(ImageIo, PngRoundTripIsBitExactAtOddSizes) {
    for (const auto& size : {std::pair<int, int>{3, 5}, {1, 1}, {17, 2}, {64, 33}}) {
        const rad::Image8 image = randomImage(size.first, size.second, unsigned(size.first * 100 + size.second));
        const std::string path = tmpPath("roundtrip_" + std::to_string(size.first) + "x" + std::to_string(size.second) + ".png");
        rad::writePng(path, image);
        const rad::Image8 back = rad::readImage8(path);
        ASSERT_EQ(back.width, image.width);
        ASSERT_EQ(back.height, image.height);
        EXPECT_EQ(back.rgb, image.rgb);
    }
}

TEST(ImageIo, PngEncodedInMemoryIsAFileTheReaderDecodesExactly) {
    const rad::Image8 image = randomImage(13, 7, 42);
    const std::vector<unsigned char> bytes = rad::encodePng(image);
    ASSERT_GT(bytes.size(), 8u);
    const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    EXPECT_TRUE(std::equal(signature, signature + 8, bytes.begin()));
    const std::string path = tmpPath("encoded.png");
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    const rad::Image8 back = rad::readImage8(path);
    ASSERT_EQ(back.width, 13);
    ASSERT_EQ(back.height, 7);
    EXPECT_EQ(back.rgb, image.rgb);
    rad::Image8 wrong(4, 4);
    wrong.rgb.resize(5);
    EXPECT_THROW(rad::encodePng(wrong), rad::ImageFileError);
}

TEST(ImageIo, GreyAndRgbaPngsAreReadAsRgb) {
    const int w = 3, h = 5;
    std::vector<std::uint8_t> grey(w * h), rgba(w * h * 4);
    for (int i = 0; i < w * h; ++i) {
        grey[i] = static_cast<std::uint8_t>(17 * i);
        for (int k = 0; k < 4; ++k) rgba[4 * i + k] = static_cast<std::uint8_t>(11 * i + 50 * k);
    }
    const std::string greyPath = tmpPath("grey.png"), rgbaPath = tmpPath("rgba.png");
    ASSERT_TRUE(stbi_write_png(greyPath.c_str(), w, h, 1, grey.data(), w));
    ASSERT_TRUE(stbi_write_png(rgbaPath.c_str(), w, h, 4, rgba.data(), 4 * w));
    const rad::Image8 g = rad::readImage8(greyPath), c = rad::readImage8(rgbaPath);
    ASSERT_EQ(g.width, w);
    ASSERT_EQ(c.height, h);
    for (int i = 0; i < w * h; ++i)
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(g.rgb[3 * i + k], grey[i]);          // grey replicated
            EXPECT_EQ(c.rgb[3 * i + k], rgba[4 * i + k]);  // alpha dropped, not premultiplied
        }
}

TEST(ImageIo, ReadsAJpegWrittenByStb) {
    const int w = 21, h = 13;  // not multiples of the 8x8 blocks
    const rad::Image8 image = smoothImage(w, h);
    const std::string path = tmpPath("smooth.jpg");
    ASSERT_TRUE(stbi_write_jpg(path.c_str(), w, h, 3, image.rgb.data(), 95));
    const rad::Image8 back = rad::readImage8(path);
    ASSERT_EQ(back.width, w);
    ASSERT_EQ(back.height, h);
    // Quality 95 with chroma subsampling: a few codes per channel on smooth content.
    double sumError = 0.0;
    int worst = 0;
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        const int e = std::abs(int(back.rgb[i]) - int(image.rgb[i]));
        worst = std::max(worst, e);
        sumError += e;
    }
    EXPECT_LE(worst, 16);
    EXPECT_LT(sumError / image.rgb.size(), 3.0);
}

TEST(ImageIo, MissingEmptyForeignAndTruncatedPngFilesAreRefusedNamingTheFile) {
    const std::string missing = tmpPath("does_not_exist.png");
    std::remove(missing.c_str());
    std::string why = readError(missing);
    EXPECT_NE(why.find(missing), std::string::npos) << why;

    const std::string empty = tmpPath("empty.png");
    radtest::writeBytes(empty, {});
    why = readError(empty);
    EXPECT_NE(why.find(empty), std::string::npos) << why;

    const std::string text = tmpPath("text.jpg");
    const std::string content = "not an image at all\n";
    radtest::writeBytes(text, std::vector<char>(content.begin(), content.end()));
    why = readError(text);
    EXPECT_NE(why.find(text), std::string::npos) << why;

    // Truncations of a PNG, from inside the header to just before the end.
    const rad::Image8 image = randomImage(40, 30, 9);
    const std::string png = tmpPath("whole.png");
    rad::writePng(png, image);
    expectTruncationsRefused(png);
}

TEST(ImageIo, TruncatedJpegIsRefusedNamingTheFile) {
    const rad::Image8 image = randomImage(40, 30, 9);
    const std::string jpg = tmpPath("whole.jpg");
    ASSERT_TRUE(stbi_write_jpg(jpg.c_str(), image.width, image.height, 3, image.rgb.data(), 90));
    expectTruncationsRefused(jpg);
}

TEST(ImageIo, UnwritablePathsAndEmptyImagesAreRefused) {
    const rad::Image8 image = randomImage(3, 5, 1);
    const std::string badPath = tmpPath("no_such_directory/out.png");
    try {
        rad::writePng(badPath, image);
        FAIL() << "writing into a missing directory succeeded";
    } catch (const rad::ImageFileError& e) {
        EXPECT_NE(std::string(e.what()).find(badPath), std::string::npos) << e.what();
    }
    EXPECT_THROW(rad::writePng(tmpPath("empty_image.png"), rad::Image8()), rad::ImageFileError);
}

std::string read16Error(const std::string& path) {
    try {
        int w, h, c;
        rad::readPng16(path, w, h, c);
    } catch (const rad::ImageFileError& e) {
        return e.what();
    }
    return "";
}

TEST(ImageIo, Png16RoundTripIsExactForEveryChannelCount) {
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> code(0, 65535);
    for (int channels = 1; channels <= 4; ++channels)
        for (const auto& size : {std::pair<int, int>{1, 1}, {7, 3}, {64, 33}}) {
            std::vector<std::uint16_t> samples(std::size_t(size.first) * size.second * channels);
            for (auto& s : samples) s = static_cast<std::uint16_t>(code(rng));
            samples[0] = 0;
            samples.back() = 65535;
            if (samples.size() > 2) samples[1] = 0x0102;  // byte order: 258, not 513
            const std::string path = tmpPath("png16_" + std::to_string(channels) + "_" + std::to_string(size.first) + ".png");
            rad::writePng16(path, size.first, size.second, channels, samples.data());
            int w = 0, h = 0, c = 0;
            const std::vector<std::uint16_t> back = rad::readPng16(path, w, h, c);
            EXPECT_EQ(w, size.first);
            EXPECT_EQ(h, size.second);
            EXPECT_EQ(c, channels);
            EXPECT_EQ(back, samples);
        }
}

TEST(ImageIo, Png16ReaderScalesEightBitFilesExactly) {
    const rad::Image8 image = randomImage(9, 4, 21);
    const std::string path = tmpPath("eight_for_16.png");
    rad::writePng(path, image);
    int w = 0, h = 0, c = 0;
    const std::vector<std::uint16_t> back = rad::readPng16(path, w, h, c);
    ASSERT_EQ(w, 9);
    ASSERT_EQ(h, 4);
    ASSERT_EQ(c, 3);
    for (std::size_t i = 0; i < image.rgb.size(); ++i) EXPECT_EQ(back[i], image.rgb[i] * 257) << i;
}

TEST(ImageIo, TruncatedOrMissingPng16IsRefusedNamingTheFile) {
    const int w = 40, h = 30;
    std::vector<std::uint16_t> samples(std::size_t(w) * h * 3);
    std::mt19937 rng(4);
    for (auto& s : samples) s = static_cast<std::uint16_t>(rng());
    const std::string whole = tmpPath("whole16.png");
    rad::writePng16(whole, w, h, 3, samples.data());
    EXPECT_EQ(read16Error(whole), "");
    const std::vector<char> bytes = radtest::readBytes(whole);
    for (const double fraction : {0.02, 0.3, 0.7, 0.98}) {
        const std::size_t keep = static_cast<std::size_t>(fraction * bytes.size());
        const std::string cut = tmpPath("truncated16_" + std::to_string(keep) + ".png");
        radtest::writeBytes(cut, std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(keep)));
        const std::string why = read16Error(cut);
        EXPECT_NE(why.find(cut), std::string::npos) << "kept " << keep << " of " << bytes.size() << ": '" << why << "'";
    }
    const std::string missing = tmpPath("missing16.png");
    std::remove(missing.c_str());
    EXPECT_NE(read16Error(missing).find(missing), std::string::npos);
}

TEST(ImageIo, Png16WriterRefusesBadInputAndUnwritablePaths) {
    const std::vector<std::uint16_t> samples(5 * 3 * 3, 7);
    const std::string badPath = tmpPath("no_such_directory/out16.png");
    try {
        rad::writePng16(badPath, 5, 3, 3, samples.data());
        FAIL() << "writing into a missing directory succeeded";
    } catch (const rad::ImageFileError& e) {
        EXPECT_NE(std::string(e.what()).find(badPath), std::string::npos) << e.what();
    }
    EXPECT_THROW(rad::writePng16(tmpPath("bad16.png"), 5, 3, 5, samples.data()), rad::ImageFileError);
    EXPECT_THROW(rad::writePng16(tmpPath("bad16.png"), 0, 3, 3, samples.data()), rad::ImageFileError);
}

// stb's writer ignored fwrite's result: under a file-size limit (or on a full disk) the 8-bit map
// was reported written and was truncated. Under a 2000-byte soft limit (lowered and restored here;
// SIGXFSZ ignored meanwhile, as Python does, so the write fails with EFBIG) each kind of PNG write
// must fail naming the cause and leave no file.
TEST(ImageIo, WriteErrorsAreReportedWithTheReasonAndLeaveNoFile) {
    const std::string path8 = tmpPath("limited8.png"), path16 = tmpPath("limited16.png");
    std::remove(path8.c_str());
    std::remove(path16.c_str());
    std::mt19937 rng(5);
    rad::Image8 image(128, 128);
    for (auto& c : image.rgb) c = std::uint8_t(rng());  // noise: far above 2000 bytes compressed
    std::vector<std::uint16_t> samples(128 * 128 * 3);
    for (auto& c : samples) c = std::uint16_t(rng());
    rlimit saved{};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limited = saved;
    limited.rlim_cur = 2000;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limited), 0);
    std::string message8, message16;
    try {
        rad::writePng(path8, image);
    } catch (const rad::ImageFileError& e) {
        message8 = e.what();
    }
    try {
        rad::writePng16(path16, 128, 128, 3, samples.data());
    } catch (const rad::ImageFileError& e) {
        message16 = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, previous);
    EXPECT_NE(message8.find("exceeds a size limit"), std::string::npos) << "8-bit: '" << message8 << "'";
    EXPECT_NE(message16.find("exceeds a size limit"), std::string::npos) << "16-bit: '" << message16 << "'";
    EXPECT_FALSE(std::filesystem::exists(path8));
    EXPECT_FALSE(std::filesystem::exists(path16));
}

}  // namespace

TEST(ImageIo, ImageSizeIsReadFromTheHeader) {
    const std::string path = tmpPath("size_23x11.png");
    rad::writePng(path, randomImage(23, 11, 5));
    int w = 0, h = 0;
    rad::readImageSize(path, w, h);
    EXPECT_EQ(w, 23);
    EXPECT_EQ(h, 11);
    EXPECT_THROW(rad::readImageSize(tmpPath("no_such_image.png"), w, h), rad::ImageFileError);
}
