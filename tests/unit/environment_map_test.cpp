// Tests of lighting/environment_map.h. Expected values come from the stated convention written out
// again here (directions, solid angles as cos differences), from files written in the test with
// OpenEXR's and stb_image_write's own writers, from spherical_harmonics.h / sh_rotation.h (the
// conventions the projection must agree with) and from brute-force quadrature of radiance()
// lookups; the real maps of data-cache/hdr are read when present.
#include "lighting/environment_map.h"
#include "test_temporary_directory.h"
#include "radiance/basis.h"
#include "radiance/lebedev_quadrature.h"
#include "radiance/sh_rotation.h"
#include "radiance/spherical_harmonics.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <stb/stb_image_write.h>  // declarations only: the implementation lives in image/image_io.cpp

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string tmpPath(const std::string& name) { return std::string(RADIANCE_TEST_TMPDIR) + "/envmap_" + name; }
std::string hdrCacheDir() { return std::string(RADIANCE_SOURCE_DIR) + "/data-cache/hdr"; }
bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

// The convention of environment_map.h, written out independently of the code under test.
Eigen::Vector3d conventionDirection(double s, double t) {
    const double theta = kPi * t, phi = kPi - 2.0 * kPi * s;
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
double conventionSolidAngle(int row, int width, int height) {
    return 2.0 * kPi / width * (std::cos(kPi * row / height) - std::cos(kPi * (row + 1) / height));
}

// A map whose texel (c, r) holds f(direction of the texel centre).
rad::EnvironmentMap mapFromFunction(int width, int height, const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& f) {
    std::vector<float> rgb(std::size_t(width) * height * 3);
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c) {
            const Eigen::Vector3d v = f(conventionDirection((c + 0.5) / width, (r + 0.5) / height));
            for (int k = 0; k < 3; ++k) rgb[(std::size_t(r) * width + c) * 3 + k] = static_cast<float>(v[k]);
        }
    return rad::EnvironmentMap(width, height, std::move(rgb));
}

// sum_k a[ch * K + k] Y_k(w), per channel.
Eigen::Vector3d evaluateSh(int degree, const std::vector<double>& a, const Eigen::Vector3d& w) {
    const int K = (degree + 1) * (degree + 1);
    std::vector<double> y(K);
    rad::evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), y.data());
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 0; k < K; ++k) out[ch] += a[ch * K + k] * y[k];
    return out;
}

std::vector<double> randomCoefficients(int degree, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    std::vector<double> a(3 * (degree + 1) * (degree + 1));
    for (double& v : a) v = g(rng);
    return a;
}

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> g;
    return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

// Writes rgb (3 floats per texel, rows top to bottom) as an OpenEXR file with R, G, B channels.
void writeExr(const std::string& path, int width, int height, const std::vector<float>& rgb,
              Imf::Compression compression, Imf::PixelType type = Imf::FLOAT) {
    Imf::Header header(width, height);
    header.compression() = compression;
    const char* names[3] = {"R", "G", "B"};
    for (const char* name : names) header.channels().insert(name, Imf::Channel(type));
    std::vector<half> halves;
    Imf::FrameBuffer frameBuffer;
    if (type == Imf::HALF) {
        halves.assign(rgb.begin(), rgb.end());
        for (int c = 0; c < 3; ++c)
            frameBuffer.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.data() + c),
                                                    3 * sizeof(half), 3 * sizeof(half) * width));
    } else {
        for (int c = 0; c < 3; ++c)
            frameBuffer.insert(names[c], Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(rgb.data() + c)),
                                                    3 * sizeof(float), 3 * sizeof(float) * width));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frameBuffer);
    file.writePixels(height);
}

std::vector<float> rampPixels(int width, int height) {
    // Distinct positive values spanning several decades, different per channel.
    std::vector<float> rgb(std::size_t(width) * height * 3);
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c)
            for (int k = 0; k < 3; ++k)
                rgb[(std::size_t(r) * width + c) * 3 + k] = 0.01f * std::pow(1.7f, float(c + 2 * r + k));
    return rgb;
}

// Runs readEnvironmentMap and returns the error text ("" when it did not throw).
std::string readError(const std::string& path) {
    try {
        rad::readEnvironmentMap(path);
    } catch (const rad::EnvironmentMapError& e) {
        return e.what();
    }
    return "";
}

// ---------------------------------------------------------------------------------------------
// Parameterisation and lookups
// ---------------------------------------------------------------------------------------------

TEST(EnvironmentMap, DirectionsFollowTheStatedConvention) {
    // Hand values: image centre +X, a quarter from the left +Y, the borders -X, the top row +Z.
    EXPECT_LT((rad::EnvironmentMap::mapDirection(0.5, 0.5) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
    EXPECT_LT((rad::EnvironmentMap::mapDirection(0.25, 0.5) - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
    EXPECT_LT((rad::EnvironmentMap::mapDirection(0.75, 0.5) - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12);
    EXPECT_LT((rad::EnvironmentMap::mapDirection(0.0, 0.5) - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-12);
    EXPECT_LT((rad::EnvironmentMap::mapDirection(0.3, 0.0) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
    EXPECT_LT((rad::EnvironmentMap::mapDirection(0.3, 1.0) - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);

    // A 4 x 2 map: texel (0, 0) is centred at s = 1/8, t = 1/4: theta = pi/4, phi = 3 pi/4,
    // i.e. (sin45 cos135, sin45 sin135, cos45) = (-1/2, 1/2, sqrt(1/2)).
    const rad::EnvironmentMap map(4, 2, std::vector<float>(24, 1.0f));
    EXPECT_LT((map.texelDirection(0, 0) - Eigen::Vector3d(-0.5, 0.5, std::sqrt(0.5))).norm(), 1e-12);
    // Texel (2, 1): s = 5/8, t = 3/4: theta = 3 pi/4, phi = -pi/4: (1/2, -1/2, -sqrt(1/2)).
    EXPECT_LT((map.texelDirection(2, 1) - Eigen::Vector3d(0.5, -0.5, -std::sqrt(0.5))).norm(), 1e-12);
}

TEST(EnvironmentMap, TexelSolidAnglesAreExactAndTileTheSphere) {
    for (const auto& size : {std::pair<int, int>{4, 2}, {37, 11}, {1024, 512}}) {
        const int W = size.first, H = size.second;
        const rad::EnvironmentMap map(W, H, std::vector<float>(std::size_t(W) * H * 3, 0.0f));
        double total = 0.0;
        for (int r = 0; r < H; ++r) {
            EXPECT_NEAR(map.texelSolidAngle(r), conventionSolidAngle(r, W, H), 1e-14) << W << "x" << H << " row " << r;
            total += W * map.texelSolidAngle(r);
        }
        EXPECT_NEAR(total, 4.0 * kPi, 1e-11);
    }
}

TEST(EnvironmentMap, BilinearLookupsHitTexelCentresAndInterpolateBetween) {
    const int W = 8, H = 4;
    std::vector<float> rgb(std::size_t(W) * H * 3);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 10.0f);
    for (float& v : rgb) v = u(rng);
    const rad::EnvironmentMap map(W, H, rgb);
    auto texel = [&](int c, int r) {
        const float* t = &rgb[(std::size_t(r) * W + c) * 3];
        return Eigen::Vector3d(t[0], t[1], t[2]);
    };
    // At every texel centre: the texel.
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            EXPECT_LT((map.radiance(conventionDirection((c + 0.5) / W, (r + 0.5) / H)) - texel(c, r)).norm(), 1e-5);
    // Halfway between two columns of a row (s on the texel border, t at the row centre): the mean.
    EXPECT_LT((map.radiance(conventionDirection(3.0 / W, 1.5 / H)) - 0.5 * (texel(2, 1) + texel(3, 1))).norm(), 1e-5);
    // Across the seam (s = 0 = 1, direction -X side): first and last columns, longitude wraps.
    EXPECT_LT((map.radiance(conventionDirection(0.0, 2.5 / H)) - 0.5 * (texel(0, 2) + texel(W - 1, 2))).norm(), 1e-5);
    // Between two rows: the mean of the texels above and below.
    EXPECT_LT((map.radiance(conventionDirection(4.5 / W, 2.0 / H)) - 0.5 * (texel(4, 1) + texel(4, 2))).norm(), 1e-5);
    // Nearer the pole than the first row's centres: clamped to that row (interpolated in longitude only).
    EXPECT_LT((map.radiance(conventionDirection(5.5 / W, 0.1 / H)) - texel(5, 0)).norm(), 1e-5);
    EXPECT_LT((map.radiance(conventionDirection(6.0 / W, 1.0 - 0.2 / H)) - 0.5 * (texel(5, H - 1) + texel(6, H - 1))).norm(),
              1e-5);
    // Non-unit directions are normalised; zero and non-finite ones are black.
    EXPECT_LT((map.radiance(7.0 * conventionDirection(1.5 / W, 2.5 / H)) - texel(1, 2)).norm(), 1e-5);
    EXPECT_EQ(map.radiance(Eigen::Vector3d::Zero()), Eigen::Vector3d::Zero());
    EXPECT_EQ(map.radiance(Eigen::Vector3d(std::nan(""), 0, 1)), Eigen::Vector3d::Zero());
}

TEST(EnvironmentMap, RotationMovesWhatTheMapShowsToTheRotatedDirection) {
    std::mt19937 rng(9);
    const rad::EnvironmentMap plain = mapFromFunction(64, 32, [](const Eigen::Vector3d& w) {
        return Eigen::Vector3d(1.0 + w.x(), 2.0 + w.y() * w.z(), std::exp(w.z()));
    });
    rad::EnvironmentMap rotated = plain;
    const Eigen::Matrix3d R = randomRotation(rng);
    rotated.setRotation(R);
    for (int i = 0; i < 50; ++i) {
        const Eigen::Vector3d d = radtest::randomUnit(rng);
        EXPECT_LT((rotated.radiance(R * d) - plain.radiance(d)).norm(), 1e-9);
    }
    for (int r = 0; r < 32; r += 5)
        for (int c = 0; c < 64; c += 7) EXPECT_LT((rotated.texelDirection(c, r) - R * plain.texelDirection(c, r)).norm(), 1e-12);

    // rotationAboutZ(pi/2) takes the map's +X (image centre) to world +Y.
    const Eigen::Matrix3d Rz = rad::rotationAboutZ(0.5 * kPi);
    EXPECT_LT((Rz * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-15);
    rad::EnvironmentMap turned = plain;
    turned.setRotation(Rz);
    EXPECT_LT((turned.radiance(Eigen::Vector3d::UnitY()) - plain.radiance(Eigen::Vector3d::UnitX())).norm(), 1e-9);
    // The integral does not depend on the rotation.
    EXPECT_LT((rotated.sphereIntegral() - plain.sphereIntegral()).norm(), 1e-12);
}

TEST(EnvironmentMap, RefusesMatricesThatAreNotRotations) {
    rad::EnvironmentMap map(4, 2, std::vector<float>(24, 1.0f));
    Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
    mirror(0, 0) = -1.0;
    EXPECT_THROW(map.setRotation(mirror), std::invalid_argument);
    EXPECT_THROW(map.setRotation(2.0 * Eigen::Matrix3d::Identity()), std::invalid_argument);
    Eigen::Matrix3d nan = Eigen::Matrix3d::Identity();
    nan(1, 2) = std::nan("");
    EXPECT_THROW(map.setRotation(nan), std::invalid_argument);
    EXPECT_TRUE(map.rotation().isIdentity(0.0));  // unchanged by the refused calls
}

TEST(EnvironmentMap, ConstructorRefusesBadDataAndClampsNegatives) {
    EXPECT_THROW(rad::EnvironmentMap(0, 2, {}), rad::EnvironmentMapError);
    EXPECT_THROW(rad::EnvironmentMap(4, 2, std::vector<float>(23, 1.0f)), rad::EnvironmentMapError);
    std::vector<float> bad(24, 1.0f);
    bad[7] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(rad::EnvironmentMap(4, 2, bad), rad::EnvironmentMapError);
    bad[7] = std::numeric_limits<float>::infinity();
    EXPECT_THROW(rad::EnvironmentMap(4, 2, bad), rad::EnvironmentMapError);

    // Ringing-sized negatives (here 1e-4 of the positive sum) are clamped and counted...
    std::vector<float> ringing(24, 1.0f);
    ringing[3] = -1e-3f;
    ringing[10] = -1e-3f;
    const rad::EnvironmentMap map(4, 2, ringing);
    EXPECT_EQ(map.clampedNegativeCount(), 2);
    EXPECT_EQ(map.texel(1, 0)[0], 0.0f);
    EXPECT_EQ(map.texel(3, 0)[1], 0.0f);
    EXPECT_EQ(map.texel(3, 0)[0], 1.0f);
    // ...but data whose negative values weigh more than 1e-3 of the positive ones is not radiance.
    std::vector<float> signedData(24, 1.0f);
    signedData[5] = -0.5f;  // 0.5 / 23 = 2 %
    try {
        rad::EnvironmentMap refused(4, 2, signedData);
        FAIL() << "signed data accepted";
    } catch (const rad::EnvironmentMapError& e) {
        EXPECT_NE(std::string(e.what()).find("not a radiance map"), std::string::npos) << e.what();
    }
}

// ---------------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------------

TEST(EnvironmentMapFile, ReadsOpenExrWithEveryCompression) {
    const int W = 7, H = 5;  // odd sizes: no row or column pairing hides an error
    const std::vector<float> rgb = rampPixels(W, H);
    struct Case {
        Imf::Compression compression;
        Imf::PixelType type;
        double relativeTolerance;  // 0: bit-exact
    };
    // Half: 11-bit mantissa (relative 2^-11). PXR24 keeps 15 mantissa bits of a float. DWAA/DWAB
    // are lossy (DCT) on half RGB; their error is far below 1 % for these smooth values.
    const Case cases[] = {
        {Imf::NO_COMPRESSION, Imf::FLOAT, 0.0},   {Imf::RLE_COMPRESSION, Imf::FLOAT, 0.0},
        {Imf::ZIPS_COMPRESSION, Imf::FLOAT, 0.0}, {Imf::ZIP_COMPRESSION, Imf::FLOAT, 0.0},
        {Imf::PIZ_COMPRESSION, Imf::FLOAT, 0.0},  {Imf::PXR24_COMPRESSION, Imf::FLOAT, 1e-4},
        {Imf::DWAB_COMPRESSION, Imf::FLOAT, 0.0}, {Imf::ZIP_COMPRESSION, Imf::HALF, 1e-3},
        {Imf::B44_COMPRESSION, Imf::HALF, 5e-2},  {Imf::DWAA_COMPRESSION, Imf::HALF, 5e-2},
        {Imf::DWAB_COMPRESSION, Imf::HALF, 5e-2},
    };
    for (const Case& test : cases) {
        const std::string path = tmpPath("compression" + std::to_string(int(test.compression)) + "_" +
                                         std::to_string(int(test.type)) + ".exr");
        writeExr(path, W, H, rgb, test.compression, test.type);
        const rad::EnvironmentMap map = rad::readEnvironmentMap(path);
        ASSERT_EQ(map.width(), W);
        ASSERT_EQ(map.height(), H);
        for (std::size_t i = 0; i < rgb.size(); ++i)
            ASSERT_NEAR(map.pixels()[i], rgb[i], test.relativeTolerance * rgb[i])
                << "compression " << int(test.compression) << " type " << int(test.type) << " value " << i;
    }
}

TEST(EnvironmentMapFile, ReadsLuminanceOnlyExrAsGrey) {
    const int W = 6, H = 3;
    std::vector<Imf::Rgba> pixels(W * H);
    for (int i = 0; i < W * H; ++i) pixels[i] = Imf::Rgba(half(0.25f * (i + 1)), half(0.25f * (i + 1)), half(0.25f * (i + 1)));
    const std::string path = tmpPath("luminance.exr");
    {
        Imf::RgbaOutputFile file(path.c_str(), W, H, Imf::WRITE_Y);
        file.setFrameBuffer(pixels.data(), 1, W);
        file.writePixels(H);
    }
    const rad::EnvironmentMap map = rad::readEnvironmentMap(path);
    ASSERT_EQ(map.width(), W);
    for (int i = 0; i < W * H; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(map.pixels()[3 * i + k], 0.25f * (i + 1), 2e-3 * (i + 1)) << i;
}

TEST(EnvironmentMapFile, DataWindowSmallerThanDisplayWindowIsBlackOutside) {
    const int W = 8, H = 4;
    Imf::Header header(Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(W - 1, H - 1)),
                       Imath::Box2i(Imath::V2i(2, 1), Imath::V2i(4, 2)));  // columns 2..4, rows 1..2
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[3] = {"R", "G", "B"};
    for (const char* name : names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    std::vector<float> data(3 * 2 * 3);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = 1.0f + float(i);
    Imf::FrameBuffer frameBuffer;
    for (int c = 0; c < 3; ++c)
        frameBuffer.insert(names[c], Imf::Slice::Make(Imf::FLOAT, data.data() + c, header.dataWindow(), 3 * sizeof(float),
                                                      3 * sizeof(float) * 3));
    const std::string path = tmpPath("datawindow.exr");
    {
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frameBuffer);
        file.writePixels(2);
    }
    const rad::EnvironmentMap map = rad::readEnvironmentMap(path);
    ASSERT_EQ(map.width(), W);
    ASSERT_EQ(map.height(), H);
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            for (int k = 0; k < 3; ++k) {
                const bool inside = c >= 2 && c <= 4 && r >= 1 && r <= 2;
                const float expected = inside ? data[((r - 1) * 3 + (c - 2)) * 3 + k] : 0.0f;
                EXPECT_EQ(map.texel(c, r)[k], expected) << c << "," << r;
            }
}

TEST(EnvironmentMapFile, ReadsRadianceRgbeFlatAndRunLengthEncoded) {
    // stb_image_write writes scanlines narrower than 8 flat and wider ones run-length encoded.
    for (const int W : {5, 19}) {
        const int H = 3;
        const std::vector<float> rgb = rampPixels(W, H);
        const std::string path = tmpPath("rgbe" + std::to_string(W) + ".hdr");
        ASSERT_TRUE(stbi_write_hdr(path.c_str(), W, H, 3, rgb.data()));
        const rad::EnvironmentMap map = rad::readEnvironmentMap(path);
        ASSERT_EQ(map.width(), W);
        ASSERT_EQ(map.height(), H);
        for (int i = 0; i < W * H; ++i) {
            // RGBE: one shared exponent, 8-bit mantissas: error below 1/128 of the largest channel.
            const float largest = std::max({rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]});
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(map.pixels()[3 * i + k], rgb[3 * i + k], largest / 128.0f) << W << " " << i;
        }
    }
}

TEST(EnvironmentMapFile, RefusesMissingEmptyForeignTruncatedAndNonFiniteFilesNamingThem) {
    const std::string missing = tmpPath("does_not_exist.exr");
    std::remove(missing.c_str());
    EXPECT_NE(readError(missing).find(missing), std::string::npos);

    const std::string empty = tmpPath("empty.hdr");
    radtest::writeBytes(empty, {});
    std::string why = readError(empty);
    EXPECT_NE(why.find(empty), std::string::npos) << why;
    EXPECT_NE(why.find("empty"), std::string::npos) << why;

    const std::string text = tmpPath("text.exr");
    const std::string content = "this is not an image\n";
    radtest::writeBytes(text, std::vector<char>(content.begin(), content.end()));
    why = readError(text);
    EXPECT_NE(why.find(text), std::string::npos) << why;

    // Truncated files: cuts of an EXR (header, offset table or pixel data) and of both RGBE layouts
    // must be refused, never read as partial black (nor hang: stb's RLE decoder would loop).
    const std::vector<float> rgb = rampPixels(19, 6);
    const std::string exr = tmpPath("whole.exr");
    writeExr(exr, 19, 6, rgb, Imf::ZIP_COMPRESSION);
    const std::string rle = tmpPath("whole_rle.hdr"), flat = tmpPath("whole_flat.hdr");
    ASSERT_TRUE(stbi_write_hdr(rle.c_str(), 19, 6, 3, rgb.data()));
    ASSERT_TRUE(stbi_write_hdr(flat.c_str(), 5, 6, 3, rgb.data()));
    for (const std::string& whole : {exr, rle, flat}) {
        const std::vector<char> bytes = radtest::readBytes(whole);
        ASSERT_GT(bytes.size(), 40u);
        for (const double fraction : {0.1, 0.5, 0.9, 0.99, 1.0}) {
            // 1.0: one byte short, the last texel's exponent.
            const std::size_t keep = std::min(bytes.size() - 1, static_cast<std::size_t>(fraction * bytes.size()));
            const std::string cut = tmpPath("truncated_" + std::to_string(keep) + "_" + whole.substr(whole.rfind('/') + 1));
            radtest::writeBytes(cut, std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(keep)));
            why = readError(cut);
            EXPECT_NE(why.find(cut), std::string::npos) << "kept " << keep << " of " << bytes.size() << ": '" << why << "'";
        }
        EXPECT_EQ(readError(whole), "");
    }

    // A complete RLE file whose first run count is 0: corrupt (stb itself would never finish it).
    {
        std::vector<char> bytes = radtest::readBytes(rle);
        const std::string header(bytes.begin(), bytes.begin() + 200);
        const std::size_t resolution = header.find("\n\n") + 2;
        const std::size_t firstCount = header.find('\n', resolution) + 1 + 4;  // after "2 2 0 19"
        ASSERT_EQ(bytes[firstCount - 4], 2);
        bytes[firstCount] = 0;
        const std::string corrupt = tmpPath("zero_run.hdr");
        radtest::writeBytes(corrupt, bytes);
        why = readError(corrupt);
        EXPECT_NE(why.find(corrupt), std::string::npos) << why;
        EXPECT_NE(why.find("corrupt"), std::string::npos) << why;
    }

    // NaN and infinity in a float EXR.
    for (const float badValue : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        std::vector<float> bad = rgb;
        bad[40] = badValue;
        const std::string path = tmpPath(std::isnan(badValue) ? "nan.exr" : "inf.exr");
        writeExr(path, 19, 6, bad, Imf::ZIP_COMPRESSION);
        why = readError(path);
        EXPECT_NE(why.find(path), std::string::npos) << why;
        EXPECT_NE(why.find(std::isnan(badValue) ? "NaN" : "infinite"), std::string::npos) << why;
        EXPECT_NE(why.find("(column 13, row 0) channel G"), std::string::npos) << why;  // value 40 = texel 13, G
    }
}

TEST(EnvironmentMapFile, NegativeValuesInFilesAreClampedToZero) {
    std::vector<float> rgb = rampPixels(7, 5);
    rgb[4] = -2e-3f;
    const std::string path = tmpPath("negative.exr");
    writeExr(path, 7, 5, rgb, Imf::ZIP_COMPRESSION);
    const rad::EnvironmentMap map = rad::readEnvironmentMap(path);
    EXPECT_EQ(map.clampedNegativeCount(), 1);
    EXPECT_EQ(map.pixels()[4], 0.0f);
    EXPECT_EQ(map.pixels()[5], rgb[5]);
}

TEST(EnvironmentMapFile, ReadsTheRealMapsOfTheDataCache) {
    const std::string dir = hdrCacheDir();
    const char* exrNames[] = {"city.exr",   "courtyard.exr", "forest.exr", "interior.exr",
                              "night.exr",  "studio.exr",    "sunrise.exr", "sunset.exr"};
    const char* hdrNames[] = {"preview_landscape.hdr", "preview_studio.hdr"};
    if (!fileExists(dir + "/" + exrNames[0])) GTEST_SKIP() << "data cache missing: " << dir;
    auto check = [](const std::string& path, bool exr) {
        SCOPED_TRACE(path);
        const rad::EnvironmentMap map = rad::readEnvironmentMap(path);
        if (exr) {  // Blender's 1k maps (DWAB-compressed float RGB)
            EXPECT_EQ(map.width(), 1024);
            EXPECT_EQ(map.height(), 512);
        } else {
            EXPECT_EQ(map.width(), 2 * map.height());  // latitude-longitude aspect
        }
        float largest = 0.0f;
        for (float v : map.pixels()) {
            ASSERT_TRUE(std::isfinite(v));
            ASSERT_GE(v, 0.0f);
            largest = std::max(largest, v);
        }
        EXPECT_GT(largest, 1.0f);  // a high dynamic range, not an 8-bit image
        EXPECT_GT(map.sphereIntegral().minCoeff(), 0.0);
        // Clamped ringing must stay a negligible fraction of the texels.
        EXPECT_LT(map.clampedNegativeCount(), static_cast<long long>(map.pixels().size() / 20));
    };
    for (const char* name : exrNames) check(dir + "/" + name, true);
    for (const char* name : hdrNames)
        if (fileExists(dir + "/" + name)) check(dir + "/" + name, false);
}

// ---------------------------------------------------------------------------------------------
// Spherical-harmonic projection
// ---------------------------------------------------------------------------------------------

TEST(EnvironmentMapSh, ConstantMapProjectsOntoY00Only) {
    const double C[3] = {0.75, 2.0, 13.5};  // exact in float, as the texels are
    for (const auto& size : {std::pair<int, int>{3, 2}, {64, 32}, {1024, 512}}) {
        const int W = size.first, H = size.second;
        std::vector<float> rgb(std::size_t(W) * H * 3);
        for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = float(C[i % 3]);
        rad::EnvironmentMap map(W, H, rgb);
        std::mt19937 rng(2);
        for (const bool rotate : {false, true}) {
            if (rotate) map.setRotation(randomRotation(rng));
            const int degree = rad::kMaxHarmonicDegree, K = (degree + 1) * (degree + 1);
            const std::vector<double> c = rad::projectOntoSphericalHarmonics(map, degree);
            ASSERT_EQ(c.size(), std::size_t(3 * K));
            for (int ch = 0; ch < 3; ++ch) {
                EXPECT_NEAR(c[ch * K], C[ch] * std::sqrt(4.0 * kPi), 1e-9 * C[ch]) << W << "x" << H;
                for (int k = 1; k < K; ++k) EXPECT_NEAR(c[ch * K + k], 0.0, 1e-9 * C[ch]) << W << "x" << H << " k " << k;
            }
        }
    }
}

TEST(EnvironmentMapSh, MapOfALowOrderExpansionProjectsBackToItsCoefficients) {
    // Texels sampled from f = sum_k a_k Y_k (degree 4) at their centres; projected to degree 10.
    // The only error is that of the box reconstruction (texel centre value vs texel mean),
    // O(texel size^2): at most 1e-3 here (256 x 128 map, coefficients of order 1, Y00 ~ 70).
    const int fDegree = 4, degree = rad::kMaxHarmonicDegree;
    const int fK = (fDegree + 1) * (fDegree + 1), K = (degree + 1) * (degree + 1);
    const std::vector<double> a = randomCoefficients(fDegree, 17);
    // Offset channel values to keep them positive (radiance); the offset goes to Y00.
    const double offset = 20.0;
    const rad::EnvironmentMap map = mapFromFunction(256, 128, [&](const Eigen::Vector3d& w) -> Eigen::Vector3d {
        return (evaluateSh(fDegree, a, w).array() + offset).matrix();
    });
    ASSERT_EQ(map.clampedNegativeCount(), 0);
    const std::vector<double> c = rad::projectOntoSphericalHarmonics(map, degree);
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 0; k < K; ++k) {
            double expected = k < fK ? a[ch * fK + k] : 0.0;
            if (k == 0) expected += offset * std::sqrt(4.0 * kPi);
            EXPECT_NEAR(c[ch * K + k], expected, 2e-3) << "channel " << ch << " k " << k;
        }
}

TEST(EnvironmentMapSh, ProjectionOfRotatedMapEqualsRotatedCoefficients) {
    const int fDegree = 3, degree = 6, K = (degree + 1) * (degree + 1);
    const std::vector<double> a = randomCoefficients(fDegree, 23);
    rad::EnvironmentMap map = mapFromFunction(256, 128, [&](const Eigen::Vector3d& w) -> Eigen::Vector3d {
        return (evaluateSh(fDegree, a, w).array() + 10.0).matrix();
    });
    const std::vector<double> plain = rad::projectOntoSphericalHarmonics(map, degree);
    std::mt19937 rng(31);
    const rad::SphereQuadrature& rule = rad::lebedevRule(1202);
    for (int trial = 0; trial < 3; ++trial) {
        const Eigen::Matrix3d R = trial == 0 ? rad::rotationAboutZ(0.7) : randomRotation(rng);
        map.setRotation(R);
        const std::vector<double> rotated = rad::projectOntoSphericalHarmonics(map, degree);

        // (1) sh_rotation.h: projecting the rotated map == rotating the projected coefficients.
        const rad::ShRotation D(degree, R);
        std::vector<double> expected(plain.size());
        for (int ch = 0; ch < 3; ++ch) D.apply(&plain[ch * K], &expected[ch * K]);
        for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(rotated[i], expected[i], 1e-10) << "trial " << trial << " " << i;

        // (2) Independently of sh_rotation.h: brute-force projection of the world-frame lookups
        // radiance(w) (Lebedev rule of precision 59; the bilinear lookups of the smooth map differ
        // from the function by O(texel^2): 6e-4 at most here).
        std::vector<double> brute(3 * K, 0.0), y(K);
        for (std::size_t p = 0; p < rule.size(); ++p) {
            const Eigen::Vector3d w(rule.x[p], rule.y[p], rule.z[p]);
            const Eigen::Vector3d L = map.radiance(w);
            rad::evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), y.data());
            for (int ch = 0; ch < 3; ++ch)
                for (int k = 0; k < K; ++k) brute[ch * K + k] += rule.w[p] * L[ch] * y[k];
        }
        for (std::size_t i = 0; i < brute.size(); ++i) EXPECT_NEAR(rotated[i], brute[i], 2e-3) << "trial " << trial << " " << i;
    }
}

TEST(EnvironmentMapSh, RefusesDegreesOutsideTheBasis) {
    const rad::EnvironmentMap map(4, 2, std::vector<float>(24, 1.0f));
    EXPECT_THROW(rad::projectOntoSphericalHarmonics(map, -1), std::out_of_range);
    EXPECT_THROW(rad::projectOntoSphericalHarmonics(map, rad::kMaxHarmonicDegree + 1), std::out_of_range);
    EXPECT_EQ(rad::projectOntoSphericalHarmonics(rad::EnvironmentMap(), 2), std::vector<double>(27, 0.0));
}

}  // namespace
