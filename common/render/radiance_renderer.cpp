#include "render/radiance_renderer.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_interpolation.h"
#include "radiance/view_colors.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

// Gouraud blend of per-vertex colours (PerVertex mode and plain vertex colours).
struct ColorShader {
    struct State {};
    const float* rgb;  // 3 per vertex
    const std::uint32_t* faces;

    Eigen::Vector3d operator()(State&, std::uint32_t face, const double a[3], const Eigen::Vector3d&) const {
        const std::uint32_t* f = faces + 3 * std::size_t(face);
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) {
            const float* ck = rgb + 3 * std::size_t(f[k]);
            c += a[k] * Eigen::Vector3d(ck[0], ck[1], ck[2]);
        }
        return c;
    }
};

// Eq. (8) per sample. The three vertex views (with their re-orthonormalised frames) are cached per
// thread for the last face hit: neighbouring samples mostly hit the same triangle.
struct FragmentShader {
    struct State {
        std::uint32_t face = std::numeric_limits<std::uint32_t>::max();
        TriangleRadiance tri;
    };
    const RadianceField* field;
    const std::uint32_t* faces;

    Eigen::Vector3d operator()(State& s, std::uint32_t face, const double a[3], const Eigen::Vector3d& dir) const {
        if (face != s.face) {
            const std::uint32_t* f = faces + 3 * std::size_t(face);
            for (int k = 0; k < 3; ++k) s.tri.vertices[k] = vertexRadiance(*field, f[k]);
            s.face = face;  // positions are not needed by eq. (8)
        }
        const Eigen::Vector3d alpha(a[0], a[1], a[2]);
        const Eigen::Vector3d w = -dir;  // fragment -> eye
        if (const std::optional<Eigen::Vector3d> L = interpolateRadiance(s.tri, alpha, w)) return *L;
        // Interpolated normal of zero length: naive interpolation of the RF values.
        double scratch[kMaxCoefficientsPerChannel];
        Eigen::Vector3d L = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) L += alpha[k] * evaluateRadiance(s.tri.vertices[k], w, scratch);
        return L;
    }
};

void checkRenderInput(const PinholeCamera& camera, const RenderOptions& options) {
    const std::string problem = camera.validate();
    if (!problem.empty()) throw std::invalid_argument("cannot render: " + problem);
    if (options.supersampling < 1 || options.supersampling > 16)
        throw std::invalid_argument("cannot render: supersampling must lie in 1..16, got " +
                                    std::to_string(options.supersampling));
    if (!options.background.allFinite()) throw std::invalid_argument("cannot render: non-finite background colour");
}

// The mesh, validated before anything is copied or built.
const TriangleMesh& checkedMesh(const TriangleMesh& mesh) {
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw std::invalid_argument("cannot render the mesh: " + problem);
    return mesh;
}

}  // namespace

std::vector<std::uint8_t> Rendering::mask(std::uint8_t minimum) const {
    std::vector<std::uint8_t> m(coverage.size());
    for (std::size_t i = 0; i < coverage.size(); ++i) m[i] = coverage[i] >= minimum && coverage[i] > 0 ? 1 : 0;
    return m;
}

MeshRenderer::MeshRenderer(const TriangleMesh& mesh)
    : MeshRenderer(checkedMesh(mesh).positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount()) {}

MeshRenderer::MeshRenderer(const float* positions, std::size_t vertexCount, const std::uint32_t* faces,
                           std::size_t faceCount)
    : positions_(positions, positions + 3 * vertexCount), faces_(faces, faces + 3 * faceCount) {
    if (faceCount == 0) throw std::invalid_argument("cannot render the mesh: it has no faces");
    for (float p : positions_)
        if (!std::isfinite(p)) throw std::invalid_argument("cannot render the mesh: a vertex position is not finite");
    for (std::uint32_t i : faces_)
        if (i >= vertexCount)
            throw std::invalid_argument("cannot render the mesh: a face refers to vertex " + std::to_string(i) +
                                        " of " + std::to_string(vertexCount));
    rays_ = std::make_unique<RayScene>(positions_.data(), vertexCount, faces_.data(), faceCount);
}

template <typename Shade>
Rendering MeshRenderer::trace(const PinholeCamera& camera, const RenderOptions& options, const Shade& shade) const {
    const int N = options.supersampling;
    const int W = camera.width, H = camera.height;
    Rendering out;
    out.image = ImageF(W, H);
    out.coverage.assign(static_cast<std::size_t>(W) * H, 0);
    const Eigen::Vector3f origin = camera.center.cast<float>();
    const float inf = std::numeric_limits<float>::infinity();
    const double weight = 1.0 / (N * N);
    const RayScene& rays = *rays_;
#pragma omp parallel
    {
        typename Shade::State state;
#pragma omp for schedule(dynamic, 4)
        for (int r = 0; r < H; ++r) {
            for (int c = 0; c < W; ++c) {
                Eigen::Vector3d sum = Eigen::Vector3d::Zero();
                int hits = 0;
                for (int j = 0; j < N; ++j)
                    for (int i = 0; i < N; ++i) {
                        const Eigen::Vector3d dir = camera.rayDirection(c + (i + 0.5) / N, r + (j + 0.5) / N);
                        const RayHit hit = rays.intersect(origin, dir.cast<float>(), 0.0f, inf);
                        if (!hit.hit) {
                            sum += options.background;
                            continue;
                        }
                        ++hits;
                        const double a[3] = {1.0 - double(hit.u) - double(hit.v), double(hit.u), double(hit.v)};
                        sum += shade(state, hit.face, a, dir);
                    }
                float* px = out.image.pixel(c, r);
                for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(sum[k] * weight);
                out.coverage[static_cast<std::size_t>(r) * W + c] =
                    static_cast<std::uint8_t>(std::lround(255.0 * hits * weight));
            }
        }
    }
    return out;
}

Rendering MeshRenderer::renderRadiance(const RadianceField& field, const PinholeCamera& camera,
                                       RadianceShading shading, const RenderOptions& options) const {
    checkRenderInput(camera, options);
    const std::string problem = field.validate();
    if (!problem.empty()) throw std::invalid_argument("cannot render the radiance: " + problem);
    if (field.vertexCount() != vertexCount())
        throw std::invalid_argument("cannot render the radiance: the field has " + std::to_string(field.vertexCount()) +
                                    " vertices, the mesh " + std::to_string(vertexCount()));
    if (shading == RadianceShading::PerVertex) {
        // Sec. 5 "vertex shader": every vertex toward the eye, then Gouraud interpolation.
        std::vector<float> colors(3 * vertexCount());
        const double eye[3] = {camera.center.x(), camera.center.y(), camera.center.z()};
        radianceTowardViewpoint(field, positions_.data(), eye, 1.0f, colors.data());
        return trace(camera, options, ColorShader{colors.data(), faces_.data()});
    }
    return trace(camera, options, FragmentShader{&field, faces_.data()});
}

Rendering MeshRenderer::renderVertexColors(const float* linearRgb, const PinholeCamera& camera,
                                           const RenderOptions& options) const {
    checkRenderInput(camera, options);
    if (linearRgb == nullptr) throw std::invalid_argument("cannot render vertex colours: no colours given");
    return trace(camera, options, ColorShader{linearRgb, faces_.data()});
}

}  // namespace rad
