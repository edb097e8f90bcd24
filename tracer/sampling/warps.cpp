#include "tracer/sampling/warps.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace terracast {

namespace {
// A direction with the given cos(theta) around +z and azimuth 2 pi v. sin(theta) comes from
// (1 - c)(1 + c) rather than 1 - c^2, which keeps its precision for the tiny cones of the sun's disc.
glm::dvec3 directionAround(double cosTheta, double oneMinusCos, double v) {
    const double sinTheta = std::sqrt(std::max(0.0, oneMinusCos * (1.0 + cosTheta)));
    const double phi = 2.0 * glm::pi<double>() * v;
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}
}  // namespace

Frame Frame::around(const glm::dvec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    Frame f;
    f.s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    f.t = {b, sign + n.y * n.y * a, -n.y};
    f.n = n;
    return f;
}

namespace {

// cos and sin of x for |x| <= pi / 4, by their Taylor series through x^16 and x^17 (the next terms are below
// 1e-17 there): a fifth of the library's sincos, which the sky-visibility rays' directions spent most of their
// set-up in. Within a few ulps of std::cos and std::sin (tests/tracer/sampling/warps_test.cpp).
glm::dvec2 cosSinQuarter(double x) {
    // The series' coefficients from the highest power down, evaluated in x^2 by Horner's rule.
    static constexpr double kCos[] = {1.0 / 20922789888000.0, -1.0 / 87178291200.0, 1.0 / 479001600.0,
                                      -1.0 / 3628800.0,       1.0 / 40320.0,        -1.0 / 720.0,
                                      1.0 / 24.0,             -0.5,                 1.0};
    static constexpr double kSin[] = {1.0 / 355687428096000.0, -1.0 / 1307674368000.0, 1.0 / 6227020800.0,
                                      -1.0 / 39916800.0,       1.0 / 362880.0,         -1.0 / 5040.0,
                                      1.0 / 120.0,             -1.0 / 6.0};
    const double x2 = x * x;
    double c = kCos[0], s = kSin[0];
    for (size_t k = 1; k < std::size(kCos); ++k) c = c * x2 + kCos[k];
    for (size_t k = 1; k < std::size(kSin); ++k) s = s * x2 + kSin[k];
    return {c, s * x2 * x + x};
}

}  // namespace

glm::dvec2 squareToConcentricDisk(glm::dvec2 u) {
    const glm::dvec2 a = 2.0 * u - 1.0;
    if (a.x == 0.0 && a.y == 0.0) return {0.0, 0.0};
    // The square's concentric squares |a|_inf = r become circles of radius r; along each one the angle
    // grows linearly with arc length, over an eighth of the circle per half side (Shirley and Chiu 1997).
    // Where |a.y| < |a.x| the angle is theta = (pi / 4) a.y / a.x; elsewhere it is pi / 2 - theta' with
    // theta' = (pi / 4) a.x / a.y, whose cosine and sine are those of theta' swapped.
    if (std::abs(a.x) > std::abs(a.y)) {
        const glm::dvec2 cs = cosSinQuarter((glm::pi<double>() / 4.0) * (a.y / a.x));
        return {a.x * cs.x, a.x * cs.y};
    }
    const glm::dvec2 cs = cosSinQuarter((glm::pi<double>() / 4.0) * (a.x / a.y));
    return {a.y * cs.y, a.y * cs.x};
}

glm::dvec3 squareToUniformSphere(glm::dvec2 u) { return squareToUniformCone(u, -1.0); }

glm::dvec3 squareToUniformCone(glm::dvec2 u, double cosThetaMax) {
    const double oneMinusCos = u.x * (1.0 - cosThetaMax);
    return directionAround(1.0 - oneMinusCos, oneMinusCos, u.y);
}

double uniformConePdf(double cosThetaMax) { return 1.0 / (2.0 * glm::pi<double>() * (1.0 - cosThetaMax)); }

double sphereConeCosine(double distance, double radius) {
    if (distance <= radius) return -1.0;
    const double sinTheta = radius / distance;
    return std::sqrt(std::max(0.0, (1.0 - sinTheta) * (1.0 + sinTheta)));
}

glm::dvec3 squareToPhongLobe(glm::dvec2 u, double exponent) {
    // The cdf of cos(theta) under the lobe is c^(n + 1), so c = u^(1 / (n + 1)). 1 - u keeps u = 0 on the
    // axis and never takes the power of 0 (the horizon, where the density vanishes).
    const double cosTheta = std::pow(1.0 - u.x, 1.0 / (exponent + 1.0));
    return directionAround(cosTheta, 1.0 - cosTheta, u.y);
}

double phongLobePdf(double cosTheta, double exponent) {
    if (cosTheta <= 0.0) return 0.0;
    return (exponent + 1.0) / (2.0 * glm::pi<double>()) * std::pow(cosTheta, exponent);
}

glm::dvec3 squareToCosineHemisphere(glm::dvec2 u) {
    const glm::dvec2 d = squareToConcentricDisk(u);
    return {d.x, d.y, std::sqrt(std::max(0.0, 1.0 - glm::dot(d, d)))};
}

double cosineHemispherePdf(double cosTheta) { return cosTheta > 0.0 ? cosTheta / glm::pi<double>() : 0.0; }

}  // namespace terracast
