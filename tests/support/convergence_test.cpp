// Convergence of sampled integrals: the power-law fit itself, then the error rates of the patterns on a
// smooth and on a discontinuous integrand over the unit square (exact integrals known).
#include "support/convergence.h"
#include "tracer/sampling/warps.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

namespace {

const std::vector<int> kCounts{4, 8, 16, 32, 64, 128, 256};

// The fitted error exponent of a pattern over kCounts, each RMS over `trials` pixels.
PowerLawFit errorRate(SamplePattern pattern, const std::function<double(glm::dvec2)>& f, double exact, int trials) {
    std::vector<double> n, rms;
    for (int count : kCounts) {
        const PixelSampler sampler(pattern, count, 77);
        n.push_back(sampler.samplesPerPixel());
        rms.push_back(integrationRmsError(sampler, f, exact, trials));
    }
    return fitPowerLaw(n, rms);
}

// Smooth: sin(pi x) sin(pi y), integral 4 / pi^2.
double smooth(glm::dvec2 p) { return std::sin(glm::pi<double>() * p.x) * std::sin(glm::pi<double>() * p.y); }
const double kSmoothIntegral = 4.0 / (glm::pi<double>() * glm::pi<double>());

// Discontinuous: the indicator of a disk of radius 0.3 inside the square, integral 0.09 pi.
double disk(glm::dvec2 p) { return glm::length(p - glm::dvec2(0.45, 0.52)) < 0.3 ? 1.0 : 0.0; }
const double kDiskIntegral = 0.09 * glm::pi<double>();

}  // namespace

TEST_CASE("A power law fit recovers the exponent and coefficient of exact data", "[tracer][sampling]") {
    std::vector<double> x, y;
    for (double v : {2.0, 5.0, 11.0, 100.0}) {
        x.push_back(v);
        y.push_back(3.0 * std::pow(v, -0.7));
    }
    const PowerLawFit fit = fitPowerLaw(x, y);
    CHECK(fit.exponent == Approx(-0.7));
    CHECK(fit.coefficient == Approx(3.0));
    CHECK(fit.r2 == Approx(1.0));
    CHECK_THROWS(fitPowerLaw({1.0}, {1.0}));
    CHECK_THROWS(fitPowerLaw({1.0, 1.0}, {1.0, 2.0}));
    CHECK(rmsError({1.0, 3.0}, 2.0) == Approx(1.0));
}

TEST_CASE("Random sampling converges as N^-1/2, stratified faster", "[tracer][sampling]") {
    // Theory: the RMS error of N independent samples is sigma / sqrt(N). Jittered sampling in 2D gives
    // N^-1 on a smooth integrand and N^-3/4 on one with a discontinuous edge (each of the ~sqrt(N) strata
    // the edge crosses contributes variance).
    const int trials = 2000;
    const PowerLawFit randomSmooth = errorRate(SamplePattern::Random, smooth, kSmoothIntegral, trials);
    const PowerLawFit randomDisk = errorRate(SamplePattern::Random, disk, kDiskIntegral, trials);
    const PowerLawFit stratSmooth = errorRate(SamplePattern::Stratified, smooth, kSmoothIntegral, trials);
    const PowerLawFit stratDisk = errorRate(SamplePattern::Stratified, disk, kDiskIntegral, trials);
    INFO("random " << randomSmooth.exponent << " / " << randomDisk.exponent << ", stratified " << stratSmooth.exponent
                   << " / " << stratDisk.exponent);
    CHECK(randomSmooth.exponent == Approx(-0.5).margin(0.05));
    CHECK(randomDisk.exponent == Approx(-0.5).margin(0.05));
    CHECK(stratSmooth.exponent < -0.9);
    CHECK(stratDisk.exponent < -0.65);
    CHECK(stratDisk.exponent > -0.85);
    // The random error's coefficient is the integrand's standard deviation: for the disk indicator,
    // sqrt(a (1 - a)) with a its area.
    CHECK(randomDisk.coefficient == Approx(std::sqrt(kDiskIntegral * (1.0 - kDiskIntegral))).epsilon(0.1));
}

TEST_CASE("Shifted Poisson and best-candidate patterns beat random at every count", "[tracer][sampling]") {
    // A randomly shifted blue-noise set is not a faster-converging estimator in general: its power spectrum
    // does not vanish at the lowest frequencies (Pilleboue et al. 2015, "Variance analysis for Monte Carlo
    // integration"), so its error keeps random sampling's N^-1/2 rate with a smaller constant, and since each
    // count has its own precomputed set the error is irregular in N. Measured for N = 16 .. 256: 0.10 to 0.48
    // of random's RMS error on these integrands; stratified sampling has the better rate.
    const int trials = 1000;
    for (int count : {16, 32, 64, 128, 256}) {
        const PixelSampler random(SamplePattern::Random, count, 77);
        const double randomSmooth = integrationRmsError(random, smooth, kSmoothIntegral, trials);
        const double randomDisk = integrationRmsError(random, disk, kDiskIntegral, trials);
        for (SamplePattern pattern : {SamplePattern::Poisson, SamplePattern::BestCandidate}) {
            const PixelSampler sampler(pattern, count, 77);
            const double s = integrationRmsError(sampler, smooth, kSmoothIntegral, trials) / randomSmooth;
            const double d = integrationRmsError(sampler, disk, kDiskIntegral, trials) / randomDisk;
            INFO(samplePatternName(pattern) << " N " << count << ": error / random's " << s << " (smooth), " << d
                                            << " (disk)");
            CHECK(s < 0.6);
            CHECK(d < 0.6);
        }
    }
}
