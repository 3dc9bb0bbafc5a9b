// bakeNormalMapFiles (bake/normal_map_bake.h): inputs that used to give silent or fatal results.
#include "bake/normal_map_bake.h"

#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Folder {
    fs::path path;
    explicit Folder(const std::string& name) : path(fs::temp_directory_path() / name) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~Folder() { fs::remove_all(path); }
    bool empty() const { return fs::is_empty(path); }
};

rad::NormalMapBakeRequest request(const rad::TriangleMesh& target, const rad::TriangleMesh& source, const Folder& out) {
    rad::NormalMapBakeRequest r;
    r.target = &target;
    r.source = &source;
    r.textureSize = 256;
    r.writeLean = false;
    r.outputBase = (out.path / "baked").string();
    return r;
}

TEST(NormalMapBake, SourceThatNeverMeetsTheTargetIsRefusedNotWrittenAsAConstantMap) {
    rad::TriangleMesh target = rad::makeIcosphere(1), source = rad::makeIcosphere(3);
    rad::computeAreaWeightedNormals(target);
    for (std::size_t i = 0; i < source.positions.size(); i += 3) source.positions[i] += 1000.0f;  // far away
    const Folder out("radiance_bake_far_source");
    rad::NormalMapBakeRequest r = request(target, source, out);
    r.maxRayDistance = 0.5f;
    try {
        rad::bakeNormalMapFiles(r);
        FAIL() << "a bake that found nothing succeeded";
    } catch (const rad::BakeInputError& e) {
        EXPECT_NE(std::string(e.what()).find("do not overlap"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(out.empty()) << "files written by a refused bake";
}

TEST(NormalMapBake, HugeCoordinatesAreRefusedBeforeEmbreeSeesThem) {
    // Embree aborts the process on rays with coordinates beyond ~1.8e18: refused first, with the fix.
    rad::TriangleMesh target = rad::makeIcosphere(1), source = rad::makeIcosphere(2);
    for (float& x : target.positions) x *= 1e19f;
    for (float& x : source.positions) x *= 1e19f;
    rad::computeAreaWeightedNormals(target);
    const Folder out("radiance_bake_huge");
    try {
        rad::bakeNormalMapFiles(request(target, source, out));
        FAIL() << "coordinates of 1e19 accepted";
    } catch (const rad::BakeInputError& e) {
        EXPECT_NE(std::string(e.what()).find("Transform: Scale, Normalize"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(out.empty());
}

}  // namespace
