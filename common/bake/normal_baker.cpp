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
// texels of a tile are neighbours on one chart. Most texels need one ray, not two: see
// castAcrossSegments.
#include "bake/normal_baker.h"

#include "bake/texel_coverage.h"
#include "bake/texture_atlas.h"
#include "geometry/mesh_normals.h"
#include "geometry/mikktspace_tangents.h"
#include "raycast/ray_scene.h"

#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
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

// The rays of a tile and their hits along +n (forward) and -n (backward), reused by the tiles of
// a row: `side` carries over from one tile to the next.
struct TileRays {
    RayPacket16 packet;
    RayHit forward[16], backward[16];
    float side = 1.0f;  // where the source was found last along the normal (+1: ahead, -1: behind)
};

// What every tile reads: the meshes, the source's scene and normals, the layout's coverage and the
// target's per-face and per-corner frames.
struct TileBakeInputs {
    const TriangleMesh& target;
    const TriangleMesh& source;
    const float* sourceColors;
    const std::vector<float>& sourceNormals;
    const TexelCoverage& coverage;
    const RayScene& scene;
    const std::vector<float>& faceFrame;
    const std::vector<float>& cornerTangents;
    const NormalBakeOptions& options;
    float maxDistance;
    bool mikkTSpace, alsoMikk, tangentSpace;
};

// A row of tiles' share of the result's statistics.
struct TexelCounts {
    std::size_t chartTexels = 0, hits = 0, fallbacks = 0, invalid = 0;
};

// Where a texel's normal and colour are read: a point of a source face, barycentrics (u, v).
struct SourcePoint {
    std::uint32_t face = 0;
    float u = 0.0f, v = 0.0f;
};

void checkBakeInput(const TriangleMesh& target, const float* targetWedgeUv, const TriangleMesh& source,
                    const float* sourceColors, const NormalBakeOptions& options) {
    checkMesh(target, "target");
    checkMesh(source, "source");
    if (!target.hasNormals())
        throw BakeInputError("the target mesh has no vertex normals: compute them first ({{Compute normals for point sets}} "
                             "or {{Re-Compute Vertex Normals}})");
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
}

// The source's vertex normals, or area-weighted ones computed into `computed` when it has none.
const std::vector<float>& sourceNormalsOf(const TriangleMesh& source, std::vector<float>& computed) {
    if (source.hasNormals()) return source.normals;
    computeAreaWeightedNormals(source.positions, source.faces, computed);
    return computed;
}

// Per target face: unit face normal, dP/du and the handedness s of (dP/du, dP/dv, face normal).
std::vector<float> computeFaceFrames(const TriangleMesh& target, const float* targetWedgeUv) {
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
    return faceFrame;
}

// MikkTSpace: per-corner tangent and sign (x, y, z, s), made unit and orthogonal where the
// algorithm has none (so that the texel frames are never singular for that reason).
std::vector<float> completedMikkTSpaceTangents(const TriangleMesh& target, const float* targetWedgeUv,
                                               std::size_t& madeUpCorners) {
    TangentSpaceInput input;
    input.positions = target.positions.data();
    input.vertexCount = target.vertexCount();
    input.faces = target.faces.data();
    input.faceCount = target.faceCount();
    input.normals = target.normals.data();
    input.normalRate = AttributeRate::PerVertex;
    input.uv = targetWedgeUv;
    input.uvRate = AttributeRate::PerCorner;
    CornerTangents tangents = computeMikkTSpaceTangents(input);
    madeUpCorners = completeTangents(tangents, input);
    return std::move(tangents.tangents);
}

// The output arrays, zero (not valid) until a texel is baked.
void allocateMaps(const NormalBakeOptions& options, bool alsoMikk, NormalBakeResult& result) {
    const std::size_t texels = std::size_t(options.width) * std::size_t(options.height);
    result.normals.assign(3 * texels, 0.0f);
    if (options.keepTangents) result.tangents.assign(3 * texels, 0.0f);
    if (options.bakeColor) result.colors.assign(3 * texels, 0.0f);
    if (alsoMikk) result.mikkTSpaceNormals.assign(3 * texels, 0.0f);
    result.chart.assign(texels, 0);
    result.valid.assign(texels, 0);
}

// The target point and unit normal of each covered texel of the tile; marks the chart texels. A
// texel whose interpolated normal vanishes takes its face's normal, or none (invalid) on a
// degenerate face.
void collectTileTexels(const TileBakeInputs& in, int tileRow, int tileX, TileTexels& tile, TexelCounts& counts,
                       std::uint8_t* chart) {
    const TriangleMesh& target = in.target;
    const int width = in.options.width, height = in.options.height;
    tile.count = 0;
    for (int r = tileRow * kTile; r < std::min(height, (tileRow + 1) * kTile); ++r) {
        for (int c = tileX * kTile; c < std::min(width, (tileX + 1) * kTile); ++c) {
            const std::size_t t = in.coverage.texelIndex(c, r);
            const std::int32_t f = in.coverage.face[t];
            if (f < 0) continue;
            chart[t] = 1;
            ++counts.chartTexels;
            const float b1 = in.coverage.barycentric[2 * t], b2 = in.coverage.barycentric[2 * t + 1], b0 = 1.0f - b1 - b2;
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
                n = Eigen::Map<const Eigen::Vector3f>(in.faceFrame.data() + 7 * std::size_t(f));
                if (n.squaredNorm() == 0.0f) {
                    ++counts.invalid;
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
}

// The nearer hit along +n or -n within the distance D. First one ray over the whole segment, from
// its end on the side away from where the surface was last found (`side`): when its first hit
// lies on the far half (or it meets nothing), that hit is the nearest one on that side and nothing
// lies on the other, so one ray settles the texel. Otherwise the surface is (also) on the near
// side, and castFromTexels decides. Returns the texels this ray did not settle.
std::uint32_t castAcrossSegments(const TileBakeInputs& in, const TileTexels& tile, TileRays& rays) {
    const float maxDistance = in.maxDistance;
    RayPacket16& packet = rays.packet;
    const std::uint32_t active = tile.count == 16 ? 0xffffu : ((1u << tile.count) - 1u);
    for (int i = 0; i < tile.count; ++i) {
        const Eigen::Vector3f direction = rays.side * tile.normal[i];
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
    in.scene.intersect16(packet, active, rays.forward);
    std::uint32_t unsettled = 0;
    for (int i = 0; i < tile.count; ++i) {
        RayHit first = rays.forward[i];
        rays.forward[i] = RayHit();
        rays.backward[i] = RayHit();
        if (!first.hit) continue;  // nothing within D either way: the closest point below
        if (first.distance < maxDistance) {
            unsettled |= 1u << i;
            continue;
        }
        first.distance -= maxDistance;
        (rays.side > 0.0f ? rays.forward[i] : rays.backward[i]) = first;
    }
    return unsettled;
}

// The texels whose surface lies (also) on the near side: the two rays from the texel decide, +n,
// then -n up to the +n hit (the nearer hit wins, ties to +n). The packet's tNear stays 0 from
// castAcrossSegments.
void castFromTexels(const TileBakeInputs& in, const TileTexels& tile, std::uint32_t unsettled, TileRays& rays) {
    RayPacket16& packet = rays.packet;
    for (int i = 0; i < tile.count; ++i) {
        packet.originX[i] = tile.point[i].x();
        packet.originY[i] = tile.point[i].y();
        packet.originZ[i] = tile.point[i].z();
        packet.directionX[i] = tile.normal[i].x();
        packet.directionY[i] = tile.normal[i].y();
        packet.directionZ[i] = tile.normal[i].z();
        packet.tFar[i] = in.maxDistance;
    }
    RayHit nearForward[16], nearBackward[16];
    in.scene.intersect16(packet, unsettled, nearForward);
    for (int i = 0; i < tile.count; ++i) {
        packet.directionX[i] = -tile.normal[i].x();
        packet.directionY[i] = -tile.normal[i].y();
        packet.directionZ[i] = -tile.normal[i].z();
        packet.tFar[i] = nearForward[i].hit ? nearForward[i].distance : in.maxDistance;
    }
    in.scene.intersect16(packet, unsettled, nearBackward);
    for (int i = 0; i < tile.count; ++i) {
        if (!((unsettled >> i) & 1u)) continue;
        rays.forward[i] = nearForward[i];
        rays.backward[i] = nearBackward[i];
    }
    // Most of this tile's surface was on the other side: start from there next time.
    if (2 * __builtin_popcount(unsettled) > tile.count) rays.side = -rays.side;
}

// Texel i's point on the source: the nearer ray hit, else the closest point of the source (a
// fallback); false when there is none.
bool findSourcePoint(const TileBakeInputs& in, const TileTexels& tile, const TileRays& rays, int i, SourcePoint& at,
                     TexelCounts& counts) {
    const RayHit& forward = rays.forward[i];
    const RayHit& backward = rays.backward[i];
    if (backward.hit && (!forward.hit || backward.distance < forward.distance)) {
        at = SourcePoint{backward.face, backward.u, backward.v};
        ++counts.hits;
    } else if (forward.hit) {
        at = SourcePoint{forward.face, forward.u, forward.v};
        ++counts.hits;
    } else {
        const ClosestPoint closest = in.scene.closestPoint(tile.point[i]);
        if (!closest.found) return false;
        at = SourcePoint{closest.face, closest.u, closest.v};
        ++counts.fallbacks;
    }
    return true;
}

// The unit source normal at the point: the interpolated vertex normal, or the face normal where
// that vanishes; false when both do.
bool sourceNormalAt(const TileBakeInputs& in, const SourcePoint& at, Eigen::Vector3f& n) {
    const TriangleMesh& source = in.source;
    const std::uint32_t* tri = source.faces.data() + 3 * std::size_t(at.face);
    const float w0 = 1.0f - at.u - at.v;
    n = w0 * vertexOf(in.sourceNormals, tri[0]) + at.u * vertexOf(in.sourceNormals, tri[1]) +
        at.v * vertexOf(in.sourceNormals, tri[2]);
    if (!(n.norm() > 1e-6f)) {
        const Eigen::Vector3f a = vertexOf(source.positions, tri[0]);
        n = (vertexOf(source.positions, tri[1]) - a).cross(vertexOf(source.positions, tri[2]) - a);
        if (!(n.norm() > 0.0f)) return false;
    }
    n.normalize();
    return true;
}

// The MikkTSpace tangent-space normal of source normal n at texel i, into `out`, and the unit
// tangent orthogonal to the texel's normal; false when the frame is singular.
bool mikkTSpaceLocalNormal(const std::vector<float>& cornerTangents, const TileTexels& tile, int i,
                           const Eigen::Vector3f& n, float* out, Eigen::Vector3f& unitTangent) {
    const Eigen::Vector3f& N = tile.normal[i];
    // Interpolated, not renormalised: the frame a MikkTSpace renderer rebuilds.
    const float* corner = cornerTangents.data() + 12 * std::size_t(tile.face[i]);
    const float* b = tile.barycentric[i];
    const Eigen::Vector3f Tm = b[0] * Eigen::Vector3f(corner[0], corner[1], corner[2]) +
                               b[1] * Eigen::Vector3f(corner[4], corner[5], corner[6]) +
                               b[2] * Eigen::Vector3f(corner[8], corner[9], corner[10]);
    // The three corners of a triangle share its orientation; a made-up corner may not, and the
    // majority decides then.
    const float sign = corner[3] + corner[7] + corner[11] < 0.0f ? -1.0f : 1.0f;
    const Eigen::Vector3f Nm = tile.normalLength[i] * N;
    const Eigen::Vector3f Bm = sign * Nm.cross(Tm);
    // The inverse of the matrix with columns (T, B, N) has the rows B x N, N x T, T x B over its
    // determinant; the common factor goes with the normalisation.
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
}

// The per-face frame of texel i (Lengyel 2001: the face's dP/du orthogonalised against the texel's
// normal N): source normal n in it, or n itself in object space, into `out`; returns its unit tangent.
Eigen::Vector3f perFaceFrameNormal(const TileBakeInputs& in, const TileTexels& tile, int i, const Eigen::Vector3f& n,
                                   float* out) {
    const Eigen::Vector3f& N = tile.normal[i];
    const float* frame = in.faceFrame.data() + 7 * std::size_t(tile.face[i]);
    const Eigen::Vector3f dPdu(frame[3], frame[4], frame[5]);
    Eigen::Vector3f T = dPdu - dPdu.dot(N) * N;
    const float tLength = T.norm();
    T = tLength > 1e-12f * std::max(1.0f, dPdu.norm()) ? Eigen::Vector3f(T / tLength) : anyOrthogonal(N);
    if (in.tangentSpace) {
        const Eigen::Vector3f B = frame[6] * N.cross(T);
        out[0] = n.dot(T);
        out[1] = n.dot(B);
        out[2] = n.dot(N);
    } else {
        out[0] = n.x();
        out[1] = n.y();
        out[2] = n.z();
    }
    return T;
}

// The second, MikkTSpace, normal of texel i (alsoMikkTSpace); T is the texel's unit tangent.
void writeSecondMikkTSpaceNormal(const TileBakeInputs& in, const TileTexels& tile, int i, const Eigen::Vector3f& n,
                                 const Eigen::Vector3f& T, float* out) {
    Eigen::Vector3f unused;
    if (mikkTSpaceLocalNormal(in.cornerTangents, tile, i, n, out, unused)) return;
    // Singular frame: the unit normal in the orthonormalised frame instead.
    const Eigen::Vector3f& N = tile.normal[i];
    const Eigen::Vector3f B = N.cross(T);
    out[0] = n.dot(T);
    out[1] = n.dot(B);
    out[2] = n.dot(N);
}

// Texel i's values from unit source normal n at the source point: the normal in the requested
// space and frame (normal_baker.h), and as asked the second MikkTSpace normal, the tangent and
// the interpolated source colour.
void writeTexel(const TileBakeInputs& in, const TileTexels& tile, int i, const SourcePoint& at,
                const Eigen::Vector3f& n, NormalBakeResult& result) {
    const std::size_t t = tile.texel[i];
    float* outNormal = result.normals.data() + 3 * t;
    Eigen::Vector3f T;
    const bool framed = in.mikkTSpace && mikkTSpaceLocalNormal(in.cornerTangents, tile, i, n, outNormal, T);
    if (!framed) T = perFaceFrameNormal(in, tile, i, n, outNormal);
    if (in.alsoMikk) writeSecondMikkTSpaceNormal(in, tile, i, n, T, result.mikkTSpaceNormals.data() + 3 * t);
    if (in.options.keepTangents) {
        float* outTangent = result.tangents.data() + 3 * t;
        outTangent[0] = T.x();
        outTangent[1] = T.y();
        outTangent[2] = T.z();
    }
    if (in.options.bakeColor) {
        const std::uint32_t* tri = in.source.faces.data() + 3 * std::size_t(at.face);
        const float w0 = 1.0f - at.u - at.v;
        float* outColor = result.colors.data() + 3 * t;
        for (int k = 0; k < 3; ++k)
            outColor[k] = w0 * in.sourceColors[3 * std::size_t(tri[0]) + k] +
                          at.u * in.sourceColors[3 * std::size_t(tri[1]) + k] +
                          at.v * in.sourceColors[3 * std::size_t(tri[2]) + k];
    }
    result.valid[t] = 1;
}

// Source normal (and colour) at each texel's hit, or at its closest point.
void bakeTileTexels(const TileBakeInputs& in, const TileTexels& tile, const TileRays& rays, TexelCounts& counts,
                    NormalBakeResult& result) {
    for (int i = 0; i < tile.count; ++i) {
        SourcePoint at;
        Eigen::Vector3f n;
        if (!findSourcePoint(in, tile, rays, i, at, counts) || !sourceNormalAt(in, at, n)) {
            ++counts.invalid;
            continue;
        }
        writeTexel(in, tile, i, at, n, result);
    }
}

// One row of tiles, left to right: per tile, its texels, their rays, their values.
void bakeTileRow(const TileBakeInputs& in, int tileRow, TexelCounts& counts, NormalBakeResult& result) {
    const int tilesX = (in.options.width + kTile - 1) / kTile;
    TileTexels tile;
    TileRays rays;
    for (int tileX = 0; tileX < tilesX; ++tileX) {
        collectTileTexels(in, tileRow, tileX, tile, counts, result.chart.data());
        if (tile.count == 0) continue;
        const std::uint32_t unsettled = castAcrossSegments(in, tile, rays);
        if (unsettled) castFromTexels(in, tile, unsettled, rays);
        bakeTileTexels(in, tile, rays, counts, result);
    }
}

// Every row of tiles (OpenMP, dynamic), with progress and stop requests; the statistics into
// `result`. Throws what the progress callback threw, or OperationCancelled.
void bakeTileRows(const TileBakeInputs& in, NormalBakeResult& result) {
    const int tileRows = (in.options.height + kTile - 1) / kTile;
    LoopProgress progress(in.options.progress, "casting rays from the target to the scan",
                          static_cast<std::size_t>(tileRows));
    std::size_t chartTexels = 0, hits = 0, fallbacks = 0, invalid = 0;

#pragma omp parallel for schedule(dynamic, 1) reduction(+ : chartTexels, hits, fallbacks, invalid)
    for (int tileRow = 0; tileRow < tileRows; ++tileRow) {
        progress.runItem(omp_get_thread_num() == 0, [&] {
            TexelCounts counts;
            bakeTileRow(in, tileRow, counts, result);
            chartTexels += counts.chartTexels;
            hits += counts.hits;
            fallbacks += counts.fallbacks;
            invalid += counts.invalid;
        });
    }
    progress.finish();
    result.chartTexels = chartTexels;
    result.rayHits = hits;
    result.closestPointFallbacks = fallbacks;
    result.invalidTexels = invalid;
}

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
    checkBakeInput(target, targetWedgeUv, source, sourceColors, options);
    NormalBakeResult result;
    result.width = options.width;
    result.height = options.height;

    Clock::time_point t0 = Clock::now();
    const TexelCoverage coverage = rasterizeTexelCoverage(targetWedgeUv, target.faceCount(), options.width, options.height);
    result.coverageSeconds = secondsSince(t0);

    t0 = Clock::now();
    // Medium BVH quality: a bake casts a few rays per source triangle (a million-face scan onto a
    // 2048^2 map: ~2 each), too few to repay High's spatial-split build, which took as long as all
    // the rays there; the ray time itself did not change measurably (README, Blender section).
    const RayScene scene(source.positions.data(), source.vertexCount(), source.faces.data(), source.faceCount(),
                         SceneBuildQuality::Medium);
    std::vector<float> computedNormals;
    const std::vector<float>& sourceNormals = sourceNormalsOf(source, computedNormals);
    result.maxRayDistance =
        options.maxRayDistance > 0.0f ? options.maxRayDistance : automaticRayDistanceWith(target, source, scene);
    const std::vector<float> faceFrame = computeFaceFrames(target, targetWedgeUv);
    const bool mikkTSpace = options.space == NormalSpace::Tangent && options.tangentFrame == TangentFrame::MikkTSpace;
    const bool alsoMikk = options.alsoMikkTSpace && !mikkTSpace;
    std::vector<float> cornerTangents;
    if (mikkTSpace || alsoMikk)
        cornerTangents = completedMikkTSpaceTangents(target, targetWedgeUv, result.madeUpTangentCorners);
    result.sceneSeconds = secondsSince(t0);

    t0 = Clock::now();
    allocateMaps(options, alsoMikk, result);
    const TileBakeInputs inputs{target, source, sourceColors, sourceNormals, coverage, scene, faceFrame, cornerTangents,
                                options, result.maxRayDistance, mikkTSpace, alsoMikk,
                                options.space == NormalSpace::Tangent};
    bakeTileRows(inputs, result);
    result.raySeconds = secondsSince(t0);
    result.cornerTangents = std::move(cornerTangents);
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
