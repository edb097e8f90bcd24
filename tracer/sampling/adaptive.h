// Adaptive sampling: a running estimate of a pixel's mean and variance, and the rule that stops sampling
// the pixel once its estimated error is small enough.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

namespace terracast {

// Relative luminance of linear RGB with Rec. 709 (sRGB) primaries.
inline double luminance(const glm::vec3& rgb) { return 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b; }

// Running mean and variance by Welford's update (1962, "Note on a method for calculating corrected sums of
// squares and products"): no sum of squares is kept, so a large mean does not cancel away a small variance.
struct RunningStats {
    int64_t count = 0;
    double mean = 0.0;
    double m2 = 0.0;  // sum of squared deviations from the current mean

    void add(double x) {
        ++count;
        const double delta = x - mean;
        mean += delta / double(count);
        m2 += delta * (x - mean);
    }
    // The unbiased sample variance (0 below two samples).
    double variance() const { return count > 1 ? m2 / double(count - 1) : 0.0; }
    // The standard error of the mean, sqrt(variance / n), as if the samples were independent. Stratified and
    // blue-noise samples are negatively correlated, so for them this overstates the error: the rule below
    // then stops later than it needs to, never earlier.
    double standardError() const { return count > 0 ? std::sqrt(variance() / double(count)) : 0.0; }
};

// When to stop sampling a pixel: after at least minSamples, once the standard error of its luminance is
// below absoluteError + relativeError * |mean|, or at maxSamples whatever the error.
struct AdaptiveStopRule {
    int minSamples = 16;          // never stop before this many (the variance estimate needs a few samples)
    int maxSamples = 256;         // always stop here
    double absoluteError = 0.002; // standard error allowed in linear luminance
    double relativeError = 0.01;  // plus this fraction of the mean luminance

    bool done(const RunningStats& s) const {
        if (s.count >= maxSamples) return true;
        if (s.count < minSamples) return false;
        return s.standardError() <= absoluteError + relativeError * std::abs(s.mean);
    }
};

}  // namespace terracast
