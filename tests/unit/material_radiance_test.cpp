#include "radiance/material_radiance.h"

#include "radiance/basis.h"
#include "radiance/radiance_frame.h"
#include "radiance/radiance_evaluation.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

struct Points {
    std::vector<float> positions, normals;
    std::size_t size() const { return positions.size() / 3; }
};

Points randomPoints(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    Points p;
    for (std::size_t v = 0; v < n; ++v) {
        const Eigen::Vector3d d = radtest::randomUnit(rng);
        for (int k = 0; k < 3; ++k) {
            p.positions.push_back(static_cast<float>(d[k]));
            p.normals.push_back(static_cast<float>(d[k]));
        }
    }
    return p;
}

rad::AnalyticLighting oneLight(const Eigen::Vector3d& direction, double irradiance, double ambient) {
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({direction, rad::Rgb::Constant(irradiance)});
    lighting.ambient = rad::Rgb::Constant(ambient);
    return lighting;
}

// Lambert: the RF is the constant albedo/pi E max(0, n.l) + albedo ambient (written out here, not
// taken from the material code), so PB keeps it in coefficient 0 and SH in Y_0^0 = 1/(2 sqrt(pi)).
TEST(MaterialRadiance, LambertIsTheExpectedConstant) {
    const Points pts = randomPoints(200, 1);
    rad::AnalyticMaterial material;
    material.albedo = rad::Rgb(0.7, 0.4, 0.1);
    material.specular = rad::Rgb::Zero();
    const Eigen::Vector3d light = Eigen::Vector3d(0.2, 0.9, 0.4).normalized();
    const rad::AnalyticLighting lighting = oneLight(light, 2.5, 0.1);
    for (auto basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4},
                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 5}}) {
        rad::MaterialRadianceOptions options;
        options.basis = basis;
        const rad::RadianceField field =
            rad::makeMaterialRadiance(pts.positions.data(), pts.normals.data(), pts.size(), material, lighting, options);
        ASSERT_TRUE(field.validate().empty()) << field.validate();
        const double scale = basis.kind == rad::BasisKind::SphericalHarmonics ? 2.0 * std::sqrt(M_PI) : 1.0;
        for (std::size_t v = 0; v < pts.size(); ++v) {
            const Eigen::Vector3d n(pts.normals[3 * v], pts.normals[3 * v + 1], pts.normals[3 * v + 2]);
            const double cosine = std::max(0.0, n.normalized().dot(light));
            for (int c = 0; c < 3; ++c) {
                const double expected = material.albedo[c] / M_PI * 2.5 * cosine + material.albedo[c] * 0.1;
                const float* coefficients = field.channelCoefficients(v, c);
                EXPECT_NEAR(coefficients[0] / scale, expected, 1e-5);
                for (int k = 1; k < basis.coefficientCount(); ++k) EXPECT_NEAR(coefficients[k], 0.0, 1e-5);
            }
        }
        std::vector<float> mean(3 * pts.size());
        rad::meanHemisphereColors(field, mean.data());
        for (std::size_t v = 0; v < pts.size(); ++v)
            EXPECT_NEAR(mean[3 * v], field.channelCoefficients(v, 0)[0] / scale, 1e-5);
    }
}

// A glossy material is approximated better as the degree grows, measured against the ground
// truth at random directions of each hemisphere; plain and reflected storage agree.
TEST(MaterialRadiance, GlossyApproximationImprovesWithDegreeAndStorageDoesNotMatter) {
    const Points pts = randomPoints(60, 2);
    rad::AnalyticMaterial material;
    material.albedo = rad::Rgb(0.5, 0.5, 0.5);
    material.specular = rad::Rgb(0.4, 0.4, 0.4);
    material.exponent = 8.0;
    const rad::AnalyticLighting lighting = oneLight(Eigen::Vector3d(0.0, 0.3, 1.0), 3.0, 0.0);
    std::mt19937 rng(9);
    std::normal_distribution<double> g;
    double previousError = 1e9;
    for (int degree : {1, 3, 6}) {
        rad::MaterialRadianceOptions options;
        options.basis = {rad::BasisKind::HemisphericalPolynomial, degree};
        const rad::RadianceField plain =
            rad::makeMaterialRadiance(pts.positions.data(), pts.normals.data(), pts.size(), material, lighting, options);
        options.reflected = true;
        const rad::RadianceField reflected =
            rad::makeMaterialRadiance(pts.positions.data(), pts.normals.data(), pts.size(), material, lighting, options);
        double squaredError = 0.0, squaredTruth = 0.0;
        for (std::size_t v = 0; v < pts.size(); ++v) {
            const Eigen::Vector3d p(pts.positions[3 * v], pts.positions[3 * v + 1], pts.positions[3 * v + 2]);
            const Eigen::Vector3d n(pts.normals[3 * v], pts.normals[3 * v + 1], pts.normals[3 * v + 2]);
            for (int s = 0; s < 50; ++s) {
                Eigen::Vector3d w(g(rng), g(rng), g(rng));
                w.normalize();
                if (w.dot(n) < 0) w = -w;
                const Eigen::Vector3d truth = rad::outgoingRadiance(material, lighting, p, n, w);
                const Eigen::Vector3d fromPlain = rad::evaluateRadiance(plain, v, w);
                const Eigen::Vector3d fromReflected = rad::evaluateRadiance(reflected, v, w);
                EXPECT_NEAR((fromPlain - fromReflected).norm(), 0.0, 1e-4);
                squaredError += (fromPlain - truth).squaredNorm();
                squaredTruth += truth.squaredNorm();
            }
        }
        const double relativeError = std::sqrt(squaredError / squaredTruth);
        EXPECT_LT(relativeError, previousError) << "degree " << degree;
        previousError = relativeError;
    }
    EXPECT_LT(previousError, 0.05);  // PB(6) of a lobe of exponent 8: a few percent
}

TEST(MaterialRadiance, MeanOfAKnownPolynomial) {
    // PB(2) with the single monomial u^2: (1/2pi) integral over the hemisphere of x^2 = 1/3.
    rad::RadianceField field(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 2}, 1);
    rad::storeFrame(rad::Frame{}, field.frame(0));  // tangent x, normal z
    field.channelCoefficients(0, 1)[rad::polynomialIndex(2, 0)] = 1.0f;
    field.channelCoefficients(0, 2)[rad::polynomialIndex(0, 0)] = 0.25f;
    float mean[3];
    rad::meanHemisphereColors(field, mean);
    EXPECT_NEAR(mean[0], 0.0, 1e-7);
    EXPECT_NEAR(mean[1], 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(mean[2], 0.25, 1e-7);
}

// SH: the closed form (Funk-Hecke) against a direct midpoint integration over each vertex's
// hemisphere, in the vertex's frame, of the function as evaluated, for random coefficients and
// normals, plain and reflected.
TEST(MaterialRadiance, MeanOfSphericalHarmonicsMatchesDirectIntegration) {
    std::mt19937 rng(21);
    std::normal_distribution<double> g;
    for (bool reflected : {false, true}) {
        const int vertices = 5;
        rad::RadianceField field(rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 5}, vertices, reflected);
        for (int v = 0; v < vertices; ++v) {
            const Eigen::Vector3d normal = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
            rad::storeFrame(rad::frameFromNormal(normal), field.frame(v));
            float* coefficients = field.vertexCoefficients(v);
            for (int k = 0; k < field.coefficientsPerVertex(); ++k) coefficients[k] = static_cast<float>(g(rng));
        }
        std::vector<float> mean(3 * vertices);
        rad::meanHemisphereColors(field, mean.data());
        const int rings = 200, sectors = 400;
        for (int v = 0; v < vertices; ++v) {
            const rad::Frame frame = rad::frameFromStored(field.frame(v));
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            for (int i = 0; i < rings; ++i)
                for (int j = 0; j < sectors; ++j) {
                    // Uniform in z = cos(theta) and phi: equal solid angles 2 pi / (rings sectors).
                    const double z = (i + 0.5) / rings, phi = 2.0 * M_PI * (j + 0.5) / sectors;
                    const double r = std::sqrt(1.0 - z * z);
                    const Eigen::Vector3d local(r * std::cos(phi), r * std::sin(phi), z);
                    sum += rad::evaluateRadiance(field, v, frame.toWorld(local));
                }
            sum /= double(rings) * sectors;
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[3 * v + c], sum[c], 2e-3 * (1.0 + std::abs(sum[c]))) << v << " " << c;
        }
    }
}

TEST(MaterialRadiance, InputChecksSayWhatIsWrong) {
    rad::MaterialRadianceOptions options;
    options.basis = {rad::BasisKind::HemisphericalPolynomial, 4};
    std::vector<float> positions = {0, 0, 0, 1, 0, 0};
    std::vector<float> normals = {0, 0, 1, 0, 0, 1};
    EXPECT_TRUE(rad::checkMaterialRadianceInput(positions.data(), normals.data(), 2, options).empty());
    EXPECT_NE(rad::checkMaterialRadianceInput(positions.data(), normals.data(), 0, options).find("no vertices"),
              std::string::npos);
    normals[5] = 0;
    EXPECT_NE(rad::checkMaterialRadianceInput(positions.data(), normals.data(), 2, options).find("normal"),
              std::string::npos);
    normals[5] = 1;
    positions[4] = std::nanf("");
    EXPECT_NE(rad::checkMaterialRadianceInput(positions.data(), normals.data(), 2, options).find("non-finite"),
              std::string::npos);
    positions[4] = 0;
    options.basis.degree = 42;
    EXPECT_NE(rad::checkMaterialRadianceInput(positions.data(), normals.data(), 2, options).find("unsupported"),
              std::string::npos);
}

TEST(MaterialRadiance, ProgressReachesOneHundred) {
    const Points pts = randomPoints(500, 4);
    rad::MaterialRadianceOptions options;
    options.basis = {rad::BasisKind::SphericalHarmonics, 2};
    double last = -1.0;
    bool monotonic = true;
    rad::makeMaterialRadiance(pts.positions.data(), pts.normals.data(), pts.size(), rad::AnalyticMaterial{},
                              oneLight(Eigen::Vector3d::UnitZ(), 1.0, 0.0), options, [&](double fraction, const char*) {
                                  monotonic = monotonic && fraction >= last;
                                  last = fraction;
                                  return true;
                              });
    EXPECT_EQ(last, 1.0);
    EXPECT_TRUE(monotonic);
}

TEST(MaterialRadiance, StopRequestThrowsCancelled) {
    const Points pts = randomPoints(5000, 5);
    rad::MaterialRadianceOptions options;
    options.basis = {rad::BasisKind::SphericalHarmonics, 2};
    int calls = 0;
    EXPECT_THROW(rad::makeMaterialRadiance(pts.positions.data(), pts.normals.data(), pts.size(), rad::AnalyticMaterial{},
                                           oneLight(Eigen::Vector3d::UnitZ(), 1.0, 0.0), options,
                                           [&](double, const char*) { return ++calls < 3; }),
                 rad::OperationCancelled);
    EXPECT_EQ(calls, 3);  // no report after the stop request
}

}  // namespace
