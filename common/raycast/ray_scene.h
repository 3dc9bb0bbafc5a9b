// Ray casting against a triangle mesh with Embree (Debian's libembree-dev, Embree 3): the one
// place that talks to Embree, used for visibility in the fitting, shadows and primary rays in the
// virtual acquisition and the CPU renderers, and later PRT transfer and normal-map baking.
//
// Every query is const and thread-safe (Embree allows concurrent rtcIntersect1/rtcIntersect16/
// rtcOccluded1/rtcOccluded16 on a committed scene); the scene holds its own copy of the geometry.
#pragma once

#include "errors/error_categories.h"

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace rad {

struct RayHit {
    bool hit = false;
    float distance = 0.0f;      // t along the (unit or not) ray direction
    std::uint32_t face = 0;     // triangle index in the input face array
    float u = 0.0f, v = 0.0f;   // barycentrics: point = (1 - u - v) a + u b + v c of face (a, b, c)
};

// Up to 16 rays in structure-of-arrays layout, the input of RayScene::occluded16. Aligned like
// Embree's RTCRay16 so that the copy into it is a few aligned vector moves. Ray i is
// origin_i + t * direction_i for t in [tNear_i, tFar_i]; lanes not in the active mask are ignored
// (need not be initialised).
struct alignas(64) RayPacket16 {
    static constexpr int kSize = 16;
    float originX[kSize], originY[kSize], originZ[kSize];
    float directionX[kSize], directionY[kSize], directionZ[kSize];
    float tNear[kSize], tFar[kSize];
};

// The point of the mesh nearest to a query point (RayScene::closestPoint).
struct ClosestPoint {
    bool found = false;
    float distance = 0.0f;
    std::uint32_t face = 0;
    float u = 0.0f, v = 0.0f;   // barycentrics, as in RayHit
    Eigen::Vector3f point = Eigen::Vector3f::Zero();
};

struct RayCastError : ResourceError {
    using ResourceError::ResourceError;
};

// Embree's BVH build: High (spatial splits, the fastest traversal) pays off when many rays are
// cast per triangle; Medium builds several times faster, for scenes that see few rays.
enum class SceneBuildQuality { Medium, High };

class RayScene {
public:
    // positions: 3 * vertexCount floats; faces: 3 * faceCount indices (validated by the caller).
    // Throws RayCastError when Embree cannot create the device or the scene.
    RayScene(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount,
             SceneBuildQuality quality = SceneBuildQuality::High);
    ~RayScene();
    RayScene(const RayScene&) = delete;
    RayScene& operator=(const RayScene&) = delete;

    // Closest hit of origin + t * direction for t in [tNear, tFar]. Rays Embree would abort the
    // process on (an origin or direction component beyond 1.844e18 or NaN) hit and occlude
    // nothing, in every query below; a hit at a non-finite distance (the overflow of Embree's
    // triangle test far beyond kMaxCoordinateMagnitude, geometry/coordinate_range.h) is a miss.
    RayHit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tNear, float tFar) const;
    // Whether anything is hit for t in [tNear, tFar] (any hit, faster than intersect).
    bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tNear, float tFar) const;

    // The nearest point of the mesh to `query` within maxDistance (Embree's BVH point query
    // with an exact point-triangle distance, Ericson, Real-Time Collision Detection, 5.1.5).
    // found = false when the mesh is empty or nothing lies within maxDistance.
    ClosestPoint closestPoint(const Eigen::Vector3f& query,
                              float maxDistance = std::numeric_limits<float>::infinity()) const;

    // Packet form of occluded(): one Embree packet query (rtcOccluded16) for the rays of `rays`
    // whose bit is set in activeMask (bit i = lane i, bits >= 16 ignored). Returns the mask of the
    // active rays that are occluded; lane by lane the same answer as occluded() (an empty or NaN
    // interval is never occluded). Cheaper per ray than occluded() when the 16 rays are coherent
    // (e.g. one origin, a hemisphere of directions: PRT transfer).
    std::uint32_t occluded16(const RayPacket16& rays, std::uint32_t activeMask) const;

    // Packet form of intersect(): closest hits of the rays of `rays` whose bit is set in
    // activeMask (one rtcIntersect16). hits[i] is lane i's answer, the same as intersect() gives
    // (hit = false for inactive lanes and for empty or NaN intervals). Cheaper per ray than
    // intersect() for coherent rays (e.g. the texels of a tile of a normal-map bake).
    void intersect16(const RayPacket16& rays, std::uint32_t activeMask, RayHit hits[RayPacket16::kSize]) const;

    std::size_t faceCount() const { return faceCount_; }

private:
    void* device_ = nullptr;  // RTCDevice
    void* scene_ = nullptr;   // RTCScene
    std::size_t faceCount_ = 0;
    const float* vertices_ = nullptr;           // Embree's copy of the positions (3 floats each)
    const std::uint32_t* indices_ = nullptr;    // Embree's copy of the faces
};

}  // namespace rad
