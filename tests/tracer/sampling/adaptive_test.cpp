// Adaptive sampling: Welford's running statistics against exact values, and the stop rule against the
// sample count the standard-error formula predicts.
#include "tracer/sampling/adaptive.h"
#include "tracer/sampling/rng.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

TEST_CASE("Running statistics match exact means and variances", "[tracer][sampling]") {
    // 1, 2, ..., 10: mean 5.5, sample variance n (n + 1) / 12 = 110 / 12.
    RunningStats s;
    CHECK(s.variance() == 0.0);
    CHECK(s.standardError() == 0.0);
    for (int i = 1; i <= 10; ++i) s.add(i);
    CHECK(s.count == 10);
    CHECK(s.mean == Approx(5.5));
    CHECK(s.variance() == Approx(110.0 / 12.0));
    CHECK(s.standardError() == Approx(std::sqrt(110.0 / 12.0 / 10.0)));

    // A large offset with a small spread, where a running sum of squares in double would lose every digit of
    // the variance: compare with a two-pass computation in long double.
    RunningStats big;
    RandomStream r(1);
    std::vector<long double> xs;
    for (int i = 0; i < 100000; ++i) {
        const double x = 1e9 + (r.next() - 0.5);
        xs.push_back(x);
        big.add(x);
    }
    long double mean = 0.0L, m2 = 0.0L;
    for (long double x : xs) mean += x;
    mean /= xs.size();
    for (long double x : xs) m2 += (x - mean) * (x - mean);
    const long double variance = m2 / (xs.size() - 1);
    CHECK(big.mean == Approx(double(mean)).epsilon(1e-13));
    CHECK(big.variance() == Approx(double(variance)).epsilon(1e-6));
    CHECK(big.variance() == Approx(1.0 / 12.0).epsilon(0.02));  // uniform over an interval of width 1
}

TEST_CASE("The stop rule waits for the minimum, then for the standard error", "[tracer][sampling]") {
    AdaptiveStopRule rule;
    rule.minSamples = 8;
    rule.maxSamples = 100000;
    rule.absoluteError = 0.05;
    rule.relativeError = 0.0;

    // A constant pixel stops as soon as it may.
    RunningStats constant;
    while (!rule.done(constant)) constant.add(0.7);
    CHECK(constant.count == 8);

    // A pixel that is 0 or 1 with equal odds has standard error 0.5 / sqrt(n): it should stop near n = 100.
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        RunningStats coin;
        RandomStream r(seed);
        while (!rule.done(coin)) coin.add(r.next() < 0.5 ? 1.0 : 0.0);
        INFO("seed " << seed << " stopped after " << coin.count);
        CHECK(coin.count >= 70);
        CHECK(coin.count <= 140);
        CHECK(coin.standardError() <= 0.05);
    }

    // The cap always wins.
    rule.maxSamples = 20;
    RunningStats noisy;
    RandomStream r(3);
    while (!rule.done(noisy)) noisy.add(100.0 * r.next());
    CHECK(noisy.count == 20);

    // A relative threshold scales with the mean: a bright pixel with the same relative noise stops as early.
    AdaptiveStopRule relative;
    relative.minSamples = 8;
    relative.maxSamples = 100000;
    relative.absoluteError = 0.0;
    relative.relativeError = 0.02;
    for (double scale : {1.0, 1000.0}) {
        RunningStats s;
        RandomStream q(4);
        while (!relative.done(s)) s.add(scale * (1.0 + (q.next() - 0.5)));
        // Standard deviation sqrt(1/12) of a mean 1: n = (0.2887 / 0.02)^2 = 208.
        CHECK(s.count == Approx(208).epsilon(0.25));
    }
}

TEST_CASE("Luminance weighs linear RGB by the Rec. 709 coefficients", "[tracer][sampling]") {
    CHECK(luminance({1.0f, 1.0f, 1.0f}) == Approx(1.0));
    CHECK(luminance({1.0f, 0.0f, 0.0f}) == Approx(0.2126));
    CHECK(luminance({0.0f, 1.0f, 0.0f}) == Approx(0.7152));
    CHECK(luminance({0.0f, 0.0f, 2.0f}) == Approx(0.1444));
}
