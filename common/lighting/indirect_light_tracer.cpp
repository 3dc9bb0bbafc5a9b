// See indirect_light_tracer.h for the estimator. This file keeps the 16 lanes of a packet in
// structure-of-arrays form through the whole path (wavefront per packet): every segment is one
// intersect16 and every light one occluded16, so Embree always gets packets.
#include "lighting/indirect_light_tracer.h"

#include "geometry/coordinate_range.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rad {

namespace {

constexpr int kLanes = RayPacket16::kSize;
constexpr float kPi = 3.14159265358979323846f;

bool finite3(const Eigen::Vector3d& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// A unit direction around n distributed with pdf cos / pi (Malley: uniform on the disc, lifted).
void cosineDirection(float nx, float ny, float nz, float u1, float u2, float& dx, float& dy, float& dz) {
    // Orthonormal basis of Duff et al., JCGT 6(1) 2017.
    const float sign = std::copysign(1.0f, nz);
    const float a = -1.0f / (sign + nz);
    const float b = nx * ny * a;
    const float tx = 1.0f + sign * nx * nx * a, ty = sign * b, tz = -sign * nx;
    const float bx = b, by = sign + ny * ny * a, bz = -ny;
    const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
    const float x = r * std::cos(phi), y = r * std::sin(phi);
    const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
    dx = tx * x + bx * y + nx * z;
    dy = ty * x + by * y + ny * z;
    dz = tz * x + bz * y + nz * z;
}

}  // namespace

IndirectLightTracer::IndirectLightTracer(const TriangleMesh& mesh, const std::vector<float>& albedo,
                                         const AnalyticLighting& lights, const IndirectLightSetup& setup)
    : setup_(setup) {
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw IndirectLightError("The scene mesh is invalid: " + problem);
    if (mesh.faceCount() == 0) throw IndirectLightError("The scene has no faces: indirect light needs surfaces to bounce on.");
    // Embree's triangle test overflows near 1e13 (and aborts the process on the rays that follow)
    // and underflows for tiny scenes (every ray misses: an all-zero grid): refuse both first.
    const std::string range = sceneScaleProblem(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(),
                                                mesh.faceCount(), "The scene");
    if (!range.empty()) throw IndirectLightError(range);
    if (!albedo.empty() && albedo.size() != 3 * mesh.vertexCount())
        throw IndirectLightError("The albedo array has " + std::to_string(albedo.size()) + " values for " +
                                 std::to_string(mesh.vertexCount()) + " vertices (3 per vertex expected).");
    if (setup.bounces < 1 || setup.bounces > 16)
        throw IndirectLightError("The bounce count is " + std::to_string(setup.bounces) +
                                 ": choose 1 (one diffuse bounce of the direct light) to 16.");
    if (setup.lightSamples < 0) throw IndirectLightError("The light sample count must be 0 (every light) or more.");
    if (!(setup.relativeRayOffset > 0.0 && setup.relativeRayOffset < 0.01))
        throw IndirectLightError("The ray offset must be a small positive fraction of the scene diagonal, below 0.01.");

    for (const DirectionalLight& d : lights.directional) {
        if (!finite3(d.direction) || !finite3(d.irradiance) || d.irradiance.minCoeff() < 0.0 || d.direction.norm() == 0.0)
            throw IndirectLightError("A directional light has a zero or non-finite direction or a negative or non-finite "
                                     "irradiance: give a non-zero direction and irradiances >= 0.");
        if (d.irradiance.maxCoeff() <= 0.0) continue;
        Light l;
        const Eigen::Vector3d u = d.direction.normalized();
        for (int c = 0; c < 3; ++c) {
            l.direction[c] = float(u[c]);
            l.value[c] = float(d.irradiance[c]);
        }
        lights_.push_back(l);
    }
    for (const PointLight& p : lights.points) {
        if (!finite3(p.position) || !finite3(p.intensity) || p.intensity.minCoeff() < 0.0)
            throw IndirectLightError("A point light has a non-finite position or a negative or non-finite intensity.");
        if (p.intensity.maxCoeff() <= 0.0) continue;
        Light l;
        l.point = true;
        for (int c = 0; c < 3; ++c) {
            l.position[c] = float(p.position[c]);
            l.value[c] = float(p.intensity[c]);
        }
        lights_.push_back(l);
    }
    if (lights_.empty())
        throw IndirectLightError("No light: give an environment map, a directional light or a point light with a "
                                 "positive value (indirect light is the bounce of the direct light).");

    faces_ = mesh.faces;
    const std::size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
    albedo_.resize(3 * nv);
    for (std::size_t i = 0; i < 3 * nv; ++i)
        albedo_[i] = albedo.empty() ? kDefaultIndirectAlbedo : std::clamp(albedo[i], 0.0f, 1.0f);
    faceNormals_.assign(3 * nf, 0.0f);
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (std::size_t v = 0; v < nv; ++v)
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], double(mesh.positions[3 * v + c]));
            hi[c] = std::max(hi[c], double(mesh.positions[3 * v + c]));
        }
    for (std::size_t f = 0; f < nf; ++f) {
        const float* a = &mesh.positions[3 * mesh.faces[3 * f]];
        const float* b = &mesh.positions[3 * mesh.faces[3 * f + 1]];
        const float* c = &mesh.positions[3 * mesh.faces[3 * f + 2]];
        const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0.0)
            for (int k = 0; k < 3; ++k) faceNormals_[3 * f + k] = float(n[k] / len);
    }
    const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(diagonal > 0.0) || !std::isfinite(float(diagonal)))
        throw IndirectLightError("The scene has no extent or one too large for single-precision ray casting.");
    diagonal_ = float(diagonal);
    rayOffset_ = float(setup.relativeRayOffset * diagonal);

    // Selection by power; a point light's irradiance taken at half the scene's diagonal.
    const double r2 = 0.25 * diagonal * diagonal;
    double total = 0.0;
    std::vector<double> power(lights_.size());
    for (std::size_t i = 0; i < lights_.size(); ++i) {
        const float* v = lights_[i].value;
        double p = 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
        if (lights_[i].point) p /= r2;
        power[i] = std::max(p, 1e-12 * (v[0] + v[1] + v[2]));  // a pure blue light is still drawn
        total += power[i];
    }
    double running = 0.0;
    for (std::size_t i = 0; i < lights_.size(); ++i) {
        running += power[i];
        lightProbability_.push_back(float(power[i] / total));
        lightCdf_.push_back(float(running / total));
    }
    lightCdf_.back() = 1.0f;

    scene_ = std::make_unique<RayScene>(mesh.positions.data(), nv, mesh.faces.data(), nf);
}

IndirectLightTracer::~IndirectLightTracer() = default;

void IndirectLightTracer::accumulateDirect(const float* px, const float* py, const float* pz, const float* nx,
                                           const float* ny, const float* nz, const float* weight, std::uint32_t mask,
                                           Pcg32& rng, float* out, IndirectTraceCounts& counts) const {
    // weight[3 * lane]: beta * rho / pi per channel; out[3 * lane] += weight * E_d.
    const bool all = setup_.lightSamples == 0 || lights_.size() <= std::size_t(setup_.lightSamples);
    const int rounds = all ? int(lights_.size()) : setup_.lightSamples;
    const float sampleScale = all ? 1.0f : 1.0f / float(setup_.lightSamples);
    RayPacket16 shadow;
    float contribution[3 * kLanes];
    for (int round = 0; round < rounds; ++round) {
        std::uint32_t active = 0;
        for (std::uint32_t m = mask; m; m &= m - 1u) {
            const int i = __builtin_ctz(m);
            std::size_t index = std::size_t(round);
            float scale = 1.0f;
            if (!all) {
                const float u = rng.uniform();
                index = std::size_t(std::lower_bound(lightCdf_.begin(), lightCdf_.end(), u) - lightCdf_.begin());
                if (index >= lights_.size()) index = lights_.size() - 1;
                scale = sampleScale / lightProbability_[index];
            }
            const Light& l = lights_[index];
            const float ox = px[i] + rayOffset_ * nx[i], oy = py[i] + rayOffset_ * ny[i], oz = pz[i] + rayOffset_ * nz[i];
            float dx, dy, dz, tFar, falloff = 1.0f;
            if (l.point) {
                dx = l.position[0] - ox;
                dy = l.position[1] - oy;
                dz = l.position[2] - oz;
                const float d2 = dx * dx + dy * dy + dz * dz;
                const float d = std::sqrt(d2);
                if (!(d > rayOffset_)) continue;
                dx /= d;
                dy /= d;
                dz /= d;
                tFar = d - rayOffset_;
                falloff = 1.0f / d2;
            } else {
                dx = l.direction[0];
                dy = l.direction[1];
                dz = l.direction[2];
                tFar = std::numeric_limits<float>::infinity();
            }
            const float cosine = dx * nx[i] + dy * ny[i] + dz * nz[i];
            if (!(cosine > 0.0f)) continue;
            for (int c = 0; c < 3; ++c) contribution[3 * i + c] = weight[3 * i + c] * l.value[c] * cosine * falloff * scale;
            shadow.originX[i] = ox;
            shadow.originY[i] = oy;
            shadow.originZ[i] = oz;
            shadow.directionX[i] = dx;
            shadow.directionY[i] = dy;
            shadow.directionZ[i] = dz;
            shadow.tNear[i] = 0.0f;
            shadow.tFar[i] = tFar;
            active |= 1u << i;
        }
        if (!active) continue;
        counts.rays += std::uint64_t(__builtin_popcount(active));
        std::uint32_t lit = active & ~scene_->occluded16(shadow, active);
        for (; lit; lit &= lit - 1u) {
            const int i = __builtin_ctz(lit);
            for (int c = 0; c < 3; ++c) out[3 * i + c] += contribution[3 * i + c];
        }
    }
}

void IndirectLightTracer::trace(const RayPacket16& rays, std::uint32_t activeMask, Pcg32& rng,
                                float radiance[3 * RayPacket16::kSize], std::uint32_t& backFaceMask,
                                IndirectTraceCounts& counts) const {
    activeMask &= 0xffffu;
    std::fill(radiance, radiance + 3 * kLanes, 0.0f);
    backFaceMask = 0;
    RayPacket16 segment = rays;
    RayHit hits[kLanes];
    float px[kLanes], py[kLanes], pz[kLanes], nx[kLanes], ny[kLanes], nz[kLanes];
    float beta[3 * kLanes], rho[3 * kLanes], weight[3 * kLanes];
    for (int i = 0; i < 3 * kLanes; ++i) beta[i] = 1.0f;
    std::uint32_t alive = activeMask;
    for (int bounce = 1; bounce <= setup_.bounces && alive; ++bounce) {
        counts.rays += std::uint64_t(__builtin_popcount(alive));
        scene_->intersect16(segment, alive, hits);
        std::uint32_t front = 0;
        for (std::uint32_t m = alive; m; m &= m - 1u) {
            const int i = __builtin_ctz(m);
            if (!hits[i].hit) {
                if (bounce == 1) ++counts.escaped;
                continue;
            }
            const std::uint32_t f = hits[i].face;
            const float* n = &faceNormals_[3 * f];
            const float cosine = n[0] * segment.directionX[i] + n[1] * segment.directionY[i] + n[2] * segment.directionZ[i];
            if (!(cosine < 0.0f)) {  // back face (or a degenerate face, zero normal): no light, path ends
                if (bounce == 1) {
                    backFaceMask |= 1u << i;
                    ++counts.backFaces;
                }
                continue;
            }
            const float t = hits[i].distance;
            px[i] = segment.originX[i] + t * segment.directionX[i];
            py[i] = segment.originY[i] + t * segment.directionY[i];
            pz[i] = segment.originZ[i] + t * segment.directionZ[i];
            nx[i] = n[0];
            ny[i] = n[1];
            nz[i] = n[2];
            const float u = hits[i].u, v = hits[i].v, w = 1.0f - u - v;
            const float* a0 = &albedo_[3 * faces_[3 * f]];
            const float* a1 = &albedo_[3 * faces_[3 * f + 1]];
            const float* a2 = &albedo_[3 * faces_[3 * f + 2]];
            for (int c = 0; c < 3; ++c) {
                rho[3 * i + c] = w * a0[c] + u * a1[c] + v * a2[c];
                weight[3 * i + c] = beta[3 * i + c] * rho[3 * i + c] * (1.0f / kPi);
            }
            front |= 1u << i;
        }
        if (!front) break;
        accumulateDirect(px, py, pz, nx, ny, nz, weight, front, rng, radiance, counts);
        if (bounce == setup_.bounces) break;
        // Continue every front-hit path: throughput times rho, a cosine-distributed direction.
        alive = 0;
        for (std::uint32_t m = front; m; m &= m - 1u) {
            const int i = __builtin_ctz(m);
            for (int c = 0; c < 3; ++c) beta[3 * i + c] *= rho[3 * i + c];
            if (beta[3 * i] == 0.0f && beta[3 * i + 1] == 0.0f && beta[3 * i + 2] == 0.0f) continue;
            float dx, dy, dz;
            const float u1 = rng.uniform(), u2 = rng.uniform();
            cosineDirection(nx[i], ny[i], nz[i], u1, u2, dx, dy, dz);
            segment.originX[i] = px[i] + rayOffset_ * nx[i];
            segment.originY[i] = py[i] + rayOffset_ * ny[i];
            segment.originZ[i] = pz[i] + rayOffset_ * nz[i];
            segment.directionX[i] = dx;
            segment.directionY[i] = dy;
            segment.directionZ[i] = dz;
            segment.tNear[i] = 0.0f;
            segment.tFar[i] = std::numeric_limits<float>::infinity();
            alive |= 1u << i;
        }
    }
}

bool IndirectLightTracer::firstHit(const float origin[3], const float direction[3], float point[3], float faceNormal[3],
                                   float albedo[3], bool& backFace) const {
    const RayHit h = scene_->intersect(Eigen::Vector3f(origin[0], origin[1], origin[2]),
                                       Eigen::Vector3f(direction[0], direction[1], direction[2]), 0.0f,
                                       std::numeric_limits<float>::infinity());
    if (!h.hit) return false;
    const std::uint32_t f = h.face;
    for (int c = 0; c < 3; ++c) {
        point[c] = origin[c] + h.distance * direction[c];
        faceNormal[c] = faceNormals_[3 * f + c];
    }
    backFace = !(faceNormal[0] * direction[0] + faceNormal[1] * direction[1] + faceNormal[2] * direction[2] < 0.0f);
    const float u = h.u, v = h.v, w = 1.0f - u - v;
    const float* a0 = &albedo_[3 * faces_[3 * f]];
    const float* a1 = &albedo_[3 * faces_[3 * f + 1]];
    const float* a2 = &albedo_[3 * faces_[3 * f + 2]];
    for (int c = 0; c < 3; ++c) albedo[c] = w * a0[c] + u * a1[c] + v * a2[c];
    return true;
}

void IndirectLightTracer::directIrradiance(const float point[3], const float normal[3], float out[3]) const {
    out[0] = out[1] = out[2] = 0.0f;
    const Eigen::Vector3f o(point[0] + rayOffset_ * normal[0], point[1] + rayOffset_ * normal[1],
                            point[2] + rayOffset_ * normal[2]);
    for (const Light& l : lights_) {
        Eigen::Vector3f d;
        float tFar = std::numeric_limits<float>::infinity(), falloff = 1.0f;
        if (l.point) {
            d = Eigen::Vector3f(l.position[0], l.position[1], l.position[2]) - o;
            const float distance = d.norm();
            if (!(distance > rayOffset_)) continue;
            d /= distance;
            tFar = distance - rayOffset_;
            falloff = 1.0f / (distance * distance);
        } else {
            d = Eigen::Vector3f(l.direction[0], l.direction[1], l.direction[2]);
        }
        const float cosine = d[0] * normal[0] + d[1] * normal[1] + d[2] * normal[2];
        if (!(cosine > 0.0f) || scene_->occluded(o, d, 0.0f, tFar)) continue;
        for (int c = 0; c < 3; ++c) out[c] += l.value[c] * cosine * falloff;
    }
}

}  // namespace rad
