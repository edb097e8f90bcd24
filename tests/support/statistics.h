// Small statistical yardsticks for the sampling tests: chi-square and Kolmogorov-Smirnov uniformity checks,
// means with their standard errors, and brute-force point spacing.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace terracast::testing {

// Pearson's chi-square statistic of bin counts against the same expected count in every bin.
inline double chiSquare(const std::vector<int64_t>& counts, double expectedPerBin) {
    double x2 = 0.0;
    for (int64_t c : counts) x2 += (double(c) - expectedPerBin) * (double(c) - expectedPerBin) / expectedPerBin;
    return x2;
}

// A generous acceptance limit for a chi-square statistic with `dof` degrees of freedom: the mean plus six
// standard deviations (a correct generator fails it far less than once in a million runs).
inline double chiSquareLimit(int dof) { return dof + 6.0 * std::sqrt(2.0 * dof); }

// The Kolmogorov-Smirnov distance between the sample's empirical distribution and the uniform one on [0, 1].
// sqrt(n) D above 1.95 rejects uniformity at the 0.1 % level.
inline double ksUniformDistance(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const double n = double(values.size());
    double d = 0.0;
    for (size_t i = 0; i < values.size(); ++i)
        d = std::max({d, (double(i) + 1.0) / n - values[i], values[i] - double(i) / n});
    return d;
}

struct MeanAndError {
    double mean = 0.0;
    double standardError = 0.0;  // of the mean
};
inline MeanAndError meanAndError(const std::vector<double>& xs) {
    double sum = 0.0, sum2 = 0.0;
    for (double x : xs) sum += x;
    const double n = double(xs.size()), mean = sum / n;
    for (double x : xs) sum2 += (x - mean) * (x - mean);
    return {mean, std::sqrt(sum2 / (n - 1.0) / n)};
}

// Shortest difference between two points of the unit torus.
inline glm::dvec2 torusDifference(glm::dvec2 a, glm::dvec2 b) {
    glm::dvec2 d = a - b;
    return d - glm::round(d);
}

// The smallest distance between two points of the set, checking every pair (toroidal when asked).
inline double minPairDistance(const std::vector<glm::dvec2>& p, bool toroidal) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < p.size(); ++i)
        for (size_t j = i + 1; j < p.size(); ++j)
            best = std::min(best, glm::length(toroidal ? torusDifference(p[i], p[j]) : p[i] - p[j]));
    return best;
}

// The smallest angle (radians) between two directions of the set, checking every pair.
inline double minPairAngle(const std::vector<glm::dvec3>& d) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < d.size(); ++i)
        for (size_t j = i + 1; j < d.size(); ++j)
            best = std::min(best, std::atan2(glm::length(glm::cross(d[i], d[j])), glm::dot(d[i], d[j])));
    return best;
}

}  // namespace terracast::testing
