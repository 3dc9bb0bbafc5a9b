// Accuracy of "Fit Radiance Functions from Rasters" on a real scan photographed virtually
// (Vanhoey et al. 2015 sec. 7; issue targets in the README):
//  1. ground truth: the fitted RF of every vertex against the scene's exact outgoing radiance
//     (VirtualScene::radiance, with cast shadows) over the vertex's OBSERVED hemisphere: the
//     directions of a dense hemisphere set (1,000 Fibonacci directions per vertex) lying within
//     20 degrees of one of the vertex's sample directions. Relative RMSE = sqrt(sum |fit - truth|^2
//     / sum |truth|^2) over all those (vertex, direction, channel) triples.
//  2. held-out views: fit on 80 % of the photographs, render the other 20 % from the RF (per-vertex
//     and per-fragment eq. 8 shading, same camera, same 2x2 supersampling as the photographs) and
//     report PSNR (8-bit sRGB, peak 255) over the pixels the mesh covers.
//  3. poorly sampled vertices: fit from few photographs, then for every vertex flagged poorly
//     sampled evaluate its RF on a dense hemisphere set (2,000 directions, not the fitter's own
//     check set) and report how far it leaves the range of that vertex's observed colours, as a
//     fraction of the range (target: never more than 10 %).
//
//   bench_fit_accuracy [MESH.off] [--views N] [--size WxH] [--basis PB4] [--few N]
// MESH defaults to data-cache/meshes/bunny00.off of the source tree (samples/fetch_data.sh).
#include "acquisition/camera_rig.h"
#include "acquisition/virtual_photographs.h"
#include "acquisition/virtual_scene.h"
#include "fit/radiance_from_views.h"
#include "fit/view_sampling.h"
#include "geometry/mesh_normals.h"
#include "io/off_reader.h"
#include "io/radiance_ply.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_projection.h"
#include "render/image_metrics.h"
#include "render/radiance_renderer.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace rad;

namespace {

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// n unit directions on the upper hemisphere z >= 0 (Fibonacci spiral, equal areas).
std::vector<Eigen::Vector3d> hemisphereDirections(int n) {
    std::vector<Eigen::Vector3d> out;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = (i + 0.5) / n;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        out.emplace_back(r * std::cos(i * golden), r * std::sin(i * golden), z);
    }
    return out;
}

struct Photographs {
    std::vector<PinholeCamera> cameras;
    std::vector<Image8> images;
    std::vector<CalibratedView> views(const std::vector<int>& which) const {
        std::vector<CalibratedView> out;
        for (int i : which) out.push_back({cameras[i], images[i].view()});
        return out;
    }
};

}  // namespace

int main(int argc, char** argv) {
    std::string meshPath = std::string(RADIANCE_SOURCE_DIR) + "/data-cache/meshes/bunny00.off";
    int viewCount = 40, fewViews = 6, width = 800, height = 600;
    std::string basisName = "PB4", materialName = "glossy";
    double exponent = -1.0, shadowsOn = 1.0;
    bool exposure = true, validation = true, robust = true;
    double margin = -1.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--views" && i + 1 < argc) viewCount = std::atoi(argv[++i]);
        else if (a == "--few" && i + 1 < argc) fewViews = std::atoi(argv[++i]);
        else if (a == "--size" && i + 1 < argc) std::sscanf(argv[++i], "%dx%d", &width, &height);
        else if (a == "--basis" && i + 1 < argc) basisName = argv[++i];
        else if (a == "--material" && i + 1 < argc) materialName = argv[++i];
        else if (a == "--exponent" && i + 1 < argc) exponent = std::atof(argv[++i]);
        else if (a == "--no-shadows") shadowsOn = 0.0;
        else if (a == "--no-exposure") exposure = false;
        else if (a == "--no-validation") validation = false;
        else if (a == "--no-robust") robust = false;
        else if (a == "--margin" && i + 1 < argc) margin = std::atof(argv[++i]);
        else if (a[0] != '-') meshPath = a;
        else { std::fprintf(stderr, "unknown option %s\n", a.c_str()); return 2; }
    }
    const auto basis = BasisSpec::parse(basisName);
    if (!basis) { std::fprintf(stderr, "bad basis %s\n", basisName.c_str()); return 2; }

    TriangleMesh mesh;
    if (meshPath.size() > 4 && meshPath.substr(meshPath.size() - 4) == ".ply") {
        RadianceMesh plain = readRadiancePly(meshPath);
        mesh.positions = plain.positions;
        mesh.faces = plain.faces;
    } else {
        mesh = readOff(meshPath);
    }
    computeAreaWeightedNormals(mesh);
    Eigen::AlignedBox3d box;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        box.extend(Eigen::Vector3d(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]));
    const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d centre = box.center();
    const double radius = 0.5 * box.diagonal().norm();
    AnalyticMaterial material = makeSampleMaterial(parseSampleMaterial(materialName), box, up);
    if (exponent >= 0.0) material.exponent = exponent;
    VirtualSceneOptions sceneOptions;
    sceneOptions.castShadows = shadowsOn > 0.0;
    VirtualScene scene(mesh, material, makeSampleLighting(centre, radius, up), sceneOptions);
    std::printf("mesh %s: %zu vertices, %zu faces; %s; %s sample material (Blinn-Phong exponent %g, ks %.2f) with "
                "smooth variation, key + fill lights%s, %d threads\n",
                meshPath.c_str(), mesh.vertexCount(), mesh.faceCount(), basis->name().c_str(), materialName.c_str(),
                material.exponent, material.specular.mean(), sceneOptions.castShadows ? " with cast shadows" : "",
                omp_get_max_threads());

    CameraRigOptions rig;
    rig.count = viewCount;
    rig.width = width;
    rig.height = height;
    rig.up = up;
    rig.minElevationDegrees = -60.0;
    rig.maxElevationDegrees = 80.0;
    Photographs photos;
    photos.cameras = makeCameraRig(centre, radius, rig);
    double t0 = now();
    for (const PinholeCamera& camera : photos.cameras) photos.images.push_back(encodeToSrgb8(renderPhotograph(scene, camera)));
    std::printf("%d photographs %dx%d rendered in %.1f s\n", viewCount, width, height, now() - t0);

    RadianceFromViewsOptions options;
    options.fit.basis = *basis;
    options.compensateExposure = exposure;
    if (!validation) options.fit.validationLambdas = 0;
    if (!robust) options.fit.robustIterations = 0;
    if (margin >= 0.0) options.fit.validationMargin = margin;

    // ---- 1. all views, against the ground truth over the observed hemisphere.
    std::vector<int> all(viewCount);
    for (int i = 0; i < viewCount; ++i) all[i] = i;
    t0 = now();
    RadianceFromViewsResult fit = fitRadianceFromViews(scene.mesh(), photos.views(all), options);
    std::printf("\n[1] fit on all %d views: %.2f s; %zu fitted, %zu poorly sampled, %zu filled, %zu unseen; "
                "%.1f samples per vertex\n",
                viewCount, now() - t0, fit.fitted, fit.poorlySampled, fit.unseenFilled, fit.unseenLeft,
                double(fit.totalSamples) / mesh.vertexCount());
    {
        ViewSampler sampler(scene.mesh(), photos.views(all), options.sampling);
        const std::vector<Eigen::Vector3d> dense = hemisphereDirections(1000);
        const double cosCover = std::cos(20.0 * M_PI / 180.0);
        // Floors, for reading the figure: the photographs themselves against the truth at the sample
        // directions (pixel footprint around the vertex, 8-bit quantisation, clipping), the fit
        // against its own samples, and the best the basis can do (the L2 projection of the truth).
        FunctionProjector projector(*basis);
        double sumErr = 0.0, sumTruth = 0.0, sumPhotoErr = 0.0, sumPhotoTruth = 0.0, sumResidual = 0.0;
        double sumProjErr = 0.0;
        std::size_t pairs = 0;
#pragma omp parallel reduction(+ : sumErr, sumTruth, pairs, sumPhotoErr, sumPhotoTruth, sumResidual, sumProjErr)
        {
            std::vector<DirectionalSample> samples(viewCount);
            std::vector<double> best(3 * basis->coefficientCount());
#pragma omp for schedule(dynamic, 256)
            for (long long v = 0; v < (long long)mesh.vertexCount(); ++v) {
                const std::size_t count = sampler.sampleVertex(v, samples.data());
                if (count == 0) continue;
                // The vertex's RF and frame once; every direction below reuses them.
                const VertexRadiance rf = vertexRadiance(fit.field, v);
                const Frame& frame = rf.frame;
                double scratch[3 * kMaxCoefficientsPerChannel];
                const Eigen::Vector3d p(scene.mesh().positions[3 * v], scene.mesh().positions[3 * v + 1],
                                        scene.mesh().positions[3 * v + 2]);
                for (std::size_t s = 0; s < count; ++s) {
                    const Eigen::Vector3d w(samples[s].direction[0], samples[s].direction[1], samples[s].direction[2]);
                    const Eigen::Vector3d seen(samples[s].rgb[0], samples[s].rgb[1], samples[s].rgb[2]);
                    const Eigen::Vector3d truth = scene.radiance(p, frame.n, w);
                    sumPhotoErr += (seen - truth).squaredNorm();
                    sumPhotoTruth += truth.squaredNorm();
                    sumResidual += (evaluateRadiance(rf, w, scratch) - seen).squaredNorm();
                }
                projector.project(frame, [&](const Eigen::Vector3d& w) { return scene.radiance(p, frame.n, w); },
                                  best.data());
                const VertexRadianceT<double> bestRf{basis.value(), best.data(), frame, false};
                for (const Eigen::Vector3d& local : dense) {
                    const Eigen::Vector3d w = frame.toWorld(local);
                    bool observed = false;
                    for (std::size_t s = 0; s < count && !observed; ++s)
                        observed = w.dot(Eigen::Vector3d(samples[s].direction[0], samples[s].direction[1],
                                                         samples[s].direction[2])) >= cosCover;
                    if (!observed) continue;
                    const Eigen::Vector3d truth = scene.radiance(p, frame.n, w);
                    const Eigen::Vector3d got = evaluateRadiance(rf, w, scratch);
                    sumErr += (got - truth).squaredNorm();
                    sumProjErr += (evaluateRadiance(bestRf, w, scratch) - truth).squaredNorm();
                    sumTruth += truth.squaredNorm();
                    ++pairs;
                }
            }
        }
        std::printf("[1] relative RMSE against the ground truth over the observed hemispheres: %.2f %% "
                    "(%zu vertex-directions; target <= 3 %%)\n",
                    100.0 * std::sqrt(sumErr / sumTruth), pairs);
        std::printf("    for reading it: photographs vs truth at the sample directions %.2f %%; fit vs its samples "
                    "%.2f %%; best %s approximation of the truth (L2 projection) %.2f %% on the same directions\n",
                    100.0 * std::sqrt(sumPhotoErr / sumPhotoTruth), 100.0 * std::sqrt(sumResidual / sumPhotoTruth),
                    basis->name().c_str(), 100.0 * std::sqrt(sumProjErr / sumTruth));
    }

    // ---- 2. held out: every fifth view is not fitted, then rendered from the RF.
    std::vector<int> train, test;
    for (int i = 0; i < viewCount; ++i) (i % 5 == 2 ? test : train).push_back(i);
    RadianceFromViewsResult trainFit = fitRadianceFromViews(scene.mesh(), photos.views(train), options);
    MeshRenderer renderer(scene.mesh());
    RenderOptions renderOptions;
    renderOptions.supersampling = 2;  // as the photographs
    double sumVertex = 0.0, sumFragment = 0.0, worst = 1e9;
    for (int i : test) {
        const Rendering byVertex = renderer.renderRadiance(trainFit.field, photos.cameras[i], RadianceShading::PerVertex, renderOptions);
        const Rendering byFragment =
            renderer.renderRadiance(trainFit.field, photos.cameras[i], RadianceShading::PerFragment, renderOptions);
        const std::vector<std::uint8_t> mask = byVertex.mask(1);
        const ImageErrors ev = compareImages(byVertex.image, photos.images[i], mask);
        const ImageErrors ef = compareImages(byFragment.image, photos.images[i], mask);
        std::printf("[2] held-out view %2d: %zu object pixels, PSNR per-vertex %.2f dB, per-fragment %.2f dB\n", i,
                    ev.pixelCount, ev.psnrSrgb8, ef.psnrSrgb8);
        sumVertex += ev.psnrSrgb8;
        sumFragment += ef.psnrSrgb8;
        worst = std::min(worst, std::min(ev.psnrSrgb8, ef.psnrSrgb8));
    }
    std::printf("[2] fit on %zu views, %zu held out: mean PSNR per-vertex %.2f dB, per-fragment %.2f dB, "
                "worst view %.2f dB (target >= 35 dB)\n",
                train.size(), test.size(), sumVertex / test.size(), sumFragment / test.size(), worst);

    // ---- 3. poorly sampled vertices: few views.
    std::vector<int> few;
    for (int i = 0; i < fewViews; ++i) few.push_back(i * viewCount / fewViews);
    RadianceFromViewsResult fewFit = fitRadianceFromViews(scene.mesh(), photos.views(few), options);
    {
        ViewSampler sampler(scene.mesh(), photos.views(few), options.sampling);
        const std::vector<Eigen::Vector3d> dense = hemisphereDirections(2000);
        double worstExcess = 0.0;
        std::size_t checked = 0, over = 0, threeOrFewer = 0;
#pragma omp parallel reduction(+ : checked, over, threeOrFewer) reduction(max : worstExcess)
        {
            std::vector<DirectionalSample> samples(few.size());
            std::vector<int> viewOf(few.size());
#pragma omp for schedule(dynamic, 256)
            for (long long v = 0; v < (long long)mesh.vertexCount(); ++v) {
                if (fewFit.status[v] != std::uint8_t(FitStatus::PoorlySampled)) continue;
                const std::size_t count = sampler.sampleVertex(v, samples.data(), nullptr, viewOf.data());
                if (count == 0) continue;
                // The range the fit saw: the samples divided by their photograph's exposure gains.
                for (std::size_t s = 0; s < count; ++s)
                    for (int c = 0; c < 3; ++c)
                        samples[s].rgb[c] = float(samples[s].rgb[c] / fewFit.viewGains[3 * viewOf[s] + c]);
                double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
                for (std::size_t s = 0; s < count; ++s)
                    for (int c = 0; c < 3; ++c) {
                        lo[c] = std::min(lo[c], double(samples[s].rgb[c]));
                        hi[c] = std::max(hi[c], double(samples[s].rgb[c]));
                    }
                const VertexRadiance rf = vertexRadiance(fewFit.field, v);
                double scratch[3 * kMaxCoefficientsPerChannel];
                double excess = 0.0;
                for (const Eigen::Vector3d& local : dense) {
                    const Eigen::Vector3d value = evaluateRadiance(rf, rf.frame.toWorld(local), scratch);
                    for (int c = 0; c < 3; ++c) {
                        const double range = std::max(hi[c] - lo[c], 1e-6);
                        excess = std::max(excess, std::max(lo[c] - value[c], value[c] - hi[c]) / range);
                    }
                }
                ++checked;
                if (count <= 3) ++threeOrFewer;
                if (excess > 0.1) ++over;
                worstExcess = std::max(worstExcess, excess);
            }
        }
        std::printf("\n[3] fit on %zu views: %zu poorly sampled vertices checked (%zu with at most 3 samples) on "
                    "2,000 directions each: worst excursion outside the observed range %.1f %% of the range, "
                    "%zu vertices beyond 10 %% (target: none)\n",
                    few.size(), checked, threeOrFewer, 100.0 * std::max(0.0, worstExcess), over);
    }
    return 0;
}
