// A radiance fit that shares what the surface has in common, for sparse captures (a few dozen
// photographs: ~10 samples per vertex, too few for a free per-vertex function). Per vertex a diffuse
// colour d_v plus a scale s_v of ONE lobe G of the world-space reflected direction, shared by the
// whole object: L_v(w) = d_v + s_v h(n_v . w) G(r_v(w)). A distant light's highlight sits at the same
// reflected direction at every vertex, so G, fitted on all vertices' samples, predicts a highlight
// where a vertex has no sample (Wood et al. 2000; Chen et al. 2002; Lensch et al. 2003). Fitted by
// alternating weighted least squares, then written in the user's basis with a per-vertex leave-one-out
// check against the constant. The model, the steps and the memory: docs/fitting.md, "How the shared
// fit works".
#pragma once

#include "fit/robust_radiance_fit.h"
#include "geometry/triangle_mesh.h"
#include "progress/progress_callback.h"
#include "radiance/radiance_field.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace rad {

// The samples of every vertex (compressed rows): vertex v owns samples[offsets[v] .. offsets[v+1]),
// view[i] the view index of sample i.
struct SampleSet {
    std::vector<std::size_t> offsets;
    std::vector<DirectionalSample> samples;
    std::vector<std::uint32_t> view;
    std::size_t vertexCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

// The light distances the fit chooses from (SharedFitOptions::lightDistance = 0), in bounding radii:
// distant lights, then steps of 0.1 in radius / distance.
inline constexpr double kLightDistanceCandidates[] = {std::numeric_limits<double>::infinity(), 10.0, 5.0,
                                                      10.0 / 3.0, 2.5, 2.0};

// The nearest lights the model takes: the shifted direction r + (x_v - c) / D stays at least 1/3 long
// (a light nearer than that nearly touches the object, where one lobe cannot describe it anyway).
inline constexpr double kMinLightDistance = 1.5;

struct SharedFitOptions {
    int lobeDegree = 8;              // SH degree of G, 1..kMaxHarmonicDegree
    double specularPrior = 3.0;      // >= 0: weight of the neighbours' scale, in the vertex's sample mass
    int iterations = 6;              // alternations, 1..50
    int refitIterations = 4;         // alternations of a fit started from an earlier model, 1..50
    // Alternations of the automatic choice's shared candidate, 1..50 (radiance_from_views.h): its
    // model only decides between the fits and warm-starts the final one (robustIterations capped to it).
    int choiceIterations = 4;
    int robustIterations = 4;        // of them, the last ones use Huber weights (0: none)
    double huberThreshold = 3.0;     // > 0, in robust standard deviations
    double lobeRidge = 0.01;         // >= 0: Tikhonov weight of G (times 1 + l(l+1), relative to trace / M)
    std::size_t lobeSampleBudget = 50000;  // >= 1000: samples the G step uses at most (about)
    int octahedralResolution = 128;  // 16..1024: table of G for the per-vertex steps
    // The lobe term is s_v * (n_v . w)_+ * G(r_v(w)) (the irradiance cosine at the mirror
    // configuration, where n.l = n.r = n.w): without it, a lobe fitted on frontal views predicts the
    // same highlight at grazing views, where the light arrives at a grazing angle too.
    bool cosineFactor = true;
    // With cosineFactor: the factor is a curve h(n.w) (piecewise linear, 5 knots, h(1) = 1, >= 0)
    // fitted in the alternation, starting from the cosine and pulled weakly toward it (a metal's
    // Fresnel brightening at grazing angles offsets the cosine; a plastic's does not).
    bool fitFactorCurve = true;
    // The per-vertex guard: a vertex keeps d + s * lobe unless its own samples, each left out in
    // turn, are predicted better by its constant mean colour by more than this many standard errors
    // of the per-sample difference. The lobe is validated for the whole capture (the automatic
    // choice's left-out rasters); ten samples of one vertex rarely show where it predicts a
    // highlight nobody photographed there, so a vertex's own evidence overrides it only when clear
    // (docs/design-notes.md, "The per-vertex guard of the shared fit"). 0: whenever the constant is
    // better at all (the rule until 2026-11-29). >= 0.
    double guardStandardErrors = 3.0;
    // Lights at a finite distance (SharedModel::lobeShift), in bounding radii of the mesh (the largest
    // distance of a vertex from the centre of its bounding box): 0 chooses it (the default: the
    // candidates kLightDistanceCandidates, by the fit's weighted residual; infinity among them),
    // infinity keeps the plain reflected direction (distant lights), a finite value >= kMinLightDistance
    // fixes it.
    // Only with vertex positions (fitSharedModel's `positions`); without them, distant lights.
    double lightDistance = 0.0;
    std::string validate() const;
};

// The fitted model (linear RGB, after any exposure compensation the caller applied to the samples).
struct SharedModel {
    int lobeDegree = 0;
    bool cosineFactor = false;       // the lobe term carries factor(n.w) (SharedFitOptions::cosineFactor)
    static constexpr int kCurveKnots = 5;
    std::vector<double> curve;       // kCurveKnots values of h at n.w = k / (kCurveKnots - 1); empty: the cosine
    // 1 without the cosine factor; h(clamp(n.w, 0, 1)) with it.
    double factor(double nw) const;
    std::vector<double> lobe;        // 3 x (lobeDegree+1)^2, channel-major: SH coefficients of G (world frame)
    std::vector<float> diffuse;      // 3 per vertex
    std::vector<float> specular;     // 3 per vertex: s_v
    std::vector<float> robustWeight; // per sample of the SampleSet (1 when not down-weighted or not used)
    double lobeEnergy[3] = {0, 0, 0};  // q_c: mean of G_c^2 over the G step's samples
    // Lights at a finite distance D from the centre c of the bounding box: 3 per vertex, (x_v - c) / D
    // (empty: distant lights). The lobe is read at normalize(r + shift_v) instead of the reflected
    // direction r: a light at c + D l puts a vertex's highlight where r points from x_v to the light,
    // r = normalize(D l - (x_v - c)), so r + shift_v is parallel to l at every vertex to first order
    // in |x_v - c| / D, and one lobe holds the highlight of the whole object. With distant lights,
    // vertices far apart see a near light's highlight at reflected directions up to
    // 2 atan(radius / D) apart, and one lobe of r blurs it over that spread.
    std::vector<float> lobeShift;
    double lightDistance = std::numeric_limits<double>::infinity();  // D in bounding radii (log)
    // r + shift_v (the octahedral table reads any non-zero vector's direction).
    void addLobeShift(std::size_t v, double* r) const {
        if (lobeShift.empty()) return;
        const float* t = lobeShift.data() + 3 * v;
        for (int k = 0; k < 3; ++k) r[k] += t[k];
    }
    // normalize(r + shift_v) (for the SH evaluation, which needs a unit vector).
    void shiftLobeDirection(std::size_t v, double* r) const {
        if (lobeShift.empty()) return;
        addLobeShift(v, r);
        const double len2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        const double inverse = len2 > 0.0 ? 1.0 / std::sqrt(len2) : 0.0;
        for (int k = 0; k < 3; ++k) r[k] *= inverse;
    }
    // Value of the model for vertex v (unit normal n) toward unit direction w (exact SH evaluation).
    void evaluate(std::size_t v, const float* n, const double* w, double* rgb) const;
};

// use: per sample of `set`, 1 when the sample may be used (nullptr: all) - the caller's held-out split.
// normals: unit per-vertex normals (3 per vertex; the frames' normals). adjacency: as
// buildVertexAdjacency of radiance_from_views.h (empty offsets: no neighbour prior, s pulled to 1).
// warmStart (optional): a model fitted earlier from these samples or a subset of them (the same set,
// e.g. the automatic choice's fit without its left-out views); the fit starts from its lobe, curve,
// scales and robust weights at the per-vertex step and makes refitIterations alternations.
// Throws std::invalid_argument on invalid options or sizes, OperationCancelled when progress asks.
// positions (optional, 3 per vertex): for the distance of the lights (SharedFitOptions::lightDistance);
// nullptr: distant lights. A warm start keeps its model's light distance.
SharedModel fitSharedModel(const std::vector<float>& normals, const std::vector<std::size_t>& adjacencyOffsets,
                           const std::vector<std::uint32_t>& adjacency, const SampleSet& set,
                           const std::uint8_t* use, const SharedFitOptions& options,
                           const ProgressCallback& progress = {}, const SharedModel* warmStart = nullptr,
                           const std::vector<float>* positions = nullptr);

struct SharedConversionStats {
    std::size_t shared = 0;      // vertices given d + s * lobe
    std::size_t constant = 0;    // constant mean colour: leave-one-out preferred it
    std::size_t tooFew = 0;      // constant: fewer than minSamples samples
    std::size_t downweighted = 0;  // samples with a robust weight below 1
};

// Writes every vertex with at least one usable sample into `field` (frames must already be stored in
// it: frameFromNormal of the vertex normal, as radiance_from_views.cpp does), `meanColor`, `residual`,
// `status` (Fitted / PoorlySampled by fit.poorSamplingFactor, as the per-vertex fit). fit: basis,
// storeReflected, minSamples, poorSamplingFactor are used. Vertices without usable sample: untouched.
// keptShared (optional): resized to the vertex count, 1 where the vertex got d + s * lobe, 0 elsewhere
// (the caller may give those vertices another fit, e.g. the per-vertex one).
SharedConversionStats writeSharedRadiance(const SharedModel& model, const SampleSet& set, const std::uint8_t* use,
                                          const std::vector<std::size_t>& adjacencyOffsets,
                                          const std::vector<std::uint32_t>& adjacency, const RobustFitOptions& fit,
                                          const SharedFitOptions& options, RadianceField& field,
                                          std::vector<float>& meanColor, std::vector<float>& residual,
                                          std::vector<std::uint8_t>& status, const ProgressCallback& progress = {},
                                          std::vector<std::uint8_t>* keptShared = nullptr);

}  // namespace rad
