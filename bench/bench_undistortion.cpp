// Undistortion of one large photograph (issue 29): the exact map through an OPENCV lens, the cubic
// resampling on linear light, and the PNG encoding of the cache image, timed separately on 1 thread
// and on every thread. Prints figures; asserts nothing.
//   bench_undistortion [width height]   (default 6000 4000: 24 MP)
#include "cameras/colmap_model_reader.h"
#include "cameras/image_undistortion.h"
#include "image/parallel_png_encoder.h"

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace {

double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

}  // namespace

int main(int argc, char** argv) {
    const int width = argc > 2 ? std::atoi(argv[1]) : 6000, height = argc > 2 ? std::atoi(argv[2]) : 4000;
    rad::ImportedCamera camera;
    camera.imageName = "bench";
    camera.width = width;
    camera.height = height;
    camera.lens = rad::colmapLens("OPENCV", {0.83 * width, 0.83 * width, width / 2.0, height / 2.0, -0.12, 0.03, 0.0008, -0.0005});
    // A photograph-like image: smooth gradients plus noise (compresses like a photograph, not like a flat image).
    rad::Image8 photograph(width, height);
    std::mt19937 rng(1);
    std::uniform_int_distribution<int> noise(-6, 6);
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c)
            for (int k = 0; k < 3; ++k)
                photograph.pixel(c, r)[k] = std::uint8_t(std::min(255, std::max(0, (c * (k + 1) / 40 + r / 30) % 200 + 20 + noise(rng))));
    const rad::UndistortionPlan plan = rad::planUndistortion(camera, width, height);
    std::printf("%d x %d (%.1f MP), OPENCV lens, zoom %.2f, %d threads available\n", width, height, width * height / 1e6,
                plan.zoom, omp_get_max_threads());
    const int all = omp_get_max_threads();
    for (int threads : {1, all}) {
        omp_set_num_threads(threads);
        const auto t0 = std::chrono::steady_clock::now();
        const rad::Image8 out = rad::undistortImage(photograph.view(), plan);
        const auto t1 = std::chrono::steady_clock::now();
        const std::vector<unsigned char> png = rad::encodePngParallel(out.rgb.data(), width, height, 3, 8, 1);
        const auto t2 = std::chrono::steady_clock::now();
        std::printf("%d thread%s: undistortion %.2f s (%.0f ns a pixel), PNG encoding %.2f s (%.1f MB)\n", threads,
                    threads > 1 ? "s" : "", seconds(t0, t1), 1e9 * seconds(t0, t1) / (double(width) * height),
                    seconds(t1, t2), png.size() / 1e6);
        if (all == 1) break;
    }
    return 0;
}
