// Shadowed diffuse transfer vectors of precomputed radiance transfer (PRT):
//   P.-P. Sloan, J. Kautz, J. Snyder, "Precomputed radiance transfer for real-time rendering in
//   dynamic, low-frequency lighting environments", SIGGRAPH 2002, sec. 5 ("shadowed diffuse").
// At a surface point x with unit normal n the transfer vector is
//     t_k(x) = (1 / pi) * integral over the sphere of V(x, w) max(0, n.w) Y_k(w) dw,
// k < (degree + 1)^2, Y_k the real spherical harmonics of radiance/spherical_harmonics.h (global
// frame), V(x, w) = 1 when the ray from x toward w escapes the scene. The exit radiance of a white
// Lambertian surface under a distant lighting with SH coefficients l_k is then
//     L(x) = <t(x), l>                          (Křivánek et al. 2004 sec. 3.3, L(x, l) = <t_x | l>)
// so a constant unit lighting on an unoccluded point gives L = 1. Albedo (per channel) multiplies
// t; it is applied by the caller (TransferField::channels == 3 then), not here.
//
// Křivánek et al. 2004 uses "SH of order 6" = 36 coefficients, i.e. degree 5 in our convention (order =
// degree + 1): kDefaultTransferDegree.
//
// Estimator: N cosine-weighted directions (pdf = max(0, n.w) / pi), so
//     t_k(x) ~= (1 / N) * sum_i V(x, w_i) Y_k(w_i).
// The directions are a fixed low-discrepancy set in the vertex's LOCAL frame (Hammersley points
// mapped by Shirley-Chiu's concentric disc map and lifted to the hemisphere: Malley's method), the
// same for every point, so neighbouring points with similar normals see correlated sample patterns
// and the differences of their transfer vectors (what Křivánek et al. 2004's error estimates measure) carry
// little Monte-Carlo noise. The local frame (tangent, bitangent, normal) is built from n alone by
// Duff et al., "Building an orthonormal basis, revisited", JCGT 6(1) 2017, listing 3: orthonormal
// and right-handed for every unit n (no singularity at n = -z, unlike Frisvad's original), smooth
// on each hemisphere n.z > 0 and n.z < 0 but discontinuous across the plane n.z = 0 (the
// copysign): two neighbours whose normals straddle it get unrelated sample patterns. Some
// discontinuity is unavoidable (no continuous tangent field on the sphere); this is where it is.
// The direction set: the N cell-centred Hammersley points ((i + 1/2) / N, radicalInverse2(i) +
// 1/(2N)), which keeps every sample off the square's border, so no direction lies exactly on the
// horizon.
// Speed: Y_k of the local directions is tabulated once; per point the visible rows are summed in
// the local frame and the sum is rotated to the global frame once with radiance/sh_rotation.h, so
// the cost per point is the rays (Embree, 16-wide packets) plus O(N K + degree^3).
//
// Rays: origin x + offset * n, tNear = offset (offset = TransferOptions::relativeRayOffset times
// the scene's bounding-box diagonal): no self-hit on the point's own triangles. Directions below
// the geometric horizon of a curved surface may hit the point's own neighbourhood: that is
// self-shadowing, and correct.
#pragma once

#include "progress/progress_callback.h"
#include "raycast/ray_scene.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

namespace rad {

constexpr int kDefaultTransferDegree = 5;        // 36 coefficients, Křivánek et al. 2004's "order 6"
constexpr int kDefaultTransferRayCount = 256;
constexpr int kMaxTransferRayCount = 65536;         // beyond it the estimate no longer improves visibly
constexpr double kMaxRelativeRayOffset = 0.1;      // a larger offset skips whole features

struct TransferOptions {
    int degree = kDefaultTransferDegree;         // 0 .. kMaxHarmonicDegree
    int rayCount = kDefaultTransferRayCount;     // directions per point, >= 1
    double relativeRayOffset = 1e-4;             // times the scene diagonal, > 0
    int threads = 0;                             // 0: all cores (OpenMP), >= 0
    // progress/progress_callback.h (a stop request: computeTransferVectors throws
    // OperationCancelled). May be empty. threads and progress are the defaults of
    // computeTransferVectors (its own arguments win when given: threads > 0, a non-empty progress).
    ProgressCallback progress;
};

// Per-vertex transfer vectors, flat: values[(v * channels + c) * coefficientCount() + k].
// channels is 1 (white albedo: the transfer of the geometry alone) or 3 (times an RGB albedo).
struct TransferField {
    int degree = kDefaultTransferDegree;
    int channels = 1;
    std::vector<float> values;

    int coefficientCount() const { return (degree + 1) * (degree + 1); }
    int width() const { return channels * coefficientCount(); }  // floats per vertex
    std::size_t vertexCount() const { return width() > 0 ? values.size() / width() : 0; }
    const float* vertex(std::size_t v) const { return values.data() + v * width(); }
    float* vertex(std::size_t v) { return values.data() + v * width(); }
};

// The local frame of a point, columns of the local -> world rotation R = [tangent bitangent normal].
struct TransferFrame {
    float tangent[3], bitangent[3], normal[3];
};

// Normalises `normal` and completes it to a right-handed orthonormal frame (Duff et al. 2017).
// Returns false (frame untouched) when the normal is zero or not finite.
bool makeTransferFrame(const float normal[3], TransferFrame& frame);

// The fixed local direction set and its SH table; immutable, shared by threads.
class TransferEstimator {
public:
    // scene: the occluders (the mesh itself, or all visible layers); it is referenced, not copied,
    // and must outlive the estimator. sceneDiagonal > 0 sets the ray offset.
    // Throws std::invalid_argument on bad options.
    TransferEstimator(const RayScene& scene, float sceneDiagonal, const TransferOptions& options);

    int degree() const;
    int coefficientCount() const;
    int rayCount() const;
    // Ray i of a point x with frame F: origin x + rayOffset() * n, direction
    // d_x t + d_y b + d_z n with (d_x, d_y, d_z) = localDirections()[3i .. 3i+2] (unit, d_z > 0),
    // t in [rayOffset(), +inf). For benchmarks and tests that shoot the same rays.
    const float* localDirections() const;
    float rayOffset() const;
    const TransferOptions& options() const;

    // out[0 .. coefficientCount()) = t(x) for one point (single-threaded, thread-safe).
    // The normal need not be unit (normalised here); a zero or non-finite normal, or a non-finite
    // position, gives all zeros (and casts no ray).
    void computeAt(const float position[3], const float normal[3], float* out) const;

    // Rays shot so far by this estimator (all threads), for the rays-per-second figures.
    std::uint64_t raysCast() const;

private:
    // Shares the per-point worker without its per-call atomic update (rays are counted per chunk).
    friend void computeTransferVectors(const TransferEstimator&, const float*, const float*, std::size_t,
                                       std::vector<float>&, const ProgressCallback&, int);
    struct Impl;
    std::shared_ptr<const Impl> impl_;
};

// Transfer vectors of `count` points (positions and normals: 3 floats each), both cores busy
// (OpenMP, dynamic schedule), out resized to count * coefficientCount(). Progress from the calling
// thread. Throws OperationCancelled on a stop request (out is then incomplete).
// Empty progress / threads == 0: those of the estimator's options. Every point's result is
// independent of the thread count and of the schedule (bitwise identical to computeAt).
void computeTransferVectors(const TransferEstimator& estimator, const float* positions, const float* normals,
                            std::size_t count, std::vector<float>& out,
                            const ProgressCallback& progress = {}, int threads = 0);

// Multiplies a 1-channel field by per-vertex RGB albedos (3 floats per vertex, linear) into a
// 3-channel field. Throws std::invalid_argument on size mismatch or a field that is not 1-channel.
TransferField multiplyByAlbedo(const TransferField& geometryTransfer, const std::vector<float>& rgbAlbedo);

}  // namespace rad
