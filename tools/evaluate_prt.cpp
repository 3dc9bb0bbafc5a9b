// evaluate_prt: adaptive (Křivánek et al. 2004, Krivanek et al., Fig. 2) against uniform PRT subdivision at the
// same triangle count, judged by the relighting error of the interpolated shading against transfer
// ray-cast at dense sample points (common/prt/relighting_error.h), over many lightings: random
// directional lights (Hanning-windowed SH) and HDR environment maps in several rotations.
//
//   evaluate_prt [--scene column | --mesh FILE] [options]
//
// Scenes: "column" is Křivánek et al. 2004 Fig. 1's column on a ground plane (~200 vertices); --mesh puts a
// real scan (OFF / PLY), optionally simplified first (geometry-only QEM), standing on a square ground
// plane (its lowest point on the plane, up axis --up).
// The uniform baseline splits every triangle --levels times (faces x 4^levels); the adaptive
// subdivision gets exactly the uniform result's face count as its budget.
// Prints, per mesh (input, uniform, adaptive), faces, vertices and the Weber-normalised relative
// error (mean, 95th percentile) per lighting group and overall, then adaptive / uniform ratios.
// --out DIR writes pictures relit by a directional light toward (1, 0.4, 0.6) (reference with
// per-pixel ray-cast transfer, and each mesh with interpolated vertex colours) and the meshes as .rply
// with their transfer vectors.
// Exit status: 0 success, 1 data error, 2 bad command line.
#include "acquisition/sample_scene_radiance_mesh.h"
#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"
#include "image/image_io.h"
#include "image/rgb_image.h"
#include "io/radiance_ply.h"
#include "lighting/environment_map.h"
#include "prt/adaptive_subdivision.h"
#include "prt/prt_lighting.h"
#include "prt/relighting_error.h"
#include "prt/transfer_vectors.h"
#include "render/radiance_renderer.h"
#include "simplify/radiance_simplification.h"

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "command_line.h"
#include "scene_setup.h"

namespace {

using radtools::UsageError;
using radtools::toInt;
using radtools::toNumber;

void usage(std::ostream& out) {
    out << "usage: evaluate_prt [--scene column | --mesh FILE] [options]\n"
           "  --scene column            Křivánek et al. 2004 Fig. 1 column on a plane [default]\n"
           "  --mesh FILE               a scan (.off/.ply) standing on a ground plane instead\n"
           "  --up x|y|z|-x|-y|-z       the scan's up axis [y]\n"
           "  --simplify-to F           simplify the scan to F faces first (geometry QEM) [0: no]\n"
           "  --ground N                ground plane cells per side for --mesh [8]\n"
           "  --levels L                uniform subdivision levels; budget = faces x 4^L [2]\n"
           "  --measure M               error estimate: 2, 3, 4 (Křivánek et al. 2004 eq. 2-4), probed\n"
           "                            (ray-cast midpoints, relative) or probed-absolute [library default]\n"
           "  --alpha A                 eq. 4 alpha [library default]\n"
           "  --order N                 SH order (N^2 coefficients) [6]\n"
           "  --rays N                  rays per transfer vector [256]\n"
           "  --samples N               evaluation sample points [200000]\n"
           "  --lights N                random directional lights [32]\n"
           "  --hdr FILE                an environment map (repeatable), used in --rotations rotations\n"
           "  --rotations N             rotations of each map about the up axis [4]\n"
           "  --seed S                  random seed [1]\n"
           "  --out DIR                 write pictures and meshes there\n"
           "  --size WxH                picture size [480x360]\n";
}

struct Settings {
    std::string scene = "column";
    std::string meshPath;
    Eigen::Vector3d up = Eigen::Vector3d::UnitY();
    int simplifyTo = 0;
    int ground = 8;
    int levels = 2;
    rad::TransferErrorMeasure measure = rad::AdaptiveSubdivisionOptions{}.measure;
    double alpha = rad::kDefaultNormalDivergenceAlpha;
    int order = rad::kDefaultTransferDegree + 1;
    int rays = rad::kDefaultTransferRayCount;
    long samples = 200000;
    int lights = 32;
    std::vector<std::string> hdr;
    int rotations = 4;
    unsigned seed = 1;
    std::string outDir;
    int width = 480, height = 360;
};

Settings parse(int argc, char** argv) {
    Settings s;
    for (int i = 1; i < argc; ++i) {
        const std::string key = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(key + " needs a value");
            return argv[++i];
        };
        if (key == "--scene") s.scene = value();
        else if (key == "--mesh") s.meshPath = value(), s.scene = "mesh";
        else if (key == "--up") s.up = radtools::parseAxis(value());
        else if (key == "--simplify-to") s.simplifyTo = toInt(key, value());
        else if (key == "--ground") s.ground = toInt(key, value());
        else if (key == "--levels") s.levels = toInt(key, value());
        else if (key == "--measure") {
            const std::string m = value();
            if (m == "2") s.measure = rad::TransferErrorMeasure::Contrast;
            else if (m == "3") s.measure = rad::TransferErrorMeasure::Difference;
            else if (m == "4") s.measure = rad::TransferErrorMeasure::NormalDivergence;
            else if (m == "probed") s.measure = rad::TransferErrorMeasure::ProbedRelative;
            else if (m == "probed-absolute") s.measure = rad::TransferErrorMeasure::ProbedAbsolute;
            else throw UsageError("--measure needs 2, 3, 4, probed or probed-absolute");
        } else if (key == "--alpha") s.alpha = toNumber(key, value());
        else if (key == "--order") s.order = toInt(key, value());
        else if (key == "--rays") s.rays = toInt(key, value());
        else if (key == "--samples") s.samples = toInt(key, value());
        else if (key == "--lights") s.lights = toInt(key, value());
        else if (key == "--hdr") s.hdr.push_back(value());
        else if (key == "--rotations") s.rotations = toInt(key, value());
        else if (key == "--seed") s.seed = static_cast<unsigned>(toInt(key, value()));
        else if (key == "--out") s.outDir = value();
        else if (key == "--size") {
            const std::string v = value();
            const auto x = v.find('x');
            if (x == std::string::npos) throw UsageError("--size needs WxH");
            s.width = toInt(key, v.substr(0, x));
            s.height = toInt(key, v.substr(x + 1));
        } else if (key == "-h" || key == "--help") {
            usage(std::cout);
            std::exit(0);
        } else
            throw UsageError("unknown option " + key);
    }
    if (s.scene != "column" && s.scene != "mesh") throw UsageError("--scene must be column (or use --mesh FILE)");
    if (s.levels < 0 || s.levels > 6) throw UsageError("--levels must be in 0..6");
    if (s.order < 1 || s.order > 11) throw UsageError("--order must be in 1..11");
    if (s.rays < 1 || s.samples < 1 || s.lights < 0 || s.rotations < 1 || s.ground < 1)
        throw UsageError("--rays, --samples, --rotations, --ground must be positive, --lights >= 0");
    if (s.width < 8 || s.height < 8) throw UsageError("--size must be at least 8x8");
    return s;
}

// The scan, simplified if asked, turned so that `up` becomes +Z, scaled to unit height, its lowest
// point on z = 0 and centred above the origin, plus a square ground plane of n x n cells around it.
rad::TriangleMesh scanOnPlane(const Settings& s) {
    rad::TriangleMesh scan = radtools::loadMesh(s.meshPath);
    if (s.simplifyTo > 0 && static_cast<std::size_t>(s.simplifyTo) < scan.faceCount()) {
        rad::RadianceMesh plain;
        plain.positions = scan.positions;
        plain.faces = scan.faces;
        rad::RadianceSimplificationOptions options;
        options.metric = rad::SimplificationMetric::GeometryOnly;
        options.collapse.targetFaceCount = static_cast<std::size_t>(s.simplifyTo);
        options.collapse.geometryWeight = 1.0;
        const auto result = rad::simplifyRadianceMesh(std::move(plain), options);
        const rad::RadianceMesh coarse = result.progressive.extract(result.progressive.steps.size());
        scan.positions = coarse.positions;
        scan.faces = coarse.faces;
    }
    const Eigen::Matrix3d toZUp =
        Eigen::Quaterniond::FromTwoVectors(s.up.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    Eigen::AlignedBox3d box;
    for (std::size_t v = 0; v < scan.vertexCount(); ++v) {
        Eigen::Vector3d p(scan.positions[3 * v], scan.positions[3 * v + 1], scan.positions[3 * v + 2]);
        p = toZUp * p;
        for (int k = 0; k < 3; ++k) scan.positions[3 * v + k] = static_cast<float>(p[k]);
        box.extend(p);
    }
    const double height = box.sizes().z();
    if (!(height > 0.0)) throw std::invalid_argument("the scan is flat along its up axis");
    const Eigen::Vector3d base(box.center().x(), box.center().y(), box.min().z());
    double footprint = 0.0;
    for (std::size_t v = 0; v < scan.vertexCount(); ++v) {
        Eigen::Vector3d p(scan.positions[3 * v], scan.positions[3 * v + 1], scan.positions[3 * v + 2]);
        p = (p - base) / height;
        for (int k = 0; k < 3; ++k) scan.positions[3 * v + k] = static_cast<float>(p[k]);
        footprint = std::max(footprint, std::hypot(p.x(), p.y()));
    }
    scan.normals.clear();
    rad::computeAreaWeightedNormals(scan);
    // The ground: twice the footprint (at least the height) on each side, normals up.
    const double half = std::max(2.0 * footprint, 1.0);
    const int n = s.ground;
    const std::uint32_t first = static_cast<std::uint32_t>(scan.vertexCount());
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            scan.positions.insert(scan.positions.end(),
                                  {float(-half + 2.0 * half * i / n), float(-half + 2.0 * half * j / n), 0.0f});
            scan.normals.insert(scan.normals.end(), {0.0f, 0.0f, 1.0f});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = first + j * (n + 1) + i, b = a + 1, c = a + (n + 1), d = c + 1;
            scan.faces.insert(scan.faces.end(), {a, b, d, a, d, c});
        }
    return scan;
}

struct Lighting {
    std::string group;
    std::vector<double> sh;
};

std::vector<Lighting> makeLightings(const Settings& s, int degree) {
    std::vector<Lighting> out;
    std::mt19937 rng(s.seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int i = 0; i < s.lights; ++i) {
        // Uniform over the upper hemisphere above 10 degrees of elevation (the scenes stand on a plane).
        const double z = std::sin(10.0 * M_PI / 180.0) + (1.0 - std::sin(10.0 * M_PI / 180.0)) * uniform(rng);
        const double phi = 2.0 * M_PI * uniform(rng);
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const Eigen::Vector3d d(r * std::cos(phi), r * std::sin(phi), z);
        out.push_back({"directional", rad::directionalLightSH(degree, d, Eigen::Vector3d::Ones())});
    }
    for (const std::string& path : s.hdr) {
        const rad::EnvironmentMap map = rad::readEnvironmentMap(path);
        const std::string name = std::filesystem::path(path).filename().string();
        for (int r = 0; r < s.rotations; ++r)
            out.push_back({name, rad::environmentLightSH(map, degree, 2.0 * M_PI * r / s.rotations)});
    }
    return out;
}

rad::SubdivisionResult identitySubdivision(const rad::PrtMesh& input) {
    rad::SubdivisionResult r;
    r.mesh = input;
    r.originFace.resize(input.faceCount());
    for (std::size_t f = 0; f < input.faceCount(); ++f) r.originFace[f] = static_cast<std::uint32_t>(f);
    return r;
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Per-pixel reference: the transfer ray-cast at every visible surface point (normal interpolated
// from the input's vertex normals), relit; vertex-interpolated renderings for the meshes.
void writePictures(const Settings& s, const rad::PrtMesh& input, const rad::TransferEstimator& estimator,
                   const rad::RayScene& scene, const std::vector<std::pair<std::string, const rad::PrtMesh*>>& meshes,
                   const std::vector<double>& lighting, int degree) {
    std::filesystem::create_directories(s.outDir);
    Eigen::AlignedBox3d box;
    for (std::size_t v = 0; v < input.vertexCount(); ++v)
        box.extend(Eigen::Vector3d(input.positions[3 * v], input.positions[3 * v + 1], input.positions[3 * v + 2]));
    const Eigen::Vector3d target(0.0, 0.0, 0.3);
    const double radius = 0.5 * box.diagonal().norm();
    const Eigen::Vector3d eye = target + radius * Eigen::Vector3d(1.1, -1.3, 0.9);
    const rad::PinholeCamera camera =
        rad::PinholeCamera::lookAt(eye, target, Eigen::Vector3d::UnitZ(), 50.0, s.width, s.height);
    const int k = (degree + 1) * (degree + 1);
    auto shade = [&](const float* t) {
        Eigen::Vector3f c;
        for (int ch = 0; ch < 3; ++ch) {
            double sum = 0.0;
            for (int i = 0; i < k; ++i) sum += double(t[i]) * lighting[ch * k + i];
            c[ch] = static_cast<float>(sum);
        }
        return c;
    };
    // Exposure: the 99th percentile of the reference's luminance maps to 1.
    rad::ImageF reference(s.width, s.height);
    std::vector<float> lum;
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < s.height; ++y) {
        std::vector<float> t(k);
        for (int x = 0; x < s.width; ++x) {
            const Eigen::Vector3d dir = camera.rayDirection(x + 0.5, y + 0.5);
            const rad::RayHit hit = scene.intersect(camera.center.cast<float>(), dir.cast<float>(), 0.0f, 1e30f);
            if (!hit.hit || hit.face >= input.faceCount()) continue;
            const std::uint32_t* f = &input.faces[3 * hit.face];
            const float b[3] = {1.0f - hit.u - hit.v, hit.u, hit.v};
            float p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
            for (int c = 0; c < 3; ++c)
                for (int q = 0; q < 3; ++q) {
                    p[q] += b[c] * input.positions[3 * f[c] + q];
                    n[q] += b[c] * input.normals[3 * f[c] + q];
                }
            estimator.computeAt(p, n, t.data());
            const Eigen::Vector3f c = shade(t.data());
            float* px = reference.rgb.data() + 3 * (static_cast<std::size_t>(y) * s.width + x);
            for (int q = 0; q < 3; ++q) px[q] = c[q];
        }
    }
    for (std::size_t i = 0; i < reference.rgb.size(); i += 3)
        lum.push_back(0.2126f * reference.rgb[i] + 0.7152f * reference.rgb[i + 1] + 0.0722f * reference.rgb[i + 2]);
    std::nth_element(lum.begin(), lum.begin() + lum.size() * 99 / 100, lum.end());
    const float top = lum[lum.size() * 99 / 100];
    const float exposure = top > 0.0f ? 1.0f / top : 1.0f;
    rad::writePng(s.outDir + "/reference.png", rad::encodeToSrgb8(reference, exposure));
    for (const auto& [name, mesh] : meshes) {
        std::vector<float> rgb(3 * mesh->vertexCount());
        for (std::size_t v = 0; v < mesh->vertexCount(); ++v) {
            const Eigen::Vector3f c = shade(mesh->transfer.data() + v * mesh->width);
            for (int q = 0; q < 3; ++q) rgb[3 * v + q] = c[q];
        }
        const rad::MeshRenderer renderer(mesh->positions.data(), mesh->vertexCount(), mesh->faces.data(),
                                         mesh->faceCount());
        const rad::Rendering r = renderer.renderVertexColors(rgb.data(), camera);
        rad::writePng(s.outDir + "/" + name + ".png", rad::encodeToSrgb8(r.image, exposure));
        rad::RadianceMesh out;
        out.positions = mesh->positions;
        out.normals = mesh->normals;
        out.faces = mesh->faces;
        rad::NamedVertexBlock block;
        block.prefix = "prt";
        block.width = mesh->width;
        block.values = mesh->transfer;
        block.metadata["kind"] = "sh_transfer_shadowed_diffuse";
        block.metadata["sh_degree"] = std::to_string(degree);
        block.metadata["channels"] = "1";
        block.metadata["rays"] = std::to_string(s.rays);
        out.extraBlocks.push_back(std::move(block));
        rad::writeRadiancePly(s.outDir + "/" + name + ".rply", out);
    }
}

void printRow(const char* name, const rad::PrtMesh& mesh, const std::vector<std::string>& groups,
              const std::vector<Lighting>& lightings, const rad::RelightingErrorReport& report) {
    std::printf("%-10s %8zu %8zu", name, mesh.faceCount(), mesh.vertexCount());
    for (const std::string& g : groups) {
        double mean = 0.0, p95 = 0.0;
        int count = 0;
        for (std::size_t i = 0; i < lightings.size(); ++i)
            if (lightings[i].group == g) {
                mean += report.perLighting[i].meanRelativeError;
                p95 += report.perLighting[i].p95RelativeError;
                ++count;
            }
        std::printf("  %9.5f %9.5f", mean / count, p95 / count);
    }
    std::printf("  %9.5f %9.5f\n", report.overall.meanRelativeError, report.overall.p95RelativeError);
}

int run(int argc, char** argv) {
    const Settings s = parse(argc, argv);
    const auto start = std::chrono::steady_clock::now();
    rad::TriangleMesh scene = s.scene == "column" ? rad::makeColumnOnPlane() : scanOnPlane(s);
    if (const std::string problem = scene.validate(); !problem.empty()) throw std::invalid_argument(problem);
    Eigen::AlignedBox3d box;
    double radius = 0.0;
    rad::sampleSceneBounds(scene, rad::SampleLightRadius::FarthestVertex, box, radius);
    const rad::RayScene rays(scene.positions.data(), scene.vertexCount(), scene.faces.data(), scene.faceCount());
    rad::TransferOptions options;
    options.degree = s.order - 1;
    options.rayCount = s.rays;
    const rad::TransferEstimator estimator(rays, static_cast<float>(box.diagonal().norm()), options);
    std::vector<float> batch;
    const rad::TransferOracle oracle = [&](const float* p, const float* n, std::size_t count, float* out) {
        rad::computeTransferVectors(estimator, p, n, count, batch);
        std::copy(batch.begin(), batch.end(), out);
    };

    rad::PrtMesh input;
    input.positions = scene.positions;
    input.normals = scene.normals;
    input.faces = scene.faces;
    input.width = estimator.coefficientCount();
    input.transfer.resize(input.vertexCount() * input.width);
    oracle(input.positions.data(), input.normals.data(), input.vertexCount(), input.transfer.data());
    if (const std::string problem = rad::checkPrtSubdivisionInput(input); !problem.empty())
        throw std::invalid_argument(problem);

    auto t0 = std::chrono::steady_clock::now();
    const std::size_t uniformBudget = input.faceCount() << (2 * s.levels);
    const rad::SubdivisionResult uniform = rad::subdivideUniformly(input, oracle, uniformBudget, s.measure, s.alpha);
    const double uniformSeconds = seconds(t0);
    rad::AdaptiveSubdivisionOptions adaptiveOptions;
    adaptiveOptions.measure = s.measure;
    adaptiveOptions.alpha = s.alpha;
    adaptiveOptions.triangleBudget = uniform.mesh.faceCount();
    t0 = std::chrono::steady_clock::now();
    const rad::SubdivisionResult adaptive = rad::subdivideAdaptively(input, oracle, adaptiveOptions);
    const double adaptiveSeconds = seconds(t0);

    t0 = std::chrono::steady_clock::now();
    const rad::RelightingSamples samples =
        rad::makeRelightingSamples(input, static_cast<std::size_t>(s.samples), oracle, s.seed);
    const double sampleSeconds = seconds(t0);
    const int degree = s.order - 1;
    const std::vector<Lighting> lightings = makeLightings(s, degree);
    if (lightings.empty()) throw UsageError("no lighting: give --lights N > 0 or --hdr FILE");
    std::vector<std::vector<double>> sh;
    std::vector<std::string> groups;
    for (const Lighting& l : lightings) {
        sh.push_back(l.sh);
        if (std::find(groups.begin(), groups.end(), l.group) == groups.end()) groups.push_back(l.group);
    }

    const rad::SubdivisionResult original = identitySubdivision(input);
    const std::vector<std::pair<const char*, const rad::SubdivisionResult*>> meshes = {
        {"input", &original}, {"uniform", &uniform}, {"adaptive", &adaptive}};
    // Each mesh's transfer interpolated at the samples, once for every table below.
    std::vector<std::vector<float>> interpolations;
    std::vector<rad::RelightingErrorReport> reports;
    for (const auto& [name, result] : meshes) {
        interpolations.push_back(rad::interpolateAtSamples(samples, input, *result));
        reports.push_back(rad::relightingErrorOverLightings(samples, interpolations.back(), degree, 1, sh, degree));
    }

    std::printf("scene: %s, %zu vertices, %zu faces; SH order %d, %d rays; estimate %s, alpha %.3g\n",
                s.scene == "column" ? "column on a plane (Křivánek et al. 2004 Fig. 1)" : s.meshPath.c_str(),
                scene.vertexCount(), scene.faceCount(), s.order, s.rays,
                s.measure == rad::TransferErrorMeasure::Contrast           ? "eq. 2"
                : s.measure == rad::TransferErrorMeasure::Difference       ? "eq. 3"
                : s.measure == rad::TransferErrorMeasure::NormalDivergence ? "eq. 4"
                : s.measure == rad::TransferErrorMeasure::ProbedRelative   ? "probed (relative)"
                                                                           : "probed (absolute)",
                s.alpha);
    std::printf("uniform: %d levels, %.2f s; adaptive: budget %zu, %zu regular splits (%zu forced), %zu T-vertex "
                "fixes, %.2f s; %zu samples (%.2f s); %zu lightings (Weber floor %.2f of the mean)\n",
                s.levels, uniformSeconds, adaptiveOptions.triangleBudget, adaptive.regularSplits,
                adaptive.forcedSplits, adaptive.tVertexFixes, adaptiveSeconds, samples.count(), sampleSeconds,
                lightings.size(), rad::kWeberFloorFraction);
    std::printf("%-10s %8s %8s", "mesh", "faces", "vertices");
    for (const std::string& g : groups) std::printf("  %19.19s", (g + " mean/p95").c_str());
    std::printf("  %19s\n", "all mean/p95");
    for (std::size_t i = 0; i < meshes.size(); ++i)
        printRow(meshes[i].first, meshes[i].second->mesh, groups, lightings, reports[i]);
    // Where the error is: samples on the ground plane (z = 0, normal up) and on the object.
    std::vector<char> onGround(samples.count());
    for (std::size_t i = 0; i < samples.count(); ++i)
        onGround[i] = std::fabs(samples.positions[3 * i + 2]) < 1e-6f && samples.normals[3 * i + 2] > 0.99f;
    std::printf("%-10s %19s %19s   (all lightings, samples split by surface)\n", "mesh", "ground mean/p95",
                "object mean/p95");
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const std::vector<float>& interpolated = interpolations[m];
        std::printf("%-10s", meshes[m].first);
        for (int part = 1; part >= 0; --part) {
            rad::RelightingSamples subset;
            subset.width = samples.width;
            std::vector<float> values;
            for (std::size_t i = 0; i < samples.count(); ++i) {
                if (onGround[i] != part) continue;
                subset.inputFace.push_back(samples.inputFace[i]);
                subset.positions.insert(subset.positions.end(), &samples.positions[3 * i], &samples.positions[3 * i + 3]);
                subset.normals.insert(subset.normals.end(), &samples.normals[3 * i], &samples.normals[3 * i + 3]);
                subset.weights.push_back(samples.weights[i]);
                subset.groundTruth.insert(subset.groundTruth.end(), samples.groundTruth.begin() + i * samples.width,
                                          samples.groundTruth.begin() + (i + 1) * samples.width);
                values.insert(values.end(), interpolated.begin() + i * samples.width,
                              interpolated.begin() + (i + 1) * samples.width);
            }
            if (subset.count() == 0) {
                std::printf(" %19s", "-");
                continue;
            }
            const auto r = rad::relightingErrorOverLightings(subset, values, degree, 1, sh, degree);
            std::printf("  %8.5f %8.5f", r.overall.meanRelativeError, r.overall.p95RelativeError);
        }
        std::printf("\n");
    }
    const double ratio = reports[2].overall.meanRelativeError / reports[1].overall.meanRelativeError;
    std::printf("adaptive / uniform mean relative error: %.3f (%.1f %% lower); p95: %.3f\n", ratio,
                100.0 * (1.0 - ratio), reports[2].overall.p95RelativeError / reports[1].overall.p95RelativeError);
    // The same comparison with |L - L_int| divided by the lighting's mean luminance (absolute: the
    // dark regions that dominate the relative error weigh little here).
    std::vector<rad::RelightingErrorReport> absolute;
    for (const std::vector<float>& interpolated : interpolations)
        absolute.push_back(rad::relightingErrorOverLightings(samples, interpolated, degree, 1, sh, degree,
                                                             rad::RelightingErrorNormalisation::MeanLuminance));
    std::printf("absolute error (|L - L_int| / mean L), mean/p95: input %.5f %.5f, uniform %.5f %.5f, adaptive %.5f "
                "%.5f; adaptive / uniform mean %.3f, p95 %.3f\n",
                absolute[0].overall.meanRelativeError, absolute[0].overall.p95RelativeError,
                absolute[1].overall.meanRelativeError, absolute[1].overall.p95RelativeError,
                absolute[2].overall.meanRelativeError, absolute[2].overall.p95RelativeError,
                absolute[2].overall.meanRelativeError / absolute[1].overall.meanRelativeError,
                absolute[2].overall.p95RelativeError / absolute[1].overall.p95RelativeError);
    std::printf("adaptive probes: %zu midpoints ray-cast for the estimate\n", adaptive.probes);

    if (!s.outDir.empty()) {
        writePictures(s, input, estimator, rays,
                      {{"input", &original.mesh}, {"uniform", &uniform.mesh}, {"adaptive", &adaptive.mesh}},
                      rad::directionalLightSH(degree, Eigen::Vector3d(1.0, 0.4, 0.6).normalized(), Eigen::Vector3d::Ones()),
                      degree);
        std::printf("pictures and meshes written to %s (a directional light toward (1, 0.4, 0.6))\n",
                    s.outDir.c_str());
    }
    std::printf("total %.2f s\n", seconds(start));
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("evaluate_prt", argc, argv, run, usage); }
