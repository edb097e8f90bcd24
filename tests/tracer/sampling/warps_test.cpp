// Warps from the square: they land where they should, preserve area where promised, and integrate known
// functions to their analytic values.
#include "support/statistics.h"
#include "tracer/sampling/rng.h"
#include "tracer/sampling/warps.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

using namespace terracast;
using namespace terracast::testing;

namespace {

constexpr double kPi = glm::pi<double>();
constexpr int kDraws = 200000;

// The mean of g over kDraws random points of the square, with its standard error.
MeanAndError monteCarlo(uint64_t seed, const std::function<double(glm::dvec2)>& g) {
    RandomStream s(seed);
    std::vector<double> values(kDraws);
    for (double& v : values) v = g(s.next2());
    return meanAndError(values);
}

// Checks that a Monte Carlo estimate is within four standard errors of the exact value.
void checkEstimate(const MeanAndError& m, double exact) {
    INFO("estimate " << m.mean << " +- " << m.standardError << ", exact " << exact);
    CHECK(std::abs(m.mean - exact) <= 4.0 * m.standardError + 1e-12);
}

// The area enclosed by the image of a square cell under the disk map, from its boundary traced densely.
double imageArea(glm::dvec2 lo, double size, int perEdge) {
    std::vector<glm::dvec2> outline;
    const glm::dvec2 corners[4] = {lo, lo + glm::dvec2(size, 0), lo + glm::dvec2(size), lo + glm::dvec2(0, size)};
    for (int e = 0; e < 4; ++e)
        for (int k = 0; k < perEdge; ++k) {
            const double t = double(k) / perEdge;
            outline.push_back(squareToConcentricDisk(glm::mix(corners[e], corners[(e + 1) % 4], t)));
        }
    double twice = 0.0;  // the shoelace formula
    for (size_t i = 0; i < outline.size(); ++i) {
        const glm::dvec2 a = outline[i], b = outline[(i + 1) % outline.size()];
        twice += a.x * b.y - a.y * b.x;
    }
    return std::abs(twice) / 2.0;
}

}  // namespace

TEST_CASE("The concentric map fills the unit disk and preserves area", "[tracer][sampling]") {
    // Every cell of an 8 x 8 split of the square maps to 1/64 of the disk's area pi.
    const int n = 8;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            INFO("cell " << i << ", " << j);
            CHECK(imageArea({double(i) / n, double(j) / n}, 1.0 / n, 256) == Approx(kPi / (n * n)).epsilon(1e-4));
        }
    // The centre goes to the centre, the square's edges to the circle, and nothing leaves the disk.
    CHECK(glm::length(squareToConcentricDisk({0.5, 0.5})) == 0.0);
    for (double t : {0.0, 0.1, 0.5, 0.77}) {
        CHECK(glm::length(squareToConcentricDisk({t, 0.0})) == Approx(1.0));
        CHECK(glm::length(squareToConcentricDisk({1.0, t})) == Approx(1.0));
    }
    RandomStream s(1);
    for (int k = 0; k < 10000; ++k) REQUIRE(glm::length(squareToConcentricDisk(s.next2())) <= 1.0 + 1e-15);
    // Uniform by area: E|p|^2 = 1/2, and a quarter of the points within radius 1/2.
    checkEstimate(monteCarlo(2, [](glm::dvec2 u) { const glm::dvec2 p = squareToConcentricDisk(u); return glm::dot(p, p); }),
                  0.5);
    checkEstimate(monteCarlo(3, [](glm::dvec2 u) { return glm::length(squareToConcentricDisk(u)) < 0.5 ? 1.0 : 0.0; }),
                  0.25);
}

TEST_CASE("The concentric map's angle is the library's cosine and sine within four ulps", "[tracer][sampling]") {
    // Shirley and Chiu's map written with std::cos and std::sin, against the map's own series for them: random
    // points, the diagonals (the largest angle, pi / 4) and points next to the axes (the smallest).
    const auto reference = [](glm::dvec2 u) {
        const glm::dvec2 a = 2.0 * u - 1.0;
        if (a.x == 0.0 && a.y == 0.0) return glm::dvec2(0.0);
        const bool xWide = std::abs(a.x) > std::abs(a.y);
        const double r = xWide ? a.x : a.y;
        const double phi = xWide ? kPi / 4.0 * (a.y / a.x) : kPi / 2.0 - kPi / 4.0 * (a.x / a.y);
        return glm::dvec2(r * std::cos(phi), r * std::sin(phi));
    };
    std::vector<glm::dvec2> points;
    RandomStream s(11);
    for (int k = 0; k < 100000; ++k) points.push_back(s.next2());
    for (double t : {0.0, 1e-12, 0.25, 0.5 - 1e-9, 0.75, 1.0 - 1e-15, 1.0}) {
        points.push_back({t, t});
        points.push_back({t, 1.0 - t});
        points.push_back({t, 0.5 + 1e-13});
        points.push_back({0.5 - 1e-13, t});
    }
    double worst = 0.0;
    for (const glm::dvec2& u : points) {
        const glm::dvec2 p = squareToConcentricDisk(u), q = reference(u);
        // Ulps of the point's distance from the centre, the scale both coordinates are computed at.
        const double ulp = std::max(std::abs(q.x), std::abs(q.y)) * std::numeric_limits<double>::epsilon();
        worst = std::max(worst, std::max(std::abs(p.x - q.x), std::abs(p.y - q.y)) / std::max(ulp, 1e-300));
    }
    INFO("worst difference " << worst << " ulps");
    CHECK(worst <= 4.0);
}

TEST_CASE("Uniform sphere directions integrate known functions", "[tracer][sampling]") {
    RandomStream s(4);
    for (int k = 0; k < 10000; ++k) REQUIRE(std::abs(glm::length(squareToUniformSphere(s.next2())) - 1.0) < 1e-14);
    // Estimates of integrals over the sphere: f / pdf averaged.
    const auto integral = [](uint64_t seed, std::function<double(glm::dvec3)> f) {
        return monteCarlo(seed, [f](glm::dvec2 u) { return f(squareToUniformSphere(u)) / uniformSpherePdf(); });
    };
    checkEstimate(integral(5, [](glm::dvec3 d) { return d.z; }), 0.0);
    checkEstimate(integral(6, [](glm::dvec3 d) { return d.x * d.x; }), 4.0 * kPi / 3.0);
    checkEstimate(integral(7, [](glm::dvec3 d) { return std::max(0.0, d.z); }), kPi);  // cosine over the hemisphere
}

TEST_CASE("Cone samples stay in the cap and are uniform in it", "[tracer][sampling]") {
    for (double thetaMax : {0.00465, 0.3, 1.2, kPi / 2.0, 2.5}) {
        INFO("theta max " << thetaMax);
        const double cosMax = std::cos(thetaMax);
        RandomStream s(8);
        std::vector<double> cosines;
        double widest = 0.0;
        for (int k = 0; k < 20000; ++k) {
            const glm::dvec3 d = squareToUniformCone(s.next2(), cosMax);
            REQUIRE(std::abs(glm::length(d) - 1.0) < 1e-14);
            const double angle = std::atan2(std::hypot(d.x, d.y), d.z);
            REQUIRE(angle <= thetaMax * (1.0 + 1e-9));
            widest = std::max(widest, angle);
            cosines.push_back((d.z - cosMax) / (1.0 - cosMax));
        }
        CHECK(widest > 0.99 * thetaMax);
        // Uniform by solid angle in a cap means cos(theta) uniform over [cos theta_max, 1].
        CHECK(ksUniformDistance(cosines) * std::sqrt(double(cosines.size())) < 1.95);
        // The cap's projected solid angle, the integral of cos(theta) over it, is pi sin^2(theta_max) (minus the
        // part below the horizon for caps wider than a hemisphere, where cos < 0 counts negatively).
        const double exact = kPi * std::sin(thetaMax) * std::sin(thetaMax);
        checkEstimate(monteCarlo(9, [cosMax](glm::dvec2 u) { return squareToUniformCone(u, cosMax).z / uniformConePdf(cosMax); }),
                      exact);
    }
}

TEST_CASE("Cone directions towards a spherical light all hit it", "[tracer][sampling]") {
    const glm::dvec3 centre{3.0, -4.0, 12.0};
    const double radius = 2.0, distance = glm::length(centre);
    const double cosMax = sphereConeCosine(distance, radius);
    CHECK(cosMax == Approx(std::sqrt(1.0 - radius * radius / (distance * distance))));
    CHECK(sphereConeCosine(1.0, 2.0) == -1.0);
    const Frame frame = Frame::around(centre / distance);
    RandomStream s(10);
    for (int k = 0; k < 10000; ++k) {
        const glm::dvec3 d = frame.toWorld(squareToUniformCone(s.next2(), cosMax));
        // Ray from the origin along d: the closest approach to the centre is within the radius.
        const double along = glm::dot(centre, d);
        const double miss2 = glm::dot(centre, centre) - along * along;
        REQUIRE(along > 0.0);
        REQUIRE(miss2 <= radius * radius * (1.0 + 1e-12));
    }
    // A direction just outside the cone misses.
    const double outside = std::acos(cosMax) * 1.001;
    const glm::dvec3 d = frame.toWorld({std::sin(outside), 0.0, std::cos(outside)});
    const double along = glm::dot(centre, d);
    CHECK(glm::dot(centre, centre) - along * along > radius * radius);
}

TEST_CASE("Frames around any axis are orthonormal and right-handed", "[tracer][sampling]") {
    RandomStream s(11);
    std::vector<glm::dvec3> axes{{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, glm::normalize(glm::dvec3(1e-9, 0, -1))};
    for (int k = 0; k < 1000; ++k) axes.push_back(squareToUniformSphere(s.next2()));
    for (const glm::dvec3& n : axes) {
        const Frame f = Frame::around(n);
        REQUIRE(std::abs(glm::length(f.s) - 1.0) < 1e-12);
        REQUIRE(std::abs(glm::length(f.t) - 1.0) < 1e-12);
        REQUIRE(std::abs(glm::dot(f.s, f.t)) < 1e-12);
        REQUIRE(std::abs(glm::dot(f.s, n)) < 1e-12);
        REQUIRE(std::abs(glm::dot(f.t, n)) < 1e-12);
        REQUIRE(glm::length(glm::cross(f.s, f.t) - n) < 1e-12);
        const glm::dvec3 v{0.3, -0.2, 0.9};
        REQUIRE(glm::length(f.toLocal(f.toWorld(v)) - v) < 1e-12);
    }
}

TEST_CASE("The Phong lobe has the moments of its power-cosine density", "[tracer][sampling]") {
    for (double n : {0.0, 1.0, 10.0, 100.0, 1000.0}) {
        INFO("exponent " << n);
        // E[cos^m] under pdf (n + 1) / (2 pi) cos^n is (n + 1) / (n + m + 1).
        for (double m : {1.0, 2.0}) {
            checkEstimate(monteCarlo(12, [n, m](glm::dvec2 u) { return std::pow(squareToPhongLobe(u, n).z, m); }),
                          (n + 1.0) / (n + m + 1.0));
        }
        // Around a tilted axis, the angle to the axis is what the lobe sampled.
        const glm::dvec3 axis = glm::normalize(glm::dvec3(0.2, -0.5, 0.7));
        const Frame frame = Frame::around(axis);
        checkEstimate(monteCarlo(13, [&](glm::dvec2 u) { return glm::dot(frame.toWorld(squareToPhongLobe(u, n)), axis); }),
                      (n + 1.0) / (n + 2.0));
        // The density integrates to 1 over the hemisphere (estimated with uniform hemisphere directions).
        if (n <= 10.0)
            checkEstimate(monteCarlo(14, [n](glm::dvec2 u) {
                              return phongLobePdf(squareToUniformCone(u, 0.0).z, n) / uniformConePdf(0.0);
                          }),
                          1.0);
    }
    CHECK(phongLobePdf(-0.1, 5.0) == 0.0);
    CHECK(phongLobePdf(1.0, 5.0) == Approx(6.0 / (2.0 * kPi)));
}

TEST_CASE("Cosine-weighted hemisphere directions have the cosine density", "[tracer][sampling]") {
    RandomStream s(15);
    for (int k = 0; k < 10000; ++k) {
        const glm::dvec3 d = squareToCosineHemisphere(s.next2());
        REQUIRE(d.z >= 0.0);
        REQUIRE(std::abs(glm::length(d) - 1.0) < 1e-12);
    }
    // E[cos] = (1 / pi) * integral of cos^2 over the hemisphere = 2/3; E[cos^2] = 1/2.
    checkEstimate(monteCarlo(16, [](glm::dvec2 u) { return squareToCosineHemisphere(u).z; }), 2.0 / 3.0);
    checkEstimate(monteCarlo(17, [](glm::dvec2 u) { const double c = squareToCosineHemisphere(u).z; return c * c; }), 0.5);
    // Importance sampling the cosine with its own density gives pi exactly, every sample.
    RandomStream t(18);
    for (int k = 0; k < 1000; ++k) {
        const glm::dvec3 d = squareToCosineHemisphere(t.next2());
        if (d.z > 1e-6) REQUIRE(d.z / cosineHemispherePdf(d.z) == Approx(kPi));
    }
}
