// Normal (and colour) map baking from a full-resolution source onto a simplified target
// (normal_baker.h).
//
// Granier et al. 2007, sec. "simplification": the normals of the full scan are stored in a
// texture of the simplified mesh. The ray set-up is the usual cage-less baker's (as in xNormal or
// Blender): from the target point along +/- its interpolated normal, nearer hit first. The tangent
// frame is MikkTSpace's (Mikkelsen 2008; geometry/mikktspace_tangents.h), or on request the
// per-face one of Lengyel 2001: dP/du from the face's UV derivatives, Gram-Schmidt against the
// interpolated normal.
//
// The texture is walked in 4 x 4 texel tiles (OpenMP, dynamic schedule over rows of tiles); a
// tile's rays are cast as Embree packets of 16 (RayScene::intersect16), coherent because the
// texels of a tile are neighbours on one chart. Most texels need one ray, not two: see the tile
// loop ("The nearer hit along +n or -n").
#include "bake/normal_baker.h"

#include "bake/texel_coverage.h"
#include "bake/texture_atlas.h"
#include "geometry/mesh_normals.h"
#include "geometry/mikktspace_tangents.h"
#include "raycast/ray_scene.h"

#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <string>

namespace rad {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr int kTile = 4;

Eigen::Vector3f vertexOf(const std::vector<float>& array, std::uint32_t v) {
    return Eigen::Vector3f(array[3 * std::size_t(v)], array[3 * std::size_t(v) + 1], array[3 * std::size_t(v) + 2]);
}

// The largest distance from the target's vertices and face centroids to the source.
float automaticRayDistanceWith(const TriangleMesh& target, const TriangleMesh& source, const RayScene& scene) {
    const std::size_t vertices = target.vertexCount(), faces = target.faceCount();
    const long long queries = (long long)(vertices + faces);
    float largest = 0.0f;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : largest)
    for (long long i = 0; i < queries; ++i) {
        Eigen::Vector3f q;
        if (std::size_t(i) < vertices) {
            q = vertexOf(target.positions, std::uint32_t(i));
        } else {
            const std::uint32_t* f = target.faces.data() + 3 * (std::size_t(i) - vertices);
            q = (vertexOf(target.positions, f[0]) + vertexOf(target.positions, f[1]) +
                 vertexOf(target.positions, f[2])) / 3.0f;
        }
        const ClosestPoint c = scene.closestPoint(q);
        if (c.found) largest = std::max(largest, c.distance);
    }
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
    for (std::size_t v = 0; v < source.vertexCount(); ++v) {
        const Eigen::Vector3f p = vertexOf(source.positions, std::uint32_t(v));
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const float diagonal = source.vertexCount() > 0 ? (hi - lo).norm() : 0.0f;
    return std::max(2.0f * largest, 0.005f * diagonal);
}

void checkMesh(const TriangleMesh& mesh, const char* which) {
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw BakeInputError(std::string("the ") + which + " mesh is invalid: " + problem);
    if (mesh.faceCount() == 0) throw BakeInputError(std::string("the ") + which + " mesh has no faces");
}

// A unit vector orthogonal to unit n (for a tangent whose dP/du is parallel to n).
Eigen::Vector3f anyOrthogonal(const Eigen::Vector3f& n) {
    const Eigen::Vector3f helper = std::fabs(n.x()) < 0.9f ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY();
    return n.cross(helper).normalized();
}

// What a tile carries between the set-up of its texels and their rays.
struct TileTexels {
    int count = 0;
    std::size_t texel[16];
    std::uint32_t face[16];
    Eigen::Vector3f point[16], normal[16];
    float normalLength[16];   // of the interpolated vertex normal before normalisation
    float barycentric[16][3];
};

}  // namespace

float automaticRayDistance(const TriangleMesh& target, const TriangleMesh& source) {
    checkMesh(target, "target");
    checkMesh(source, "source");
    const RayScene scene(source.positions.data(), source.vertexCount(), source.faces.data(), source.faceCount());
    return automaticRayDistanceWith(target, source, scene);
}

NormalBakeResult bakeNormalMap(const TriangleMesh& target, const float* targetWedgeUv, const TriangleMesh& source,
                               const float* sourceColors, const NormalBakeOptions& options) {
    const Clock::time_point start = Clock::now();
    checkMesh(target, "target");
    checkMesh(source, "source");
    if (!target.hasNormals())
        throw BakeInputError("the target mesh has no vertex normals: compute them first (Normals, Curvatures and "
                             "Orientation > Compute normals for point sets / Re-Compute Vertex Normals)");
    for (std::size_t v = 0; v < target.vertexCount(); ++v) {
        if (!(vertexOf(target.normals, std::uint32_t(v)).squaredNorm() > 1e-12f))
            throw BakeInputError("the target mesh's vertex normal " + std::to_string(v) +
                                 " is zero: recompute the vertex normals");
    }
    if (!targetWedgeUv) throw BakeInputError("the target mesh has no texture coordinates");
    if (options.width <= 0 || options.height <= 0 || options.width > 16384 || options.height > 16384)
        throw BakeInputError("the texture size " + std::to_string(options.width) + " x " +
                             std::to_string(options.height) + " is outside 1 to 16384 texels per side");
    if (options.bakeColor && !sourceColors)
        throw BakeInputError("colour baking asked for, but the source mesh has no vertex colours");
    if (!(options.maxRayDistance <= 0.0f) && !std::isfinite(options.maxRayDistance))
        throw BakeInputError("the maximum ray distance must be finite");

    NormalBakeResult result;
    const int width = options.width, height = options.height;
    result.width = width;
    result.height = height;

    // Coverage of the layout.
    Clock::time_point t0 = Clock::now();
    const TexelCoverage coverage = rasterizeTexelCoverage(targetWedgeUv, target.faceCount(), width, height);
    result.coverageSeconds = secondsSince(t0);

    // Source scene, normals, ray length.
    t0 = Clock::now();
    // Medium BVH quality: a bake casts a few rays per source triangle (a million-face scan onto a
    // 2048^2 map: ~2 each), too few to repay High's spatial-split build, which took as long as all
    // the rays there; the ray time itself did not change measurably (README, Blender section).
    const RayScene scene(source.positions.data(), source.vertexCount(), source.faces.data(), source.faceCount(),
                         SceneBuildQuality::Medium);
    std::vector<float> computedNormals;
    const std::vector<float>* sourceNormals = &source.normals;
    if (!source.hasNormals()) {
        computeAreaWeightedNormals(source.positions, source.faces, computedNormals);
        sourceNormals = &computedNormals;
    }
    const float maxDistance =
        options.maxRayDistance > 0.0f ? options.maxRayDistance : automaticRayDistanceWith(target, source, scene);
    result.maxRayDistance = maxDistance;

    // Per target face: unit face normal, dP/du and the handedness s of (dP/du, dP/dv, face normal).
    const std::size_t targetFaces = target.faceCount();
    std::vector<float> faceFrame(7 * targetFaces);
#pragma omp parallel for schedule(static)
    for (long long fl = 0; fl < (long long)targetFaces; ++fl) {
        const std::size_t f = std::size_t(fl);
        const std::uint32_t* tri = target.faces.data() + 3 * f;
        const Eigen::Vector3f p0 = vertexOf(target.positions, tri[0]);
        const Eigen::Vector3f e1 = vertexOf(target.positions, tri[1]) - p0, e2 = vertexOf(target.positions, tri[2]) - p0;
        Eigen::Vector3f faceNormal = e1.cross(e2);
        faceNormal = faceNormal.norm() > 0 ? faceNormal.normalized() : Eigen::Vector3f::Zero();
        const float* uv = targetWedgeUv + 6 * f;
        const float du1 = uv[2] - uv[0], dv1 = uv[3] - uv[1], du2 = uv[4] - uv[0], dv2 = uv[5] - uv[1];
        const float det = du1 * dv2 - du2 * dv1;
        Eigen::Vector3f dPdu = Eigen::Vector3f::Zero();
        float handedness = 1.0f;
        if (std::isfinite(det) && det != 0.0f) {
            dPdu = (e1 * dv2 - e2 * dv1) / det;
            const Eigen::Vector3f dPdv = (e2 * du1 - e1 * du2) / det;
            handedness = dPdu.cross(dPdv).dot(faceNormal) < 0 ? -1.0f : 1.0f;
        }
        float* out = faceFrame.data() + 7 * f;
        for (int k = 0; k < 3; ++k) {
            out[k] = faceNormal[k];
            out[3 + k] = dPdu[k];
        }
        out[6] = handedness;
    }
    // MikkTSpace: per-corner tangent and sign (x, y, z, s), made unit and orthogonal where the
    // algorithm has none (so that the frame below is never singular for that reason).
    const bool mikkTSpace = options.space == NormalSpace::Tangent && options.tangentFrame == TangentFrame::MikkTSpace;
    const bool alsoMikk = options.alsoMikkTSpace && !mikkTSpace;
    std::vector<float> cornerTangents;
    if (mikkTSpace || alsoMikk) {
        TangentSpaceInput input;
        input.positions = target.positions.data();
        input.vertexCount = target.vertexCount();
        input.faces = target.faces.data();
        input.faceCount = targetFaces;
        input.normals = target.normals.data();
        input.normalRate = AttributeRate::PerVertex;
        input.uv = targetWedgeUv;
        input.uvRate = AttributeRate::PerCorner;
        CornerTangents tangents = computeMikkTSpaceTangents(input);
        result.madeUpTangentCorners = completeTangents(tangents, input);
        cornerTangents = std::move(tangents.tangents);
    }
    result.sceneSeconds = secondsSince(t0);

    // Rays.
    t0 = Clock::now();
    const std::size_t texels = std::size_t(width) * std::size_t(height);
    result.normals.assign(3 * texels, 0.0f);
    if (options.keepTangents) result.tangents.assign(3 * texels, 0.0f);
    if (options.bakeColor) result.colors.assign(3 * texels, 0.0f);
    if (alsoMikk) result.mikkTSpaceNormals.assign(3 * texels, 0.0f);
    result.chart.assign(texels, 0);
    result.valid.assign(texels, 0);

    const int tilesX = (width + kTile - 1) / kTile, tileRows = (height + kTile - 1) / kTile;
    std::atomic<bool> cancelled{false};
    std::atomic<int> rowsDone{0};
    std::mutex progressMutex;
    int lastPercent = -1;
    std::exception_ptr failure;
    std::size_t chartTexels = 0, hits = 0, fallbacks = 0, invalid = 0;
    const bool tangentSpace = options.space == NormalSpace::Tangent;
    const std::vector<float>& sourceNormalArray = *sourceNormals;

#pragma omp parallel for schedule(dynamic, 1) reduction(+ : chartTexels, hits, fallbacks, invalid)
    for (int tileRow = 0; tileRow < tileRows; ++tileRow) {
        if (cancelled.load(std::memory_order_relaxed)) continue;
        TileTexels tile;
        RayPacket16 packet;
        RayHit forward[16], backward[16];
        float side = 1.0f;  // where the source was found last along the normal (+1: ahead, -1: behind)
        for (int tileX = 0; tileX < tilesX; ++tileX) {
            // Set-up: the target point and normal of each covered texel of the tile.
            tile.count = 0;
            for (int r = tileRow * kTile; r < std::min(height, (tileRow + 1) * kTile); ++r) {
                for (int c = tileX * kTile; c < std::min(width, (tileX + 1) * kTile); ++c) {
                    const std::size_t t = coverage.texelIndex(c, r);
                    const std::int32_t f = coverage.face[t];
                    if (f < 0) continue;
                    result.chart[t] = 1;
                    ++chartTexels;
                    const float b1 = coverage.barycentric[2 * t], b2 = coverage.barycentric[2 * t + 1], b0 = 1.0f - b1 - b2;
                    const std::uint32_t* tri = target.faces.data() + 3 * std::size_t(f);
                    const Eigen::Vector3f p = b0 * vertexOf(target.positions, tri[0]) +
                                              b1 * vertexOf(target.positions, tri[1]) +
                                              b2 * vertexOf(target.positions, tri[2]);
                    Eigen::Vector3f n = b0 * vertexOf(target.normals, tri[0]) + b1 * vertexOf(target.normals, tri[1]) +
                                        b2 * vertexOf(target.normals, tri[2]);
                    const float length = n.norm();
                    float keptLength = length;
                    if (length > 1e-6f) {
                        n /= length;
                    } else {
                        n = Eigen::Map<const Eigen::Vector3f>(faceFrame.data() + 7 * std::size_t(f));
                        if (n.squaredNorm() == 0.0f) {
                            ++invalid;
                            continue;
                        }
                        keptLength = 1.0f;
                    }
                    const int i = tile.count++;
                    tile.normalLength[i] = keptLength;
                    tile.barycentric[i][0] = b0;
                    tile.barycentric[i][1] = b1;
                    tile.barycentric[i][2] = b2;
                    tile.texel[i] = t;
                    tile.face[i] = std::uint32_t(f);
                    tile.point[i] = p;
                    tile.normal[i] = n;
                }
            }
            if (tile.count == 0) continue;

            // The nearer hit along +n or -n within the distance D. First one ray over the whole
            // segment, from its end on the side away from where the surface was last found
            // (`side`): when its first hit lies on the far half (or it meets nothing), that hit
            // is the nearest one on that side and nothing lies on the other, so one ray settles
            // the texel. Otherwise the surface is (also) on the near side, and the two rays from
            // the texel decide: +n, then -n up to the +n hit (the nearer hit wins, ties to +n).
            const std::uint32_t active = tile.count == 16 ? 0xffffu : ((1u << tile.count) - 1u);
            for (int i = 0; i < tile.count; ++i) {
                const Eigen::Vector3f direction = side * tile.normal[i];
                const Eigen::Vector3f origin = tile.point[i] - maxDistance * direction;
                packet.originX[i] = origin.x();
                packet.originY[i] = origin.y();
                packet.originZ[i] = origin.z();
                packet.directionX[i] = direction.x();
                packet.directionY[i] = direction.y();
                packet.directionZ[i] = direction.z();
                packet.tNear[i] = 0.0f;
                packet.tFar[i] = 2.0f * maxDistance;
            }
            scene.intersect16(packet, active, forward);
            std::uint32_t unsettled = 0;
            for (int i = 0; i < tile.count; ++i) {
                RayHit first = forward[i];
                forward[i] = RayHit();
                backward[i] = RayHit();
                if (!first.hit) continue;  // nothing within D either way: the closest point below
                if (first.distance < maxDistance) {
                    unsettled |= 1u << i;
                    continue;
                }
                first.distance -= maxDistance;
                (side > 0.0f ? forward[i] : backward[i]) = first;
            }
            if (unsettled) {
                for (int i = 0; i < tile.count; ++i) {
                    packet.originX[i] = tile.point[i].x();
                    packet.originY[i] = tile.point[i].y();
                    packet.originZ[i] = tile.point[i].z();
                    packet.directionX[i] = tile.normal[i].x();
                    packet.directionY[i] = tile.normal[i].y();
                    packet.directionZ[i] = tile.normal[i].z();
                    packet.tFar[i] = maxDistance;
                }
                RayHit nearForward[16], nearBackward[16];
                scene.intersect16(packet, unsettled, nearForward);
                for (int i = 0; i < tile.count; ++i) {
                    packet.directionX[i] = -tile.normal[i].x();
                    packet.directionY[i] = -tile.normal[i].y();
                    packet.directionZ[i] = -tile.normal[i].z();
                    packet.tFar[i] = nearForward[i].hit ? nearForward[i].distance : maxDistance;
                }
                scene.intersect16(packet, unsettled, nearBackward);
                for (int i = 0; i < tile.count; ++i) {
                    if (!((unsettled >> i) & 1u)) continue;
                    forward[i] = nearForward[i];
                    backward[i] = nearBackward[i];
                }
                // Most of this tile's surface was on the other side: start from there next time.
                if (2 * __builtin_popcount(unsettled) > tile.count) side = -side;
            }

            // Source normal (and colour) at the hit, or at the closest point.
            for (int i = 0; i < tile.count; ++i) {
                std::uint32_t sourceFace;
                float u, v;
                if (backward[i].hit && (!forward[i].hit || backward[i].distance < forward[i].distance)) {
                    sourceFace = backward[i].face;
                    u = backward[i].u;
                    v = backward[i].v;
                    ++hits;
                } else if (forward[i].hit) {
                    sourceFace = forward[i].face;
                    u = forward[i].u;
                    v = forward[i].v;
                    ++hits;
                } else {
                    const ClosestPoint closest = scene.closestPoint(tile.point[i]);
                    if (!closest.found) {
                        ++invalid;
                        continue;
                    }
                    sourceFace = closest.face;
                    u = closest.u;
                    v = closest.v;
                    ++fallbacks;
                }
                const std::uint32_t* tri = source.faces.data() + 3 * std::size_t(sourceFace);
                const float w0 = 1.0f - u - v;
                Eigen::Vector3f n = w0 * vertexOf(sourceNormalArray, tri[0]) + u * vertexOf(sourceNormalArray, tri[1]) +
                                    v * vertexOf(sourceNormalArray, tri[2]);
                if (!(n.norm() > 1e-6f)) {
                    const Eigen::Vector3f a = vertexOf(source.positions, tri[0]);
                    n = (vertexOf(source.positions, tri[1]) - a).cross(vertexOf(source.positions, tri[2]) - a);
                    if (!(n.norm() > 0.0f)) {
                        ++invalid;
                        continue;
                    }
                }
                n.normalize();

                // Tangent frame of the texel (normal_baker.h).
                const Eigen::Vector3f& N = tile.normal[i];
                const std::size_t t = tile.texel[i];
                float* outNormal = result.normals.data() + 3 * t;
                Eigen::Vector3f T;
                bool framed = false;
                // The MikkTSpace tangent-space normal of the texel, into `out`; false when the
                // frame is singular.
                const auto mikkLocal = [&](float* out, Eigen::Vector3f& unitTangent) {
                    // Interpolated, not renormalised: the frame a MikkTSpace renderer rebuilds.
                    const float* corner = cornerTangents.data() + 12 * std::size_t(tile.face[i]);
                    const float* b = tile.barycentric[i];
                    const Eigen::Vector3f Tm = b[0] * Eigen::Vector3f(corner[0], corner[1], corner[2]) +
                                               b[1] * Eigen::Vector3f(corner[4], corner[5], corner[6]) +
                                               b[2] * Eigen::Vector3f(corner[8], corner[9], corner[10]);
                    // The three corners of a triangle share its orientation; a made-up corner
                    // may not, and the majority decides then.
                    const float sign = corner[3] + corner[7] + corner[11] < 0.0f ? -1.0f : 1.0f;
                    const Eigen::Vector3f Nm = tile.normalLength[i] * N;
                    const Eigen::Vector3f Bm = sign * Nm.cross(Tm);
                    // The inverse of the matrix with columns (T, B, N) has the rows B x N, N x T,
                    // T x B over its determinant; the common factor goes with the normalisation.
                    const Eigen::Vector3f bn = Bm.cross(Nm), nt = Nm.cross(Tm), tb = Tm.cross(Bm);
                    const float det = Tm.dot(bn);
                    const float scale = std::sqrt(Tm.squaredNorm() * Bm.squaredNorm() * Nm.squaredNorm());
                    if (!(std::isfinite(det) && std::fabs(det) > 1e-6f * scale && scale > 0.0f)) return false;
                    Eigen::Vector3f local = Eigen::Vector3f(bn.dot(n), nt.dot(n), tb.dot(n)) / det;
                    const float localLength = local.norm();
                    if (!(localLength > 0.0f && std::isfinite(localLength))) return false;
                    local /= localLength;
                    out[0] = local.x();
                    out[1] = local.y();
                    out[2] = local.z();
                    unitTangent = (Tm - Tm.dot(N) * N).normalized();
                    return true;
                };
                if (mikkTSpace) framed = mikkLocal(outNormal, T);
                if (!framed) {
                    const float* frame = faceFrame.data() + 7 * std::size_t(tile.face[i]);
                    const Eigen::Vector3f dPdu(frame[3], frame[4], frame[5]);
                    T = dPdu - dPdu.dot(N) * N;
                    const float tLength = T.norm();
                    T = tLength > 1e-12f * std::max(1.0f, dPdu.norm()) ? Eigen::Vector3f(T / tLength) : anyOrthogonal(N);
                    if (tangentSpace) {
                        const Eigen::Vector3f B = frame[6] * N.cross(T);
                        outNormal[0] = n.dot(T);
                        outNormal[1] = n.dot(B);
                        outNormal[2] = n.dot(N);
                    } else {
                        outNormal[0] = n.x();
                        outNormal[1] = n.y();
                        outNormal[2] = n.z();
                    }
                }
                if (alsoMikk) {
                    float* outMikk = result.mikkTSpaceNormals.data() + 3 * t;
                    Eigen::Vector3f unused;
                    if (!mikkLocal(outMikk, unused)) {
                        // Singular frame: the unit normal in the orthonormalised frame instead.
                        const Eigen::Vector3f B = N.cross(T);
                        outMikk[0] = n.dot(T);
                        outMikk[1] = n.dot(B);
                        outMikk[2] = n.dot(N);
                    }
                }
                if (options.keepTangents) {
                    float* outTangent = result.tangents.data() + 3 * t;
                    outTangent[0] = T.x();
                    outTangent[1] = T.y();
                    outTangent[2] = T.z();
                }
                if (options.bakeColor) {
                    float* outColor = result.colors.data() + 3 * t;
                    for (int k = 0; k < 3; ++k)
                        outColor[k] = w0 * sourceColors[3 * std::size_t(tri[0]) + k] +
                                      u * sourceColors[3 * std::size_t(tri[1]) + k] +
                                      v * sourceColors[3 * std::size_t(tri[2]) + k];
                }
                result.valid[t] = 1;
            }
        }

        // Progress, from whichever thread crosses a whole percent (never two at once).
        const int done = rowsDone.fetch_add(1) + 1;
        if (options.progress) {
            const int percent = int(100LL * done / tileRows);
            std::lock_guard<std::mutex> lock(progressMutex);
            if (percent > lastPercent && !cancelled.load()) {
                lastPercent = percent;
                try {
                    if (!options.progress(percent / 100.0, "casting rays from the target to the scan")) cancelled = true;
                } catch (...) {
                    failure = std::current_exception();
                    cancelled = true;
                }
            }
        }
    }
    if (failure) std::rethrow_exception(failure);
    if (cancelled) throw OperationCancelled();
    result.raySeconds = secondsSince(t0);
    result.cornerTangents = std::move(cornerTangents);
    result.chartTexels = chartTexels;
    result.rayHits = hits;
    result.closestPointFallbacks = fallbacks;
    result.invalidTexels = invalid;
    result.seconds = secondsSince(start);
    return result;
}

// std::lround of a value v >= 0 without the library call: the whole part plus one when the
// fraction (exact: v - trunc(v) loses nothing) is at least a half.
std::uint8_t encodeNormal8(float component) {
    const float x = std::isfinite(component) ? std::clamp(component, -1.0f, 1.0f) : 0.0f;
    const float v = (x + 1.0f) * 0.5f * 255.0f;
    const std::uint32_t whole = std::uint32_t(v);
    return std::uint8_t(whole + (v - float(whole) >= 0.5f ? 1u : 0u));
}

std::uint16_t encodeNormal16(float component) {
    const float x = std::isfinite(component) ? std::clamp(component, -1.0f, 1.0f) : 0.0f;
    const double v = (double(x) + 1.0) * 0.5 * 65535.0;
    const std::uint32_t whole = std::uint32_t(v);
    return std::uint16_t(whole + (v - double(whole) >= 0.5 ? 1u : 0u));
}

float decodeNormal8(std::uint8_t code) { return float(code) * (2.0f / 255.0f) - 1.0f; }

float decodeNormal16(std::uint16_t code) { return float(double(code) * (2.0 / 65535.0) - 1.0); }

}  // namespace rad
