#include "lighting/environment_map.h"

#include "radiance/basis.h"
#include "radiance/sh_rotation.h"
#include "radiance/spherical_harmonics.h"

#include <Eigen/LU>  // determinant

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfRgba.h>
#include <ImfRgbaFile.h>
#include <stb/stb_image.h>  // declarations only: the implementation is compiled in image/image_io.cpp

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Refuse absurd sizes from corrupt headers before allocating (16384 x 16384 texels, 3 GB of floats).
constexpr long long kMaxTexels = 1LL << 28;

// Shared by the constructor and the readers: NaN/Inf refused; negatives clamped and counted when
// they are ringing (lossy compression, resampling: the Blender maps of data-cache/hdr have
// negative sums of 1e-11..1e-6 of their positive sums, the most negative value -0.004), refused
// when they weigh more than 1e-3 of the positive values: such data is not radiance (a normal or
// difference map), and clamping would silently change its lighting.
long long sanitise(std::vector<float>& rgb, int width, const std::string& what) {
    long long negatives = 0;
    double negativeSum = 0.0, positiveSum = 0.0;
    float mostNegative = 0.0f;
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        const float v = rgb[i];
        if (!std::isfinite(v)) {
            const std::size_t texel = i / 3;
            throw EnvironmentMapError(what + ": texel (column " + std::to_string(texel % std::size_t(width)) + ", row " +
                                      std::to_string(texel / std::size_t(width)) + ") channel " + "RGB"[i % 3] + " is " +
                                      (std::isnan(v) ? "NaN" : "infinite") +
                                      " (an environment map must hold finite radiance)");
        }
        if (v < 0.0f) {
            negativeSum -= v;
            mostNegative = std::min(mostNegative, v);
            rgb[i] = 0.0f;
            ++negatives;
        } else {
            positiveSum += v;
        }
    }
    if (negativeSum > 1e-3 * positiveSum)
        throw EnvironmentMapError(what + ": " + std::to_string(negatives) + " negative values (down to " +
                                  std::to_string(mostNegative) + ") weigh " +
                                  std::to_string(100.0 * negativeSum / std::max(positiveSum, 1e-300)) +
                                  " % of the positive ones: not a radiance map");
    return negatives;
}

// ---------------------------------------------------------------------------------------------
// OpenEXR
// ---------------------------------------------------------------------------------------------

std::vector<float> readExr(const std::string& path, int& width, int& height) {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    // The latitude-longitude parameterisation spans the display window; texels of the display
    // window outside the data window are black (OpenEXR semantics), data outside it is dropped.
    const Imath::Box2i display = header.displayWindow();
    const Imath::Box2i data = header.dataWindow();
    const long long w = static_cast<long long>(display.max.x) - display.min.x + 1;
    const long long h = static_cast<long long>(display.max.y) - display.min.y + 1;
    const long long dw = static_cast<long long>(data.max.x) - data.min.x + 1;
    const long long dh = static_cast<long long>(data.max.y) - data.min.y + 1;
    if (w <= 0 || h <= 0 || dw <= 0 || dh <= 0) throw std::runtime_error("empty display or data window");
    if (w * h > kMaxTexels || dw * dh > kMaxTexels)
        throw std::runtime_error("image too large (" + std::to_string(w) + " x " + std::to_string(h) + ")");

    std::vector<float> dataRgb(static_cast<std::size_t>(dw * dh) * 3, 0.0f);
    const Imf::ChannelList& channels = header.channels();
    const char* names[3] = {"R", "G", "B"};
    bool haveRgb = true;
    for (const char* name : names) {
        const Imf::Channel* channel = channels.findChannel(name);
        if (!channel) haveRgb = false;
        else if (channel->xSampling != 1 || channel->ySampling != 1)
            throw std::runtime_error(std::string("channel ") + name + " is subsampled, which is not supported");
    }
    if (haveRgb) {
        // Read as 32-bit float whatever the stored type (half, float or uint): a half buffer
        // would turn sun pixels above 65504 of a float file into infinity.
        Imf::FrameBuffer frameBuffer;
        for (int c = 0; c < 3; ++c)
            frameBuffer.insert(names[c], Imf::Slice::Make(Imf::FLOAT, dataRgb.data() + c, data, 3 * sizeof(float),
                                                          3 * sizeof(float) * static_cast<std::size_t>(dw)));
        file.setFrameBuffer(frameBuffer);
        file.readPixels(data.min.y, data.max.y);
    } else {
        // Luminance(-chroma) files, or RGB with a missing channel: the RGBA interface converts
        // them to RGB (half precision is all such files carry).
        Imf::RgbaInputFile rgbaFile(path.c_str());
        if (!(rgbaFile.channels() & (Imf::WRITE_RGB | Imf::WRITE_Y))) {
            std::string list;
            for (auto it = channels.begin(); it != channels.end(); ++it) list += std::string(list.empty() ? "" : ", ") + it.name();
            throw std::runtime_error("no R, G, B or Y channel (channels: " + (list.empty() ? "none" : list) + ")");
        }
        std::vector<Imf::Rgba> halves(static_cast<std::size_t>(dw * dh));
        rgbaFile.setFrameBuffer(halves.data() - data.min.x - static_cast<std::ptrdiff_t>(data.min.y) * dw, 1,
                                static_cast<std::size_t>(dw));
        rgbaFile.readPixels(data.min.y, data.max.y);
        for (std::size_t i = 0; i < halves.size(); ++i) {
            dataRgb[3 * i + 0] = halves[i].r;
            dataRgb[3 * i + 1] = halves[i].g;
            dataRgb[3 * i + 2] = halves[i].b;
        }
    }

    width = static_cast<int>(w);
    height = static_cast<int>(h);
    if (data == display) return dataRgb;
    std::vector<float> rgb(static_cast<std::size_t>(w * h) * 3, 0.0f);
    for (long long y = std::max(data.min.y, display.min.y); y <= std::min(data.max.y, display.max.y); ++y)
        for (long long x = std::max(data.min.x, display.min.x); x <= std::min(data.max.x, display.max.x); ++x)
            std::memcpy(&rgb[static_cast<std::size_t>((y - display.min.y) * w + (x - display.min.x)) * 3],
                        &dataRgb[static_cast<std::size_t>((y - data.min.y) * dw + (x - data.min.x)) * 3],
                        3 * sizeof(float));
    return rgb;
}

// ---------------------------------------------------------------------------------------------
// Radiance RGBE through stb_image
// ---------------------------------------------------------------------------------------------

// stb_image decodes RGBE well but cannot tell a truncated file from a complete one: past the end
// it reads zero bytes, so a cut file comes back with black (or garbage) rows, and in a
// run-length-encoded scanline a zero count never advances, so stb loops forever on a truncated
// file, or on a corrupt one with a zero count. Hence this walk over the file's structure (the
// format of G. Ward's Radiance, as stb reads it: header lines up to an empty line, the line
// "-Y <height> +X <width>", then per scanline either "2 2 <width high> <width low>" followed by
// four run-length-encoded channel planes (a byte n > 128 repeats the next byte n - 128 times,
// 0 < n <= 128 copies n bytes), or flat 4-byte RGBE texels). It checks that every byte stb will
// read is there and that no count is zero, before stb decodes. Throws std::runtime_error.
void checkRgbeStructure(const std::vector<unsigned char>& bytes) {
    const std::size_t n = bytes.size();
    // End of the header: the first empty line.
    std::size_t pos = 0;
    for (;;) {
        std::size_t eol = pos;
        while (eol < n && bytes[eol] != '\n') ++eol;
        if (eol >= n) throw std::runtime_error("the file is truncated (incomplete header)");
        const bool emptyLine = eol == pos;
        pos = eol + 1;
        if (emptyLine) break;
    }
    // The resolution line, parsed as stb parses it.
    std::size_t eol = pos;
    while (eol < n && bytes[eol] != '\n') ++eol;
    if (eol >= n) throw std::runtime_error("the file is truncated (no complete resolution line)");
    const std::string line(bytes.begin() + std::ptrdiff_t(pos), bytes.begin() + std::ptrdiff_t(eol));
    pos = eol + 1;
    long height = 0, width = 0;
    if (line.compare(0, 3, "-Y ") != 0) return;  // a layout stb refuses with its own message
    char* end = nullptr;
    height = std::strtol(line.c_str() + 3, &end, 10);
    while (*end == ' ') ++end;
    if (std::strncmp(end, "+X ", 3) != 0) return;
    width = std::strtol(end + 3, nullptr, 10);
    if (width <= 0 || height <= 0 || width * height > kMaxTexels)
        throw std::runtime_error("invalid resolution line '" + line + "'");

    for (long row = 0; row < height; ++row) {
        const bool rle = width >= 8 && width < 32768 && pos + 4 <= n && bytes[pos] == 2 && bytes[pos + 1] == 2 &&
                         !(bytes[pos + 2] & 0x80);
        if (!rle) {
            // stb decodes the rest of the image as flat texels, but restarting from the first
            // row: only right when the very first scanline is flat.
            if (row > 0)
                throw std::runtime_error("scanline " + std::to_string(row) +
                                         " is not run-length encoded after encoded ones (unsupported)");
            if (n - pos < static_cast<std::size_t>(width) * height * 4)
                throw std::runtime_error("the file is truncated (flat pixel data)");
            return;
        }
        if (((std::size_t(bytes[pos + 2]) << 8) | bytes[pos + 3]) != std::size_t(width))
            throw std::runtime_error("scanline " + std::to_string(row) + " has the wrong length");
        pos += 4;
        for (int channel = 0; channel < 4; ++channel)
            for (long i = 0; i < width;) {
                if (pos >= n) throw std::runtime_error("the file is truncated (scanline " + std::to_string(row) + ")");
                int count = bytes[pos++];
                if (count > 128) {
                    count -= 128;
                    ++pos;  // the repeated byte
                } else {
                    pos += std::size_t(count);
                }
                if (count == 0 || count > width - i)
                    throw std::runtime_error("corrupt run length in scanline " + std::to_string(row));
                if (pos > n) throw std::runtime_error("the file is truncated (scanline " + std::to_string(row) + ")");
                i += count;
            }
    }
}

std::vector<float> readRgbe(const std::string& path, int& width, int& height) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open the file");
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw std::runtime_error("file too large for the RGBE decoder");
    checkRgbeStructure(bytes);
    int w = 0, h = 0, channels = 0;
    std::unique_ptr<float, void (*)(void*)> pixels(
        stbi_loadf_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &channels, 3), stbi_image_free);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        throw std::runtime_error(std::string("Radiance RGBE decoder: ") + (reason ? reason : "unknown error"));
    }
    if (w <= 0 || h <= 0) throw std::runtime_error("empty image");
    width = w;
    height = h;
    return std::vector<float>(pixels.get(), pixels.get() + static_cast<std::size_t>(w) * h * 3);
}

// ---------------------------------------------------------------------------------------------
// Gauss-Legendre nodes on [-1, 1] (Newton on the three-term recurrence, Numerical Recipes 3rd ed.
// sec. 4.6 gauleg), computed once.
// ---------------------------------------------------------------------------------------------

constexpr int kGaussPoints = 8;

struct GaussLegendre {
    double x[kGaussPoints], w[kGaussPoints];
    GaussLegendre() {
        const int n = kGaussPoints;
        for (int i = 0; i < (n + 1) / 2; ++i) {
            double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 0.0;
            for (int iter = 0; iter < 100; ++iter) {
                double p1 = 1.0, p2 = 0.0;
                for (int j = 1; j <= n; ++j) {
                    const double p3 = p2;
                    p2 = p1;
                    p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
                }
                pp = n * (z * p1 - p2) / (z * z - 1.0);
                const double z1 = z;
                z = z1 - p1 / pp;
                if (std::fabs(z - z1) < 1e-16) break;
            }
            x[i] = -z;
            x[n - 1 - i] = z;
            w[i] = w[n - 1 - i] = 2.0 / ((1.0 - z * z) * pp * pp);
        }
    }
};

const GaussLegendre& gaussLegendre() {
    static const GaussLegendre rule;
    return rule;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// EnvironmentMap
// ---------------------------------------------------------------------------------------------

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<float> rgb) {
    if (width <= 0 || height <= 0)
        throw EnvironmentMapError("environment map: empty size " + std::to_string(width) + " x " + std::to_string(height));
    if (static_cast<long long>(width) * height > kMaxTexels)
        throw EnvironmentMapError("environment map: too large (" + std::to_string(width) + " x " +
                                  std::to_string(height) + ")");
    if (rgb.size() != static_cast<std::size_t>(width) * height * 3)
        throw EnvironmentMapError("environment map: " + std::to_string(rgb.size()) + " values for " +
                                  std::to_string(width) + " x " + std::to_string(height) + " RGB texels");
    clampedNegatives_ = sanitise(rgb, width, "environment map");
    width_ = width;
    height_ = height;
    rgb_ = std::move(rgb);
}

void EnvironmentMap::setRotation(const Eigen::Matrix3d& worldFromMap) {
    if (!worldFromMap.allFinite() ||
        (worldFromMap * worldFromMap.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
        worldFromMap.determinant() < 0.0)
        throw std::invalid_argument("EnvironmentMap::setRotation: not a proper rotation matrix (orthonormal, det +1)");
    rotation_ = worldFromMap;
}

Eigen::Vector3d EnvironmentMap::mapDirection(double s, double t) {
    const double theta = kPi * t, phi = kPi - 2.0 * kPi * s;
    const double st = std::sin(theta);
    return Eigen::Vector3d(st * std::cos(phi), st * std::sin(phi), std::cos(theta));
}

Eigen::Vector3d EnvironmentMap::texelDirection(int column, int row) const {
    return rotation_ * mapDirection((column + 0.5) / width_, (row + 0.5) / height_);
}

double EnvironmentMap::texelSolidAngle(int row) const {
    // 2 pi / W times the band's cos(theta_top) - cos(theta_bottom), written as
    // 2 sin(mid) sin(half) so that thin rows near the poles do not lose digits to cancellation.
    const double dTheta = kPi / height_;
    const double mid = (row + 0.5) * dTheta;
    return (2.0 * kPi / width_) * 2.0 * std::sin(mid) * std::sin(0.5 * dTheta);
}

Eigen::Vector3d EnvironmentMap::radiance(const Eigen::Vector3d& worldDirection) const {
    if (empty() || !worldDirection.allFinite()) return Eigen::Vector3d::Zero();
    const Eigen::Vector3d d = rotation_.transpose() * worldDirection;
    const double rxy = std::hypot(d.x(), d.y());
    if (rxy == 0.0 && d.z() == 0.0) return Eigen::Vector3d::Zero();
    const double theta = std::atan2(rxy, d.z());
    const double phi = std::atan2(d.y(), d.x());
    // Continuous texel-centre coordinates: texel c's centre is at x = c.
    double x = (0.5 - phi / (2.0 * kPi)) * width_ - 0.5;
    double y = theta / kPi * height_ - 0.5;
    y = std::min(std::max(y, 0.0), double(height_ - 1));
    const double fx = std::floor(x);
    const double ax = x - fx;
    int x0 = static_cast<int>(fx) % width_;
    if (x0 < 0) x0 += width_;
    const int x1 = (x0 + 1) % width_;  // longitude wraps
    const int y0 = static_cast<int>(y);
    const int y1 = std::min(y0 + 1, height_ - 1);
    const double ay = y - y0;
    Eigen::Vector3d out;
    for (int c = 0; c < 3; ++c) {
        const double top = texel(x0, y0)[c] + ax * (double(texel(x1, y0)[c]) - texel(x0, y0)[c]);
        const double bottom = texel(x0, y1)[c] + ax * (double(texel(x1, y1)[c]) - texel(x0, y1)[c]);
        out[c] = top + ay * (bottom - top);
    }
    return out;
}

Eigen::Vector3d EnvironmentMap::sphereIntegral() const {
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (int r = 0; r < height_; ++r) {
        Eigen::Vector3d row = Eigen::Vector3d::Zero();
        for (int c = 0; c < width_; ++c)
            for (int k = 0; k < 3; ++k) row[k] += texel(c, r)[k];
        total += row * texelSolidAngle(r);
    }
    return total;
}

// ---------------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------------

EnvironmentMap readEnvironmentMap(const std::string& path) {
    const std::string what = "environment map '" + path + "'";
    std::error_code folderError;
    if (std::filesystem::is_directory(path, folderError))
        throw EnvironmentMapError(what + " is a folder, not an image: choose the .exr or .hdr file inside it");
    unsigned char magic[4] = {0, 0, 0, 0};
    std::streamsize got = 0;
    {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw EnvironmentMapError("cannot open " + what + " (missing or unreadable)");
        in.read(reinterpret_cast<char*>(magic), 4);
        got = in.gcount();
    }
    if (got == 0) throw EnvironmentMapError(what + " is empty");

    const bool isExr = got == 4 && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01;
    const bool isRgbe = got >= 2 && magic[0] == '#' && magic[1] == '?';
    if (!isExr && !isRgbe)
        throw EnvironmentMapError(what + " is neither an OpenEXR nor a Radiance RGBE (.hdr) file");

    int width = 0, height = 0;
    std::vector<float> rgb;
    try {
        rgb = isExr ? readExr(path, width, height) : readRgbe(path, width, height);
    } catch (const EnvironmentMapError&) {
        throw;
    } catch (const std::exception& e) {
        // OpenEXR's Iex exceptions derive from std::exception; their text already says which
        // part of the file failed ("Early end of file", "Cannot read image file ...").
        throw EnvironmentMapError("cannot read " + what + ": " + e.what());
    }
    try {
        return EnvironmentMap(width, height, std::move(rgb));
    } catch (const EnvironmentMapError& e) {
        // Re-issue with the file name in place of the generic "environment map".
        std::string reason = e.what();
        const std::string generic = "environment map: ";
        if (reason.compare(0, generic.size(), generic) == 0) reason = reason.substr(generic.size());
        throw EnvironmentMapError(what + ": " + reason);
    }
}

Eigen::Matrix3d rotationAboutZ(double radians) {
    const double c = std::cos(radians), s = std::sin(radians);
    Eigen::Matrix3d R;
    R << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
    return R;
}

// ---------------------------------------------------------------------------------------------
// Spherical-harmonic projection
// ---------------------------------------------------------------------------------------------

std::vector<double> projectOntoSphericalHarmonics(const EnvironmentMap& map, int degree) {
    if (degree < 0 || degree > kMaxHarmonicDegree)
        throw std::out_of_range("projectOntoSphericalHarmonics: degree " + std::to_string(degree) + " outside [0, " +
                                std::to_string(kMaxHarmonicDegree) + "]");
    const int K = (degree + 1) * (degree + 1);
    std::vector<double> coefficients(static_cast<std::size_t>(kColorChannels) * K, 0.0);
    if (map.empty()) return coefficients;
    const int W = map.width(), H = map.height();

    // Y_l^{+m}(w) = A_l^m(cos theta) cos(m phi), Y_l^{-m}(w) = A_l^m(cos theta) sin(m phi) (m >= 0),
    // so the integral of Y over a texel, dw = sin theta dtheta dphi, separates into
    //   Theta_l^m(row) = int A_l^m(cos theta) sin theta dtheta  over the row,
    //   Phi_{+-m}(column) = int {cos, sin}(m phi) dphi           over the column.
    // Phi: analytic. Column c spans phi in [pi - 2 pi (c+1)/W, pi - 2 pi c/W].
    const int mCount = degree + 1;
    std::vector<double> phiCos(static_cast<std::size_t>(W) * mCount), phiSin(static_cast<std::size_t>(W) * mCount);
    for (int c = 0; c < W; ++c) {
        const double lo = kPi - 2.0 * kPi * (c + 1) / W, hi = kPi - 2.0 * kPi * c / W;
        phiCos[static_cast<std::size_t>(c) * mCount] = hi - lo;
        phiSin[static_cast<std::size_t>(c) * mCount] = 0.0;
        for (int m = 1; m <= degree; ++m) {
            phiCos[static_cast<std::size_t>(c) * mCount + m] = (std::sin(m * hi) - std::sin(m * lo)) / m;
            phiSin[static_cast<std::size_t>(c) * mCount + m] = (std::cos(m * lo) - std::cos(m * hi)) / m;
        }
    }

    // Theta: A_l^m(cos theta) sin theta is a trigonometric polynomial of degree <= degree + 1 in
    // theta; 8-point Gauss-Legendre on pieces short enough that (degree + 1) * piece <= 0.5 is
    // exact to rounding (the error term scales as (0.25)^16 / 16!).
    const GaussLegendre& gl = gaussLegendre();
    const double dTheta = kPi / H;
    const int pieces = std::max(1, static_cast<int>(std::ceil((degree + 1) * dTheta / 0.5)));
    const double pieceWidth = dTheta / pieces;

    // One block of K x 3 per row, summed afterwards in row order: deterministic whatever the
    // number of threads.
    std::vector<double> perRow(static_cast<std::size_t>(H) * K * kColorChannels, 0.0);
#pragma omp parallel for schedule(dynamic, 4)
    for (int r = 0; r < H; ++r) {
        double y[(kMaxHarmonicDegree + 1) * (kMaxHarmonicDegree + 1)];
        // Theta_l^m for m >= 0, stored at index l*l + l + m.
        double thetaIntegral[(kMaxHarmonicDegree + 1) * (kMaxHarmonicDegree + 1)] = {};
        for (int p = 0; p < pieces; ++p) {
            const double a = r * dTheta + p * pieceWidth;
            for (int g = 0; g < kGaussPoints; ++g) {
                const double theta = a + 0.5 * pieceWidth * (gl.x[g] + 1.0);
                const double st = std::sin(theta), ct = std::cos(theta);
                // At phi = 0 the basis gives Y_l^{+m} = A_l^m (m >= 0): the project's own
                // evaluation, so normalisation and sign conventions are the same by construction.
                evaluateSphericalHarmonics(degree, st, 0.0, ct, y);
                const double weight = 0.5 * pieceWidth * gl.w[g] * st;
                for (int l = 0; l <= degree; ++l)
                    for (int m = 0; m <= l; ++m) thetaIntegral[l * l + l + m] += weight * y[l * l + l + m];
            }
        }
        // Row sums of texel * Phi per channel and m.
        double sumCos[kColorChannels][kMaxHarmonicDegree + 1] = {}, sumSin[kColorChannels][kMaxHarmonicDegree + 1] = {};
        for (int c = 0; c < W; ++c) {
            const float* t = map.texel(c, r);
            const double* pc = &phiCos[static_cast<std::size_t>(c) * mCount];
            const double* ps = &phiSin[static_cast<std::size_t>(c) * mCount];
            for (int ch = 0; ch < kColorChannels; ++ch) {
                const double v = t[ch];
                if (v == 0.0) continue;
                for (int m = 0; m <= degree; ++m) {
                    sumCos[ch][m] += v * pc[m];
                    sumSin[ch][m] += v * ps[m];
                }
            }
        }
        double* out = &perRow[static_cast<std::size_t>(r) * K * kColorChannels];
        for (int ch = 0; ch < kColorChannels; ++ch)
            for (int l = 0; l <= degree; ++l) {
                const int centre = l * l + l;
                out[ch * K + centre] = thetaIntegral[centre] * sumCos[ch][0];
                for (int m = 1; m <= l; ++m) {
                    out[ch * K + centre + m] = thetaIntegral[centre + m] * sumCos[ch][m];
                    out[ch * K + centre - m] = thetaIntegral[centre + m] * sumSin[ch][m];
                }
            }
    }
    for (int r = 0; r < H; ++r) {
        const double* row = &perRow[static_cast<std::size_t>(r) * K * kColorChannels];
        for (int i = 0; i < K * kColorChannels; ++i) coefficients[i] += row[i];
    }

    // Map frame -> world frame: L_world(w) = L_map(R^T w) is "rotated by R" in sh_rotation.h's sense.
    if (!map.rotation().isIdentity(0.0)) {
        const ShRotation rotation(degree, map.rotation());
        for (int ch = 0; ch < kColorChannels; ++ch) rotation.apply(&coefficients[ch * K], &coefficients[ch * K]);
    }
    return coefficients;
}

}  // namespace rad
