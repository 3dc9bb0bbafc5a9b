// Radiance data made from an analytic material: at every vertex the outgoing radiance of the
// material under the given lights (analytic_material.h) is projected onto the chosen basis
// (radiance_projection.h). It makes samples, tests and benchmarks possible without photographs;
// Vanhoey et al. 2015 (sec. 7) fitted its synthetic scenes (Fig. 6, Fig. 8) from such materials too.
#pragma once

#include "progress/progress_callback.h"
#include "radiance/analytic_material.h"
#include "radiance/radiance_field.h"

#include <cstddef>
#include <functional>
#include <string>

namespace rad {

struct MaterialRadianceOptions {
    BasisSpec basis;
    bool reflected = false;  // store L~ (Vanhoey et al. 2015 sec. 3.1) instead of L
};

// positions / normals: 3 floats per vertex; normals need not be unit but must be non-zero and finite
// (checkMaterialRadianceInput says so). Parallel over vertices (OpenMP). OperationCancelled when
// `progress` asks to stop.
RadianceField makeMaterialRadiance(const float* positions, const float* normals, std::size_t vertexCount,
                                   const AnalyticMaterial& material, const AnalyticLighting& lighting,
                                   const MaterialRadianceOptions& options, const ProgressCallback& progress = {});

// Empty when makeMaterialRadiance can run; otherwise a sentence saying what is wrong with the input.
std::string checkMaterialRadianceInput(const float* positions, const float* normals, std::size_t vertexCount,
                                       const MaterialRadianceOptions& options);

// Average of L over the hemisphere of every vertex, (1/2pi) integral of L dw: the RF's "diffuse"
// colour that colour-based tools (vertex colour, extended QEM) see. rgbOut: 3 floats per vertex.
// Exact: linear in the coefficients, with the basis's hemisphere means (PB: one quadrature; SH:
// Funk-Hecke). Parallel (OpenMP).
void meanHemisphereColors(const RadianceField& field, float* rgbOut);

}  // namespace rad
