#include "support/convergence.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace terracast {

PowerLawFit fitPowerLaw(const std::vector<double>& x, const std::vector<double>& y) {
    if (x.size() != y.size() || x.size() < 2) throw std::invalid_argument("fitPowerLaw: needs two or more (x, y) pairs");
    const double n = double(x.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        if (!(x[i] > 0.0 && y[i] > 0.0)) throw std::invalid_argument("fitPowerLaw: needs positive x and y");
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
        syy += ly * ly;
    }
    const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n, cxy = sxy - sx * sy / n;
    if (!(vx > 0.0)) throw std::invalid_argument("fitPowerLaw: needs distinct x values");
    PowerLawFit fit;
    fit.exponent = cxy / vx;
    fit.coefficient = std::exp((sy - fit.exponent * sx) / n);
    fit.r2 = vy > 0.0 ? cxy * cxy / (vx * vy) : 1.0;
    return fit;
}

double rmsError(const std::vector<double>& estimates, double reference) {
    if (estimates.empty()) return 0.0;
    double sum = 0.0;
    for (double e : estimates) sum += (e - reference) * (e - reference);
    return std::sqrt(sum / double(estimates.size()));
}

double estimateIntegral(const PixelSampler& sampler, int64_t px, int64_t py, const std::function<double(glm::dvec2)>& f) {
    const int n = sampler.samplesPerPixel();
    double sum = 0.0;
    for (int k = 0; k < n; ++k) sum += f(sampler.sample(px, py, k));
    return sum / n;
}

double integrationRmsError(const PixelSampler& sampler, const std::function<double(glm::dvec2)>& f, double exact,
                           int trials) {
    std::vector<double> estimates(size_t(std::max(trials, 0)));
    for (int t = 0; t < trials; ++t) estimates[size_t(t)] = estimateIntegral(sampler, t, 0, f);
    return rmsError(estimates, exact);
}

}  // namespace terracast
