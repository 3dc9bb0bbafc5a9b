// Shadowed diffuse PRT transfer vectors, Sloan, Kautz, Snyder, SIGGRAPH 2002, sec. 5:
//     t_k(x) = (1 / pi) * integral V(x, w) max(0, n.w) Y_k(w) dw
// estimated with N cosine-weighted directions (pdf max(0, n.w) / pi, so the 1/pi and the cosine
// cancel): t_k ~= (1 / N) sum_i V(x, w_i) Y_k(w_i). See transfer_vectors.h for the choices; this
// file is about doing it fast:
//   - the N local directions d_i and their SH values Y_k(d_i) are tabulated once (the table rows
//     padded to a multiple of 8 floats so the row sums vectorise);
//   - per point, the rays are shot in 16-wide Embree packets (one origin, 16 directions), and the
//     table rows of the visible rays are summed: c_k = (1/N) sum_i V_i Y_k(d_i), the transfer in
//     LOCAL coordinates (a packet whose 16 rays all escape adds its tabulated row sum instead);
//   - one SH rotation by R = [t b n] (local -> world) gives the global vector. Why it is exact (not
//     an approximation of the rotation): ShRotation(R).apply(c) are the coefficients of
//     g(w) = f(R^T w), f = sum_j c_j Y_j; projecting, g_k = sum_j c_j <Y_j(R^T .), Y_k>
//     = (1/N) sum_i V_i sum_j Y_j(d_i) <Y_j, Y_k(R .)> = (1/N) sum_i V_i Y_k(R d_i), because
//     u -> Y_k(R u) lies in band l, where sum_j Y_j(d) <Y_j, h> = h(d). And R d_i = w_i is the
//     world direction of ray i.
// No heap allocation per point (ShRotation keeps its blocks in fixed storage); rays are counted
// per thread and added to the shared atomic counter once per chunk.
#include "prt/transfer_vectors.h"

#include "radiance/basis.h"
#include "radiance/sh_rotation.h"
#include "radiance/spherical_harmonics.h"
#include "sampling/radical_inverse.h"

#include <Eigen/Core>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kPacket = RayPacket16::kSize;
constexpr int kRowAlignment = 8;  // floats: one AVX register, two SSE registers

// Shirley & Chiu, "A low distortion map between disk and square", JGT 2(3) 1997: the square
// [0,1]^2 onto the unit disc, area-preserving up to a constant (so uniform points stay uniform and
// their stratification survives, unlike the polar map r = sqrt(u)).
void concentricDisc(double u1, double u2, double& x, double& y) {
    const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
    if (a == 0.0 && b == 0.0) {
        x = y = 0.0;
        return;
    }
    double r, phi;
    if (std::fabs(a) > std::fabs(b)) {
        r = a;
        phi = (kPi / 4.0) * (b / a);
    } else {
        r = b;
        phi = kPi / 2.0 - (kPi / 4.0) * (a / b);
    }
    x = r * std::cos(phi);
    y = r * std::sin(phi);
}

constexpr int roundUp(int value, int multiple) { return (value + multiple - 1) / multiple * multiple; }

// The messages speak of the SH order n = degree + 1 (n^2 coefficients), as the filters do.
void validate(float sceneDiagonal, const TransferOptions& options) {
    if (options.degree < 0 || options.degree > kMaxHarmonicDegree)
        throw std::invalid_argument("The SH order of the transfer is " + std::to_string(options.degree + 1) +
                                    ": choose an order from 1 to " + std::to_string(kMaxHarmonicDegree + 1) +
                                    " (Křivánek et al. 2004 use 6, i.e. 36 coefficients).");
    if (options.rayCount < 1 || options.rayCount > kMaxTransferRayCount)
        throw std::invalid_argument("The ray count is " + std::to_string(options.rayCount) +
                                    ": choose between 1 and " + std::to_string(kMaxTransferRayCount) +
                                    " rays per vertex (256 or more for smooth shadows).");
    if (!(options.relativeRayOffset > 0.0 && options.relativeRayOffset < kMaxRelativeRayOffset))
        throw std::invalid_argument("The ray offset must be a small positive fraction of the scene diagonal, below " +
                                    std::to_string(kMaxRelativeRayOffset) + " (e.g. 0.0001); it is " +
                                    std::to_string(options.relativeRayOffset) + ".");
    if (!std::isfinite(sceneDiagonal))
        throw std::invalid_argument("The scene's bounding box is too large for single-precision ray casting "
                                    "(its diagonal overflows): scale the mesh down ({{Transform: Scale, "
                                    "Normalize}}) or remove the far-away vertices.");
    if (!(sceneDiagonal > 0.0f))
        throw std::invalid_argument("The scene has no extent (every vertex at the same position): PRT transfer "
                                    "needs a surface; check the layer's vertices.");
    if (options.threads < 0) throw std::invalid_argument("The thread count must be 0 (all cores) or more.");
}

}  // namespace

bool makeTransferFrame(const float normal[3], TransferFrame& frame) {
    // Double: a float normal of length ~1e-20 would underflow its squared length in float.
    const double x = normal[0], y = normal[1], z = normal[2];
    const double length = std::sqrt(x * x + y * y + z * z);
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    const double nx = x / length, ny = y / length, nz = z / length;
    // Duff, Burgess, Christensen, Hery, Kensler, Liani, Villemin, JCGT 6(1) 2017, listing 3.
    const double sign = std::copysign(1.0, nz);
    const double a = -1.0 / (sign + nz);
    const double b = nx * ny * a;
    const double t[3] = {1.0 + sign * nx * nx * a, sign * b, -sign * nx};
    const double bt[3] = {b, sign + ny * ny * a, -ny};
    const double n[3] = {nx, ny, nz};
    for (int i = 0; i < 3; ++i) {
        frame.tangent[i] = static_cast<float>(t[i]);
        frame.bitangent[i] = static_cast<float>(bt[i]);
        frame.normal[i] = static_cast<float>(n[i]);
    }
    return true;
}

struct TransferEstimator::Impl {
    const RayScene* scene = nullptr;
    TransferOptions options;
    int coefficients = 0;   // K = (degree + 1)^2
    int rowStride = 0;      // K rounded up to kRowAlignment
    float rayOffset = 0.0f;
    std::vector<float> directions;               // N x 3, local frame (public accessor)
    std::vector<float> dirX, dirY, dirZ;         // the same, N rounded up to kPacket, zero-padded
    std::vector<float> table;                    // N x rowStride: Y_k(d_i), zero-padded columns
    std::vector<float> packetSums;               // one row per packet: the sum of its rows
    mutable std::atomic<std::uint64_t> rays{0};

    // Local-frame transfer times N into acc[0 .. rowStride): sum of the table rows of the visible
    // rays. Returns whether any ray was visible (acc untouched otherwise). Shoots rayCount rays.
    bool accumulateVisible(const float position[3], const TransferFrame& frame, float* acc) const;
    // The whole per-point computation; returns the number of rays shot (0 for a bad normal).
    int computePoint(const float position[3], const float normal[3], float* out) const;
};

bool TransferEstimator::Impl::accumulateVisible(const float position[3], const TransferFrame& f, float* acc) const {
    const int n = options.rayCount;
    RayPacket16 packet;
    // One origin for all rays of the point: filled once, only the directions change per packet.
    const float ox = position[0] + rayOffset * f.normal[0];
    const float oy = position[1] + rayOffset * f.normal[1];
    const float oz = position[2] + rayOffset * f.normal[2];
    for (int i = 0; i < kPacket; ++i) {
        packet.originX[i] = ox;
        packet.originY[i] = oy;
        packet.originZ[i] = oz;
        packet.tNear[i] = rayOffset;
        packet.tFar[i] = std::numeric_limits<float>::infinity();
    }
    const float tx = f.tangent[0], ty = f.tangent[1], tz = f.tangent[2];
    const float bx = f.bitangent[0], by = f.bitangent[1], bz = f.bitangent[2];
    const float nx = f.normal[0], ny = f.normal[1], nz = f.normal[2];
    bool anyVisible = false;
    const int stride = rowStride;
    for (int first = 0; first < n; first += kPacket) {
        const float* dx = dirX.data() + first;
        const float* dy = dirY.data() + first;
        const float* dz = dirZ.data() + first;
        // Full 16 lanes always (the direction arrays are padded): a fixed trip count vectorises.
        for (int i = 0; i < kPacket; ++i) {
            packet.directionX[i] = tx * dx[i] + bx * dy[i] + nx * dz[i];
            packet.directionY[i] = ty * dx[i] + by * dy[i] + ny * dz[i];
            packet.directionZ[i] = tz * dx[i] + bz * dy[i] + nz * dz[i];
        }
        const int lanes = std::min(kPacket, n - first);
        const std::uint32_t active = lanes == kPacket ? 0xffffu : (1u << lanes) - 1u;
        std::uint32_t visible = active & ~scene->occluded16(packet, active);
        if (visible) anyVisible = true;
        // Sum the visible rows, lowest lane first (a fixed order: deterministic results). Most
        // packets of most points see the sky entirely: their rows' sum is tabulated.
        if (visible == active) {
            const float* row = packetSums.data() + static_cast<std::size_t>(first / kPacket) * stride;
            for (int k = 0; k < stride; ++k) acc[k] += row[k];
            continue;
        }
        while (visible) {
            const int lane = __builtin_ctz(visible);
            visible &= visible - 1u;
            const float* row = table.data() + static_cast<std::size_t>(first + lane) * stride;
            for (int k = 0; k < stride; ++k) acc[k] += row[k];
        }
    }
    return anyVisible;
}

int TransferEstimator::Impl::computePoint(const float position[3], const float normal[3], float* out) const {
    const int K = coefficients;
    TransferFrame frame;
    if (!std::isfinite(position[0]) || !std::isfinite(position[1]) || !std::isfinite(position[2]) ||
        !makeTransferFrame(normal, frame)) {
        std::fill(out, out + K, 0.0f);
        return 0;
    }
    alignas(64) float acc[roundUp((kMaxHarmonicDegree + 1) * (kMaxHarmonicDegree + 1), kRowAlignment)];
    std::fill(acc, acc + rowStride, 0.0f);
    if (!accumulateVisible(position, frame, acc)) {
        // Fully occluded: exactly zero, and no rotation to pay for.
        std::fill(out, out + K, 0.0f);
        return options.rayCount;
    }
    const float scale = 1.0f / static_cast<float>(options.rayCount);
    for (int k = 0; k < K; ++k) acc[k] *= scale;
    Eigen::Matrix3d R;  // local -> world: columns t, b, n
    for (int i = 0; i < 3; ++i) {
        R(i, 0) = frame.tangent[i];
        R(i, 1) = frame.bitangent[i];
        R(i, 2) = frame.normal[i];
    }
    ShRotation(options.degree, R).apply(acc, out);
    return options.rayCount;
}

TransferEstimator::TransferEstimator(const RayScene& scene, float sceneDiagonal, const TransferOptions& options) {
    validate(sceneDiagonal, options);
    auto impl = std::make_shared<Impl>();
    impl->scene = &scene;
    impl->options = options;
    impl->coefficients = (options.degree + 1) * (options.degree + 1);
    impl->rowStride = roundUp(impl->coefficients, kRowAlignment);
    impl->rayOffset = static_cast<float>(options.relativeRayOffset * sceneDiagonal);

    const int n = options.rayCount;
    const int padded = roundUp(n, kPacket);
    impl->directions.resize(3 * static_cast<std::size_t>(n));
    impl->dirX.assign(padded, 0.0f);
    impl->dirY.assign(padded, 0.0f);
    impl->dirZ.assign(padded, 0.0f);
    impl->table.assign(static_cast<std::size_t>(n) * impl->rowStride, 0.0f);
    std::vector<double> y(impl->coefficients);
    for (int i = 0; i < n; ++i) {
        // Cell-centred Hammersley point, both coordinates strictly inside (0, 1) so that no sample
        // maps to the disc's rim (a horizon direction): with 2^(m-1) < N <= 2^m, radicalInverse2(i)
        // for i < N is a multiple of 2^-m, at most 1 - 2^-m, and 1/(2N) < 2^-m.
        const double u1 = (i + 0.5) / n;
        const double u2 = radicalInverse2(static_cast<std::uint32_t>(i)) + 0.5 / n;
        double x, yy;
        concentricDisc(u1, u2, x, yy);
        // Malley's method: uniform on the disc, lifted to the hemisphere, is cosine-distributed.
        const double z = std::sqrt(std::max(0.0, 1.0 - x * x - yy * yy));
        const double length = std::sqrt(x * x + yy * yy + z * z);
        const float d[3] = {static_cast<float>(x / length), static_cast<float>(yy / length),
                            static_cast<float>(z / length)};
        for (int c = 0; c < 3; ++c) impl->directions[3 * i + c] = d[c];
        impl->dirX[i] = d[0];
        impl->dirY[i] = d[1];
        impl->dirZ[i] = d[2];
        // The table of the directions the rays really use (the float ones).
        evaluateSphericalHarmonics(options.degree, double(d[0]), double(d[1]), double(d[2]), y.data());
        for (int k = 0; k < impl->coefficients; ++k)
            impl->table[static_cast<std::size_t>(i) * impl->rowStride + k] = static_cast<float>(y[k]);
    }
    // Packet row sums, accumulated in double then rounded once.
    const int packets = padded / kPacket;
    impl->packetSums.assign(static_cast<std::size_t>(packets) * impl->rowStride, 0.0f);
    std::vector<double> sum(impl->rowStride);
    for (int p = 0; p < packets; ++p) {
        std::fill(sum.begin(), sum.end(), 0.0);
        for (int i = p * kPacket; i < std::min(n, (p + 1) * kPacket); ++i)
            for (int k = 0; k < impl->rowStride; ++k) sum[k] += impl->table[static_cast<std::size_t>(i) * impl->rowStride + k];
        for (int k = 0; k < impl->rowStride; ++k)
            impl->packetSums[static_cast<std::size_t>(p) * impl->rowStride + k] = static_cast<float>(sum[k]);
    }
    impl_ = std::move(impl);
}

int TransferEstimator::degree() const { return impl_->options.degree; }
int TransferEstimator::coefficientCount() const { return impl_->coefficients; }
int TransferEstimator::rayCount() const { return impl_->options.rayCount; }
const float* TransferEstimator::localDirections() const { return impl_->directions.data(); }
float TransferEstimator::rayOffset() const { return impl_->rayOffset; }
const TransferOptions& TransferEstimator::options() const { return impl_->options; }
std::uint64_t TransferEstimator::raysCast() const { return impl_->rays.load(std::memory_order_relaxed); }

void TransferEstimator::computeAt(const float position[3], const float normal[3], float* out) const {
    const int shot = impl_->computePoint(position, normal, out);
    if (shot) impl_->rays.fetch_add(static_cast<std::uint64_t>(shot), std::memory_order_relaxed);
}

void computeTransferVectors(const TransferEstimator& estimator, const float* positions, const float* normals,
                            std::size_t count, std::vector<float>& out, const ProgressCallback& progress,
                            int threads) {
    if (threads < 0) throw std::invalid_argument("computeTransferVectors: threads must be >= 0");
    const int K = estimator.coefficientCount();
    out.resize(count * static_cast<std::size_t>(K));
    const ProgressCallback& report = progress ? progress : estimator.options().progress;
    constexpr const char* kStage = "casting rays for the transfer vectors";
    if (threads == 0) threads = estimator.options().threads;
    if (threads == 0) threads = omp_get_max_threads();
    reportProgress(report, 0.0, kStage);
    if (count == 0) {
        reportProgress(report, 1.0, kStage);
        return;
    }

    // Chunks of points handed out dynamically: the cost per point varies a lot (rays that escape
    // at once vs rays that traverse the whole mesh), and a chunk amortises the scheduling and the
    // progress bookkeeping. Small enough that a cancel is seen within a few milliseconds.
    const std::size_t chunk = 32;
    // One chunk (the adaptive subdivision's calls of a few new vertices): the calling thread alone,
    // so that the call never waits at the team's barrier for a second thread that has nothing to do
    // (on a busy machine that wait costs a scheduler time slice per call).
    if (count <= chunk) threads = 1;
    const auto chunkCount = static_cast<std::ptrdiff_t>((count + chunk - 1) / chunk);
    // Counts points, a chunk at a time; at most 1000 progress calls (a stop request is seen within
    // 0.1 % of the work). Captures what a chunk or the callback throws for finish() to rethrow.
    LoopProgress loop(report, kStage, count, 1000);
    const TransferEstimator::Impl& impl = *estimator.impl_;

#pragma omp parallel num_threads(threads)
    {
        const bool callingThread = omp_get_thread_num() == 0;
#pragma omp for schedule(dynamic, 1) nowait
        for (std::ptrdiff_t c = 0; c < chunkCount; ++c) {
            const std::size_t begin = static_cast<std::size_t>(c) * chunk, end = std::min(count, begin + chunk);
            loop.runItem(
                callingThread,
                [&] {
                    std::uint64_t rays = 0;  // this thread's rays of this chunk: one atomic add per chunk
                    for (std::size_t p = begin; p < end; ++p)
                        rays += static_cast<std::uint64_t>(
                            impl.computePoint(positions + 3 * p, normals + 3 * p, out.data() + p * K));
                    impl.rays.fetch_add(rays, std::memory_order_relaxed);
                },
                end - begin);
        }
    }
    // The first exception rethrown, else OperationCancelled after a stop, else 1.0 reported if the
    // calling thread has not (it may have finished its last chunk before the others).
    loop.finish();
}

TransferField multiplyByAlbedo(const TransferField& geometryTransfer, const std::vector<float>& rgbAlbedo) {
    if (geometryTransfer.channels != 1)
        throw std::invalid_argument("multiplyByAlbedo: the transfer field has " +
                                    std::to_string(geometryTransfer.channels) + " channels, expected 1");
    const int K = geometryTransfer.coefficientCount();
    if (K <= 0 || geometryTransfer.values.size() % K != 0)
        throw std::invalid_argument("multiplyByAlbedo: the transfer values are not whole vectors of " +
                                    std::to_string(K) + " coefficients");
    const std::size_t vertices = geometryTransfer.values.size() / K;
    if (rgbAlbedo.size() != 3 * vertices)
        throw std::invalid_argument("multiplyByAlbedo: " + std::to_string(rgbAlbedo.size()) + " albedo values for " +
                                    std::to_string(vertices) + " vertices (3 per vertex expected)");
    TransferField out;
    out.degree = geometryTransfer.degree;
    out.channels = 3;
    out.values.resize(3 * geometryTransfer.values.size());
    for (std::size_t v = 0; v < vertices; ++v)
        for (int c = 0; c < 3; ++c) {
            const float a = rgbAlbedo[3 * v + c];
            const float* src = geometryTransfer.vertex(v);
            float* dst = out.values.data() + (v * 3 + c) * K;
            for (int k = 0; k < K; ++k) dst[k] = a * src[k];
        }
    return out;
}

}  // namespace rad
