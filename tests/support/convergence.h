// Measuring how estimates converge: RMS errors over many independent trials and the power law they follow.
// The tests of the samplers use it on a known integral; render tests use it against a high-sample reference.
#pragma once

#include "tracer/sampling/samplers.h"

#include <functional>
#include <vector>

namespace terracast {

// error = coefficient * n^exponent, fitted by least squares on (log n, log error).
struct PowerLawFit {
    double exponent = 0.0;
    double coefficient = 0.0;
    double r2 = 0.0;  // coefficient of determination of the log-log line (1 = a perfect power law)
};
// Needs at least two points with distinct positive x and positive y.
PowerLawFit fitPowerLaw(const std::vector<double>& x, const std::vector<double>& y);

// The root-mean-square difference between estimates and a reference value.
double rmsError(const std::vector<double>& estimates, double reference);

// The N-sample estimate of the integral of f over [0, 1]^2 for one pixel of a sampler: the mean of f over
// the pixel's samples in dimension 0. Different pixels are independent trials.
double estimateIntegral(const PixelSampler& sampler, int64_t px, int64_t py, const std::function<double(glm::dvec2)>& f);

// RMS error of that estimate over `trials` pixels (a row of pixels 0 .. trials - 1) against `exact`.
double integrationRmsError(const PixelSampler& sampler, const std::function<double(glm::dvec2)>& f, double exact,
                           int trials);

}  // namespace terracast
