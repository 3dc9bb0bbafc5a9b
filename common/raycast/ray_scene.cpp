#include "raycast/ray_scene.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace rad {

namespace {
std::string embreeErrorText(RTCDevice device) {
    switch (rtcGetDeviceError(device)) {
        case RTC_ERROR_NONE: return "no error";
        case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
        case RTC_ERROR_CANCELLED: return "cancelled";
        default: return "unknown error";
    }
}

// Copies the mesh into a new triangle geometry of `scene`. On failure releases the scene and the
// device (the constructor is then left by the exception, so the destructor will not) and throws.
void attachTriangles(RTCDevice device, RTCScene scene, const float* positions, std::size_t vertexCount,
                     const std::uint32_t* faces, std::size_t faceCount, const float*& verticesOut,
                     const std::uint32_t*& indicesOut) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree may read 16 bytes past the last vertex: one spare float triple.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                                 RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertexCount + 1));
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), faceCount));
    if (!vertices || !indices) {
        const std::string why = embreeErrorText(device);
        rtcReleaseGeometry(geometry);
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
        throw RayCastError("Embree could not allocate the mesh buffers: " + why);
    }
    std::memcpy(vertices, positions, vertexCount * 3 * sizeof(float));
    std::memset(vertices + vertexCount * 3, 0, 3 * sizeof(float));
    std::memcpy(indices, faces, faceCount * 3 * sizeof(std::uint32_t));
    verticesOut = vertices;
    indicesOut = indices;
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
}

// Closest point of triangle (a, b, c) to p, with its barycentrics (u on b, v on c): Ericson,
// Real-Time Collision Detection, sec. 5.1.5 (Voronoi regions of the vertices and edges).
Eigen::Vector3f closestPointOnTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                       const Eigen::Vector3f& c, float& u, float& v) {
    const Eigen::Vector3f ab = b - a, ac = c - a, ap = p - a;
    const float d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0f && d2 <= 0.0f) { u = 0.0f; v = 0.0f; return a; }
    const Eigen::Vector3f bp = p - b;
    const float d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0f && d4 <= d3) { u = 1.0f; v = 0.0f; return b; }
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
        const float t = d1 / (d1 - d3);
        u = t; v = 0.0f;
        return a + t * ab;
    }
    const Eigen::Vector3f cp = p - c;
    const float d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0f && d5 <= d6) { u = 0.0f; v = 1.0f; return c; }
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
        const float t = d2 / (d2 - d6);
        u = 0.0f; v = t;
        return a + t * ac;
    }
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
        const float t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        u = 1.0f - t; v = t;
        return b + t * (c - b);
    }
    const float denominator = 1.0f / (va + vb + vc);
    u = vb * denominator;
    v = vc * denominator;
    return a + u * ab + v * ac;
}

struct PointQueryState {
    const float* vertices;
    const std::uint32_t* indices;
    ClosestPoint* best;
};

// Embree calls this for every triangle whose box is within the query's current radius; shrinking
// the radius prunes the rest of the traversal.
bool closestPointCallback(RTCPointQueryFunctionArguments* arguments) {
    auto* state = static_cast<PointQueryState*>(arguments->userPtr);
    const std::uint32_t* face = state->indices + 3 * std::size_t(arguments->primID);
    const auto vertex = [&](std::uint32_t i) { return Eigen::Map<const Eigen::Vector3f>(state->vertices + 3 * std::size_t(i)); };
    const Eigen::Vector3f query(arguments->query->x, arguments->query->y, arguments->query->z);
    float u = 0.0f, v = 0.0f;
    const Eigen::Vector3f point = closestPointOnTriangle(query, vertex(face[0]), vertex(face[1]), vertex(face[2]), u, v);
    const float distance = (point - query).norm();
    if (!(distance < arguments->query->radius)) return false;
    arguments->query->radius = distance;
    ClosestPoint& best = *state->best;
    best.found = true;
    best.distance = distance;
    best.face = arguments->primID;
    best.u = u;
    best.v = v;
    best.point = point;
    return true;
}

// Embree's check of its input (RayK::valid, FLT_LARGE): origins and directions within 1.844e18.
// Beyond it (or NaN) Embree asserts and aborts the whole process, MeshLab included.
constexpr float kEmbreeLargest = 1.844e18f;

bool traceable(float ox, float oy, float oz, float dx, float dy, float dz) {
    return std::fabs(ox) <= kEmbreeLargest && std::fabs(oy) <= kEmbreeLargest && std::fabs(oz) <= kEmbreeLargest &&
           std::fabs(dx) <= kEmbreeLargest && std::fabs(dy) <= kEmbreeLargest && std::fabs(dz) <= kEmbreeLargest;
}

// Copies `rays` into Embree's packet layout and sets the valid lanes: those in activeMask whose
// interval is not empty or NaN (the rule of occluded(): such an interval holds nothing, and Embree
// would leave its tfar as given, read as a hit when tFar = -inf). Returns the mask of valid lanes.
//
// The lanes left out are written as an empty ray (tnear 0 > tfar -1), not left as they came: on a
// CPU without AVX-512, Embree 3 traces a 16-wide packet through its ray-stream path, which ignores
// the `valid` array and takes every lane with tnear <= tfar as live, asserting (and aborting the
// process) on a live lane whose tnear is negative or whose origin is not finite. A valid lane's
// tnear is clamped to 0 for the same reason (Embree defines no interval behind the origin).
std::uint32_t fillRayPacket(const RayPacket16& rays, std::uint32_t activeMask, RTCRay16& packet, int valid[16]) {
    static_assert(RayPacket16::kSize == 16, "one RTCRay16 per packet");
    std::uint32_t live = 0;
    for (int i = 0; i < 16; ++i) {
        // A lane Embree would assert on (an origin or direction beyond its limit or not finite, a
        // NaN interval) is left out rather than passed on: such a ray holds nothing.
        const float tNear = std::max(rays.tNear[i], 0.0f);
        const bool on = ((activeMask >> i) & 1u) && tNear <= rays.tFar[i] &&
                        traceable(rays.originX[i], rays.originY[i], rays.originZ[i], rays.directionX[i],
                                  rays.directionY[i], rays.directionZ[i]);
        valid[i] = on ? -1 : 0;
        live |= std::uint32_t(on) << i;
        packet.org_x[i] = on ? rays.originX[i] : 0.0f;
        packet.org_y[i] = on ? rays.originY[i] : 0.0f;
        packet.org_z[i] = on ? rays.originZ[i] : 0.0f;
        packet.tnear[i] = on ? tNear : 0.0f;
        packet.dir_x[i] = on ? rays.directionX[i] : 0.0f;
        packet.dir_y[i] = on ? rays.directionY[i] : 0.0f;
        packet.dir_z[i] = on ? rays.directionZ[i] : 1.0f;
        packet.time[i] = 0.0f;
        packet.tfar[i] = on ? rays.tFar[i] : -1.0f;
        packet.mask[i] = std::numeric_limits<unsigned>::max();
        packet.id[i] = static_cast<unsigned>(i);
        packet.flags[i] = 0;
    }
    return live;
}

}  // namespace

RayScene::RayScene(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount,
                   SceneBuildQuality quality)
    : faceCount_(faceCount) {
    RTCDevice device = rtcNewDevice(nullptr);
    if (!device) throw RayCastError("Embree could not create a device");
    device_ = device;
    RTCScene scene = rtcNewScene(device);
    if (!scene) {
        const std::string why = embreeErrorText(device);  // before the device is released
        rtcReleaseDevice(device);
        throw RayCastError("Embree could not create a scene: " + why);
    }
    scene_ = scene;
    rtcSetSceneBuildQuality(scene, quality == SceneBuildQuality::High ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    // Robust traversal: without it rays aimed exactly at a shared vertex or edge can slip between
    // the triangles (light leaking into shadows, vertices "seen" through a closed surface);
    // ray_scene_test measures the leak. Costs ~10-15 % per query.
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    // A mesh without faces (e.g. a point cloud) is a valid, empty scene that every ray misses;
    // Embree refuses zero-sized buffers, so no geometry is attached then.
    if (faceCount > 0) attachTriangles(device, scene, positions, vertexCount, faces, faceCount, vertices_, indices_);
    rtcCommitScene(scene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
        const std::string why = embreeErrorText(device);
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
        throw RayCastError("Embree could not build the scene: " + why);
    }
}

RayScene::~RayScene() {
    if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
    if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

RayHit RayScene::intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tNear,
                           float tFar) const {
    tNear = std::max(tNear, 0.0f);  // Embree asserts on a negative tnear (fillRayPacket)
    if (!(tNear <= tFar) || !traceable(origin.x(), origin.y(), origin.z(), direction.x(), direction.y(), direction.z()))
        return RayHit();
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit query;
    query.ray.org_x = origin.x();
    query.ray.org_y = origin.y();
    query.ray.org_z = origin.z();
    query.ray.dir_x = direction.x();
    query.ray.dir_y = direction.y();
    query.ray.dir_z = direction.z();
    query.ray.tnear = tNear;
    query.ray.tfar = tFar;
    query.ray.time = 0.0f;
    query.ray.mask = std::numeric_limits<unsigned>::max();
    query.ray.id = 0;
    query.ray.flags = 0;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(static_cast<RTCScene>(scene_), &context, &query);
    RayHit hit;
    // A hit at a distance that is not finite is the overflow of Embree's triangle test (coordinates
    // near 1e13), not a surface: a miss.
    if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID || !std::isfinite(query.ray.tfar)) return hit;
    hit.hit = true;
    hit.distance = query.ray.tfar;
    hit.face = query.hit.primID;
    hit.u = query.hit.u;
    hit.v = query.hit.v;
    return hit;
}

bool RayScene::occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tNear,
                        float tFar) const {
    // An empty (or NaN) interval holds nothing. Embree leaves such a ray's tfar as given, which
    // the test at the end would read as a hit whenever tFar < 0.
    tNear = std::max(tNear, 0.0f);  // Embree asserts on a negative tnear (fillRayPacket)
    if (!(tNear <= tFar)) return false;
    if (!traceable(origin.x(), origin.y(), origin.z(), direction.x(), direction.y(), direction.z())) return false;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    ray.org_x = origin.x();
    ray.org_y = origin.y();
    ray.org_z = origin.z();
    ray.dir_x = direction.x();
    ray.dir_y = direction.y();
    ray.dir_z = direction.z();
    ray.tnear = tNear;
    ray.tfar = tFar;
    ray.time = 0.0f;
    ray.mask = std::numeric_limits<unsigned>::max();
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(static_cast<RTCScene>(scene_), &context, &ray);
    // Embree sets tfar to -inf when the ray is occluded (and leaves it alone otherwise).
    return ray.tfar == -std::numeric_limits<float>::infinity();
}

ClosestPoint RayScene::closestPoint(const Eigen::Vector3f& query, float maxDistance) const {
    ClosestPoint best;
    if (faceCount_ == 0 || !query.allFinite() || !(maxDistance >= 0.0f)) return best;
    RTCPointQuery pointQuery;
    pointQuery.x = query.x();
    pointQuery.y = query.y();
    pointQuery.z = query.z();
    pointQuery.time = 0.0f;
    pointQuery.radius = maxDistance;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    PointQueryState state{vertices_, indices_, &best};
    rtcPointQuery(static_cast<RTCScene>(scene_), &pointQuery, &context, closestPointCallback, &state);
    return best;
}

std::uint32_t RayScene::occluded16(const RayPacket16& rays, std::uint32_t activeMask) const {
    alignas(64) int valid[16];
    RTCRay16 packet;  // RTC_ALIGN(64) in rtcore_ray.h, as rtcOccluded16 requires
    const std::uint32_t live = fillRayPacket(rays, activeMask, packet, valid);
    if (live == 0) return 0;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded16(valid, static_cast<RTCScene>(scene_), &context, &packet);
    std::uint32_t hit = 0;
    for (int i = 0; i < 16; ++i)
        hit |= std::uint32_t(packet.tfar[i] == -std::numeric_limits<float>::infinity()) << i;
    return hit & live;
}

void RayScene::intersect16(const RayPacket16& rays, std::uint32_t activeMask, RayHit hits[RayPacket16::kSize]) const {
    alignas(64) int valid[16];
    RTCRayHit16 packet;  // RTC_ALIGN(64) in rtcore_ray.h, as rtcIntersect16 requires
    const std::uint32_t live = fillRayPacket(rays, activeMask, packet.ray, valid);
    for (int i = 0; i < 16; ++i) {
        hits[i] = RayHit();
        packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    if (live == 0) return;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect16(valid, static_cast<RTCScene>(scene_), &context, &packet);
    for (int i = 0; i < 16; ++i) {
        if (!((live >> i) & 1u) || packet.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID || !std::isfinite(packet.ray.tfar[i]))
            continue;  // as in intersect()
        hits[i].hit = true;
        hits[i].distance = packet.ray.tfar[i];
        hits[i].face = packet.hit.primID[i];
        hits[i].u = packet.hit.u[i];
        hits[i].v = packet.hit.v[i];
    }
}

}  // namespace rad
