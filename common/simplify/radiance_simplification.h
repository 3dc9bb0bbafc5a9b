// One call from a radiance mesh to a progressive (level-of-detail) simplification of it: input
// checks, the metric of choice plugged into the edge-collapse engine (edge_collapse.h), the collapse
// sequence recorded (progressive_mesh.h). The MeshLab filter, the tools and the benchmarks all go
// through here. Metrics: the accumulating radiance quadric (default, radiance_quadric.h), the
// radiance error of Vanhoey et al. 2015 eq. 7 (radiance_collapse_error.h), the light-field metric of
// Vanhoey et al. 2010 (light_field_quadric.h), the colour QEM of Garland & Heckbert 1998
// (color_quadric.h), or geometry alone. Refusals throw SimplificationError (an InputError).
// Details: docs/simplification.md, "`common/simplify/radiance_simplification.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include "io/radiance_mesh.h"
#include "simplify/edge_collapse.h"
#include "simplify/progressive_mesh.h"

#include <stdexcept>
#include <string>

namespace rad {

enum class SimplificationMetric { Radiance, LightField2010, ColorQuadric, GeometryOnly, RadianceQuadric };

// The radiance quadric's radiance term weighs attributeWeight x kRadianceQuadricBalance against its
// plane terms' geometryWeight: at the default weights (0.01 / 0.99) 0.99 x 1.5e-6 / 0.01 ~ 0.015 % in
// normalised units, the balance the image-error benchmark measured best over analytic fields and
// fields fitted from path-traced photographs (docs/design-notes.md, "Re-choosing the balance").
inline constexpr double kRadianceQuadricBalance = 1.5e-6;
inline constexpr double kRadianceQuadricPerceptualExponent = 0.5;
std::string describe(SimplificationMetric metric);

struct SimplificationError : InputError {
    using InputError::InputError;
};

struct RadianceSimplificationOptions {
    RadianceSimplificationOptions() { collapse.kind = CollapseKind::Full; }  // the radiance quadric's best
    SimplificationMetric metric = SimplificationMetric::RadianceQuadric;
    // Radiance quadric: how much errors in dark regions weigh more (radiance_quadric.h).
    double perceptualExponent = kRadianceQuadricPerceptualExponent;
    // Engine options: kind, targetFaceCount, maxError, weights, boundary, valence, progress...
    EdgeCollapseOptions collapse;
    // Memory the simplification may take; 0: what the machine has available now
    // (memory/available_memory.h). A mesh whose estimate exceeds it is refused before any work.
    std::size_t memoryLimitBytes = 0;
};

// About how much memory simplifyRadianceMesh takes at its peak beside its input, in bytes: the
// metric's per-vertex state (for the radiance quadric, 20 bytes per attribute of the world-SH space
// and about 230 more), the working copy of the field, the progressive records, the collapse mesh and
// the priced edges. Within about 10 % of the measured peak on the 1.66M-vertex armadillo
// (docs/simplification.md).
std::size_t estimatedSimplificationBytes(const RadianceMesh& mesh, const RadianceSimplificationOptions& options);

struct RadianceSimplificationResult {
    ProgressiveRadianceMesh progressive;  // base = the input, steps down to the coarsest mesh
    EdgeCollapseResult collapse;
    std::size_t facesRepeatingAVertexRemoved = 0;  // dropped before simplifying (the base lacks them)
    std::size_t duplicateFacesRemoved = 0;         // later copies of a triangle, dropped likewise
    std::size_t zeroAreaFaces = 0;                 // of the base, simplified like the others
    std::size_t boundaryEdges = 0;                 // of the base (0: a closed mesh)
    std::size_t nonManifoldEdges = 0;              // of the base, kept with their vertices (preserved boundary)
    double seconds = 0.0;                 // setup + simplification (not extraction)
};

// Empty when `mesh` can be simplified with `metric`; otherwise a sentence saying what is wrong and
// how to fix it in MeshLab: no faces, invalid arrays, radiance missing (for the metrics that need
// it) or of mismatched size, non-finite values, coordinates beyond float precision, non-manifold edges
// (more than two faces, once the dropped faces are gone) unless the boundary is preserved (then their
// vertices, whose fans are open, never move). Faces repeating a vertex, repeated triangles and faces
// of zero area are accepted (see simplifyRadianceMesh).
std::string checkSimplificationInput(const RadianceMesh& mesh, SimplificationMetric metric,
                                     CollapseKind kind = CollapseKind::HalfEdge, bool preserveBoundary = true);

// Simplifies (the mesh is taken by value: move it in to avoid a copy; it becomes the progressive
// mesh's base, without its faces that repeat a vertex and without the later copies of a triangle
// (same three vertices, either orientation): both counted in the result). Zero-area faces of
// real scans are simplified like the others: the collapse of their short edge costs nothing. Throws SimplificationError when checkSimplificationInput fails, the target is
// not below the face count or the memory estimate exceeds what is available, std::invalid_argument for inconsistent options (e.g. full collapse
// with a PB field and the radiance metric: the message says why).
RadianceSimplificationResult simplifyRadianceMesh(RadianceMesh mesh, const RadianceSimplificationOptions& options);

}  // namespace rad
