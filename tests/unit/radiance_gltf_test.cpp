// io/radiance_gltf.h: the .glb read back here (container, JSON parsed by io/json_value.h, accessors
// decoded from the binary chunk), and the radiance it describes evaluated the way a reader would:
//  - SH: as 3D Gaussian Splatting evaluates them (Kerbl et al. 2023: the real-SH normalisations with
//    the Condon-Shortley signs that its published eval_sh uses, written out below) at the viewing ray
//    d = -w, which must give our L(w) (radiance_evaluation.h), plain and reflected storage;
//  - PB: monomials u^i v^j in the frame (TANGENT, cross(NORMAL, TANGENT), NORMAL) read from the file;
//  - COLOR_0 of constant functions (whose mean is the constant, whatever the basis), clamped;
//  - refusals. Parsing by pygltflib and Blender's import are in tests/python/test_pymeshlab_export_gltf.py.
#include "io/radiance_gltf.h"

#include "io/gltf_writer.h"
#include "io/json_value.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

std::uint32_t u32(const std::vector<unsigned char>& b, std::size_t at) {
    return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
           std::uint32_t(b[at + 3]) << 24;
}

struct Glb {
    rad::JsonValue json;
    std::vector<unsigned char> bin;

    const rad::JsonValue& primitive() const { return json.find("meshes")->array[0].find("primitives")->array[0]; }
    bool has(const std::string& attribute) const {
        return primitive().find("attributes")->find(attribute) != nullptr;
    }
    // The float accessor of `attribute`, as read from the binary chunk.
    std::vector<float> floats(const std::string& attribute, int width) const {
        const rad::JsonValue* index = primitive().find("attributes")->find(attribute);
        EXPECT_NE(index, nullptr) << attribute;
        if (!index) return {};
        const rad::JsonValue& acc = json.find("accessors")->array[std::size_t(index->number)];
        EXPECT_EQ(acc.find("componentType")->number, 5126);
        const rad::JsonValue& view = json.find("bufferViews")->array[std::size_t(acc.find("bufferView")->number)];
        const std::size_t count = std::size_t(acc.find("count")->number);
        const std::size_t offset = std::size_t(view.find("byteOffset")->number);
        EXPECT_EQ(std::size_t(view.find("byteLength")->number), count * width * 4);
        EXPECT_EQ(offset % 4, 0u);
        std::vector<float> out(count * width);
        std::memcpy(out.data(), bin.data() + offset, out.size() * 4);
        return out;
    }
    const rad::JsonValue& extension() const {
        return *primitive().find("extensions")->find(rad::kRadianceGltfExtension);
    }
};

Glb parse(const std::vector<unsigned char>& b) {
    Glb g;
    EXPECT_EQ(u32(b, 0), 0x46546C67u);
    EXPECT_EQ(u32(b, 4), 2u);
    EXPECT_EQ(u32(b, 8), b.size());
    const std::uint32_t jsonLength = u32(b, 12);
    EXPECT_EQ(u32(b, 16), 0x4E4F534Au);
    EXPECT_EQ(jsonLength % 4, 0u);
    g.json = rad::parseJson(std::string(reinterpret_cast<const char*>(b.data() + 20), jsonLength), "glb");
    const std::size_t binAt = 20 + jsonLength;
    EXPECT_EQ(u32(b, binAt + 4), 0x004E4942u);
    EXPECT_EQ(binAt + 8 + u32(b, binAt), b.size());
    g.bin.assign(b.begin() + binAt + 8, b.end());
    return g;
}

// An octahedron (6 vertices, 8 faces) with random RF of `basis` and normals tilted away from the
// vertex positions, so that the frame written is the RF's, not something derived from the geometry.
rad::RadianceMesh octahedron(rad::BasisSpec basis, bool reflected, unsigned seed = 7) {
    rad::RadianceMesh m;
    m.positions = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    m.faces = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    rad::RadianceField field(basis, 6, reflected);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float& c : field.coefficients) c = u(rng);
    for (std::size_t v = 0; v < 6; ++v) {
        const Eigen::Vector3d p(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
        const Eigen::Vector3d tilt(u(rng), u(rng), u(rng));
        rad::storeFrame(rad::frameFromNormalAndTangent(p + 0.3 * tilt, Eigen::Vector3d(u(rng), u(rng), u(rng))),
                        field.frame(v));
    }
    m.radiance = field;
    return m;
}

// eval_sh of the 3DGS reference implementation, degree <= 3, one channel, at direction (x, y, z).
double evalSh3dgs(int degree, const float* sh, double x, double y, double z) {
    const double C0 = 0.28209479177387814, C1 = 0.4886025119029199;
    const double C2[] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792,
                         0.5462742152960396};
    const double C3[] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                         -0.4570457994644658, 1.445305721320277, -0.5900435899266435};
    double r = C0 * sh[0];
    if (degree > 0) r = r - C1 * y * sh[1] + C1 * z * sh[2] - C1 * x * sh[3];
    if (degree > 1) {
        const double xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
        r = r + C2[0] * xy * sh[4] + C2[1] * yz * sh[5] + C2[2] * (2.0 * zz - xx - yy) * sh[6] + C2[3] * xz * sh[7] +
            C2[4] * (xx - yy) * sh[8];
        if (degree > 2)
            r = r + C3[0] * y * (3 * xx - yy) * sh[9] + C3[1] * xy * z * sh[10] + C3[2] * y * (4 * zz - xx - yy) * sh[11] +
                C3[3] * z * (2 * zz - 3 * xx - 3 * yy) * sh[12] + C3[4] * x * (4 * zz - xx - yy) * sh[13] +
                C3[5] * z * (xx - yy) * sh[14] + C3[6] * x * (xx - 3 * yy) * sh[15];
    }
    return r;
}

Eigen::Vector3d at(const std::vector<float>& a, std::size_t v) { return {a[3 * v], a[3 * v + 1], a[3 * v + 2]}; }

// Directions above every tangent plane we test (the border extension is the viewer's business).
std::vector<Eigen::Vector3d> upperDirections(const Eigen::Vector3d& n, std::mt19937& rng) {
    std::normal_distribution<double> g;
    std::vector<Eigen::Vector3d> out;
    while (out.size() < 20) {
        Eigen::Vector3d w(g(rng), g(rng), g(rng));
        w.normalize();
        if (w.dot(n) > 0.05) out.push_back(w);
    }
    return out;
}

class ShConvention : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(ShConvention, ThreeDgsEvaluationAtTheViewingRayGivesOurRadiance) {
    const auto [degree, reflected] = GetParam();
    const rad::RadianceMesh mesh = octahedron({rad::BasisKind::SphericalHarmonics, degree}, reflected);
    const Glb g = parse(rad::buildRadianceGlb(mesh));
    EXPECT_FALSE(g.has("TANGENT")) << "SH lives in the global frame";
    const int k = (degree + 1) * (degree + 1);
    std::vector<std::vector<float>> coefficient(k);
    for (int l = 0; l <= degree; ++l)
        for (int n = 0; n <= 2 * l; ++n)
            coefficient[l * l + n] = g.floats("_RF_SH_DEGREE_" + std::to_string(l) + "_COEF_" + std::to_string(n), 3);
    const std::vector<float> normals = g.floats("NORMAL", 3);
    std::mt19937 rng(3);
    for (std::size_t v = 0; v < 6; ++v) {
        const Eigen::Vector3d n = at(normals, v);
        EXPECT_NEAR(n.norm(), 1.0, 1e-6);
        EXPECT_NEAR((n - rad::frameFromStored(mesh.radiance->frame(v)).n).norm(), 0.0, 1e-6);
        for (const Eigen::Vector3d& w : upperDirections(n, rng)) {
            // Reflected storage: L(w) = L~(R_n w), so the reader evaluates at the ray of R_n w.
            const Eigen::Vector3d d = -(reflected ? rad::reflect(n, w) : w);
            const Eigen::Vector3d expected = rad::evaluateRadiance(*mesh.radiance, v, w);
            for (int c = 0; c < 3; ++c) {
                std::vector<float> sh(k);
                for (int j = 0; j < k; ++j) sh[j] = coefficient[j][3 * v + c];
                EXPECT_NEAR(evalSh3dgs(degree, sh.data(), d.x(), d.y(), d.z()), expected[c], 2e-5)
                    << "vertex " << v << " channel " << c;
            }
        }
    }
    const rad::JsonValue& e = g.extension();
    EXPECT_EQ(e.find("basis")->string, "SH");
    EXPECT_EQ(e.find("degree")->number, degree);
    EXPECT_EQ(e.find("reflected")->boolean, reflected);
    EXPECT_EQ(e.find("shConvention")->string, "3dgs");
    EXPECT_EQ(e.find("colorSpace")->string, "srgb-linear");
    ASSERT_EQ(e.find("attributes")->array.size(), std::size_t(k));
    EXPECT_EQ(e.find("attributes")->array[2].string, "_RF_SH_DEGREE_1_COEF_1");
}

INSTANTIATE_TEST_SUITE_P(Degrees, ShConvention,
                         ::testing::Values(std::make_tuple(1, false), std::make_tuple(2, false),
                                           std::make_tuple(3, false), std::make_tuple(3, true)));

TEST(RadianceGltf, PolynomialsInTheWrittenFrameGiveOurRadiance) {
    for (bool reflected : {false, true}) {
        const rad::BasisSpec basis{rad::BasisKind::HemisphericalPolynomial, 3};
        const rad::RadianceMesh mesh = octahedron(basis, reflected, 11);
        const Glb g = parse(rad::buildRadianceGlb(mesh));
        const std::vector<float> normals = g.floats("NORMAL", 3), tangents = g.floats("TANGENT", 4);
        std::vector<std::vector<float>> coefficient(10);
        for (int j = 0; j < 10; ++j) coefficient[j] = g.floats("_RF_PB_COEF_" + std::to_string(j), 3);
        std::mt19937 rng(5);
        for (std::size_t v = 0; v < 6; ++v) {
            const Eigen::Vector3d n = at(normals, v);
            const Eigen::Vector3d t(tangents[4 * v], tangents[4 * v + 1], tangents[4 * v + 2]);
            const Eigen::Vector3d b = n.cross(t) * tangents[4 * v + 3];
            EXPECT_NEAR(t.dot(n), 0.0, 1e-6);
            for (const Eigen::Vector3d& w : upperDirections(n, rng)) {
                const Eigen::Vector3d r = reflected ? rad::reflect(n, w) : w;
                const double u = t.dot(r), vv = b.dot(r);
                const Eigen::Vector3d expected = rad::evaluateRadiance(*mesh.radiance, v, w);
                for (int c = 0; c < 3; ++c) {
                    double sum = 0.0;
                    for (int total = 0, j = 0; total <= 3; ++total)
                        for (int q = 0; q <= total; ++q, ++j)  // u^(total-q) v^q, ordered by total then by q
                            sum += coefficient[j][3 * v + c] * std::pow(u, total - q) * std::pow(vv, q);
                    EXPECT_NEAR(sum, expected[c], 2e-5) << "vertex " << v << " channel " << c;
                }
            }
        }
        EXPECT_EQ(g.extension().find("basis")->string, "PB");
        EXPECT_EQ(g.extension().find("reflected")->boolean, reflected);
    }
}

TEST(RadianceGltf, GeometryAndMeanColourOfConstantFunctions) {
    for (rad::BasisSpec basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 2},
                                 rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 2}}) {
        rad::RadianceMesh mesh = octahedron(basis, false);
        rad::RadianceField& f = *mesh.radiance;
        std::fill(f.coefficients.begin(), f.coefficients.end(), 0.0f);
        // Constant radiance (0.25, 0.5, 1.5) at vertex 0 and (-0.1, 0.75, 0) elsewhere: the mean is
        // the constant, clamped to [0, 1] in COLOR_0.
        const double scale = basis.usesLocalFrame() ? 1.0 : 2.0 * std::sqrt(M_PI);  // 1 / Y_0^0
        for (std::size_t v = 0; v < 6; ++v) {
            const double rgb[3] = {v == 0 ? 0.25 : -0.1, v == 0 ? 0.5 : 0.75, v == 0 ? 1.5 : 0.0};
            for (int c = 0; c < 3; ++c) f.channelCoefficients(v, c)[0] = float(rgb[c] * scale);
        }
        const Glb g = parse(rad::buildRadianceGlb(mesh));
        const std::vector<float> color = g.floats("COLOR_0", 3), positions = g.floats("POSITION", 3);
        EXPECT_NEAR(color[0], 0.25, 1e-6);
        EXPECT_NEAR(color[1], 0.5, 1e-6);
        EXPECT_EQ(color[2], 1.0f);
        for (std::size_t v = 1; v < 6; ++v) {
            EXPECT_EQ(color[3 * v], 0.0f);
            EXPECT_NEAR(color[3 * v + 1], 0.75, 1e-6);
            EXPECT_EQ(color[3 * v + 2], 0.0f);
        }
        EXPECT_EQ(positions, mesh.positions);
        const rad::JsonValue& acc = g.json.find("accessors")->array[std::size_t(
            g.primitive().find("attributes")->find("POSITION")->number)];
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(acc.find("min")->array[a].number, -1.0);
            EXPECT_EQ(acc.find("max")->array[a].number, 1.0);
        }
        const rad::JsonValue& indices = g.json.find("accessors")->array[std::size_t(g.primitive().find("indices")->number)];
        EXPECT_EQ(indices.find("count")->number, 24);
        EXPECT_EQ(indices.find("componentType")->number, 5125);
        EXPECT_EQ(g.primitive().find("mode")->number, 4);
        // The same description in extras, for readers that drop unknown extensions.
        EXPECT_EQ(g.primitive().find("extras")->find("radianceFunctions")->find("degree")->number, 2);
    }
}

TEST(RadianceGltf, AttributeNames) {
    const rad::BasisSpec sh{rad::BasisKind::SphericalHarmonics, 3}, pb{rad::BasisKind::HemisphericalPolynomial, 3};
    EXPECT_EQ(rad::radianceGltfAttributeName(sh, 0), "_RF_SH_DEGREE_0_COEF_0");
    EXPECT_EQ(rad::radianceGltfAttributeName(sh, rad::harmonicIndex(2, -2)), "_RF_SH_DEGREE_2_COEF_0");
    EXPECT_EQ(rad::radianceGltfAttributeName(sh, rad::harmonicIndex(3, 3)), "_RF_SH_DEGREE_3_COEF_6");
    EXPECT_EQ(rad::radianceGltfAttributeName(pb, 7), "_RF_PB_COEF_7");
}

TEST(RadianceGltf, Refusals) {
    const rad::BasisSpec basis{rad::BasisKind::SphericalHarmonics, 1};
    const auto refuses = [](const rad::RadianceMesh& m, const std::string& part) {
        try {
            rad::buildRadianceGlb(m);
            ADD_FAILURE() << "accepted; expected a refusal mentioning " << part;
        } catch (const rad::GltfInputError& e) {
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    rad::RadianceMesh none = octahedron(basis, false);
    none.radiance.reset();
    refuses(none, "no radiance functions: fit them");
    rad::RadianceMesh noFaces = octahedron(basis, false);
    noFaces.faces.clear();
    refuses(noFaces, "no faces");
    rad::RadianceMesh fewer = octahedron(basis, false);
    fewer.positions.resize(15);
    for (std::uint32_t& i : fewer.faces) i = std::min<std::uint32_t>(i, 4);
    refuses(fewer, "recompute the radiance");
    rad::RadianceMesh nan = octahedron(basis, false);
    nan.positions[4] = std::nanf("");
    refuses(nan, "Vertex 1");
    rad::RadianceMesh badIndex = octahedron(basis, false);
    badIndex.faces[5] = 6;
    refuses(badIndex, "Face 1");
}

}  // namespace
