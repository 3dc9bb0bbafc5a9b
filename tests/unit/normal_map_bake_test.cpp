// bakeNormalMapFiles (bake/normal_map_bake.h): inputs that used to give silent or fatal results.
#include "bake/normal_map_bake.h"

#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace {

using Folder = radtest::TemporaryFolder;

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

TEST(NormalMapBake, EstimatedMemoryGrowsWithTheMapsWritten) {
    rad::TriangleMesh mesh = rad::makeIcosphere(1);
    std::vector<float> colours(3 * mesh.vertexCount(), 0.5f);
    rad::NormalMapBakeRequest r;
    r.textureSize = 4096;
    r.writeLean = false;
    const std::size_t plain = rad::estimatedBakeBytes(r);
    // Measured peaks (pymeshlab, 4096^2): 622 MB plain, 814 MB with the diffuse map, 1139 MB with LEAN
    // too. The estimate must cover each with a margin of at most 25 %.
    EXPECT_GE(plain, 622u << 20);
    EXPECT_LE(plain, std::size_t(1.25 * (622u << 20)));
    r.sourceColors = &colours;
    const std::size_t diffuse = rad::estimatedBakeBytes(r);
    EXPECT_GE(diffuse, 814u << 20);
    r.writeLean = true;
    const std::size_t both = rad::estimatedBakeBytes(r);
    EXPECT_GE(both, 1139u << 20);
    EXPECT_LE(both, std::size_t(1.25 * (1139u << 20)));
    r.space = rad::NormalSpace::Tangent;  // no LEAN maps in tangent space
    EXPECT_EQ(rad::estimatedBakeBytes(r), diffuse);
}

TEST(NormalMapBake, BakeBeyondTheMemoryLimitIsRefusedWithTheSizeThatFits) {
    rad::TriangleMesh target = rad::makeIcosphere(1), source = rad::makeIcosphere(3);
    rad::computeAreaWeightedNormals(target);
    const Folder out("radiance_bake_memory");
    rad::NormalMapBakeRequest r = request(target, source, out);
    r.textureSize = 4096;
    r.memoryLimitBytes = 100u << 20;  // 100 MB: 1024^2 (1.1 x 39 B x 2^20 = 45 MB) fits, 2048^2 (180 MB) does not; 4096^2 is 720 MB
    try {
        rad::bakeNormalMapFiles(r);
        FAIL() << "a bake beyond the memory limit ran";
    } catch (const rad::BakeInputError& e) {
        const std::string text = e.what();
        EXPECT_NE(text.find("A 4096 x 4096 bake needs about 720 MB of memory and 105 MB are available"),
                  std::string::npos) << text;
        EXPECT_NE(text.find("choose a texture size of 1024 or less"), std::string::npos) << text;
    }
    EXPECT_TRUE(out.empty());
    r.textureSize = 1024;  // the advice, followed, works
    EXPECT_NO_THROW(rad::bakeNormalMapFiles(r));
}

}  // namespace
