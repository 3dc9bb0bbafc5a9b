#include "fit/exposure_compensation.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace rad {

std::string ExposureOptions::validate() const {
    std::ostringstream why;
    if (!(darkLevel > 0.0) || !std::isfinite(darkLevel))
        why << "the dark level must be a finite number > 0 (got " << darkLevel << ")";
    else if (!(saturationLevel > darkLevel) || !std::isfinite(saturationLevel))
        why << "the saturation level must be a finite number above the dark level (got " << saturationLevel << ")";
    else if (robustPasses < 0)
        why << "the number of robust passes must be >= 0 (got " << robustPasses << ")";
    else if (!(huberThreshold > 0.0))
        why << "the Huber threshold must be > 0 (got " << huberThreshold << ")";
    return why.str();
}

ExposureGains solveExposureGains(const std::vector<ExposureSample>& samples, std::size_t viewCount,
                                 const ExposureOptions& options) {
    const std::string why = options.validate();
    if (!why.empty()) throw std::invalid_argument("exposure compensation: " + why);
    ExposureGains out;
    out.gains.assign(3 * viewCount, 1.0);
    out.constrained.assign(viewCount, 0);

    // Usable samples: finite, positive weight, every channel between the dark and saturation levels.
    std::uint32_t maxPoint = 0;
    std::vector<std::size_t> usable;
    usable.reserve(samples.size());
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const ExposureSample& x = samples[s];
        if (x.view >= viewCount)
            throw std::invalid_argument("exposure compensation: a sample refers to view " + std::to_string(x.view) +
                                        " of " + std::to_string(viewCount));
        if (!(x.weight > 0.0f) || !std::isfinite(x.weight)) continue;
        bool ok = true;
        for (int c = 0; c < 3; ++c)
            ok = ok && std::isfinite(x.rgb[c]) && x.rgb[c] >= options.darkLevel && x.rgb[c] < options.saturationLevel;
        if (!ok) continue;
        usable.push_back(s);
        maxPoint = std::max(maxPoint, x.point);
    }
    if (usable.empty()) return out;
    // Points seen by at least two distinct views (only they relate views to each other).
    const std::size_t pointSlots = static_cast<std::size_t>(maxPoint) + 1;
    std::vector<std::uint32_t> firstView(pointSlots, UINT32_MAX);
    std::vector<std::uint8_t> multi(pointSlots, 0);
    for (std::size_t s : usable) {
        const ExposureSample& x = samples[s];
        if (firstView[x.point] == UINT32_MAX)
            firstView[x.point] = x.view;
        else if (firstView[x.point] != x.view)
            multi[x.point] = 1;
    }
    std::vector<std::uint32_t> pointIndex(pointSlots, UINT32_MAX);
    std::uint32_t points = 0;
    for (std::size_t p = 0; p < pointSlots; ++p)
        if (multi[p]) pointIndex[p] = points++;
    struct Obs {
        std::uint32_t point, view;
        double logY[3];
        double weight;
    };
    std::vector<Obs> obs;
    for (std::size_t s : usable) {
        const ExposureSample& x = samples[s];
        if (!multi[x.point]) continue;
        Obs o{pointIndex[x.point], x.view, {std::log(double(x.rgb[0])), std::log(double(x.rgb[1])),
                                            std::log(double(x.rgb[2]))}, double(x.weight)};
        obs.push_back(o);
        out.constrained[x.view] = 1;
    }
    out.samplesUsed = obs.size();
    out.pointsUsed = points;
    if (obs.empty()) return out;

    // Observations grouped by point (counting sort), for the elimination of the points below.
    std::vector<std::size_t> pointStart(static_cast<std::size_t>(points) + 1, 0), byPoint(obs.size());
    for (const Obs& o : obs) ++pointStart[o.point + 1];
    for (std::uint32_t p = 0; p < points; ++p) pointStart[p + 1] += pointStart[p];
    {
        std::vector<std::size_t> next(pointStart.begin(), pointStart.end() - 1);
        for (std::size_t k = 0; k < obs.size(); ++k) byPoint[next[obs[k].point]++] = k;
    }
    // The constrained views, numbered 0..m-1: the unknowns.
    std::vector<std::uint32_t> unknown(viewCount, UINT32_MAX);
    std::uint32_t m = 0;
    for (std::size_t i = 0; i < viewCount; ++i)
        if (out.constrained[i]) unknown[i] = m++;

    std::vector<double> logG(3 * viewCount, 0.0), logX(3 * static_cast<std::size_t>(points), 0.0);
    std::vector<double> robust(obs.size(), 1.0), residual(obs.size());

    // min sum_k w_k (logY_k - logG_view - logX_point)^2 per channel, solved exactly: each point's
    // logX is its weighted mean given the gains, and eliminating it leaves a weighted graph Laplacian
    // over the views, L logG = b (L the same for the three channels), whose null space (a constant
    // added to every gain) is fixed by a geometric mean of 1 over the constrained views.
    auto solve = [&]() {
        ++out.solves;
        Eigen::MatrixXd laplacian = Eigen::MatrixXd::Zero(m, m);
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 3);
        struct ViewShare {  // one point's observations in one view
            std::uint32_t unknown;
            double weight, weightedLogY[3];
        };
        std::vector<ViewShare> shares;
        for (std::uint32_t p = 0; p < points; ++p) {
            shares.clear();
            double total = 0.0, totalY[3] = {0.0, 0.0, 0.0};
            for (std::size_t at = pointStart[p]; at < pointStart[p + 1]; ++at) {
                const std::size_t k = byPoint[at];
                const Obs& o = obs[k];
                const double w = o.weight * robust[k];
                std::size_t slot = 0;
                while (slot < shares.size() && shares[slot].unknown != unknown[o.view]) ++slot;
                if (slot == shares.size()) shares.push_back({unknown[o.view], 0.0, {0.0, 0.0, 0.0}});
                shares[slot].weight += w;
                total += w;
                for (int c = 0; c < 3; ++c) {
                    shares[slot].weightedLogY[c] += w * o.logY[c];
                    totalY[c] += w * o.logY[c];
                }
            }
            if (!(total > 0.0)) continue;
            for (const ViewShare& a : shares) {
                laplacian(a.unknown, a.unknown) += a.weight;
                for (const ViewShare& b : shares) laplacian(a.unknown, b.unknown) -= a.weight * b.weight / total;
                for (int c = 0; c < 3; ++c) rhs(a.unknown, c) += a.weightedLogY[c] - a.weight * totalY[c] / total;
            }
        }
        // The gauge: + (scale / m) 1 1^T makes L definite on a connected view graph and gives the
        // solution mean 0; a tiny ridge keeps views the graph splits off well-posed.
        const double scale = std::max(laplacian.trace() / m, 1e-300);
        laplacian.array() += scale / m;
        laplacian.diagonal().array() += 1e-12 * scale;
        const Eigen::MatrixXd g = laplacian.ldlt().solve(rhs);
        for (int c = 0; c < 3; ++c) {
            const double mean = g.col(c).mean();
            for (std::size_t i = 0; i < viewCount; ++i)
                if (out.constrained[i]) logG[3 * i + c] = g(unknown[i], c) - mean;
        }
        // The points given the gains (for the residuals of the reweighting).
        for (std::uint32_t p = 0; p < points; ++p) {
            double total = 0.0, sum[3] = {0.0, 0.0, 0.0};
            for (std::size_t at = pointStart[p]; at < pointStart[p + 1]; ++at) {
                const std::size_t k = byPoint[at];
                const double w = obs[k].weight * robust[k];
                total += w;
                for (int c = 0; c < 3; ++c) sum[c] += w * (obs[k].logY[c] - logG[3 * obs[k].view + c]);
            }
            for (int c = 0; c < 3; ++c) logX[3 * p + c] = total > 0.0 ? sum[c] / total : 0.0;
        }
    };

    solve();
    for (int pass = 0; pass < options.robustPasses; ++pass) {
        for (std::size_t k = 0; k < obs.size(); ++k) {
            const Obs& o = obs[k];
            double e = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double r = o.logY[c] - logG[3 * o.view + c] - logX[3 * o.point + c];
                e += r * r;
            }
            residual[k] = std::sqrt(e / 3.0);
        }
        std::vector<double> sorted(residual);
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        // Floor: log residuals of 1e-3 (0.1 %) are rounding, not outliers.
        const double sigma = std::max(sorted[sorted.size() / 2] / 0.6745, 1e-3);
        const double threshold = options.huberThreshold * sigma;
        for (std::size_t k = 0; k < obs.size(); ++k) robust[k] = residual[k] > threshold ? threshold / residual[k] : 1.0;
        solve();
    }
    for (std::size_t i = 0; i < viewCount; ++i)
        if (out.constrained[i])
            for (int c = 0; c < 3; ++c) out.gains[3 * i + c] = std::exp(logG[3 * i + c]);
    return out;
}

}  // namespace rad
