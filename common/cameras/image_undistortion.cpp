#include "cameras/image_undistortion.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

namespace rad {

namespace {

// Whether every pinhole pixel of `plan` maps inside the photograph and the map moves outward along
// each ray from the principal point (checked on the border's pixel centres and 48 steps toward them).
bool mapsInsideAndMonotonic(const UndistortionPlan& plan) {
    const int w = plan.target.width, h = plan.target.height;
    const double cx = plan.target.cx, cy = plan.target.cy;
    const Eigen::Vector2d centre = plan.sourcePixel(cx, cy);
    const auto inside = [&](const Eigen::Vector2d& p) {
        return std::isfinite(p.x()) && std::isfinite(p.y()) && p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= w && p.y() <= h;
    };
    const auto rayOk = [&](double u, double v) {
        double previous = 0.0;
        const int steps = 48;
        for (int i = 1; i <= steps; ++i) {
            const double t = double(i) / steps;
            const Eigen::Vector2d p = plan.sourcePixel(cx + t * (u - cx), cy + t * (v - cy));
            if (!inside(p)) return false;
            const double distance = (p - centre).norm();
            if (!(distance > previous)) return false;
            previous = distance;
        }
        return true;
    };
    if (!inside(centre)) return false;
    const int samples = 64;
    for (int i = 0; i <= samples; ++i) {
        const double fu = 0.5 + (w - 1.0) * i / samples, fv = 0.5 + (h - 1.0) * i / samples;
        if (!rayOk(fu, 0.5) || !rayOk(fu, h - 0.5) || !rayOk(0.5, fv) || !rayOk(w - 0.5, fv)) return false;
    }
    return true;
}

// sRGB encoding of a linear value to its 8-bit code by the 255 decision thresholds (the linear
// values whose encoding is exactly c + 0.5), found through a table of 65536 buckets (no pow, no
// search): a bucket holds at most one threshold (they are at least 3e-4 apart, the buckets 1.5e-5
// wide), so the bucket's first code and one comparison give the code. Equals
// radiance/view_colors.h's encodeSrgb8 except exactly at a threshold.
class SrgbEncoder {
public:
    SrgbEncoder() {
        for (int c = 0; c < 255; ++c) {
            const double s = (c + 0.5) / 255.0;
            threshold_[c] = float(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
        }
        threshold_[255] = 2.0f;  // above every clamped input
        int code = 0;
        for (int i = 0; i < kBuckets; ++i) {
            while (code < 255 && threshold_[code] <= float(i) / (kBuckets - 1)) ++code;
            first_[i] = std::uint8_t(code);
        }
    }
    std::uint8_t operator()(float linear) const {
        const float x = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;
        const int code = first_[int(x * (kBuckets - 1))];
        return std::uint8_t(code + (x >= threshold_[code] ? 1 : 0));
    }

private:
    static constexpr int kBuckets = 65536;
    float threshold_[256];
    std::uint8_t first_[kBuckets];
};

// Keys (1981) cubic convolution (a = -0.5) on linear light at image coordinates (u, v), pixel
// centres at +0.5, taps clamped to the border, the result clamped to [0, 1] (the overshoot of a
// sharp edge). Sharper than bilinear interpolation, whose averaging of the two nearest pixels blurs
// by up to half a pixel where the map lands between them.
void sampleCubicLinear(const ImageView8& image, double u, double v, const float* decode, float out[3]) {
    const double x = u - 0.5, y = v - 0.5;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    float wx[4], wy[4];
    const auto weights = [](float t, float w[4]) {
        const float a = -0.5f;
        const float d[4] = {1.0f + t, t, 1.0f - t, 2.0f - t};
        for (int i = 0; i < 4; ++i)
            w[i] = d[i] <= 1.0f ? ((a + 2.0f) * d[i] - (a + 3.0f)) * d[i] * d[i] + 1.0f
                                : ((a * d[i] - 5.0f * a) * d[i] + 8.0f * a) * d[i] - 4.0f * a;
    };
    weights(float(x - x0), wx);
    weights(float(y - y0), wy);
    float sum[3] = {0.0f, 0.0f, 0.0f};
    const int o0 = image.channelOffset[0], o1 = image.channelOffset[1], o2 = image.channelOffset[2];
    const bool inside = x0 >= 1 && y0 >= 1 && x0 + 2 < image.width && y0 + 2 < image.height;
    for (int j = 0; j < 4; ++j) {
        const int r = inside ? y0 - 1 + j : std::min(std::max(y0 - 1 + j, 0), image.height - 1);
        float r0 = 0.0f, r1 = 0.0f, r2 = 0.0f;
        for (int i = 0; i < 4; ++i) {
            // Most points are at least 2 pixels inside: no clamping there.
            const int c = inside ? x0 - 1 + i : std::min(std::max(x0 - 1 + i, 0), image.width - 1);
            const std::uint8_t* p = image.pixel(c, r);
            r0 += wx[i] * decode[p[o0]];
            r1 += wx[i] * decode[p[o1]];
            r2 += wx[i] * decode[p[o2]];
        }
        sum[0] += wy[j] * r0;
        sum[1] += wy[j] * r1;
        sum[2] += wy[j] * r2;
    }
    for (int k = 0; k < 3; ++k) out[k] = std::min(std::max(sum[k], 0.0f), 1.0f);
}

std::uint64_t fnv1a64(const std::string& text) {
    std::uint64_t hash = 1469598103934665603ull;
    for (unsigned char c : text) {
        hash ^= c;
        hash *= 1099511628211ull;
    }
    return hash;
}

}  // namespace

Eigen::Vector2d UndistortionPlan::sourcePixel(double u, double v) const {
    const Eigen::Vector2d ideal((u - target.cx) / target.fx, (v - target.cy) / target.fy);
    return lens.pixelOf(ideal);
}

std::string imageSizeProblem(const ImportedCamera& camera, int width, int height) {
    if (width == camera.width && height == camera.height) return {};
    // One scale s with |s W - width| <= 1 and |s H - height| <= 1 (a resized copy, rounded per axis).
    const double low = std::max((width - 1.0) / camera.width, (height - 1.0) / camera.height);
    const double high = std::min((width + 1.0) / camera.width, (height + 1.0) / camera.height);
    if (width > 0 && height > 0 && low <= high) return {};
    return "image '" + camera.imageName + "' is " + std::to_string(width) + " x " + std::to_string(height) +
           " pixels, but its calibration is for " + std::to_string(camera.width) + " x " + std::to_string(camera.height) +
           " (nor a resized copy of that shape); give the photographs the calibration was made with";
}

UndistortionPlan planUndistortion(const ImportedCamera& camera, int width, int height) {
    UndistortionPlan plan;
    plan.lens = camera.lens.scaled(double(width) / camera.width, double(height) / camera.height);
    plan.target.rotation = camera.rotation;
    plan.target.center = camera.center;
    plan.target.width = width;
    plan.target.height = height;
    plan.target.cx = plan.lens.cx;
    plan.target.cy = plan.lens.cy;
    plan.resample = plan.lens.distorts();
    for (int step = 0;; ++step) {
        plan.zoom = std::pow(1.01, step);
        plan.target.fx = plan.lens.fx * plan.zoom;
        plan.target.fy = plan.lens.fy * plan.zoom;
        if (!plan.resample || mapsInsideAndMonotonic(plan)) break;
        if (plan.zoom > 10.0)
            throw std::invalid_argument("the lens of image '" + camera.imageName +
                                        "' sees too wide a field for a pinhole image (no zoom up to 10x keeps the "
                                        "undistorted image inside the photograph); use a narrower lens or crop the "
                                        "photographs before calibrating");
    }
    return plan;
}

Image8 undistortImage(const ImageView8& photograph, const UndistortionPlan& plan, const ProgressCallback& progress) {
    if (photograph.width != plan.target.width || photograph.height != plan.target.height)
        throw std::invalid_argument("undistortImage: the photograph's size differs from the plan's");
    const int w = plan.target.width, h = plan.target.height;
    Image8 out(w, h);
    static const SrgbEncoder encode;
    const float* decode = srgbToLinearTable();
    LoopProgress loop(progress, "Undistorting", std::size_t(h));
#pragma omp parallel for schedule(dynamic, 16)
    for (int row = 0; row < h; ++row) {
        if (loop.stopRequested()) continue;
        for (int column = 0; column < w; ++column) {
            const Eigen::Vector2d source = plan.sourcePixel(column + 0.5, row + 0.5);
            float linear[3];
            sampleCubicLinear(photograph, source.x(), source.y(), decode, linear);
            std::uint8_t* pixel = out.pixel(column, row);
            for (int c = 0; c < 3; ++c) pixel[c] = encode(linear[c]);
        }
        loop.itemDone(omp_get_thread_num() == 0);
    }
    loop.finish();
    return out;
}

std::string undistortedFileName(const std::string& imageName, const UndistortionPlan& plan, const std::string& sourceIdentity) {
    char targetText[256];
    std::snprintf(targetText, sizeof targetText, "%.17g %.17g %.17g %.17g %d %d %.17g", plan.target.fx, plan.target.fy,
                  plan.target.cx, plan.target.cy, plan.target.width, plan.target.height, plan.zoom);
    // "v2": the resampling itself (Keys cubic on linear light, sRGB out); change it when that changes.
    const std::uint64_t hash = fnv1a64("v2|" + plan.lens.describe() + "|" + targetText + "|" + sourceIdentity);
    std::string stem = imageName;
    const std::size_t slash = stem.find_last_of('/'), dot = stem.find_last_of('.');
    if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) stem.erase(dot);
    std::string flat;
    for (char c : stem) flat += c == '/' || c == '\\' ? std::string("__") : std::string(1, c);
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
    return flat + "." + hex + ".png";
}

}  // namespace rad
