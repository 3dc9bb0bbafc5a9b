#include "simplify/radiance_simplification.h"

#include "geometry/coordinate_range.h"
#include "geometry/triangle_mesh.h"
#include "io/radiance_ply.h"
#include "memory/available_memory.h"
#include "parallel/parallel_sort.h"
#include "radiance/material_radiance.h"
#include "radiance/world_sh_conversion.h"
#include "simplify/color_quadric.h"
#include "simplify/light_field_quadric.h"
#include "simplify/radiance_collapse_error.h"
#include "simplify/radiance_quadric.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>

namespace rad {

std::string describe(SimplificationMetric metric) {
    switch (metric) {
        case SimplificationMetric::Radiance: return "radiance (Vanhoey et al. 2015, eq. 7)";
        case SimplificationMetric::LightField2010: return "light field (Vanhoey et al. 2010)";
        case SimplificationMetric::ColorQuadric: return "colour QEM (Garland-Heckbert 1998)";
        case SimplificationMetric::GeometryOnly: return "geometry only (memoryless QEM)";
        case SimplificationMetric::RadianceQuadric: return "radiance quadric (Hoppe 1999)";
    }
    return "unknown";
}

namespace {

bool needsRadiance(SimplificationMetric metric) { return metric != SimplificationMetric::GeometryOnly; }

bool repeatsAVertex(const std::uint32_t* t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

// Removes the faces that repeat a vertex (no area, no edge of their own); returns how many.
// A face's vertices in increasing order: two faces over the same three vertices (either orientation)
// are the same triangle.
std::array<std::uint32_t, 3> sortedCorners(const std::uint32_t* t) {
    std::array<std::uint32_t, 3> s{t[0], t[1], t[2]};
    std::sort(s.begin(), s.end());
    return s;
}

// Marks the faces that repeat a vertex and every copy of a triangle after its first occurrence in
// face order; returns the marks and the two counts.
struct UnusableFaces {
    std::vector<std::uint8_t> drop;
    std::size_t repeatingAVertex = 0;
    std::size_t duplicates = 0;
};

UnusableFaces findUnusableFaces(const RadianceMesh& mesh) {
    const std::size_t nf = mesh.faceCount();
    UnusableFaces u;
    u.drop.assign(nf, 0);
    std::vector<std::pair<std::array<std::uint32_t, 3>, std::uint32_t>> keyed;
    keyed.reserve(nf);
    for (std::size_t f = 0; f < nf; ++f) {
        const std::uint32_t* t = mesh.faces.data() + 3 * f;
        if (repeatsAVertex(t)) {
            u.drop[f] = 1;
            ++u.repeatingAVertex;
        } else {
            keyed.emplace_back(sortedCorners(t), static_cast<std::uint32_t>(f));
        }
    }
    // Equal triangles together, lowest face index first (the pairs are all distinct: a total order).
    sortInParallel(keyed.begin(), keyed.end(), std::less<std::pair<std::array<std::uint32_t, 3>, std::uint32_t>>());
    for (std::size_t i = 1; i < keyed.size(); ++i)
        if (keyed[i].first == keyed[i - 1].first) {
            u.drop[keyed[i].second] = 1;
            ++u.duplicates;
        }
    return u;
}

void removeFaces(RadianceMesh& mesh, const std::vector<std::uint8_t>& drop) {
    std::size_t kept = 0;
    const std::size_t nf = mesh.faceCount();
    for (std::size_t f = 0; f < nf; ++f) {
        if (drop[f]) continue;
        const std::uint32_t* t = mesh.faces.data() + 3 * f;
        if (kept != f) std::copy(t, t + 3, mesh.faces.data() + 3 * kept);
        ++kept;
    }
    mesh.faces.resize(3 * kept);
}

std::size_t countZeroAreaFaces(const RadianceMesh& mesh) {
    std::size_t count = 0;
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
        const std::uint32_t* t = mesh.faces.data() + 3 * f;
        const Eigen::Vector3d a = Eigen::Map<const Eigen::Vector3f>(&mesh.positions[3 * t[0]]).cast<double>();
        const Eigen::Vector3d b = Eigen::Map<const Eigen::Vector3f>(&mesh.positions[3 * t[1]]).cast<double>();
        const Eigen::Vector3d c = Eigen::Map<const Eigen::Vector3f>(&mesh.positions[3 * t[2]]).cast<double>();
        if ((b - a).cross(c - a).squaredNorm() == 0.0) ++count;
    }
    return count;
}

std::string plural(std::size_t n, const char* word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// checkSimplificationInput, also giving the faces simplifyRadianceMesh drops (found once: a sort of
// every face) when the mesh is valid enough to look at them.
std::string inputProblem(const RadianceMesh& mesh, SimplificationMetric metric, CollapseKind kind,
                         bool preserveBoundary, UnusableFaces& unusable, EdgeCensus& census) {
    if (mesh.faceCount() == 0)
        return "the mesh has no faces: edge-collapse simplification needs a triangle mesh (reconstruct a surface "
               "from a point cloud first, e.g. 'Surface Reconstruction: Screened Poisson')";
    if (needsRadiance(metric) && !mesh.radiance)
        return "the mesh carries no radiance data, which the " + describe(metric) +
               " metric needs: fit it with 'Radiance: Fit Radiance Functions from Rasters', create it with 'Radiance: "
               "Create Radiance Data from Analytic Material', open a .rply file, or choose the geometry-only metric";
    if (const std::string problem = validateRadianceMesh(mesh); !problem.empty()) return problem;
    if (std::string range = coordinateRangeProblem(mesh.positions.data(), mesh.vertexCount()); !range.empty())
        return range;
    if (needsRadiance(metric) && kind == CollapseKind::Full && metric == SimplificationMetric::Radiance &&
        mesh.radiance->basis.kind != BasisKind::SphericalHarmonics)
        return "full edge collapse with the radiance metric needs spherical harmonics (Vanhoey et al. 2015 sec. 4.3: the new "
               "vertex's function is interpolated between two frames, which needs a rotation-invariant basis); the mesh "
               "has " + mesh.radiance->basis.name() + ": choose half-edge collapse";

    // Faces repeating a vertex and repeated triangles are dropped by simplifyRadianceMesh, zero-area
    // faces are collapsed like any other (they are the cheapest collapses there are): none of them is
    // a reason to refuse. Non-manifold edges are kept as they are when the boundary is preserved (the
    // vertices of an edge on more than two faces have open fans: they never move); otherwise refused.
    const std::size_t nf = mesh.faceCount();
    unusable = findUnusableFaces(mesh);
    std::vector<std::uint64_t> edges;
    edges.reserve(3 * nf);
    for (std::size_t f = 0; f < nf; ++f) {
        if (unusable.drop[f]) continue;
        const std::uint32_t* t = mesh.faces.data() + 3 * f;
        for (int k = 0; k < 3; ++k) edges.push_back(undirectedEdgeKey(t[k], t[(k + 1) % 3]));
    }
    census = countEdgesByFaces(edges);
    if (census.nonManifold > 0 && !preserveBoundary)
        return "the mesh has " + plural(census.nonManifold, "non-manifold edge") +
               " (shared by more than two faces), which only a preserved boundary keeps where they are: turn 'Preserve "
               "boundary' on, or run 'Cleaning and Repairing: Repair non Manifold Edges' and try again";
    return {};
}

std::string refusalForMemory(const RadianceMesh& mesh, const RadianceSimplificationOptions& options) {
    if (mesh.radiance && !mesh.radiance->validate().empty()) return {};  // refused by the input checks, with the reason
    const std::size_t limit = options.memoryLimitBytes > 0 ? options.memoryLimitBytes : availableMemoryBytes();
    const std::size_t needed = estimatedSimplificationBytes(mesh, options);
    if (limit == 0 || needed <= limit) return {};
    return "simplifying this mesh of " + std::to_string(mesh.vertexCount()) + " vertices needs about " +
           describeBytes(double(needed)) + " of memory and " + describeBytes(double(limit)) +
           " are available: close other programs, run it on a machine with more memory, or reduce the scan "
           "first (e.g. 'Out-of-Core Simplification and Normal Map', which keeps no radiance, then fit the "
           "radiance again on the smaller mesh)";
}

}  // namespace

std::size_t estimatedSimplificationBytes(const RadianceMesh& mesh, const RadianceSimplificationOptions& options) {
    const double nv = double(mesh.vertexCount()), nf = double(mesh.faceCount());
    const RadianceField* field = needsRadiance(options.metric) && mesh.radiance ? &*mesh.radiance : nullptr;
    const double row = field ? double(field->coefficientsPerVertex() + 6) * sizeof(float) : 0.0;
    double perVertex = 0.0;
    perVertex += 24.0 + 4 * 16.0 + 8.0;  // collapse mesh: positions, incident-face lists, flags, versions
    perVertex += 3.0 * (48.0 + 48.0 + 8.0);  // about three edges each: ranked and priced entries, edge list
    perVertex += 32.0 + row;                  // progressive records: a step and the survivor's row
    if (field && (options.collapse.kind == CollapseKind::Full || field->basis.kind == BasisKind::SphericalHarmonics))
        perVertex += row;  // the metric's working copy of the field
    if (field && options.metric == SimplificationMetric::RadianceQuadric)
        perVertex += 20.0 * kColorChannels * worldShCoefficientsPerChannel(field->basis) + 232.0;  // planes, references, blocks, weights
    const double perFace = 13.0;  // the collapse mesh's faces and flags
    return static_cast<std::size_t>(nv * perVertex + nf * perFace);
}

std::string checkSimplificationInput(const RadianceMesh& mesh, SimplificationMetric metric, CollapseKind kind,
                                     bool preserveBoundary) {
    UnusableFaces unusable;
    EdgeCensus census;
    return inputProblem(mesh, metric, kind, preserveBoundary, unusable, census);
}

RadianceSimplificationResult simplifyRadianceMesh(RadianceMesh mesh, const RadianceSimplificationOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (const std::string problem = options.collapse.validate(); !problem.empty()) throw SimplificationError(problem);
    UnusableFaces unusable;
    // Memory first: the input checks below already sort every face and edge.
    if (const std::string problem = refusalForMemory(mesh, options); !problem.empty()) throw SimplificationError(problem);
    EdgeCensus census;
    if (const std::string problem =
            inputProblem(mesh, options.metric, options.collapse.kind, options.collapse.preserveBoundary, unusable, census);
        !problem.empty())
        throw SimplificationError(problem);
    const std::size_t boundaryEdges = census.boundary;
    removeFaces(mesh, unusable.drop);
    if (mesh.faceCount() == 0)
        throw SimplificationError("every face of the mesh repeats a vertex (no area): there is no surface to simplify");
    if (options.collapse.targetFaceCount >= mesh.faceCount())
        throw SimplificationError("the target of " + plural(options.collapse.targetFaceCount, "face") +
                                  " is not below the mesh's " + plural(mesh.faceCount(), "face") +
                                  ": choose a smaller target or ratio");

    RadianceSimplificationResult result;
    result.facesRepeatingAVertexRemoved = unusable.repeatingAVertex;
    result.duplicateFacesRemoved = unusable.duplicates;
    result.zeroAreaFaces = countZeroAreaFaces(mesh);
    result.boundaryEdges = boundaryEdges;
    result.nonManifoldEdges = census.nonManifold;
    // A closed mesh has no boundary to collapse along or to hold with planes: neither is looked for.
    EdgeCollapseOptions collapse = options.collapse;
    if (boundaryEdges == 0) collapse.collapseAlongBoundary = false;
    result.progressive.kind = options.collapse.kind;
    result.progressive.base = std::move(mesh);
    const RadianceMesh& base = result.progressive.base;
    CollapseMesh collapseMesh(base.positions.data(), base.vertexCount(), base.faces.data(), base.faceCount());

    // The metric's working field: a copy when the metric may rewrite it (full collapses, SH storage
    // conversion); the base field itself otherwise (PB half-edge: read only), which saves a copy of
    // the largest array on million-vertex scans.
    std::optional<RadianceField> workingCopy;
    RadianceField* field = nullptr;
    if (base.radiance && needsRadiance(options.metric)) {
        const bool mayWrite = options.collapse.kind == CollapseKind::Full ||
                              base.radiance->basis.kind == BasisKind::SphericalHarmonics ||
                              options.metric == SimplificationMetric::LightField2010;
        if (mayWrite) {
            workingCopy = *base.radiance;
            field = &*workingCopy;
        } else {
            field = const_cast<RadianceField*>(&*base.radiance);  // read-only use, see above
        }
    }

    std::unique_ptr<CollapseMetric> metric;
    switch (options.metric) {
        case SimplificationMetric::Radiance: metric = std::make_unique<RadianceCollapseMetric>(*field); break;
        case SimplificationMetric::LightField2010: metric = std::make_unique<LightFieldQuadricMetric>(collapseMesh, *field);
            break;
        case SimplificationMetric::ColorQuadric:
        {
            std::vector<float> colors(3 * field->vertexCount());
            meanHemisphereColors(*field, colors.data());  // the RF's diffuse colour
            metric = std::make_unique<ColorQuadricMetric>(collapseMesh, colors);
        }
            break;
        case SimplificationMetric::GeometryOnly: break;
        case SimplificationMetric::RadianceQuadric:
        {
            RadianceQuadricOptions quadric;
            quadric.geometryWeight = options.collapse.geometryWeight;
            quadric.radianceWeight = options.collapse.attributeWeight * kRadianceQuadricBalance;
            quadric.threads = options.collapse.threads;
            quadric.perceptualExponent = options.perceptualExponent;
            quadric.boundaryPlanes = boundaryEdges > 0;
            metric = std::make_unique<RadianceQuadricMetric>(collapseMesh, *field, quadric);
        }
            break;
    }

    // Full collapses record the survivor's RF row after every step; metrics that do not own the RF
    // (geometry, colour) leave it as v1's.
    const RadianceField* recordedField = nullptr;
    if (options.collapse.kind == CollapseKind::Full && base.radiance) recordedField = field ? field : &*base.radiance;
    ProgressiveRecorder recorder(result.progressive, recordedField);
    result.progressive.steps.reserve(base.vertexCount());
    result.progressive.faceCountAfter.reserve(base.vertexCount());
    result.collapse = simplifyByEdgeCollapse(collapseMesh, metric.get(), collapse,
                                             [&](const CollapseStep& step) { recorder(step); });
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace rad
