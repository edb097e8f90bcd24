// A pixel's value from its camera samples, for both renderers: a fixed number of samples of the pattern, or,
// adaptive, samples until the stop rule is met. Each sample is placed in the pixel by the filter's importance
// sampling (PixelFilter::offsetOf), so every sample weighs the same and the pixel is their plain mean.
#pragma once

#include "tracer/sampling/adaptive.h"
#include "tracer/sampling/filters.h"
#include "tracer/sampling/samplers.h"

#include <glm/glm.hpp>

#include <atomic>
#include <memory>

namespace terracast {

// How a render samples its pixels.
struct PixelSampling {
    int samples = 1;            // per pixel; 1 traces the pixel centre only
    SamplePattern pattern = SamplePattern::Stratified;
    PixelFilter filter;         // box over the pixel by default
    // With `adaptive`, a pixel takes samples until its standard error falls below the rule's threshold, between
    // rule.minSamples and rule.maxSamples (`samples` is then ignored).
    bool adaptive = false;
    AdaptiveStopRule rule;

    // `samples` of `pattern` through `filter` (its usual radius), or with `adaptiveError` adaptive sampling up to
    // max(samples, 2) per pixel until the standard error of a pixel's luminance is below it.
    static PixelSampling make(int samples, SamplePattern pattern, FilterKind filter, bool adaptive,
                              double adaptiveError) {
        PixelSampling s;
        s.samples = samples;
        s.pattern = pattern;
        s.filter = PixelFilter::defaults(filter);
        s.adaptive = adaptive;
        if (adaptive) {
            s.rule.maxSamples = samples > 2 ? samples : 2;
            s.rule.minSamples = s.rule.minSamples < s.rule.maxSamples ? s.rule.minSamples : s.rule.maxSamples;
            s.rule.absoluteError = adaptiveError;
        }
        return s;
    }

    // The sample pattern of a render: none for one sample per pixel (the pixel's centre alone).
    std::unique_ptr<PixelSampler> makeSampler(uint64_t seed) const {
        if (!adaptive && samples <= 1) return nullptr;
        // An adaptive pixel may stop after any number of samples: each prefix must cover the pixel.
        return std::make_unique<PixelSampler>(pattern, adaptive ? rule.maxSamples : samples, seed, adaptive);
    }
    // The samples a pixel takes at most.
    int maxSamples(const PixelSampler* sampler) const {
        if (!sampler) return 1;
        return adaptive ? rule.maxSamples : sampler->samplesPerPixel();
    }
};

// The mean of radiance(k) over the samples k = 0, 1, ... of one pixel. A long pixel stops early when `cancel`
// is raised (the caller then drops the film).
template <class Radiance>
glm::vec3 estimatePixel(const PixelSampling& sampling, const PixelSampler* sampler, const std::atomic<bool>& cancel,
                        Radiance&& radiance) {
    PixelAccumulator sum;
    RunningStats stats;
    const int n = sampling.maxSamples(sampler);
    for (int k = 0; k < n; ++k) {
        if ((k & 255) == 255 && cancel.load(std::memory_order_relaxed)) break;
        const glm::vec3 value = radiance(k);
        sum.add(value, 1.0);
        if (!sampling.adaptive) continue;
        stats.add(luminance(value));
        if (sampling.rule.done(stats)) break;
    }
    return sum.value();
}

}  // namespace terracast
