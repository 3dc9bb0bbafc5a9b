#include "acquisition/virtual_photographs.h"

#include "image/image_io.h"

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace rad {

ImageF renderPhotograph(const VirtualScene& scene, const PinholeCamera& camera, const PhotographOptions& options) {
    const std::string problem = camera.validate();
    if (!problem.empty()) throw std::invalid_argument("cannot render a photograph: " + problem);
    const int N = options.supersampling;
    if (N < 1 || N > 16) throw std::invalid_argument("cannot render a photograph: supersampling must lie in 1..16");
    if (!options.background.allFinite()) throw std::invalid_argument("cannot render a photograph: non-finite background");

    const TriangleMesh& mesh = scene.mesh();
    const float* P = mesh.positions.data();
    const float* Nrm = mesh.normals.data();
    const std::uint32_t* F = mesh.faces.data();
    const RayScene& rays = scene.rays();
    const Eigen::Vector3f origin = camera.center.cast<float>();
    const float inf = std::numeric_limits<float>::infinity();
    const double weight = 1.0 / (N * N);

    ImageF image(camera.width, camera.height);
#pragma omp parallel for schedule(dynamic, 4)
    for (int r = 0; r < camera.height; ++r) {
        for (int c = 0; c < camera.width; ++c) {
            Rgb sum = Rgb::Zero();
            for (int j = 0; j < N; ++j) {
                for (int i = 0; i < N; ++i) {
                    const double u = c + (i + 0.5) / N, v = r + (j + 0.5) / N;
                    const Eigen::Vector3d dir = camera.rayDirection(u, v);
                    const RayHit hit = rays.intersect(origin, dir.cast<float>(), 0.0f, inf);
                    if (!hit.hit) {
                        sum += options.background;
                        continue;
                    }
                    const std::uint32_t* f = F + 3 * std::size_t(hit.face);
                    const double a[3] = {1.0 - double(hit.u) - double(hit.v), double(hit.u), double(hit.v)};
                    Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
                    for (int k = 0; k < 3; ++k) {
                        const float* pk = P + 3 * std::size_t(f[k]);
                        const float* nk = Nrm + 3 * std::size_t(f[k]);
                        p += a[k] * Eigen::Vector3d(pk[0], pk[1], pk[2]);
                        n += a[k] * Eigen::Vector3d(nk[0], nk[1], nk[2]);
                    }
                    // radiance() normalises n (and returns zero for the degenerate n = 0 of exactly
                    // opposite normals, which a valid scan does not have).
                    sum += scene.radiance(p, n, -dir);
                }
            }
            float* px = image.pixel(c, r);
            for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(sum[k] * weight);
        }
    }
    return image;
}

void writePhotographPng(const std::string& path, const ImageF& image, float exposure) {
    writePng(path, encodeToSrgb8(image, exposure));
}

}  // namespace rad
