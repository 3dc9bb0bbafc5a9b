#include "radiance/radiance_evaluation.h"

#include "radiance/sh_rotation.h"

#include <cmath>
#include <vector>

namespace rad {

namespace {
// Evaluates the stored function C at basisDirection(w, reflectArgument). This is the single code
// path behind L and L~:
//   plain storage:     L(w) = C(w),          L~(w) = C(R_n w)
//   reflected storage: L(w) = C(R_n w),      L~(w) = C(w)
// with C border-extended (extension commutes with R_n).
template <typename Scalar>
Eigen::Vector3d evaluateStored(const VertexRadianceT<Scalar>& rf, const Eigen::Vector3d& w, bool reflectArgument,
                               double* scratch) {
    return evaluateCoefficients(rf.basis, rf.coefficients, basisDirection(rf.basis, rf.frame, w, reflectArgument),
                                scratch);
}
}  // namespace

VertexRadiance vertexRadiance(const RadianceField& field, std::size_t v) {
    VertexRadiance rf;
    rf.basis = field.basis;
    rf.coefficients = field.vertexCoefficients(v);
    rf.frame = frameFromStored(field.frame(v));
    rf.reflected = field.reflected;
    return rf;
}

Eigen::Vector3d borderExtendedDirection(const Frame& frame, const Eigen::Vector3d& w) {
    const double h = frame.n.dot(w);
    if (h >= 0.0) return w;
    const Eigen::Vector3d p = w - h * frame.n;
    const double r = p.norm();
    if (r < kOppositePoleRadius) return frame.t;
    return p / r;
}

Eigen::Vector3d basisDirection(const BasisSpec& basis, const Frame& frame, const Eigen::Vector3d& w,
                               bool reflectedStorage) {
    if (basis.usesLocalFrame()) {
        double x = frame.t.dot(w), y = frame.b.dot(w), z = frame.n.dot(w);
        borderExtendLocal(x, y, z);
        if (reflectedStorage) return {-x, -y, z};  // R_n in the local frame: (x, y, z) -> (-x, -y, z)
        return {x, y, z};
    }
    const Eigen::Vector3d d = borderExtendedDirection(frame, w);
    return reflectedStorage ? reflect(frame.n, d) : d;
}

template <typename Scalar>
Eigen::Vector3d evaluateCoefficients(const BasisSpec& basis, const Scalar* coefficients,
                                     const Eigen::Vector3d& d, double* scratch) {
    const int K = basis.coefficientCount();
    evaluateBasis(basis, d.x(), d.y(), d.z(), scratch);
    Eigen::Vector3d out;
    for (int c = 0; c < kColorChannels; ++c) {
        const Scalar* coef = coefficients + c * K;
        double sum = 0.0;
        for (int k = 0; k < K; ++k) sum += static_cast<double>(coef[k]) * scratch[k];
        out[c] = sum;
    }
    return out;
}

template <typename Scalar>
Eigen::Vector3d evaluateRadiance(const VertexRadianceT<Scalar>& rf, const Eigen::Vector3d& w, double* scratch) {
    return evaluateStored(rf, w, rf.reflected, scratch);
}

template <typename Scalar>
Eigen::Vector3d evaluateReflectedRadiance(const VertexRadianceT<Scalar>& rf, const Eigen::Vector3d& w,
                                          double* scratch) {
    return evaluateStored(rf, w, !rf.reflected, scratch);
}

Eigen::Vector3d evaluateRadiance(const RadianceField& field, std::size_t v, const Eigen::Vector3d& w) {
    double scratch[kMaxCoefficientsPerChannel];
    return evaluateRadiance(vertexRadiance(field, v), w, scratch);
}

Eigen::Vector3d evaluateReflectedRadiance(const RadianceField& field, std::size_t v, const Eigen::Vector3d& w) {
    double scratch[kMaxCoefficientsPerChannel];
    return evaluateReflectedRadiance(vertexRadiance(field, v), w, scratch);
}

template <typename Scalar>
void reflectCoefficients(const BasisSpec& basis, const Frame& frame, const Scalar* in, Scalar* out) {
    const int K = basis.coefficientCount();
    if (basis.usesLocalFrame()) {
        // Sign (-1)^(i+j) = (-1)^(total degree); polynomialIndex orders by total degree.
        for (int c = 0; c < kColorChannels; ++c) {
            int index = 0;
            for (int total = 0; total <= basis.degree; ++total)
                for (int j = 0; j <= total; ++j, ++index) {
                    const Scalar value = in[c * K + index];
                    out[c * K + index] = (total % 2 == 0) ? value : -value;
                }
        }
        return;
    }
    // SH: the reflection R_n = 2 n n^T - I is the rotation by pi about n (symmetric, its own inverse,
    // so both conventions "rotate the function by R" and "by R^T" coincide).
    const ShRotation rotation(basis.degree, reflectionAbout(frame.n));
    double src[kMaxCoefficientsPerChannel], dst[kMaxCoefficientsPerChannel];
    for (int c = 0; c < kColorChannels; ++c) {
        for (int k = 0; k < K; ++k) src[k] = static_cast<double>(in[c * K + k]);
        rotation.apply(src, dst);
        for (int k = 0; k < K; ++k) out[c * K + k] = static_cast<Scalar>(dst[k]);
    }
}

void vertexCoefficients(const RadianceField& field, std::size_t v, bool reflected, double* out) {
    const int count = field.coefficientsPerVertex();
    const float* src = field.vertexCoefficients(v);
    for (int k = 0; k < count; ++k) out[k] = static_cast<double>(src[k]);
    if (reflected != field.reflected) reflectCoefficients(field.basis, frameFromStored(field.frame(v)), out, out);
}

void setReflectedStorage(RadianceField& field, bool reflected) {
    if (field.reflected == reflected) return;
    const long long n = static_cast<long long>(field.vertexCount());
    const int count = field.coefficientsPerVertex();
#pragma omp parallel
    {
        std::vector<double> buffer(count);
#pragma omp for schedule(static)
        for (long long v = 0; v < n; ++v) {
            float* coef = field.vertexCoefficients(static_cast<std::size_t>(v));
            for (int k = 0; k < count; ++k) buffer[k] = coef[k];
            reflectCoefficients(field.basis, frameFromStored(field.frame(static_cast<std::size_t>(v))), buffer.data(),
                                buffer.data());
            for (int k = 0; k < count; ++k) coef[k] = static_cast<float>(buffer[k]);
        }
    }
    field.reflected = reflected;
}

template Eigen::Vector3d evaluateCoefficients<float>(const BasisSpec&, const float*, const Eigen::Vector3d&, double*);
template Eigen::Vector3d evaluateCoefficients<double>(const BasisSpec&, const double*, const Eigen::Vector3d&, double*);
template Eigen::Vector3d evaluateRadiance<float>(const VertexRadianceT<float>&, const Eigen::Vector3d&, double*);
template Eigen::Vector3d evaluateRadiance<double>(const VertexRadianceT<double>&, const Eigen::Vector3d&, double*);
template Eigen::Vector3d evaluateReflectedRadiance<float>(const VertexRadianceT<float>&, const Eigen::Vector3d&,
                                                          double*);
template Eigen::Vector3d evaluateReflectedRadiance<double>(const VertexRadianceT<double>&, const Eigen::Vector3d&,
                                                           double*);
template void reflectCoefficients<float>(const BasisSpec&, const Frame&, const float*, float*);
template void reflectCoefficients<double>(const BasisSpec&, const Frame&, const double*, double*);

}  // namespace rad
