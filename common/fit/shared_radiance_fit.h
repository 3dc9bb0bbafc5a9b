// A radiance fit that shares what the surface has in common, for sparse captures (a few dozen
// photographs: ~10 samples per vertex, far too few for a free per-vertex function of 15..49
// coefficients, which validation then regularises down to the vertex's mean colour).
//
// Model (per vertex v, colour channel c, unit direction w toward the camera, n_v the vertex normal):
//     L_vc(w) = d_vc + s_vc * h(n_v . w) * G_c(r_v(w)),     r_v(w) = 2 (n_v . w) n_v - w
// (the factor h, one curve for the whole object, starts as the cosine: at the mirror configuration
// the light's incidence cosine n.l equals n.w, so a lobe learnt on frontal views does not predict the
// same highlight at grazing ones; without it, SharedFitOptions::cosineFactor = false, grazing held-out
// views of glossy captures were predicted 2-3 levels too bright, worse than the constant. The curve
// is then fitted (fitFactorCurve), since a metal's Fresnel brightening offsets part of the cosine.)
// d_v: a per-vertex diffuse colour (everything that does not depend on the view: albedo, shading,
// shadows, interreflections); G: ONE function of the world-space reflected direction for the whole
// object (3 channels, real spherical harmonics of degree lobeDegree); s_v: a per-vertex, per-channel
// scale of G (gloss, highlight colour of a metal, a highlight's shadowing), pulled toward the mean
// of its mesh neighbours' scales (ridge prior, weight specularPrior). Why the reflected direction:
// a distant light's mirror highlight sits at the same reflected direction at every vertex, so G,
// fitted on all vertices' samples, predicts the highlight at a vertex from a view nobody
// photographed it from. This is the "reflected" parametrisation of surface light fields: the
// reflected reparametrisation of Wood et al. 2000 ("Surface Light Fields for 3D Photography"), the
// reflected RF of Vanhoey et al. 2015 (sec. 3.1), and, as a rank-1-per-channel factorisation of the
// (vertex x direction) radiance matrix into a surface map s and a view map G, a special case of the
// factorisations of Chen et al. 2002 ("Light Field Mapping"). The diffuse + lobe split is the
// classical one of Lensch et al. 2003 (who share BRDFs over material clusters; here the sharing is
// global and the per-vertex scale plays the role of the cluster's weight).
//
// Fit (fitSharedModel): alternating weighted least squares on all samples of all vertices, as the
// factorisations above are fitted:
//   0. d_v := weighted mean colour of v, s_v := 1, G := 0.
//   1. G step: with d, s fixed, G_c minimises sum a_j rho_j (y_jc - d_vc - s_vc G_c(r_j))^2 + a
//      small Tikhonov term growing with the SH band (l(l+1), relative to trace / M): directions no
//      vertex reflects a camera into get G = 0 (the diffuse colour), not an extrapolation. Only the
//      samples of every k-th vertex enter (at most lobeSampleBudget samples): a function of M <= 121
//      coefficients needs far fewer than the millions of samples of a scan.
//   2. per-vertex step: with G fixed, (d_vc, s_vc) minimises the vertex's weighted squared error +
//      lambda_v (s_vc - sbar_vc)^2, sbar_v the mean of its neighbours' s of the previous iteration
//      (Jacobi: independent of the vertex order), lambda_v = specularPrior * (sum_j a_j) * q_c, q_c the
//      mean of G_c^2 over the samples (the prior weighs like specularPrior times the vertex's samples).
//   2b. factor step (cosineFactor and fitFactorCurve): with d, s, G fixed, the 5 knot values of h by
//      least squares over the G step's samples (+ 1e-3 of the trace toward the cosine), clamped >= 0,
//      scaled so that h(1) = 1 (G takes the scale).
//   3. robust weights rho (from iteration 2 on): Huber, min(1, huberThreshold * sigma / |e_j|), e_j the
//      RGB residual, sigma = 1.4826 median |e| over the G step's samples.
// Steps 1-3 are repeated `iterations` times.
//
// Conversion to the user's basis (writeSharedRadiance): per vertex, the lobe G_c(r_v(w)) is
// projected onto the basis over the vertex's hemisphere by least squares on a fixed set of local
// directions (a Fibonacci spiral and a border ring; what the basis cannot represent is smoothed),
// giving coefficients c_vc; evaluated at the vertex's samples they give g~_j. Then (d_vc, s_vc) are
// fitted again by step 2 with g~ in place of G (so that the stored function, not the model, is what
// is fitted), and the stored RF is d_v + s_v * c_v in the basis, plain or reflected, PB in the local
// frame, SH rotated to the global frame (as robust_radiance_fit.h stores them). G is evaluated
// through an octahedral table (octahedralResolution^2 texels, bilinear) during the per-vertex steps.
// Per-vertex guarantee: the vertex keeps this function only when its leave-one-out error on its own
// samples (exact for the 2-parameter ridge regression given g~: e_j / (1 - S_jj)) in sRGB units
// (first-order, as robust_radiance_fit.h) is below the constant mean colour's; otherwise (or with
// fewer than minSamples samples) it gets the constant weighted mean colour.
//
// Memory: every sample of every vertex is kept (SampleSet, 32 bytes a sample: ~10 samples x 437k
// vertices = 140 MB); the per-vertex fit of robust_radiance_fit.h streams them instead.
#pragma once

#include "fit/robust_radiance_fit.h"
#include "geometry/triangle_mesh.h"
#include "progress/progress_callback.h"
#include "radiance/radiance_field.h"

#include <cstddef>
#include <cstdint>
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

struct SharedFitOptions {
    int lobeDegree = 8;              // SH degree of G, 1..kMaxHarmonicDegree
    double specularPrior = 3.0;      // >= 0: weight of the neighbours' scale, in the vertex's sample mass
    int iterations = 6;              // alternations, 1..50
    int robustIterations = 4;        // of them, the last ones use Huber weights (0: none)
    double huberThreshold = 3.0;     // > 0, in robust standard deviations
    double lobeRidge = 0.03;         // >= 0: Tikhonov weight of G (times 1 + l(l+1), relative to trace / M)
    std::size_t lobeSampleBudget = 100000;  // >= 1000: samples the G step uses at most
    int octahedralResolution = 128;  // 16..1024: table of G for the per-vertex steps
    // The lobe term is s_v * (n_v . w)_+ * G(r_v(w)) (the irradiance cosine at the mirror
    // configuration, where n.l = n.r = n.w): without it, a lobe fitted on frontal views predicts the
    // same highlight at grazing views, where the light arrives at a grazing angle too.
    bool cosineFactor = true;
    // With cosineFactor: the factor is a curve h(n.w) (piecewise linear, 5 knots, h(1) = 1, >= 0)
    // fitted in the alternation, starting from the cosine and pulled weakly toward it (a metal's
    // Fresnel brightening at grazing angles offsets the cosine; a plastic's does not).
    bool fitFactorCurve = true;
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
    // Value of the model for vertex v (unit normal n) toward unit direction w (exact SH evaluation).
    void evaluate(std::size_t v, const float* n, const double* w, double* rgb) const;
};

// use: per sample of `set`, 1 when the sample may be used (nullptr: all) - the caller's held-out split.
// normals: unit per-vertex normals (3 per vertex; the frames' normals). adjacency: as
// buildVertexAdjacency of radiance_from_views.h (empty offsets: no neighbour prior, s pulled to 1).
// Throws std::invalid_argument on invalid options or sizes, OperationCancelled when progress asks.
SharedModel fitSharedModel(const std::vector<float>& normals, const std::vector<std::size_t>& adjacencyOffsets,
                           const std::vector<std::uint32_t>& adjacency, const SampleSet& set,
                           const std::uint8_t* use, const SharedFitOptions& options,
                           const ProgressCallback& progress = {});

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
