#include "tracer/measure/accuracy.h"

#include "tracer/core/angles.h"
#include "tracer/core/cancel.h"

#include "tracer/terrain/camera.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <random>

namespace terracast {

namespace {

struct TestRay {
    Ray ray;
    Interval interval;
    bool shadow = false;
};

// A random point on the reference surface, found by a vertical reference ray over a random valid position.
std::optional<HeightFieldHit> randomSurfacePoint(const HeightGrid& g, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (int attempt = 0; attempt < 1000; ++attempt) {
        const glm::dvec3 above{U(rng) * g.extentXM(), U(rng) * g.extentYM(), double(g.maxHeightM()) + 100.0};
        if (auto hit = intersect(g, Ray{above, {0, 0, -1}}, {0.0, kInfinity}, CellMethod::Reference)) return hit;
    }
    return std::nullopt;
}

// Builds the ray mix: camera-like rays from the automatic view, grazing rays that skim the surface at angles
// below about 3 degrees, and shadow-like rays leaving surface points towards a random sun.
std::vector<TestRay> makeRays(const HeightGrid& g, const AccuracyOptions& o, AccuracyReport& report) {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const PinholeCamera camera = autoCamera(g, 4.0 / 3.0);
    const int64_t third = o.rays / 3;
    std::vector<TestRay> rays;
    rays.reserve(size_t(o.rays));
    for (int64_t k = 0; k < third; ++k) rays.push_back({camera.generate(U(rng), U(rng), 4.0 / 3.0), {0, kInfinity}, false});
    report.cameraRays = third;
    const double cell = std::min(g.cellSizeXM(), g.cellSizeYM());
    for (int64_t k = 0; k < third; ++k) {
        const auto p = randomSurfacePoint(g, rng);
        if (!p) break;
        // A direction in the tangent plane, tilted into the surface by up to 0.05 rad.
        const glm::dvec3 n = p->normal;
        const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 t1 = glm::normalize(glm::cross(n, a)), t2 = glm::cross(n, t1);
        const double phi = 2.0 * kPi * U(rng);
        const glm::dvec3 tangent = std::cos(phi) * t1 + std::sin(phi) * t2;
        const glm::dvec3 dir = glm::normalize(tangent - 0.05 * U(rng) * n);
        const glm::dvec3 origin = p->pointM - 5.0 * cell * dir + (0.02 * cell * U(rng)) * n;
        rays.push_back({Ray{origin, dir}, {0, kInfinity}, false});
        ++report.grazingRays;
    }
    while (int64_t(rays.size()) < o.rays) {
        const auto p = randomSurfacePoint(g, rng);
        if (!p) break;
        const double az = 2.0 * kPi * U(rng), el = radians(2.0 + 58.0 * U(rng));
        const glm::dvec3 toSun = directionFromRadians(az, el);
        // Every method traces this same ray, so it starts clear of all their surfaces' rounding: a hundredth
        // of a cell above the reference surface along its normal.
        const glm::dvec3 n = glm::dot(p->normal, toSun) >= 0.0 ? p->normal : -p->normal;
        rays.push_back({Ray{p->pointM + 0.01 * cell * n, toSun}, {0, kInfinity}, true});
        ++report.shadowRays;
    }
    report.rays = int64_t(rays.size());
    return rays;
}

}  // namespace

ErrorSummary summariseErrors(std::vector<double> errors) {
    ErrorSummary s;
    if (errors.empty()) return s;
    std::sort(errors.begin(), errors.end());
    double sum = 0.0;
    for (double e : errors) sum += e;
    s.mean = sum / double(errors.size());
    s.p99 = errors[std::min(errors.size() - 1, size_t(std::ceil(0.99 * double(errors.size()))) - 1)];
    s.max = errors.back();
    return s;
}

AccuracyReport measureAccuracy(const HeightGrid& grid, const AccuracyOptions& options) {
    AccuracyReport report;
    report.grazingToleranceM = grazingToleranceM(grid);
    const std::vector<TestRay> rays = makeRays(grid, options, report);

    std::vector<std::optional<double>> refT(rays.size());
    std::vector<char> ambiguous(rays.size(), 0);
    for (size_t k = 0; k < rays.size(); ++k) {
        if ((k & 1023) == 0) throwIfCancelled();
        TraceCounters counters;
        const auto hit = intersect(grid, rays[k].ray, rays[k].interval, CellMethod::Reference, &counters);
        if (hit) refT[k] = hit->t;
        ambiguous[k] = counters.ambiguous;
        report.referenceHits += hit.has_value();
        report.ambiguousRays += counters.ambiguous;
        if (options.keepReferenceRays)
            report.referenceRays.push_back({rays[k].ray, rays[k].interval, refT[k], counters.ambiguous != 0});
    }

    std::vector<CellMethod> methods = options.methods;
    if (methods.empty())
        for (CellMethod m : allCellMethods())
            if (m != CellMethod::Reference) methods.push_back(m);

    for (CellMethod m : methods) {
        MethodAccuracy acc;
        acc.method = m;
        std::vector<std::optional<double>> t(rays.size());
        const auto start = std::chrono::steady_clock::now();
        for (size_t k = 0; k < rays.size(); ++k) {
            if ((k & 1023) == 0) throwIfCancelled();
            if (auto hit = intersect(grid, rays[k].ray, rays[k].interval, m)) t[k] = hit->t;
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        acc.raysPerSecond = seconds > 0.0 ? double(rays.size()) / seconds : 0.0;
        std::vector<double> absErr, relErr;
        for (size_t k = 0; k < rays.size(); ++k) {
            if (t[k].has_value() != refT[k].has_value()) {
                ++acc.disagreements;
                acc.unambiguousDisagreements += !ambiguous[k];
                continue;
            }
            ++acc.agreements;
            if (!t[k]) continue;
            const double e = std::abs(*t[k] - *refT[k]);
            absErr.push_back(e);
            relErr.push_back(*refT[k] > 0.0 ? e / *refT[k] : (e > 0.0 ? kInfinity : 0.0));
        }
        acc.comparedHits = int64_t(absErr.size());
        acc.tErrorM = summariseErrors(std::move(absErr));
        acc.tErrorRel = summariseErrors(std::move(relErr));
        report.methods.push_back(acc);
    }
    return report;
}

}  // namespace terracast
