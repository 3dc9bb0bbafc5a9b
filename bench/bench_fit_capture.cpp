// Held-out accuracy of "Fit Radiance Functions from Rasters" on a capture rendered by an independent
// renderer (e.g. a path tracer): CAPTURE/mesh.ply, CAPTURE/project.mlp (rasters with cameras),
// CAPTURE/photos_twin/ (optional: the same views rendered again with another noise seed, same file
// names as the project's images).
//
//   bench_fit_capture CAPTURE [--held-out-every K] [--basis PB4] [--models per-vertex,shared,auto]
//                     [--meshlab-colors COLORS.ply]
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

#include <chrono>
#include <cmath>
#include <cstdio>
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

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s CAPTURE [--held-out-every K] [--basis PB4] [--models per-vertex,shared,auto] "
                             "[--meshlab-colors COLORS.ply]\n", argv[0]);
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    int every = 5;
    std::string basisName = "PB4", models = "per-vertex,shared,auto", meshlabColors;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--held-out-every")) every = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--basis")) basisName = argv[i + 1];
        else if (!std::strcmp(argv[i], "--models")) models = argv[i + 1];
        else if (!std::strcmp(argv[i], "--meshlab-colors")) meshlabColors = argv[i + 1];
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    try {
        const RadianceMesh plain = readRadiancePly((dir / "mesh.ply").string());
        TriangleMesh mesh;
        mesh.positions = plain.positions;
        mesh.normals = plain.normals;
        mesh.faces = plain.faces;
        const MeshLabProject project = readMeshLabProject((dir / "project.mlp").string());
        std::vector<Image8> images, twins;
        images.reserve(project.rasters.size());
        twins.reserve(project.rasters.size());
        for (const ProjectRaster& r : project.rasters) {
            images.push_back(readImage8(r.imagePath));
            const std::filesystem::path twin = dir / "photos_twin" / std::filesystem::path(r.imagePath).filename();
            twins.push_back(std::filesystem::exists(twin) ? readImage8(twin.string()) : Image8());
        }
        std::vector<CalibratedView> training, heldOut, heldOutTwin;
        for (std::size_t i = 0; i < project.rasters.size(); ++i) {
            const CalibratedView view{fromVcgCamera(project.rasters[i].camera), images[i].view()};
            if ((i + 1) % static_cast<std::size_t>(every) == 0) {
                heldOut.push_back(view);
                if (twins[i].width > 0) heldOutTwin.push_back({view.camera, twins[i].view()});
            } else {
                training.push_back(view);
            }
        }
        std::printf("capture %s: %zu vertices, %zu rasters (%zu fitted, %zu held out), basis %s\n",
                    dir.filename().string().c_str(), mesh.vertexCount(), project.rasters.size(), training.size(),
                    heldOut.size(), basisName.c_str());

        // Noise: photo vs twin at the vertices each held-out view sees.
        if (heldOutTwin.size() == heldOut.size() && !heldOut.empty()) {
            const ViewSampler a(mesh, heldOut), b(mesh, heldOutTwin);
            std::vector<DirectionalSample> sa(heldOut.size()), sb(heldOut.size());
            double sum = 0.0;
            std::size_t count = 0;
            for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
                const std::size_t m = a.sampleVertex(v, sa.data());
                b.sampleVertex(v, sb.data());
                for (std::size_t j = 0; j < m; ++j)
                    for (int c = 0; c < 3; ++c) {
                        const double e = srgbLevel(sa[j].rgb[c]) - srgbLevel(sb[j].rgb[c]);
                        sum += e * e;
                        ++count;
                    }
            }
            std::printf("noise of the photographs (RMS photo - twin, / sqrt 2): %.2f\n",
                        count ? std::sqrt(sum / count / 2.0) : 0.0);
        }

        const auto basis = BasisSpec::parse(basisName);
        if (!basis) throw std::runtime_error("bad basis " + basisName);
        RadianceFromViewsResult lastResult;
        for (const std::string& name : split(models)) {
            RadianceFromViewsOptions options;
            options.fit.basis = *basis;
            options.model = name == "per-vertex" ? FitModel::PerVertex : name == "shared" ? FitModel::Shared : FitModel::Automatic;
            const double t0 = now();
            const RadianceFromViewsResult r = fitRadianceFromViews(mesh, training, options);
            const double seconds = now() - t0;
            const HeldOutEvaluation e = evaluateHeldOutViews(mesh, r.field, r.meanColor, training, heldOut, options.sampling);
            std::printf("%-10s fit %.2f s (median %.0f samples/vertex)", name.c_str(), seconds, r.medianSamples);
            if (r.modelValidated)
                std::printf(", chose %s (left-out RMS per-vertex %.3f, shared %.3f, constant %.3f on %zu samples)",
                            r.modelUsed == FitModel::Shared ? "shared" : "per-vertex", r.validationPerVertex,
                            r.validationShared, r.validationConstant, r.validationSamples);
            std::printf("\n  held-out mean RMS: fitted %.3f  constant %.3f  projection-estimate %.3f  fitted<=constant in %zu/%zu views;"
                        " fitted/constant %.3f\n",
                        e.meanFitted, e.meanConstant, e.meanProjection, e.fittedNotWorseThanConstant, e.viewsCompared,
                        e.meanConstant > 0 ? e.meanFitted / e.meanConstant : 0.0);
            std::printf("  per view (fitted/constant):");
            for (const HeldOutViewError& v : e.views) std::printf(" %.2f/%.2f", v.fitted, v.constant);
            std::printf("\n");
            if (r.modelUsed == FitModel::Shared)
                std::printf("  shared: %zu vertices diffuse + lobe, %zu constant\n", r.sharedVertices,
                            r.validatedConstant + r.tooFewSamples);
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
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
