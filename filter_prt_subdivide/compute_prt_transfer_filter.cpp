// "Radiance: Compute PRT Transfer": the shadowed diffuse transfer vectors of precomputed radiance
// transfer (Sloan et al. 2002) at every vertex, ray-cast with Embree (common/prt/transfer_vectors.h),
// stored on the layer with the settings the subdivision filters reuse for new vertices.
#include "prt_subdivide_plugin.h"

#include "citations.h"
#include "mesh_conversion.h"
#include "prt_subdivision_common.h"
#include "transfer_attribute.h"
#include "usable_normals.h"

#include "geometry/coordinate_range.h"
#include "image/rgb_image.h"
#include "prt/transfer_vectors.h"
#include "radiance/basis.h"
#include "raycast/ray_scene.h"

#include <QElapsedTimer>

#include <cmath>

namespace radml {
namespace {

// Bounds the cores do not have (rad::TransferEstimator refuses fewer than one ray and an offset
// that is not positive, and an order outside 1 .. kMaxHarmonicDegree + 1).
// Positions of the vertices referenced by faces must be finite (normals are repaired:
// usable_normals.h; the transfer integrates over the hemisphere around the normal).
void checkTransferInput(const rad::RadianceMesh& plain) {
    const std::size_t n = plain.vertexCount();
    if (n == 0) throw Refusal("The current mesh has no vertices.");
    std::vector<char> used(n, plain.faces.empty() ? 1 : 0);
    for (std::uint32_t v : plain.faces) used[v] = 1;
    std::size_t badPosition = 0;
    for (std::size_t v = 0; v < n; ++v) {
        if (!used[v]) continue;
        const float* p = &plain.positions[3 * v];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) ++badPosition;
    }
    if (badPosition == 0) {
        if (std::string range = rad::coordinateRangeProblem(plain.positions.data(), n); !range.empty())
            throw Refusal(range);
    }
    if (badPosition > 0)
        throw Refusal(formatLine("%zu vertices have NaN or infinite coordinates: remove them first (Cleaning and "
                                 "Repairing > Remove Duplicate Vertices / Remove Unreferenced Vertices, or fix the "
                                 "file).",
                                 badPosition));
}

class ComputePrtTransferFilter : public Filter {
public:
    QString name() const override { return "Radiance: Compute PRT Transfer"; }
    QString pythonName() const override { return "radiance_compute_prt_transfer"; }
    QString description() const override {
        return QString(
                   "Computes the shadowed diffuse transfer vector of precomputed radiance transfer (PRT, Sloan et "
                   "al. 2002) at every vertex: t_k = 1/pi times the integral over the hemisphere of V(w) cos(n, w) "
                   "Y_k(w), on real spherical harmonics of the chosen order (order 6 = 36 coefficients, as in "
                   "Křivánek et al. 2004). The relit colour under a distant lighting with SH coefficients l is then "
                   "L = &lt;t, l&gt;. Visibility V is ray-cast with Embree against the current mesh or all visible "
                   "layers, with a fixed low-discrepancy set of cosine-weighted directions in each vertex's frame "
                   "(rays start slightly above the surface to avoid self-hits). Rays that leave an open mesh are "
                   "unoccluded: that is what an open mesh means. Optionally multiplied by the vertex colour as "
                   "albedo (three channels). The vertices are coloured by the shading under a uniform white sky "
                   "(ambient occlusion), also stored as vertex quality. The vectors are saved with the mesh in the "
                   "Radiance PLY format (.rply).") +
               kCiteSloan2002Krivanek2004;
    }
    int filterClass() const override { return 0x00010; /* VertexColoring */ }
    int postconditions() const override { return MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY; }

    RichParameterList parameters(const MeshDocument&, const MeshModel&) const override {
        RichParameterList par;
        par.addParam(RichInt("order", rad::kDefaultTransferDegree + 1, "SH order",
                             QString("Order n of the spherical harmonics: n^2 coefficients per vertex (1..%1). "
                                     "Křivánek et al. 2004 use order 6 (36 coefficients).")
                                 .arg(rad::kMaxHarmonicDegree + 1)));
        par.addParam(RichInt("rays", rad::kDefaultTransferRayCount, "Rays per vertex",
                             QString("Cosine-weighted visibility rays per vertex (low-discrepancy set, 1..%1).")
                                 .arg(rad::kMaxTransferRayCount)));
        par.addParam(RichEnum("occluders", kOccludersMesh, QStringList() << "The current mesh" << "All visible layers",
                              "Occluders",
                              "What casts shadows: the mesh alone, or every visible layer (e.g. a statue and the "
                              "ground it stands on, loaded as two layers)."));
        par.addParam(RichBool("albedo", false, "Multiply by vertex colour (albedo)",
                              "Three channels: the transfer times the vertex colour read as sRGB albedo. Leave off to "
                              "subdivide afterwards (the subdivision needs the geometric transfer)."));
        par.addParam(RichFloat("rayOffset", 1e-4f, "Ray offset",
                               "Rays start this far above the surface, as a fraction of the scene's bounding-box "
                               "diagonal (avoids self-intersection)."));
        return par;
    }

    std::string outOfMemoryAdvice() const override { return kPrtOutOfMemoryAdvice; }

    void apply(FilterContext& ctx) const override { compute(ctx); }

private:
    void compute(FilterContext& ctx) const {
        const RichParameterList& par = ctx.parameters;
        MeshModel& m = ctx.mesh();
        QElapsedTimer timer;
        timer.start();
        const int order = par.getInt("order");
        const int rays = par.getInt("rays");
        const double offset = par.getFloat("rayOffset");
        // (The core refuses an order, ray count or offset out of range: TransferEstimator.)

        rad::RadianceMesh plain;
        std::string why;
        ExportChoice choice;
        choice.quality = choice.radiance = choice.transfer = false;
        if (!exportPlainMesh(m.cm, choice, plain, why)) throw Refusal(why);
        checkTransferInput(plain);
        makeNormalsUsable(ctx, plain.positions, plain.faces, plain.normals);
        const bool allVisible = par.getEnum("occluders") == kOccludersVisibleLayers;
        const OccluderScene occluders = collectOccluders(ctx.document, m, allVisible);
        ctx.progress(1, "Building the ray-tracing scene");
        const rad::RayScene scene(occluders.positions.data(), occluders.positions.size() / 3,
                                  occluders.faces.data(), occluders.faces.size() / 3);
        rad::TransferOptions options;
        options.degree = order - 1;
        options.rayCount = rays;
        options.relativeRayOffset = offset;
        // Refuses (std::invalid_argument) an order, ray count or offset out of range and a scene without extent.
        const rad::TransferEstimator estimator(scene, occluders.diagonal, options);

        StoredTransfer stored;
        stored.field.degree = options.degree;
        stored.field.channels = 1;
        stored.rayCount = rays;
        stored.relativeRayOffset = offset;
        stored.allVisibleLayers = allVisible;
        const std::size_t n = plain.vertexCount();
        ctx.progress.setPhase(2, 95, "Ray-casting PRT transfer");
        rad::computeTransferVectors(estimator, plain.positions.data(), plain.normals.data(), n, stored.field.values,
                                    ctx.progress.forCore());
        const double seconds = timer.elapsed() / 1000.0;
        if (par.getBool("albedo")) {
            std::vector<float> albedo(3 * n);
            for (std::size_t v = 0; v < n; ++v)
                for (int ch = 0; ch < 3; ++ch) albedo[3 * v + ch] = rad::srgbToLinear(plain.colors[4 * v + ch]);
            stored.field = rad::multiplyByAlbedo(stored.field, albedo);
        }
        const std::vector<float> shading = whiteSkyShading(stored.field);
        const int channels = stored.field.channels;
        const int coefficients = stored.field.coefficientCount();
        attachTransfer(m.cm, std::move(stored));
        setShading(m, shading, 1.0f);
        ctx.progress.setPhase(100, 100, "Done");
        const double totalRays = double(n) * rays;
        ctx.log(formatLine("Computed PRT transfer (Sloan et al. 2002) on %zu vertices: SH order %d (%d coefficients "
                           "x %d channel(s)), %d rays per vertex against %zu occluding triangles (%s); %.3g M rays "
                           "in %.2f s = %.2f M rays/s",
                           n, order, coefficients, channels, rays, occluders.faces.size() / 3,
                           allVisible ? "all visible layers" : "the mesh", totalRays / 1e6, seconds,
                           seconds > 0 ? totalRays / seconds / 1e6 : 0.0));
    }
};

}  // namespace

std::unique_ptr<Filter> makeComputePrtTransferFilter() { return std::make_unique<ComputePrtTransferFilter>(); }

}  // namespace radml
