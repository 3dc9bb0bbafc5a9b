// simplify_radiance: radiance-aware simplification of a radiance mesh into several levels of detail
// (common/simplify/radiance_simplification.h), or replay of a progressive mesh file.
//   simplify_radiance IN.rply -o PREFIX [--ratios 0.5,0.25,0.1] [--metric ...] [--progressive OUT.rpm]
//   simplify_radiance IN.rpm  -o PREFIX [--ratios ...]        (levels extracted from the recording)
// Ratios are fractions of the input's FACE count (as MeshLab's decimation filter); on a closed
// mesh the vertex count follows (V ~ F / 2). Level files: PREFIX_<ratio in per mille>.rply.
#include "io/radiance_ply.h"
#include "simplify/directional_reduction.h"
#include "simplify/progressive_mesh.h"
#include "simplify/radiance_simplification.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.h"
#include "scene_setup.h"

namespace {

using radtools::UsageError;
using radtools::toInt;
using radtools::toNumber;

void usage(std::ostream& out) {
    out << "usage: simplify_radiance IN.{rply,rpm} -o PREFIX [options]\n"
           "  --ratios r1,r2,...       face ratios of the levels written, each in (0, 1) [0.5,0.25,0.1]\n"
           "  --metric radiance|lightfield2010|color|geometry|quadric   [radiance] (Vanhoey et al. 2015 eq. 7; Vanhoey et al.\n"
           "                           2010; Garland-Heckbert 1998 colour QEM on the mean colour; memoryless QEM; the\n"
           "                           accumulating radiance quadric of Hoppe 1999, the filter's default, best with full)\n"
           "  --collapse half|full     half-edge (sec. 4.1) or full edge collapse (sec. 4.3) [half]\n"
           "  --geometry-weight W      weight of the memoryless QEM [0.01]\n"
           "  --attribute-weight W     weight of the metric (lambda for lightfield2010) [0.99]\n"
           "  --valence MIN,MAX        valence bounds, e.g. 4,11 (Vanhoey et al. 2010) [none]\n"
           "  --free-boundary          let boundary vertices move and disappear\n"
           "  --fixed-boundary         never merge boundary vertices, even along the boundary (radiance\n"
           "                           quadric, full collapses; by default they merge along it)\n"
           "  --eager                  re-price touched vertices at once instead of lazily\n"
           "  --pass-fraction F        full collapses under the radiance quadric: passes of at most this\n"
           "                           fraction of the edges (after meshoptimizer); 0: one global queue [0.3]\n"
           "  --max-normal-change DEG  largest rotation of a face's normal by a collapse [90]\n"
           "  --progressive OUT.rpm    also write the progressive mesh (and OUT_base.rply beside it)\n"
           "  --threads N              worker threads [all]\n"
           "  --reduce PB2|SH3|...     instead: directional reduction (every vertex kept, RF projected onto\n"
           "                           the lower degree), written to PREFIX_<basis>.rply\n";
}

double peakMemoryMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;
}

std::string levelPath(const std::string& prefix, double ratio) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "_%03d.rply", static_cast<int>(std::lround(1000.0 * ratio)));
    return prefix + buffer;
}

int run(int argc, char** argv) {
    std::string input, prefix, metricName = "radiance", collapseName = "half", progressivePath, reduceTo;
    std::vector<double> ratios = {0.5, 0.25, 0.1};
    rad::RadianceSimplificationOptions options;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (a == "--free-boundary") {
            options.collapse.preserveBoundary = false;
            continue;
        }
        if (a == "--fixed-boundary") {
            options.collapse.collapseAlongBoundary = false;
            continue;
        }
        if (a == "--eager") {
            options.collapse.lazyRepricing = false;
            continue;
        }
        if (a.rfind("-", 0) != 0) {
            if (!input.empty()) throw UsageError("more than one input given: " + input + ", " + a);
            input = a;
            continue;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "-o" || a == "--output") prefix = v;
        else if (a == "--ratios") ratios = radtools::numberList(a, v, ',');
        else if (a == "--metric") metricName = v;
        else if (a == "--collapse") collapseName = v;
        else if (a == "--geometry-weight") options.collapse.geometryWeight = toNumber(a, v);
        else if (a == "--attribute-weight") options.collapse.attributeWeight = toNumber(a, v);
        else if (a == "--max-normal-change") options.collapse.maxNormalDeviationDegrees = toNumber(a, v);
        else if (a == "--threads") options.collapse.threads = toInt(a, v);
        else if (a == "--pass-fraction") options.collapse.passFraction = toNumber(a, v);
        else if (a == "--progressive") progressivePath = v;
        else if (a == "--reduce") reduceTo = v;
        else if (a == "--valence") {
            const std::vector<double> bounds = radtools::numberList(a, v, ',');
            if (bounds.size() != 2) throw UsageError("--valence needs MIN,MAX");
            options.collapse.minValence = toInt(a, std::to_string(static_cast<long long>(bounds[0])));
            options.collapse.maxValence = toInt(a, std::to_string(static_cast<long long>(bounds[1])));
        } else throw UsageError("unknown option " + a);
    }
    if (input.empty() || prefix.empty()) throw UsageError("an input and -o PREFIX are required");
    if (ratios.empty()) throw UsageError("--ratios needs at least one ratio");
    for (double r : ratios)
        if (!(r > 0.0 && r < 1.0)) throw UsageError("every ratio must lie in (0, 1)");
    std::sort(ratios.begin(), ratios.end(), std::greater<double>());
    if (metricName == "radiance") options.metric = rad::SimplificationMetric::Radiance;
    else if (metricName == "lightfield2010") options.metric = rad::SimplificationMetric::LightField2010;
    else if (metricName == "color") options.metric = rad::SimplificationMetric::ColorQuadric;
    else if (metricName == "geometry") options.metric = rad::SimplificationMetric::GeometryOnly;
    else if (metricName == "quadric") options.metric = rad::SimplificationMetric::RadianceQuadric;
    else throw UsageError("--metric needs radiance, lightfield2010, color, geometry or quadric, got '" + metricName + "'");
    if (collapseName == "half") options.collapse.kind = rad::CollapseKind::HalfEdge;
    else if (collapseName == "full") options.collapse.kind = rad::CollapseKind::Full;
    else throw UsageError("--collapse needs half or full, got '" + collapseName + "'");

    const auto t0 = std::chrono::steady_clock::now();
    if (!reduceTo.empty()) {
        const auto lower = rad::BasisSpec::parse(reduceTo);
        if (!lower) throw UsageError("--reduce needs a basis such as PB2 or SH3, got '" + reduceTo + "'");
        rad::RadianceMesh mesh = rad::readRadiancePly(input);
        if (!mesh.radiance) throw std::runtime_error(input + " has no radiance functions to reduce");
        mesh.radiance = rad::reduceDirectionalDegree(*mesh.radiance, *lower);
        const std::string path = prefix + "_" + lower->name() + ".rply";
        rad::writeRadiancePly(path, mesh);
        std::printf("directional reduction to %s: %zu vertices -> %s\n", lower->name().c_str(), mesh.vertexCount(),
                    path.c_str());
        return 0;
    }
    rad::ProgressiveRadianceMesh progressive;
    if (radtools::lower(std::filesystem::path(input).extension().string()) == ".rpm") {
        progressive = rad::readProgressiveMesh(input);
        std::printf("%s: progressive mesh of %zu faces, %zu recorded collapses (%s)\n", input.c_str(),
                    progressive.base.faceCount(), progressive.steps.size(),
                    progressive.kind == rad::CollapseKind::Full ? "full" : "half-edge");
    } else {
        rad::RadianceMesh mesh = rad::readRadiancePly(input);
        const double loaded = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const std::size_t faces = mesh.faceCount();
        std::printf("%s: %zu vertices, %zu faces, %s, read in %.2f s\n", input.c_str(), mesh.vertexCount(), faces,
                    mesh.radiance ? mesh.radiance->basis.name().c_str() : "no radiance", loaded);
        options.collapse.targetFaceCount = static_cast<std::size_t>(std::floor(ratios.back() * faces));
        rad::RadianceSimplificationResult result = rad::simplifyRadianceMesh(std::move(mesh), options);
        std::printf("simplified with the %s metric (%s collapse): %zu collapses in %.2f s, %zu faces left (%s), "
                    "last cost %.4g, %zu pricings, %zu stale entries\n",
                    rad::describe(options.metric).c_str(), collapseName.c_str(), result.collapse.collapses,
                    result.seconds, result.collapse.finalFaceCount, rad::describe(result.collapse.stop).c_str(),
                    result.collapse.lastCost, result.collapse.repricedVertices, result.collapse.staleEntries);
        progressive = std::move(result.progressive);
    }
    for (double r : ratios) {
        const std::size_t target = static_cast<std::size_t>(std::floor(r * progressive.base.faceCount()));
        const rad::RadianceMesh level = progressive.extract(progressive.stepsForFaceCount(target));
        const std::string path = levelPath(prefix, r);
        rad::writeRadiancePly(path, level);
        std::printf("  level %5.1f %%: %zu vertices, %zu faces -> %s\n", 100.0 * r, level.vertexCount(),
                    level.faceCount(), path.c_str());
    }
    if (!progressivePath.empty()) {
        std::string base = progressivePath;
        const auto dot = base.find_last_of('.');
        if (dot != std::string::npos && base.find('/', dot) == std::string::npos) base.erase(dot);
        base += "_base.rply";
        rad::writeProgressiveMesh(progressivePath, base, progressive);
        std::printf("  progressive mesh -> %s (base %s)\n", progressivePath.c_str(), base.c_str());
    }
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("total %.2f s, peak memory %.0f MB\n", total, peakMemoryMb());
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("simplify_radiance", argc, argv, run, usage); }
