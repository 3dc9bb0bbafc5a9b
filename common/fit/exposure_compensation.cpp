#include "fit/exposure_compensation.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rad {

std::string ExposureOptions::validate() const {
    std::ostringstream why;
    if (!(darkLevel > 0.0) || !std::isfinite(darkLevel))
        why << "the dark level must be a finite number > 0 (got " << darkLevel << ")";
    else if (!(saturationLevel > darkLevel) || !std::isfinite(saturationLevel))
        why << "the saturation level must be a finite number above the dark level (got " << saturationLevel << ")";
    else if (maxIterations < 1)
        why << "the number of iterations must be at least 1 (got " << maxIterations << ")";
    else if (!(tolerance > 0.0))
        why << "the tolerance must be > 0 (got " << tolerance << ")";
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

    std::vector<double> logG(3 * viewCount, 0.0), logX(3 * static_cast<std::size_t>(points), 0.0);
    std::vector<double> robust(obs.size(), 1.0), sumW(std::max<std::size_t>(viewCount, points));
    std::vector<double> acc(3 * std::max<std::size_t>(viewCount, points));
    std::vector<double> residual(obs.size());
    std::size_t constrainedViews = 0;
    for (std::size_t i = 0; i < viewCount; ++i) constrainedViews += out.constrained[i];

    auto alternate = [&]() {
        for (int it = 0; it < options.maxIterations; ++it) {
            ++out.iterations;
            // Points given the gains.
            std::fill(acc.begin(), acc.begin() + 3 * points, 0.0);
            std::fill(sumW.begin(), sumW.begin() + points, 0.0);
            for (std::size_t k = 0; k < obs.size(); ++k) {
                const Obs& o = obs[k];
                const double w = o.weight * robust[k];
                sumW[o.point] += w;
                for (int c = 0; c < 3; ++c) acc[3 * o.point + c] += w * (o.logY[c] - logG[3 * o.view + c]);
            }
            for (std::uint32_t p = 0; p < points; ++p)
                if (sumW[p] > 0.0)
                    for (int c = 0; c < 3; ++c) logX[3 * p + c] = acc[3 * p + c] / sumW[p];
            // Gains given the points, normalised to a geometric mean of 1 over the constrained views.
            std::fill(acc.begin(), acc.begin() + 3 * viewCount, 0.0);
            std::fill(sumW.begin(), sumW.begin() + viewCount, 0.0);
            for (std::size_t k = 0; k < obs.size(); ++k) {
                const Obs& o = obs[k];
                const double w = o.weight * robust[k];
                sumW[o.view] += w;
                for (int c = 0; c < 3; ++c) acc[3 * o.view + c] += w * (o.logY[c] - logX[3 * o.point + c]);
            }
            double meanLog[3] = {0.0, 0.0, 0.0};
            for (std::size_t i = 0; i < viewCount; ++i)
                if (out.constrained[i] && sumW[i] > 0.0)
                    for (int c = 0; c < 3; ++c) meanLog[c] += acc[3 * i + c] / sumW[i];
            for (int c = 0; c < 3; ++c) meanLog[c] /= static_cast<double>(constrainedViews);
            double change = 0.0;
            for (std::size_t i = 0; i < viewCount; ++i) {
                if (!out.constrained[i]) continue;
                for (int c = 0; c < 3; ++c) {
                    const double g = sumW[i] > 0.0 ? acc[3 * i + c] / sumW[i] - meanLog[c] : 0.0;
                    change = std::max(change, std::abs(g - logG[3 * i + c]));
                    logG[3 * i + c] = g;
                }
            }
            if (change < options.tolerance) break;
        }
    };

    alternate();
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
        alternate();
    }
    for (std::size_t i = 0; i < viewCount; ++i)
        if (out.constrained[i])
            for (int c = 0; c < 3; ++c) out.gains[3 * i + c] = std::exp(logG[3 * i + c]);
    return out;
}

}  // namespace rad
