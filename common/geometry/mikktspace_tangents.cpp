// MikkTSpace tangents (Mikkelsen 2008): mikktspace_tangents.h says what is computed. The steps
// and their order follow the reference implementation's behaviour, including the one order
// dependency it has (a triangle without usable UV derivatives takes the orientation of the first
// group that reaches it), so that the results agree with Blender's to float rounding. Arithmetic
// is in float, as in the reference: the thresholds (FLT_MIN tests) then decide the same way.
#include "geometry/mikktspace_tangents.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

namespace rad {

namespace {

struct V3 {
    float x = 0, y = 0, z = 0;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(float s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
float length(V3 a) { return std::sqrt(dot(a, a)); }
bool same(V3 a, V3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
bool notZero(float f) { return std::fabs(f) > FLT_MIN; }
bool notZero(V3 v) { return notZero(v.x) || notZero(v.y) || notZero(v.z); }
V3 normalized(V3 v) { return (1.0f / length(v)) * v; }
// v without its component along unit n, normalised when not zero.
V3 projectedUnit(V3 v, V3 n) {
    V3 p = v - dot(n, v) * n;
    return notZero(p) ? normalized(p) : p;
}

enum : unsigned { kDegenerate = 1, kGroupWithAny = 4, kOrientPreserving = 8 };

struct Triangle {
    unsigned flags = kGroupWithAny;
    V3 os;                      // unit dP/ds times the sign of the UV area
    int neighbor[3] = {-1, -1, -1};  // across edge k = (corner k, corner k + 1)
    int group[3] = {-1, -1, -1};     // group of corner k
};

struct Group {
    int vertex = 0;  // welded vertex id
    bool orientPreserving = false;
};

// Bits of a float with -0 taken as +0 (the reference compares with ==).
std::uint32_t keyBits(float f) {
    if (f == 0.0f) f = 0.0f;
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return bits;
}

struct CornerKey {
    std::uint32_t v[8];
    bool operator==(const CornerKey& o) const { return std::memcmp(v, o.v, sizeof v) == 0; }
};
struct CornerKeyHash {
    std::size_t operator()(const CornerKey& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (std::uint32_t x : k.v) h = (h ^ x) * 1099511628211ull;
        return std::size_t(h ^ (h >> 29));
    }
};

class Corners {
public:
    explicit Corners(const TangentSpaceInput& in) : in_(in) {}
    V3 position(std::size_t c) const { return read3(in_.positions, in_.faces[c]); }
    V3 normal(std::size_t c) const {
        return read3(in_.normals, in_.normalRate == AttributeRate::PerCorner ? c : in_.faces[c]);
    }
    void uv(std::size_t c, float& s, float& t) const {
        const std::size_t i = in_.uvRate == AttributeRate::PerCorner ? c : in_.faces[c];
        s = in_.uv[2 * i];
        t = in_.uv[2 * i + 1];
    }

private:
    static V3 read3(const float* a, std::size_t i) { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }
    const TangentSpaceInput& in_;
};

void checkInput(const TangentSpaceInput& in) {
    if (in.faceCount == 0) return;
    if (!in.positions || !in.faces)
        throw TangentSpaceInputError("Tangents need the mesh's positions and faces.");
    if (!in.normals)
        throw TangentSpaceInputError("Tangents need normals: compute the vertex normals first ({{Re-Compute Vertex "
                                     "Normals}}).");
    if (!in.uv)
        throw TangentSpaceInputError("Tangents need texture coordinates: the mesh has none (parametrize it first).");
    for (std::size_t i = 0; i < 3 * in.faceCount; ++i)
        if (in.faces[i] >= in.vertexCount)
            throw TangentSpaceInputError("Face " + std::to_string(i / 3) + " refers to vertex " +
                                         std::to_string(in.faces[i]) + " of a mesh of " +
                                         std::to_string(in.vertexCount) + " vertices.");
}

// Every triangle around welded vertex `group.vertex` reachable from `start` through edges that
// contain that vertex, with the group's orientation (the reference's recursive assignment, with
// an explicit stack in the same visiting order: the neighbour across the corner's outgoing edge
// and all it reaches first, then the one across its incoming edge).
void assignGroup(std::vector<Triangle>& tri, const std::vector<int>& welded, int start, int groupId, const Group& group) {
    std::vector<int> stack{start};
    while (!stack.empty()) {
        const int f = stack.back();
        stack.pop_back();
        Triangle& t = tri[f];
        int k = -1;
        for (int j = 0; j < 3; ++j)
            if (welded[3 * f + j] == group.vertex) k = j;
        if (k < 0 || t.group[k] >= 0) continue;
        if ((t.flags & kGroupWithAny) && t.group[0] < 0 && t.group[1] < 0 && t.group[2] < 0)
            t.flags = group.orientPreserving ? (t.flags | kOrientPreserving) : (t.flags & ~kOrientPreserving);
        if (((t.flags & kOrientPreserving) != 0) != group.orientPreserving) continue;
        t.group[k] = groupId;
        const int left = t.neighbor[k], right = t.neighbor[k > 0 ? k - 1 : 2];
        if (right >= 0) stack.push_back(right);
        if (left >= 0) stack.push_back(left);
    }
}

struct Frame {
    V3 os;
    bool orientPreserving = false;
};

// The frame of every corner, and whether a group reached it.
struct CornerFrames {
    std::vector<Frame> frame;
    std::vector<std::uint8_t> reached;
};

// Welding: corners with identical position, normal and UV share an id (the first such corner).
std::vector<int> weldCorners(const Corners& corners, std::size_t cornerCount) {
    std::vector<int> welded(cornerCount);
    std::unordered_map<CornerKey, int, CornerKeyHash> first;
    first.reserve(cornerCount);
    for (std::size_t c = 0; c < cornerCount; ++c) {
        const V3 p = corners.position(c), n = corners.normal(c);
        float s, t;
        corners.uv(c, s, t);
        const CornerKey key{{keyBits(p.x), keyBits(p.y), keyBits(p.z), keyBits(n.x), keyBits(n.y), keyBits(n.z),
                             keyBits(s), keyBits(t)}};
        welded[c] = first.emplace(key, int(c)).first->second;
    }
    return welded;
}

// Degenerate triangles (two welded corners at one position); the UV derivatives and orientation
// of the others. Counts both kinds of trouble into `result`.
std::vector<Triangle> classifyTriangles(const Corners& corners, const std::vector<int>& welded, std::size_t faceCount,
                                        CornerTangents& result) {
    std::vector<Triangle> tri(faceCount);
    for (std::size_t f = 0; f < faceCount; ++f) {
        Triangle& t = tri[f];
        const V3 p1 = corners.position(welded[3 * f]), p2 = corners.position(welded[3 * f + 1]),
                 p3 = corners.position(welded[3 * f + 2]);
        if (same(p1, p2) || same(p1, p3) || same(p2, p3)) {
            t.flags |= kDegenerate;
            ++result.degenerateTriangles;
            continue;
        }
        float s1, t1, s2, t2, s3, t3;
        corners.uv(welded[3 * f], s1, t1);
        corners.uv(welded[3 * f + 1], s2, t2);
        corners.uv(welded[3 * f + 2], s3, t3);
        const float t21x = s2 - s1, t21y = t2 - t1, t31x = s3 - s1, t31y = t3 - t1;
        const V3 d1 = p2 - p1, d2 = p3 - p1;
        const float signedArea = t21x * t31y - t21y * t31x;
        const V3 os = t31y * d1 - t21y * d2;      // dP/ds times the UV area (reference eq. 18)
        const V3 ot = (-t31x) * d1 + t21x * d2;   // dP/dt times the UV area (eq. 19): only its length matters
        if (signedArea > 0) t.flags |= kOrientPreserving;
        if (notZero(signedArea)) {
            const float lenOs2 = dot(os, os), lenOt2 = dot(ot, ot);
            const float sign = (t.flags & kOrientPreserving) ? 1.0f : -1.0f;
            if (notZero(lenOs2)) t.os = (sign / std::sqrt(lenOs2)) * os;
            if (notZero(lenOs2) && notZero(lenOt2)) t.flags &= ~kGroupWithAny;
        }
        if (t.flags & kGroupWithAny) ++result.zeroUvAreaTriangles;
    }
    return tri;
}

// Neighbours across edges (welded ids) of good triangles: sorted by (min id, max id, face), each
// edge paired with the first later one running the other way and still unpaired.
void findNeighbours(std::vector<Triangle>& tri, const std::vector<int>& welded) {
    struct Edge {
        int lo, hi, face, k;
    };
    std::vector<Edge> edges;
    edges.reserve(welded.size());
    for (std::size_t f = 0; f < tri.size(); ++f) {
        if (tri[f].flags & kDegenerate) continue;
        for (int k = 0; k < 3; ++k) {
            const int a = welded[3 * f + k], b = welded[3 * f + (k + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b), int(f), k});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
        return a.lo != b.lo ? a.lo < b.lo : a.hi != b.hi ? a.hi < b.hi : a.face < b.face;
    });
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const Edge& a = edges[i];
        if (tri[a.face].neighbor[a.k] >= 0) continue;
        const int aFrom = welded[3 * a.face + a.k];
        for (std::size_t j = i + 1; j < edges.size() && edges[j].lo == a.lo && edges[j].hi == a.hi; ++j) {
            const Edge& b = edges[j];
            const int bFrom = welded[3 * b.face + b.k];
            if (bFrom != aFrom && tri[b.face].neighbor[b.k] < 0) {
                tri[a.face].neighbor[a.k] = b.face;
                tri[b.face].neighbor[b.k] = a.face;
                break;
            }
        }
    }
}

// Groups: per corner of a good triangle not yet in one, a new group and all it reaches.
std::vector<Group> buildGroups(std::vector<Triangle>& tri, const std::vector<int>& welded) {
    std::vector<Group> groups;
    for (std::size_t f = 0; f < tri.size(); ++f) {
        if (tri[f].flags & kDegenerate) continue;
        // A triangle without UV derivatives never starts a group (Blender's rule; the original
        // reference code let it start one with its own orientation): it only joins its
        // neighbours' groups.
        if (tri[f].flags & kGroupWithAny) continue;
        for (int k = 0; k < 3; ++k) {
            if (tri[f].group[k] >= 0) continue;
            Group g;
            g.vertex = welded[3 * f + k];
            g.orientPreserving = (tri[f].flags & kOrientPreserving) != 0;
            const int id = int(groups.size());
            assignGroup(tri, welded, int(f), id, g);
            groups.push_back(std::move(g));
        }
    }
    return groups;
}

// Angle-weighted sum of the projected unit dP/ds of each group's good triangles (Mikkelsen 2008,
// sec. 4), in increasing triangle order (the order of the float sums in Blender's).
std::vector<V3> sumGroupTangents(const Corners& corners, const std::vector<int>& welded,
                                 const std::vector<Triangle>& tri, std::size_t groupCount) {
    std::vector<V3> groupSum(groupCount);
    for (std::size_t f = 0; f < tri.size(); ++f) {
        const Triangle& t = tri[f];
        if (t.flags & (kDegenerate | kGroupWithAny)) continue;
        for (int k = 0; k < 3; ++k) {
            if (t.group[k] < 0) continue;
            const std::size_t c = 3 * f + k;
            const V3 n = corners.normal(welded[c]);
            const V3 p0 = corners.position(welded[3 * f + (k > 0 ? k - 1 : 2)]);
            const V3 p1 = corners.position(welded[c]);
            const V3 p2 = corners.position(welded[3 * f + (k < 2 ? k + 1 : 0)]);
            const V3 v1 = projectedUnit(p0 - p1, n), v2 = projectedUnit(p2 - p1, n);
            const float angle = std::acos(std::clamp(dot(v1, v2), -1.0f, 1.0f));
            groupSum[t.group[k]] = groupSum[t.group[k]] + angle * projectedUnit(t.os, n);
        }
    }
    return groupSum;
}

// Frames per corner: its group's normalised sum and orientation. A corner no group reaches (every
// triangle around it lacks UV derivatives) keeps the convention's default, as Blender writes it:
// T = (1, 0, 0), sign -1.
CornerFrames groupFrames(const std::vector<Triangle>& tri, const std::vector<Group>& groups,
                         const std::vector<V3>& groupSum) {
    const std::size_t cornerCount = 3 * tri.size();
    CornerFrames frames{std::vector<Frame>(cornerCount, Frame{V3{1.0f, 0.0f, 0.0f}, false}),
                        std::vector<std::uint8_t>(cornerCount, 0)};
    for (std::size_t f = 0; f < tri.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const int g = tri[f].group[k];
            if (g < 0) continue;
            const V3 sum = groupSum[g];
            frames.frame[3 * f + k] = Frame{notZero(sum) ? normalized(sum) : sum, groups[g].orientPreserving};
            frames.reached[3 * f + k] = 1;
        }
    }
    return frames;
}

// Degenerate triangles: the frame of the first good corner of the same (welded) vertex.
void copyFramesToDegenerateTriangles(const std::vector<Triangle>& tri, const std::vector<int>& welded,
                                     CornerFrames& frames) {
    const std::size_t cornerCount = welded.size();
    std::unordered_map<int, std::size_t> firstGood;
    for (std::size_t c = 0; c < cornerCount; ++c)
        if (!(tri[c / 3].flags & kDegenerate)) firstGood.emplace(welded[c], c);
    for (std::size_t c = 0; c < cornerCount; ++c) {
        if (!(tri[c / 3].flags & kDegenerate)) continue;
        const auto it = firstGood.find(welded[c]);
        if (it != firstGood.end()) {
            frames.frame[c] = frames.frame[it->second];
            frames.reached[c] = frames.reached[it->second];
        }
    }
}

// The frames as (x, y, z, sign) per corner, with the counts of default and zero tangents.
void writeCornerTangents(CornerFrames& frames, CornerTangents& result) {
    for (std::size_t c = 0; c < frames.frame.size(); ++c) {
        float* out = result.tangents.data() + 4 * c;
        const Frame& frame = frames.frame[c];
        out[0] = frame.os.x;
        out[1] = frame.os.y;
        out[2] = frame.os.z;
        out[3] = frame.orientPreserving ? 1.0f : -1.0f;
        if (!frames.reached[c]) ++result.defaultFrameCorners;
        else if (!notZero(frame.os)) ++result.zeroTangentCorners;
    }
    result.reached = std::move(frames.reached);
}

}  // namespace

CornerTangents computeMikkTSpaceTangents(const TangentSpaceInput& input) {
    checkInput(input);
    CornerTangents result;
    const std::size_t faceCount = input.faceCount, cornerCount = 3 * faceCount;
    result.tangents.assign(4 * cornerCount, 0.0f);
    if (faceCount == 0) return result;
    const Corners corners(input);

    const std::vector<int> welded = weldCorners(corners, cornerCount);
    std::vector<Triangle> tri = classifyTriangles(corners, welded, faceCount, result);
    findNeighbours(tri, welded);
    const std::vector<Group> groups = buildGroups(tri, welded);
    const std::vector<V3> groupSum = sumGroupTangents(corners, welded, tri, groups.size());
    CornerFrames frames = groupFrames(tri, groups, groupSum);
    if (result.degenerateTriangles > 0) copyFramesToDegenerateTriangles(tri, welded, frames);
    writeCornerTangents(frames, result);
    return result;
}

std::size_t completeTangents(CornerTangents& result, const TangentSpaceInput& input) {
    const Corners corners(input);
    std::size_t replaced = 0;
    for (std::size_t c = 0; c < 3 * input.faceCount; ++c) {
        float* t = result.tangents.data() + 4 * c;
        const float squared = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
        const bool defaultFrame = c < result.reached.size() && !result.reached[c];
        if (!defaultFrame && std::isfinite(squared) && squared > 1e-12f) continue;
        V3 n = corners.normal(c);
        if (!(length(n) > 0) || !std::isfinite(length(n))) n = V3{0, 0, 1};
        n = normalized(n);
        // Gram-Schmidt of the coordinate axis least aligned with n.
        const V3 axis = std::fabs(n.x) < 0.9f ? V3{1, 0, 0} : V3{0, 1, 0};
        const V3 o = normalized(axis - dot(axis, n) * n);
        t[0] = o.x;
        t[1] = o.y;
        t[2] = o.z;
        if (defaultFrame) {
            t[3] = 1.0f;
            result.reached[c] = 1;
        } else if (!(t[3] == 1.0f || t[3] == -1.0f)) {
            t[3] = 1.0f;
        }
        ++replaced;
    }
    result.zeroTangentCorners = 0;
    result.defaultFrameCorners = 0;
    return replaced;
}

}  // namespace rad
