#include "raycast/ray_scene.h"

#include <embree3/rtcore.h>

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
                     const std::uint32_t* faces, std::size_t faceCount) {
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
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
}

}  // namespace

RayScene::RayScene(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount)
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
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    // Robust traversal: without it rays aimed exactly at a shared vertex or edge can slip between
    // the triangles (light leaking into shadows, vertices "seen" through a closed surface);
    // ray_scene_test measures the leak. Costs ~10-15 % per query.
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    // A mesh without faces (e.g. a point cloud) is a valid, empty scene that every ray misses;
    // Embree refuses zero-sized buffers, so no geometry is attached then.
    if (faceCount > 0) attachTriangles(device, scene, positions, vertexCount, faces, faceCount);
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
    if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
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
    if (!(tNear <= tFar)) return false;
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

std::uint32_t RayScene::occluded16(const RayPacket16& rays, std::uint32_t activeMask) const {
    static_assert(RayPacket16::kSize == 16, "one RTCRay16 per packet");
    alignas(64) int valid[16];
    RTCRay16 packet;  // RTC_ALIGN(64) in rtcore_ray.h, as rtcOccluded16 requires
    std::uint32_t live = 0;
    for (int i = 0; i < 16; ++i) {
        // Same rule as occluded(): an empty or NaN interval holds nothing (and Embree would leave
        // its tfar as given, read below as a hit when tFar = -inf).
        const bool on = ((activeMask >> i) & 1u) && rays.tNear[i] <= rays.tFar[i];
        valid[i] = on ? -1 : 0;
        live |= std::uint32_t(on) << i;
        packet.org_x[i] = rays.originX[i];
        packet.org_y[i] = rays.originY[i];
        packet.org_z[i] = rays.originZ[i];
        packet.tnear[i] = rays.tNear[i];
        packet.dir_x[i] = rays.directionX[i];
        packet.dir_y[i] = rays.directionY[i];
        packet.dir_z[i] = rays.directionZ[i];
        packet.time[i] = 0.0f;
        packet.tfar[i] = rays.tFar[i];
        packet.mask[i] = std::numeric_limits<unsigned>::max();
        packet.id[i] = static_cast<unsigned>(i);
        packet.flags[i] = 0;
    }
    if (live == 0) return 0;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded16(valid, static_cast<RTCScene>(scene_), &context, &packet);
    std::uint32_t hit = 0;
    for (int i = 0; i < 16; ++i)
        hit |= std::uint32_t(packet.tfar[i] == -std::numeric_limits<float>::infinity()) << i;
    return hit & live;
}

}  // namespace rad
