#include "simplify/progressive_mesh.h"

#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"
#include "radiance/material_radiance.h"
#include "io/radiance_ply.h"
#include "simplify/radiance_simplification.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <cstring>
#include <set>
#include <sstream>
#include <string>

namespace {

using rad::CollapseKind;

rad::RadianceMesh sphereWithRadiance(int level, rad::BasisSpec basis) {
    rad::TriangleMesh sphere = rad::makeIcosphere(level);
    rad::computeAreaWeightedNormals(sphere);
    rad::AnalyticMaterial material;
    material.exponent = 20.0;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.3, 0.5, 1.0), rad::Rgb(1.0, 0.9, 0.8)});
    rad::MaterialRadianceOptions options;
    options.basis = basis;
    rad::RadianceMesh mesh;
    mesh.positions = sphere.positions;
    mesh.faces = sphere.faces;
    mesh.radiance = rad::makeMaterialRadiance(sphere.positions.data(), sphere.normals.data(), sphere.vertexCount(),
                                              material, lighting, options);
    mesh.normals = std::vector<float>();
    mesh.quality.resize(mesh.vertexCount());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) mesh.quality[v] = static_cast<float>(v);
    return mesh;
}

// Faces as a set of position triples (rotated so the smallest vertex comes first, orientation kept),
// independent of vertex numbering.
std::set<std::vector<float>> faceSet(const std::vector<float>& p, const std::vector<std::uint32_t>& f) {
    std::set<std::vector<float>> out;
    for (std::size_t i = 0; i < f.size() / 3; ++i) {
        std::vector<std::vector<float>> corners;
        for (int k = 0; k < 3; ++k) corners.push_back({p[3 * f[3 * i + k]], p[3 * f[3 * i + k] + 1], p[3 * f[3 * i + k] + 2]});
        const auto smallest = std::min_element(corners.begin(), corners.end()) - corners.begin();
        std::vector<float> key;
        for (int k = 0; k < 3; ++k) {
            const auto& c = corners[(smallest + k) % 3];
            key.insert(key.end(), c.begin(), c.end());
        }
        out.insert(key);
    }
    return out;
}

TEST(ProgressiveMesh, ReplayReproducesEveryIntermediateMesh) {
    for (CollapseKind kind : {CollapseKind::HalfEdge, CollapseKind::Full}) {
        const rad::RadianceMesh original = sphereWithRadiance(3, {rad::BasisKind::SphericalHarmonics, 3});
        rad::CollapseMesh mesh(original.positions.data(), original.vertexCount(), original.faces.data(),
                               original.faceCount());
        rad::ProgressiveRadianceMesh progressive;
        progressive.base = original;
        progressive.kind = kind;
        rad::RadianceField field = *original.radiance;  // geometry-only: rows stay v1's
        rad::ProgressiveRecorder recorder(progressive, &field);
        const std::size_t checkpoints[] = {1, 37, 200};
        std::vector<std::set<std::vector<float>>> snapshots;
        rad::EdgeCollapseOptions options;
        options.kind = kind;
        options.targetFaceCount = 300;
        rad::simplifyByEdgeCollapse(mesh, nullptr, options, [&](const rad::CollapseStep& s) {
            recorder(s);
            if (std::find(std::begin(checkpoints), std::end(checkpoints), progressive.steps.size()) != std::end(checkpoints)) {
                std::vector<float> p;
                std::vector<std::uint32_t> f, map;
                mesh.compact(p, f, map);
                snapshots.push_back(faceSet(p, f));
            }
        });
        ASSERT_EQ(snapshots.size(), 3u);
        for (int i = 0; i < 3; ++i) {
            const rad::RadianceMesh lod = progressive.extract(checkpoints[i]);
            EXPECT_EQ(faceSet(lod.positions, lod.faces), snapshots[i]) << "kind " << int(kind) << " step " << checkpoints[i];
            EXPECT_EQ(lod.faceCount(), progressive.faceCountAfter[checkpoints[i] - 1]);
            EXPECT_TRUE(rad::validateRadianceMesh(lod).empty()) << rad::validateRadianceMesh(lod);
        }
        // Per-vertex data follows the vertices: quality was the original index.
        const rad::RadianceMesh last = progressive.extract(progressive.steps.size());
        std::set<float> removed;
        for (const rad::CollapseStep& s : progressive.steps) removed.insert(static_cast<float>(s.removed));
        for (float q : last.quality) EXPECT_EQ(removed.count(q), 0u);
        EXPECT_EQ(last.vertexCount() + progressive.steps.size(), original.vertexCount());
        // Zero steps is the original.
        EXPECT_EQ(progressive.extract(0).faces, original.faces);
    }
}

TEST(ProgressiveMesh, StepsForFaceCount) {
    rad::ProgressiveRadianceMesh p;
    p.base.faces.resize(3 * 10);
    p.steps.resize(4);
    p.faceCountAfter = {8, 6, 4, 2};
    EXPECT_EQ(p.stepsForFaceCount(10), 0u);
    EXPECT_EQ(p.stepsForFaceCount(9), 1u);
    EXPECT_EQ(p.stepsForFaceCount(6), 2u);
    EXPECT_EQ(p.stepsForFaceCount(5), 3u);
    EXPECT_EQ(p.stepsForFaceCount(0), 4u);
}

class ProgressiveFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir = std::filesystem::temp_directory_path() /
              ("progressive_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    std::filesystem::path dir;
};

TEST_F(ProgressiveFile, RoundTripReplaysTheSameLevels) {
    for (CollapseKind kind : {CollapseKind::HalfEdge, CollapseKind::Full}) {
        rad::RadianceSimplificationOptions options;
        options.metric = rad::SimplificationMetric::GeometryOnly;
        options.collapse.kind = kind;
        options.collapse.targetFaceCount = 100;
        const rad::RadianceSimplificationResult r =
            rad::simplifyRadianceMesh(sphereWithRadiance(2, {rad::BasisKind::SphericalHarmonics, 2}), options);
        const std::string path = (dir / "sphere.rpm").string(), base = (dir / "sphere_base.rply").string();
        rad::writeProgressiveMesh(path, base, r.progressive);
        const rad::ProgressiveRadianceMesh back = rad::readProgressiveMesh(path);
        ASSERT_EQ(back.steps.size(), r.progressive.steps.size());
        EXPECT_EQ(back.kind, kind);
        EXPECT_EQ(back.faceCountAfter, r.progressive.faceCountAfter);
        for (std::size_t i = 0; i < back.steps.size(); ++i)  // each step read carries its face count too
            ASSERT_EQ(back.steps[i].facesAfter, r.progressive.steps[i].facesAfter) << i;
        EXPECT_EQ(back.survivorRows, r.progressive.survivorRows);
        for (std::size_t k : {std::size_t(0), back.steps.size() / 2, back.steps.size()}) {
            const rad::RadianceMesh a = r.progressive.extract(k), b = back.extract(k);
            EXPECT_EQ(a.faces, b.faces);
            EXPECT_EQ(a.positions, b.positions);
            EXPECT_EQ(a.radiance->coefficients, b.radiance->coefficients);
        }
    }
}

TEST_F(ProgressiveFile, RefusesTruncatedAndMismatchedFiles) {
    rad::RadianceSimplificationOptions options;
    options.metric = rad::SimplificationMetric::GeometryOnly;
    options.collapse.targetFaceCount = 100;
    const rad::RadianceSimplificationResult r =
        rad::simplifyRadianceMesh(sphereWithRadiance(2, {rad::BasisKind::HemisphericalPolynomial, 2}), options);
    const std::string path = (dir / "a.rpm").string(), base = (dir / "a.rply").string();
    rad::writeProgressiveMesh(path, base, r.progressive);
    std::vector<char> bytes = radtest::readBytes(path);
    bytes.resize(bytes.size() - 5);
    radtest::writeBytes(path, bytes);
    try {
        rad::readProgressiveMesh(path);
        FAIL() << "truncated file accepted";
    } catch (const rad::ProgressiveMeshError& e) {
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
    // A base with another vertex count.
    rad::writeProgressiveMesh(path, base, r.progressive);
    rad::RadianceMesh other = sphereWithRadiance(1, {rad::BasisKind::HemisphericalPolynomial, 2});
    rad::writeRadiancePly(base, other);
    EXPECT_THROW(rad::readProgressiveMesh(path), rad::ProgressiveMeshError);
    const std::string garbage = "not a progressive mesh\n";
    radtest::writeBytes(path, std::vector<char>(garbage.begin(), garbage.end()));
    EXPECT_THROW(rad::readProgressiveMesh(path), rad::ProgressiveMeshError);
}

// The text before end_header and the records after it.
struct RpmParts {
    std::string header, records;
};
RpmParts splitRpm(const std::string& path) {
    const std::vector<char> bytes = radtest::readBytes(path);
    const std::string all(bytes.begin(), bytes.end());
    const std::size_t end = all.find("end_header\n") + std::string("end_header\n").size();
    return {all.substr(0, end), all.substr(end)};
}
void joinRpm(const std::string& path, const RpmParts& parts) {
    const std::string all = parts.header + parts.records;
    radtest::writeBytes(path, std::vector<char>(all.begin(), all.end()));
}
// The same file as format version 1 wrote it: no hash lines.
RpmParts asVersion1(RpmParts parts) {
    std::istringstream in(parts.header);
    std::string line, out;
    while (std::getline(in, line)) {
        if (line.rfind("base_hash", 0) == 0 || line.rfind("records_hash", 0) == 0) continue;
        if (line == "format binary_little_endian 2") line = "format binary_little_endian 1";
        out += line + "\n";
    }
    parts.header = out;
    return parts;
}
std::string refusal(const std::string& path) {
    try {
        rad::readProgressiveMesh(path);
    } catch (const rad::ProgressiveMeshError& e) {
        return e.what();
    }
    return "";
}
constexpr std::size_t kRecord = 28;  // half-edge records: removed, survivor, faces after, xyz, cost

rad::RadianceSimplificationResult simplifiedSphere() {
    rad::RadianceSimplificationOptions options;
    options.metric = rad::SimplificationMetric::GeometryOnly;
    options.collapse.kind = CollapseKind::HalfEdge;  // records of kRecord bytes
    options.collapse.targetFaceCount = 100;
    return rad::simplifyRadianceMesh(sphereWithRadiance(2, {rad::BasisKind::HemisphericalPolynomial, 2}), options);
}

TEST_F(ProgressiveFile, OlderFilesWithoutHashesAreStillRead) {
    const rad::RadianceSimplificationResult r = simplifiedSphere();
    const std::string path = (dir / "old.rpm").string(), base = (dir / "old_base.rply").string();
    rad::writeProgressiveMesh(path, base, r.progressive);
    EXPECT_NE(splitRpm(path).header.find("base_hash fnv1a64:"), std::string::npos);
    joinRpm(path, asVersion1(splitRpm(path)));
    const rad::ProgressiveRadianceMesh back = rad::readProgressiveMesh(path);
    EXPECT_EQ(back.faceCountAfter, r.progressive.faceCountAfter);
    EXPECT_EQ(back.extract(back.steps.size() / 2).faces, r.progressive.extract(back.steps.size() / 2).faces);
}

// Corruption that looks consistent (every index in range, counts non-increasing) was replayed
// as wrong levels: refused by the replay of the face counts (version 1) and the records' hash (2).
TEST_F(ProgressiveFile, RefusesConsistentLookingCorruption) {
    const rad::RadianceSimplificationResult r = simplifiedSphere();
    const std::string path = (dir / "c.rpm").string(), base = (dir / "c_base.rply").string();
    rad::writeProgressiveMesh(path, base, r.progressive);
    const RpmParts good = splitRpm(path);
    ASSERT_GT(good.records.size(), 40 * kRecord);
    // Step 30's survivor replaced by a vertex no step removed before it (in range, alive).
    const std::size_t at = 30 * kRecord;
    std::uint32_t survivor, removed;
    std::memcpy(&removed, good.records.data() + at, 4);
    std::memcpy(&survivor, good.records.data() + at + 4, 4);
    std::set<std::uint32_t> gone;
    for (std::size_t i = 0; i <= 30; ++i) {
        std::uint32_t v;
        std::memcpy(&v, good.records.data() + i * kRecord, 4);
        gone.insert(v);
    }
    std::uint32_t other = 0;
    while (gone.count(other) || other == survivor) ++other;
    RpmParts changed = good;
    std::memcpy(&changed.records[at + 4], &other, 4);
    joinRpm(path, changed);
    EXPECT_NE(refusal(path).find("do not match their hash"), std::string::npos) << refusal(path);
    joinRpm(path, asVersion1(changed));
    EXPECT_NE(refusal(path).find("replaying the collapses"), std::string::npos) << refusal(path);

    // Face counts rewritten, still non-increasing: every count after step 10 lowered by one.
    RpmParts counts = asVersion1(good);
    for (std::size_t i = 10; i < counts.records.size() / kRecord; ++i) {
        std::uint32_t faces;
        std::memcpy(&faces, counts.records.data() + i * kRecord + 8, 4);
        --faces;
        std::memcpy(&counts.records[i * kRecord + 8], &faces, 4);
    }
    joinRpm(path, counts);
    EXPECT_NE(refusal(path).find("after step 10"), std::string::npos) << refusal(path);
}

TEST_F(ProgressiveFile, RefusesPositionsTheCoresCannotComputeWith) {
    const rad::RadianceSimplificationResult r = simplifiedSphere();
    const std::string path = (dir / "p.rpm").string(), base = (dir / "p_base.rply").string();
    rad::writeProgressiveMesh(path, base, r.progressive);
    for (float bad : {std::nanf(""), 1e30f}) {
        RpmParts parts = asVersion1(splitRpm(path));
        std::memcpy(&parts.records[5 * kRecord + 12], &bad, 4);
        const std::string written = (dir / "p_bad.rpm").string();
        joinRpm(written, parts);
        // The base is named relative to the folder: the same base serves the copy.
        EXPECT_NE(refusal(written).find("step 5 moves vertex"), std::string::npos) << refusal(written);
    }
}

TEST_F(ProgressiveFile, AHugeStepCountIsRefusedWithoutReadingPastTheRecords) {
    const rad::RadianceSimplificationResult r = simplifiedSphere();
    const std::string path = (dir / "h.rpm").string(), base = (dir / "h_base.rply").string();
    rad::writeProgressiveMesh(path, base, r.progressive);
    RpmParts parts = asVersion1(splitRpm(path));
    const std::string steps = "steps " + std::to_string(r.progressive.steps.size()) + "\n";
    const std::size_t where = parts.header.find(steps);
    ASSERT_NE(where, std::string::npos);
    // S + 2^62 steps of 28 bytes wrap around 2^64 to exactly the bytes of S records: the old check
    // passed and the reader read past the records.
    const unsigned long long claimed = r.progressive.steps.size() + (1ull << 62);
    parts.header.replace(where, steps.size(), "steps " + std::to_string(claimed) + "\n");
    joinRpm(path, parts);
    EXPECT_NE(refusal(path).find("truncated or padded"), std::string::npos) << refusal(path);
}

// A kill between the base's and the .rpm's renames left a new base beside an old .rpm, replayed
// silently; a base saved again in another vertex order too. The hash of the base binds the two.
TEST_F(ProgressiveFile, RefusesABaseOtherThanTheOneRecordedOn) {
    const rad::RadianceSimplificationResult r = simplifiedSphere();
    const std::string path = (dir / "b.rpm").string(), base = (dir / "b_base.rply").string();
    rad::writeProgressiveMesh(path, base, r.progressive);
    rad::RadianceMesh reordered = r.progressive.base;  // the same mesh, its first two vertices swapped
    for (int k = 0; k < 3; ++k) std::swap(reordered.positions[k], reordered.positions[3 + k]);
    for (std::uint32_t& v : reordered.faces) v = v == 0 ? 1 : v == 1 ? 0 : v;
    if (!reordered.normals.empty())
        for (int k = 0; k < 3; ++k) std::swap(reordered.normals[k], reordered.normals[3 + k]);
    if (reordered.radiance) {
        rad::RadianceField& f = *reordered.radiance;
        const std::size_t c = f.coefficientsPerVertex();
        std::swap_ranges(f.coefficients.begin(), f.coefficients.begin() + c, f.coefficients.begin() + c);
        std::swap_ranges(f.frames.begin(), f.frames.begin() + 6, f.frames.begin() + 6);
    }
    rad::writeRadiancePly(base, reordered);
    EXPECT_NE(refusal(path).find("was recorded on another base"), std::string::npos) << refusal(path);
}

// Refused names (a space; a folder where the .rpm goes) left `<name>_base.rply` behind: now
// nothing is written, and the message says what to change.
TEST_F(ProgressiveFile, ARefusedSaveLeavesNoFile) {
    const rad::RadianceSimplificationResult r = simplifiedSphere();
    const std::string spaced = (dir / "my mesh.rpm").string(), spacedBase = (dir / "my mesh_base.rply").string();
    try {
        rad::writeProgressiveMesh(spaced, spacedBase, r.progressive);
        FAIL() << "a base name with a space accepted";
    } catch (const rad::ProgressiveMeshError& e) {
        EXPECT_NE(std::string(e.what()).find("without spaces"), std::string::npos) << e.what();
    }
    std::filesystem::create_directory(dir / "taken.rpm");
    EXPECT_THROW(rad::writeProgressiveMesh((dir / "taken.rpm").string(), (dir / "taken_base.rply").string(),
                                           r.progressive),
                 rad::ProgressiveMeshError);
    std::vector<std::string> left;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().filename() != "taken.rpm") left.push_back(entry.path().filename().string());
    EXPECT_TRUE(left.empty()) << left.front();
}

}  // namespace
