// Held-out accuracy of "Fit Radiance Functions from Rasters" on a capture rendered by an independent
// renderer (e.g. a path tracer): CAPTURE/mesh.ply, CAPTURE/project.mlp (rasters with cameras),
// CAPTURE/photos_twin/ (optional: the same views rendered again with another noise seed, same file
// names as the project's images).
//
//   bench_fit_capture CAPTURE [--held-out-every K] [--basis PB4] [--models per-vertex,shared,auto]
//                     [--meshlab-colors COLORS.ply] [--lobe-degree L] [--specular-prior P] [--lobe-ridge R]
//                     [--cosine 0|1] [--factor-curve 0|1] [--lobe-samples N] [--iterations N]
//                     [--refit-iterations N] [--choice-iterations N]
//                     [--in-sample 1] [--rejected-constant 0|1] [--diagnose-view J]
//
// Rasters K, 2K, ... (1-based, the order of the project, as the filter's heldOutEvery) are held out;
// the others are fitted with each model (radiance_from_views.h, the filter's defaults otherwise).
// Printed per model: fit time, the choice the automatic model made, and on the held-out views
// (fit/held_out_evaluation.h, 8-bit sRGB RMS at the vertices each held-out view sees): the mean of the
// per-view RMS of the fit, of the constant mean colour, of the built-in colour-projection
// estimate, and in how many views the fit is <= the constant. With --meshlab-colors (the vertex
// colours MeshLab's "Project active rasters color to current mesh" wrote, fitted on the same training
// rasters): the same RMS of those colours. Noise: RMS of (photo - twin) / sqrt(2) at the same
// vertices, the error of a perfect prediction of a noisy photograph.
#include "fit/held_out_evaluation.h"
#include "fit/radiance_from_views.h"
#include "image/image_io.h"
#include "io/meshlab_project.h"
#include "io/radiance_ply.h"
#include "radiance/radiance_evaluation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

using namespace rad;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, ',')) out.push_back(item);
    return out;
}

// Whether the object covers all four pixels a bilinear sample at (u, v) reads, by the capture's mask
// of that view (255: covered; less: the object covers the pixel in part, and the photograph mixes it
// with what lies behind, which no function of the direction at the vertex can predict).
bool fullyCovered(const Image8& mask, double u, double v) {
    const int x0 = std::clamp(static_cast<int>(std::floor(u - 0.5)), 0, mask.width - 1);
    const int y0 = std::clamp(static_cast<int>(std::floor(v - 0.5)), 0, mask.height - 1);
    for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx)
            if (mask.view().pixel(std::min(x0 + dx, mask.width - 1), std::min(y0 + dy, mask.height - 1))[0] < 255)
                return false;
    return true;
}

// --by-cosine: where the held-out error sits. Over every held-out view, the RMS error (8-bit sRGB
// levels) of the constant and of the fit by tenths of n.w (the cosine of the view to the normal), and,
// with the capture's masks, both overall at the vertices whose sample reads only fully covered pixels.
// Pooled over samples (not the mean over views of the main figures).
void printErrorByCosine(const TriangleMesh& mesh, const RadianceFromViewsResult& r, const std::vector<float>& constant,
                        const std::vector<CalibratedView>& heldOut, const std::vector<Image8>& masks) {
    double squaredConstant[10] = {0}, squaredFitted[10] = {0}, count[10] = {0};
    double coveredConstant = 0.0, coveredFitted = 0.0, covered = 0.0, all = 0.0;
    for (std::size_t i = 0; i < heldOut.size(); ++i) {
        const ViewSampler one(mesh, {heldOut[i]});
        DirectionalSample a;
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
            if (r.sampleCount[v] < 1 || !one.sampleVertex(v, &a)) continue;
            const Eigen::Vector3d w(a.direction[0], a.direction[1], a.direction[2]);
            const Eigen::Vector3d n = Eigen::Vector3d(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]).normalized();
            const Eigen::Vector3d f = evaluateRadiance(r.field, v, w);
            double ec2 = 0.0, ef2 = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double y = srgbLevel(a.rgb[c]);
                ec2 += std::pow(srgbLevel(constant[3 * v + c]) - y, 2) / 3.0;
                ef2 += std::pow(srgbLevel(f[c]) - y, 2) / 3.0;
            }
            const int q = std::clamp(static_cast<int>(w.dot(n) * 10.0), 0, 9);
            squaredConstant[q] += ec2;
            squaredFitted[q] += ef2;
            ++count[q];
            ++all;
            if (i < masks.size() && masks[i].width > 0) {
                const Eigen::Vector3d X(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
                double u = 0.0, t = 0.0;
                if (heldOut[i].camera.project(X, u, t) && fullyCovered(masks[i], u, t)) {
                    coveredConstant += ec2;
                    coveredFitted += ef2;
                    ++covered;
                }
            }
        }
    }
    std::printf("  held-out RMS by n.w (constant / fitted, samples):");
    for (int q = 0; q < 10; ++q)
        if (count[q] > 0)
            std::printf(" %.1f-%.1f: %.2f / %.2f (%.0f)", q / 10.0, (q + 1) / 10.0, std::sqrt(squaredConstant[q] / count[q]),
                        std::sqrt(squaredFitted[q] / count[q]), count[q]);
    std::printf("\n");
    if (covered > 0)
        std::printf("  held-out RMS at samples on fully covered pixels (%.1f %% of them): constant %.3f, fitted %.3f, "
                    "fitted/constant %.3f\n", 100.0 * covered / all, std::sqrt(coveredConstant / covered),
                    std::sqrt(coveredFitted / covered), std::sqrt(coveredFitted / coveredConstant));
}

// Wall time between the progress callback's stage changes: where the fit's time goes, by the stages
// the filter's progress bar names (a stage the fit enters twice is listed twice).
class StageClock {
public:
    ProgressCallback callback() {
        return [this](double, const char* stage) {
            const double t = now();
            if (current_ != stage) {
                if (!current_.empty()) spans_.push_back({current_, t - since_});
                current_ = stage;
                since_ = t;
            }
            return true;
        };
    }
    void print() const {
        for (const auto& [stage, seconds] : spans_) std::printf("  stage %-36s %.3f s\n", stage.c_str(), seconds);
    }

private:
    std::string current_;
    double since_ = 0.0;
    std::vector<std::pair<std::string, double>> spans_;
};

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s CAPTURE [--held-out-every K] [--basis PB4] [--models per-vertex,shared,auto] "
                             "[--meshlab-colors COLORS.ply] [--phases 1] [--by-cosine 1]\n", argv[0]);
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    int every = 5;
    std::string basisName = "PB4", models = "per-vertex,shared,auto", meshlabColors;
    SharedFitOptions sharedOptions;
    bool inSample = false;
    bool phases = false;     // --phases 1: the wall time of each stage the fit reports through its progress callback
    bool byCosine = false;  // --by-cosine 1: the held-out errors by n.w, and without the pixels the object only partly covers
    int diagnoseView = -1;  // --diagnose-view J: where the J-th held-out view (0-based) loses to the constant
    int rejectedConstant = -1;  // --rejected-constant 0|1: the shared fit's rejected vertices get the per-vertex fit (0) or the constant (1, the default)  // --in-sample 1: fit on ALL rasters (held-out ones included): the model's capacity
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--held-out-every")) every = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--rejected-constant")) rejectedConstant = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--diagnose-view")) diagnoseView = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--by-cosine")) byCosine = std::atoi(argv[i + 1]) != 0;
        else if (!std::strcmp(argv[i], "--in-sample")) inSample = std::atoi(argv[i + 1]) != 0;
        else if (!std::strcmp(argv[i], "--cosine")) sharedOptions.cosineFactor = std::atoi(argv[i + 1]) != 0;
        else if (!std::strcmp(argv[i], "--factor-curve")) sharedOptions.fitFactorCurve = std::atoi(argv[i + 1]) != 0;
        else if (!std::strcmp(argv[i], "--lobe-degree")) sharedOptions.lobeDegree = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--specular-prior")) sharedOptions.specularPrior = std::atof(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--lobe-ridge")) sharedOptions.lobeRidge = std::atof(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--lobe-samples")) sharedOptions.lobeSampleBudget = std::strtoul(argv[i + 1], nullptr, 10);
        else if (!std::strcmp(argv[i], "--iterations")) sharedOptions.iterations = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--refit-iterations")) sharedOptions.refitIterations = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--choice-iterations")) sharedOptions.choiceIterations = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--basis")) basisName = argv[i + 1];
        else if (!std::strcmp(argv[i], "--guard")) sharedOptions.guardStandardErrors = std::atof(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--models")) models = argv[i + 1];
        else if (!std::strcmp(argv[i], "--phases")) phases = std::atoi(argv[i + 1]) != 0;
        else if (!std::strcmp(argv[i], "--meshlab-colors")) meshlabColors = argv[i + 1];
        else if (!std::strcmp(argv[i], "--light-distance")) sharedOptions.lightDistance = std::strtod(argv[i + 1], nullptr);
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (every < 2) {
        std::fprintf(stderr, "--held-out-every must be at least 2 (every k-th raster is held out and evaluated)\n");
        return 2;
    }
    try {
        const RadianceMesh plain = readRadiancePly((dir / "mesh.ply").string());
        TriangleMesh mesh;
        mesh.positions = plain.positions;
        mesh.normals = plain.normals;
        mesh.faces = plain.faces;
        const MeshLabProject project = readMeshLabProject((dir / "project.mlp").string());
        std::vector<Image8> images, twins, heldOutMasks;
        images.reserve(project.rasters.size());
        twins.reserve(project.rasters.size());
        for (const ProjectRaster& r : project.rasters) {
            images.push_back(readImage8(r.imagePath));
            const std::filesystem::path twin = dir / "photos_twin" / std::filesystem::path(r.imagePath).filename();
            twins.push_back(std::filesystem::exists(twin) ? readImage8(twin.string()) : Image8());
        }
        std::vector<CalibratedView> training, heldOut, photoOfTwin, twinViews;
        for (std::size_t i = 0; i < project.rasters.size(); ++i) {
            const CalibratedView view{fromVcgCamera(project.rasters[i].camera), images[i].view()};
            if ((i + 1) % static_cast<std::size_t>(every) == 0) {
                heldOut.push_back(view);
                const std::filesystem::path mask = dir / "masks" / std::filesystem::path(project.rasters[i].imagePath).filename();
                heldOutMasks.push_back(byCosine && std::filesystem::exists(mask) ? readImage8(mask.string()) : Image8());
            }
            else training.push_back(view);
            if (twins[i].width > 0) {
                photoOfTwin.push_back(view);
                twinViews.push_back({view.camera, twins[i].view()});
            }
        }
        std::printf("capture %s: %zu vertices, %zu rasters (%zu fitted, %zu held out), basis %s\n",
                    dir.filename().string().c_str(), mesh.vertexCount(), project.rasters.size(), training.size(),
                    heldOut.size(), basisName.c_str());

        // Noise: photo vs twin (the same view, another seed) at the vertices each view with a twin sees
        // (any view: the noise is a property of the rendering, not of the split).
        if (!twinViews.empty()) {
            const ViewSampler a(mesh, photoOfTwin), b(mesh, twinViews);
            std::vector<DirectionalSample> sa(twinViews.size()), sb(twinViews.size());
            double sum = 0.0;
            std::size_t count = 0;
            for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
                const std::size_t m = a.sampleVertex(v, sa.data());
                if (b.sampleVertex(v, sb.data()) != m) continue;
                for (std::size_t j = 0; j < m; ++j)
                    for (int c = 0; c < 3; ++c) {
                        const double e = srgbLevel(sa[j].rgb[c]) - srgbLevel(sb[j].rgb[c]);
                        sum += e * e;
                        ++count;
                    }
            }
            std::printf("noise of the photographs (RMS photo - twin, / sqrt 2, %zu views with a twin): %.2f\n",
                        twinViews.size(), count ? std::sqrt(sum / count / 2.0) : 0.0);
        }

        const auto basis = BasisSpec::parse(basisName);
        if (!basis) throw std::runtime_error("bad basis " + basisName);
        RadianceFromViewsResult lastResult;
        std::vector<float> referenceMean;
        for (const std::string& name : split(models)) {
            RadianceFromViewsOptions options;
            options.fit.basis = *basis;
            options.shared = sharedOptions;
            if (rejectedConstant >= 0) options.sharedRejectedPerVertex = rejectedConstant == 0;
            options.model = name == "per-vertex" ? FitModel::PerVertex : name == "shared" ? FitModel::Shared : FitModel::Automatic;
            const double t0 = now();
            std::vector<CalibratedView> fitted = training;
            if (inSample) fitted.insert(fitted.end(), heldOut.begin(), heldOut.end());
            StageClock stages;
            const RadianceFromViewsResult r =
                phases ? fitRadianceFromViews(mesh, fitted, options, stages.callback()) : fitRadianceFromViews(mesh, fitted, options);
            const double seconds = now() - t0;
            if (phases) stages.print();
            const double evaluationStart = now();
            const HeldOutEvaluation e = evaluateHeldOutViews(mesh, r.field, r.meanColor, training, heldOut, options.sampling);
            const double evaluationSeconds = now() - evaluationStart;
            std::printf("%-10s fit %.2f s (median %.0f samples/vertex)", name.c_str(), seconds, r.medianSamples);
            if (r.modelValidated)
                std::printf(", chose %s (left-out RMS per-vertex %.3f, shared %.3f, constant %.3f on %zu samples)",
                            r.modelUsed == FitModel::Shared ? "shared" : "per-vertex", r.validationPerVertex,
                            r.validationShared, r.validationConstant, r.validationSamples);
            if (r.modelValidated)
                std::printf("; shared won %zu/%zu left-out views, worst view ratio shared/per-vertex %.3f",
                            r.validationViewsSharedWins, r.validationViewsCompared, r.validationWorstViewRatio);
            if (r.modelUsed == FitModel::Shared) std::printf("; lights at %.3g bounding radii", r.lightDistance);
            std::printf("\n  held-out mean RMS: fitted %.3f  constant %.3f  projection-estimate %.3f  fitted<=constant in %zu/%zu views;"
                        " fitted/constant %.3f\n",
                        e.meanFitted, e.meanConstant, e.meanProjection, e.fittedNotWorseThanConstant, e.viewsCompared,
                        e.meanConstant > 0 ? e.meanFitted / e.meanConstant : 0.0);
            std::printf("  held-out evaluation %.2f s\n", evaluationSeconds);
            std::printf("  per view (fitted/constant):");
            for (const HeldOutViewError& v : e.views) std::printf(" %.2f/%.2f", v.fitted, v.constant);
            std::printf("\n");
            // The reference constant: the per-vertex fit's mean colour (the filter's "constant mean
            // colour" before the shared fit existed), the same for every model.
            if (name == "per-vertex") referenceMean = r.meanColor;
            if (!referenceMean.empty()) {
                const HeldOutEvaluation ref = evaluateHeldOutViews(mesh, r.field, referenceMean, training, heldOut,
                                                                   options.sampling);
                std::size_t notWorse = 0;
                double worst = 0.0;
                for (std::size_t k = 0; k < e.views.size() && k < ref.views.size(); ++k) {
                    notWorse += e.views[k].fitted <= ref.views[k].constant;
                    worst = std::max(worst, e.views[k].fitted / ref.views[k].constant);
                }
                std::printf("  vs the reference constant (per-vertex fit's mean colour) %.3f: ratio %.3f, fitted<=it in"
                            " %zu/%zu views, worst view ratio %.3f\n",
                            ref.meanConstant, e.meanFitted / ref.meanConstant, notWorse, e.views.size(), worst);
            }
            if (byCosine) printErrorByCosine(mesh, r, referenceMean.empty() ? r.meanColor : referenceMean, heldOut, heldOutMasks);
            if (diagnoseView >= 0 && diagnoseView < int(heldOut.size())) {
                // Excess squared error (fitted - constant, sRGB levels^2, summed over channels) of the
                // vertices the view sees, by the angle between the view's direction and the vertex's
                // nearest training direction, and by the cosine of the view to the normal.
                const std::vector<float>& constant = referenceMean.empty() ? r.meanColor : referenceMean;
                const ViewSampler one(mesh, {heldOut[diagnoseView]}), train(mesh, training);
                std::vector<DirectionalSample> a(1), b(training.size());
                const double angleEdges[] = {5, 10, 20, 30, 45, 180};
                double excessA[6] = {0}, countA[6] = {0}, excessC[5] = {0}, countC[5] = {0}, signedC[5] = {0};
                // and by the photograph's level (eighths of 0..255): where the squared error sits (highlights?)
                double levelConstant[8] = {0}, levelFitted[8] = {0}, levelCount[8] = {0}, levelBias[8] = {0};
                for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
                    if (!one.sampleVertex(v, a.data())) continue;
                    const std::size_t m = train.sampleVertex(v, b.data());
                    if (!m) continue;
                    const Eigen::Vector3d w(a[0].direction[0], a[0].direction[1], a[0].direction[2]);
                    double best = -1.0;
                    for (std::size_t j = 0; j < m; ++j)
                        best = std::max(best, w.dot(Eigen::Vector3d(b[j].direction[0], b[j].direction[1], b[j].direction[2])));
                    const double angle = std::acos(std::min(1.0, best)) * 180.0 / M_PI;
                    const Eigen::Vector3d f = evaluateRadiance(r.field, v, w);
                    double excess = 0.0, bias = 0.0, level = 0.0, squaredConstant = 0.0, squaredFitted = 0.0, constantBias = 0.0;
                    for (int c = 0; c < 3; ++c) {
                        const double y = srgbLevel(a[0].rgb[c]);
                        const double ef = srgbLevel(f[c]) - y, ec = srgbLevel(constant[3 * v + c]) - y;
                        excess += ef * ef - ec * ec;
                        bias += (ef - ec) / 3.0;
                        level += y / 3.0;
                        squaredConstant += ec * ec;
                        squaredFitted += ef * ef;
                        constantBias += ec / 3.0;
                    }
                    const int eighth = std::min(7, static_cast<int>(level / 32.0));
                    levelConstant[eighth] += squaredConstant;
                    levelFitted[eighth] += squaredFitted;
                    levelBias[eighth] += constantBias;
                    ++levelCount[eighth];
                    int k = 0;
                    while (angle > angleEdges[k]) ++k;
                    excessA[k] += excess;
                    ++countA[k];
                    const Eigen::Vector3d nv(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]);
                    const int q = std::min(4, std::max(0, int(w.dot(nv.normalized()) * 5.0)));
                    excessC[q] += excess;
                    signedC[q] += bias;
                    ++countC[q];
                }
                std::printf("  held-out view %d: excess squared error fitted - constant (sum, vertices) by angle to the "
                            "nearest training direction:", diagnoseView);
                for (int k = 0; k < 6; ++k) std::printf(" <=%g: %.0f (%.0f)", angleEdges[k], excessA[k], countA[k]);
                std::printf("\n    by the photograph's level (squared error of the constant / of the fit, summed; vertices; "
                            "the constant's mean error):");
                for (int k = 0; k < 8; ++k)
                    std::printf("\n      %3d-%3d: %.0f / %.0f (%.0f, %+.1f)", 32 * k, 32 * k + 31, levelConstant[k], levelFitted[k],
                                levelCount[k], levelCount[k] > 0 ? levelBias[k] / levelCount[k] : 0.0);
                std::printf("\n    by cos(view, normal) fifths:");
                for (int k = 0; k < 5; ++k)
                    std::printf(" %.1f-%.1f: %.0f (%.0f vertices, fitted - constant %+.2f)", k / 5.0, (k + 1) / 5.0,
                                excessC[k], countC[k], countC[k] > 0 ? signedC[k] / countC[k] : 0.0);
                std::printf("\n");
            }
            if (r.modelUsed == FitModel::Shared)
                std::printf("  shared: %zu vertices diffuse + lobe, %zu view-dependent in all, %zu constant\n",
                            r.sharedVertices, r.viewDependent, r.validatedConstant + r.tooFewSamples + r.guardConstant);
            std::fflush(stdout);
            lastResult = r;
        }
        if (!meshlabColors.empty()) {
            const RadianceMesh colored = readRadiancePly(meshlabColors);
            if (colored.vertexCount() != mesh.vertexCount() || colored.colors.empty())
                throw std::runtime_error(meshlabColors + ": not the capture's vertex count, or no colours");
            std::vector<float> linear(3 * mesh.vertexCount());
            for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
                for (int c = 0; c < 3; ++c) linear[3 * v + c] = srgbToLinear(colored.colors[4 * v + c]);
            const HeldOutEvaluation e =
                evaluateHeldOutViews(mesh, lastResult.field, linear, training, heldOut, RadianceFromViewsOptions().sampling);
            std::printf("MeshLab projection colours: held-out mean RMS %.3f (over the same vertices)\n", e.meanConstant);
            if (!referenceMean.empty()) {  // how far MeshLab's colours are from the training samples' mean
                double diff[3] = {0, 0, 0}, sq = 0.0;
                for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
                    for (int c = 0; c < 3; ++c) {
                        const double d = double(colored.colors[4 * v + c]) - srgbLevel(referenceMean[3 * v + c]);
                        diff[c] += d;
                        sq += d * d;
                    }
                const double nv = double(mesh.vertexCount());
                std::printf("  MeshLab colour - reference mean colour: mean (%.2f, %.2f, %.2f), RMS %.2f sRGB levels\n",
                            diff[0] / nv, diff[1] / nv, diff[2] / nv, std::sqrt(sq / (3.0 * nv)));
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
