// The 3DGS .ply reader: files written by an independent writer (splat_test_support.h, after the
// reference implementation's save_ply) read back value for value in every format, property order and
// degree; bad files refused with what is wrong.
#include "splats/gaussian_splat_ply.h"
#include "test_temporary_directory.h"

#include "splat_test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace {

using splattest::PlyFormat;
using splattest::RefSplat;

std::string tmp(const std::string& name) {
    std::filesystem::create_directories(RADIANCE_TEST_TMPDIR);
    return std::string(RADIANCE_TEST_TMPDIR) + "/gaussian_splat_ply_" + name;
}

std::vector<RefSplat> randomSplats(int degree, int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    std::vector<RefSplat> splats(count);
    const int k = (degree + 1) * (degree + 1);
    for (RefSplat& s : splats) {
        s.position = Eigen::Vector3f(u(rng), u(rng), u(rng));
        for (auto& channel : s.sh) {
            channel.resize(k);
            for (float& c : channel) c = u(rng);
        }
        s.opacityLogit = u(rng);
        s.logScale = Eigen::Vector3f(u(rng), u(rng), u(rng));
        s.rotation = Eigen::Vector4f(u(rng), u(rng), u(rng), u(rng));
    }
    return splats;
}

void expectSame(const std::vector<RefSplat>& written, const rad::GaussianSplats& read, int degree) {
    ASSERT_EQ(read.count(), written.size());
    ASSERT_EQ(read.shDegree, degree);
    const int k = (degree + 1) * (degree + 1);
    for (std::size_t i = 0; i < written.size(); ++i) {
        const RefSplat& s = written[i];
        for (int a = 0; a < 3; ++a) EXPECT_FLOAT_EQ(read.positions[3 * i + a], s.position[a]);
        for (int c = 0; c < 3; ++c)
            for (int j = 0; j < k; ++j) EXPECT_FLOAT_EQ(read.sh[(3 * i + c) * k + j], s.sh[c][j]) << i << " " << c << " " << j;
        EXPECT_FLOAT_EQ(read.opacityLogit[i], s.opacityLogit);
        for (int a = 0; a < 3; ++a) EXPECT_FLOAT_EQ(read.logScale[3 * i + a], s.logScale[a]);
        for (int a = 0; a < 4; ++a) EXPECT_FLOAT_EQ(read.rotation[4 * i + a], s.rotation[a]);
    }
}

std::string refusal(const std::string& path) {
    try {
        rad::readGaussianSplatPly(path);
    } catch (const rad::SplatFileError& e) {
        return e.what();
    }
    return "(read without refusal)";
}

TEST(GaussianSplatPly, ReadsEveryDegreeAsTheReferenceWritesIt) {
    for (int degree = 0; degree <= 3; ++degree) {
        const auto splats = randomSplats(degree, 37, 10 + degree);
        const std::string path = tmp("degree" + std::to_string(degree) + ".ply");
        splattest::writeSplatPly(path, splats, degree);
        expectSame(splats, rad::readGaussianSplatPly(path), degree);
    }
}

TEST(GaussianSplatPly, ReadsAsciiAndBigEndian) {
    const auto splats = randomSplats(3, 11, 4);
    for (PlyFormat format : {PlyFormat::Ascii, PlyFormat::BinaryBigEndian}) {
        const std::string path = tmp(format == PlyFormat::Ascii ? "ascii.ply" : "big.ply");
        splattest::writeSplatPly(path, splats, 3, format);
        expectSame(splats, rad::readGaussianSplatPly(path), 3);
    }
}

TEST(GaussianSplatPly, ChannelMajorRestCoefficientsLandOnTheirChannel) {
    // One splat whose coefficients encode (channel, index): f_rest_16 is green's second band-1
    // coefficient (index 2) in the reference's channel-major order.
    RefSplat s;
    for (int c = 0; c < 3; ++c) {
        s.sh[c].resize(16);
        for (int j = 0; j < 16; ++j) s.sh[c][j] = 100.0f * c + j;
    }
    const std::string path = tmp("order.ply");
    splattest::writeSplatPly(path, {s}, 3);
    const rad::GaussianSplats read = rad::readGaussianSplatPly(path);
    EXPECT_EQ(read.sh[1 * 16 + 2], 102.0f);
    EXPECT_EQ(read.sh[2 * 16 + 15], 215.0f);
    EXPECT_EQ(read.sh[0], 0.0f);
}

TEST(GaussianSplatPly, PropertiesInAnyOrderWithoutNormalsAndWithExtras) {
    const auto splats = randomSplats(1, 9, 5);
    auto names = splattest::referenceProperties(1, false);
    std::reverse(names.begin(), names.end());
    names.push_back("state");  // an extra property is ignored
    const std::string path = tmp("reordered.ply");
    splattest::writeSplatPly(path, splats, 1, PlyFormat::BinaryLittleEndian, names);
    expectSame(splats, rad::readGaussianSplatPly(path), 1);
}

TEST(GaussianSplatPly, RefusesAPlainMeshNamingWhatIsMissing) {
    const std::string path = tmp("mesh.ply");
    std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                           "property float z\nproperty uchar red\nend_header\n0 0 0 255\n";
    const std::string why = refusal(path);
    EXPECT_NE(why.find("not a 3D Gaussian splat file"), std::string::npos) << why;
    EXPECT_NE(why.find("f_dc_0"), std::string::npos) << why;
    EXPECT_NE(why.find("x y z red"), std::string::npos) << why;
}

TEST(GaussianSplatPly, RefusesNaNNamingTheSplatAndProperty) {
    auto splats = randomSplats(2, 5, 6);
    splats[3].sh[1][4] = std::nanf("");
    const std::string path = tmp("nan.ply");
    splattest::writeSplatPly(path, splats, 2);
    const std::string why = refusal(path);
    EXPECT_NE(why.find("splat 3 has a value that is not a finite number"), std::string::npos) << why;
    // Green's coefficient 4 is f_rest_(8 + 3) in channel-major order.
    EXPECT_NE(why.find("'f_rest_11'"), std::string::npos) << why;
}

TEST(GaussianSplatPly, RefusesDegreeAboveThree) {
    RefSplat s;
    for (auto& c : s.sh) c.assign(25, 0.1f);
    const std::string path = tmp("degree4.ply");
    splattest::writeSplatPly(path, {s}, 4);
    const std::string why = refusal(path);
    EXPECT_NE(why.find("degree 4"), std::string::npos) << why;
    EXPECT_NE(why.find("degrees 0 to 3"), std::string::npos) << why;
}

TEST(GaussianSplatPly, RefusesARestCountOfNoDegree) {
    auto names = splattest::referenceProperties(0);
    for (int i = 0; i < 5; ++i) names.push_back("f_rest_" + std::to_string(i));
    const std::string path = tmp("rest5.ply");
    splattest::writeSplatPly(path, randomSplats(0, 2, 7), 0, PlyFormat::BinaryLittleEndian, names);
    const std::string why = refusal(path);
    EXPECT_NE(why.find("5 f_rest_* properties"), std::string::npos) << why;
}

TEST(GaussianSplatPly, RefusesCompressedTruncatedMissingAndZeroRotation) {
    const std::string compressed = tmp("compressed.ply");
    std::ofstream(compressed) << "ply\nformat binary_little_endian 1.0\nelement chunk 1\nproperty float min_x\n"
                                 "element vertex 1\nproperty uint packed_position\nend_header\n";
    EXPECT_NE(refusal(compressed).find("compressed splat PLY"), std::string::npos) << refusal(compressed);

    const std::string whole = tmp("whole.ply");
    splattest::writeSplatPly(whole, randomSplats(3, 20, 8), 3);
    std::ifstream in(whole, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = tmp("truncated.ply");
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 100);
    EXPECT_NE(refusal(cut).find("truncated"), std::string::npos) << refusal(cut);

    EXPECT_NE(refusal(tmp("no_such_file.ply")).find("cannot be opened"), std::string::npos);

    auto splats = randomSplats(0, 3, 9);
    splats[1].rotation.setZero();
    const std::string zero = tmp("zero_rotation.ply");
    splattest::writeSplatPly(zero, splats, 0);
    EXPECT_NE(refusal(zero).find("splat 1 has a zero rotation quaternion"), std::string::npos) << refusal(zero);

    const std::string empty = tmp("empty.ply");
    std::ofstream(empty).close();
    EXPECT_NE(refusal(empty).find("empty"), std::string::npos);
}

TEST(GaussianSplatPly, ProgressReachesOneAndCancelStops) {
    const std::string path = tmp("progress.ply");
    splattest::writeSplatPly(path, randomSplats(0, 10000, 11), 0);
    double last = -1.0;
    rad::readGaussianSplatPly(path, [&](double f, const char*) {
        EXPECT_GE(f, last);
        last = f;
        return true;
    });
    EXPECT_EQ(last, 1.0);
    EXPECT_THROW(rad::readGaussianSplatPly(path, [](double, const char*) { return false; }), rad::OperationCancelled);
}

}  // namespace
