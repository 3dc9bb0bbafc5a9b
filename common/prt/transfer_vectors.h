// Shadowed diffuse transfer vectors of precomputed radiance transfer (PRT, Sloan et al. 2002 sec. 5):
// per surface point, t_k = (1 / pi) * integral over the sphere of V(x, w) max(0, n.w) Y_k(w) dw, in
// the global-frame real SH of radiance/spherical_harmonics.h, so that a white Lambertian point under
// a distant lighting with SH coefficients l shines L = <t, l> (Křivánek et al. 2004 sec. 3.3; a
// constant unit lighting on an unoccluded point gives 1). Albedo is the caller's. Estimated with a
// fixed low-discrepancy set of cosine-weighted directions in each point's local frame, traced with
// Embree from just above the surface.
// Details: docs/prt-subdivision.md, "`common/prt/transfer_vectors.h`: how it works".
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
