// Pixel filters: unit integral, symmetry, support; samples drawn in proportion to each filter (their
// distribution, and the noise and bias of the pixel values they give); the weighted per-pixel average.
#include "tracer/sampling/filters.h"
#include "tracer/sampling/rng.h"
#include "tracer/sampling/samplers.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

namespace {

std::vector<PixelFilter> someFilters() {
    std::vector<PixelFilter> filters;
    for (FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian}) {
        filters.push_back(PixelFilter::defaults(kind));
        for (double radius : {0.3, 0.75, 1.0}) {
            PixelFilter f = PixelFilter::defaults(kind);
            f.radius = radius;
            filters.push_back(f);
        }
    }
    PixelFilter sharp = PixelFilter::defaults(FilterKind::Gaussian);
    sharp.alpha = 8.0;
    filters.push_back(sharp);
    return filters;
}

}  // namespace

TEST_CASE("Filter names parse and list", "[tracer][sampling]") {
    for (FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian}) {
        const auto parsed = parseFilterKind(filterKindName(kind));
        REQUIRE(parsed);
        CHECK(*parsed == kind);
        CHECK(std::string(filterKindList()).find(filterKindName(kind)) != std::string::npos);
    }
    CHECK_FALSE(parseFilterKind("mitchell"));
}

TEST_CASE("Filter settings outside their range are reported", "[tracer][sampling]") {
    for (const PixelFilter& f : someFilters()) CHECK_FALSE(f.problem());
    PixelFilter wide = PixelFilter::defaults(FilterKind::Tent);
    wide.radius = 1.5;
    REQUIRE(wide.problem());
    CHECK(wide.problem()->find("1.5") != std::string::npos);
    PixelFilter none = PixelFilter::defaults(FilterKind::Box);
    none.radius = 0.0;
    CHECK(none.problem());
    PixelFilter flat = PixelFilter::defaults(FilterKind::Gaussian);
    flat.alpha = -1.0;
    CHECK(flat.problem());
}

TEST_CASE("Filters integrate to one over their support", "[tracer][sampling]") {
    // Midpoint rule on a 400 x 400 grid over the support.
    const int m = 400;
    for (const PixelFilter& f : someFilters()) {
        INFO(filterKindName(f.kind) << " radius " << f.radius << " alpha " << f.alpha);
        double sum = 0.0;
        const double h = 2.0 * f.radius / m;
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) sum += f.evaluate({-f.radius + (i + 0.5) * h, -f.radius + (j + 0.5) * h});
        CHECK(sum * h * h == Approx(1.0).epsilon(1e-4));
    }
}

TEST_CASE("Filters are symmetric, positive inside and zero outside their radius", "[tracer][sampling]") {
    RandomStream s(3);
    for (const PixelFilter& f : someFilters()) {
        INFO(filterKindName(f.kind) << " radius " << f.radius);
        for (int k = 0; k < 1000; ++k) {
            const glm::dvec2 o = (2.0 * s.next2() - 1.0) * f.radius;
            const double v = f.evaluate(o);
            REQUIRE(v > 0.0);
            REQUIRE(f.evaluate({-o.x, o.y}) == v);
            REQUIRE(f.evaluate({o.x, -o.y}) == v);
            REQUIRE(f.evaluate({o.y, o.x}) == Approx(v).epsilon(1e-14));
            // Outside the support along either axis.
            const double beyond = f.radius * (1.0 + 1e-9) + s.next();
            REQUIRE(f.evaluate({beyond, o.y}) == 0.0);
            REQUIRE(f.evaluate({o.x, -beyond}) == 0.0);
        }
        // The largest value is at the centre.
        CHECK(f.evaluate({0.0, 0.0}) >= f.evaluate({0.5 * f.radius, 0.1 * f.radius}));
        if (f.kind != FilterKind::Box) CHECK(f.evaluate1D(f.radius) == 0.0);
    }
}

TEST_CASE("Tent and Gaussian filters have their documented shapes", "[tracer][sampling]") {
    const PixelFilter tent = PixelFilter::defaults(FilterKind::Tent);
    CHECK(tent.evaluate1D(0.0) == Approx(1.0));
    CHECK(tent.evaluate1D(0.25) == Approx(0.75));
    PixelFilter g = PixelFilter::defaults(FilterKind::Gaussian);
    g.alpha = 3.0;
    g.radius = 0.8;
    // Ratios do not depend on the normalisation.
    const double tail = std::exp(-3.0 * 0.64);
    CHECK(g.evaluate1D(0.3) / g.evaluate1D(0.0) == Approx((std::exp(-3.0 * 0.09) - tail) / (1.0 - tail)));
    const PixelFilter box = PixelFilter::defaults(FilterKind::Box);
    CHECK(box.evaluate({0.49, -0.2}) == Approx(1.0));
    CHECK(box.offsetOf({0.0, 0.999}).x == Approx(-0.5));
}

TEST_CASE("A pixel's value is its samples' filter-weighted mean", "[tracer][sampling]") {
    AccumulationFilm film(3, 2, PixelFilter::defaults(FilterKind::Tent));
    // Tent of radius 1: weights (1 - |x|)(1 - |y|), computed by hand.
    film.add(1, 1, {0.25, 0.0}, {1.0f, 2.0f, 3.0f});    // weight 0.75
    film.add(1, 1, {-0.5, 0.5}, {5.0f, 6.0f, 7.0f});    // weight 0.25
    film.add(1, 1, {1.0, 0.0}, {100.0f, 0.0f, 0.0f});   // weight 0: on the edge of the support
    const PixelAccumulator& p = film.at(1, 1);
    CHECK(p.samples == 3);
    CHECK(p.weightSum == Approx(1.0));
    const glm::vec3 v = p.value();
    CHECK(v.r == Approx(0.75 * 1.0 + 0.25 * 5.0));
    CHECK(v.g == Approx(0.75 * 2.0 + 0.25 * 6.0));
    CHECK(v.b == Approx(0.75 * 3.0 + 0.25 * 7.0));
    // Samples reach only their own pixel; a pixel without samples is black.
    const Film out = film.resolve();
    CHECK(out.get(1, 1) == v);
    CHECK(out.get(0, 1) == glm::vec3(0.0f));
    CHECK(out.get(2, 0) == glm::vec3(0.0f));

    // A radiance linear in the offset averages to its value at the centre under any symmetric filter when the
    // samples come in mirrored pairs.
    for (FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian}) {
        AccumulationFilm f(1, 1, PixelFilter::defaults(kind));
        RandomStream s(4);
        for (int k = 0; k < 50; ++k) {
            const glm::dvec2 o = f.filter().offsetOf(s.next2());
            for (double sign : {1.0, -1.0})
                f.add(0, 0, sign * o, glm::vec3(float(2.0 + sign * (o.x - 3.0 * o.y))));
        }
        CHECK(f.at(0, 0).value().r == Approx(2.0f).epsilon(1e-6));
    }
}

TEST_CASE("Offsets drawn from a filter follow its cumulative distribution, stratum by stratum", "[tracer][sampling]") {
    for (const PixelFilter& f : someFilters()) {
        INFO(filterKindName(f.kind) << " radius " << f.radius << " alpha " << f.alpha);
        // The cumulative distribution integrates the filter (midpoint rule) and inverts sample1D.
        const int m = 4000;
        double sum = 0.0;
        for (int i = 0; i < m; ++i) {
            const double x0 = -f.radius + 2.0 * f.radius * i / m, x1 = -f.radius + 2.0 * f.radius * (i + 1) / m;
            sum += f.evaluate1D(0.5 * (x0 + x1)) * (x1 - x0);
            if (i % 400 == 399) CHECK(f.cumulative1D(x1) == Approx(sum).margin(1e-6));
        }
        for (double u : {0.0, 0.001, 0.1, 0.25, 0.5, 0.6, 0.9, 0.999}) {
            const double x = f.sample1D(u);
            CHECK(std::abs(x) <= f.radius);
            CHECK(f.cumulative1D(x) == Approx(u).margin(1e-9));
        }
        CHECK(f.sample1D(0.5) == Approx(0.0).margin(1e-12));
        // Monotonic: stratified points stay in order.
        double last = -f.radius;
        for (int i = 0; i < 200; ++i) {
            const double x = f.sample1D((i + 0.5) / 200.0);
            CHECK(x > last);
            last = x;
        }
    }
}

TEST_CASE("Every filter's pixel values are unbiased and no noisier than the box's at equal samples",
          "[tracer][sampling]") {
    // A sharp edge at an angle through the pixel's centre: the values 1 beyond it, 0 before (a half under every
    // filter, so that each filter's samples see the same spread of values).
    const auto image = [](glm::dvec2 o) { return 0.9 * o.x + 0.436 * o.y > 0.0 ? 1.0 : 0.0; };
    const int pixels = 3000, spp = 16;
    double boxNoise = 0.0;
    for (FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian}) {
        const PixelFilter f = PixelFilter::defaults(kind);
        INFO(filterKindName(kind));
        // The exact filtered value by the midpoint rule over the support.
        const int m = 600;
        const double h = 2.0 * f.radius / m;
        double exact = 0.0;
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) {
                const glm::dvec2 o{-f.radius + (i + 0.5) * h, -f.radius + (j + 0.5) * h};
                exact += f.evaluate(o) * image(o) * h * h;
            }
        // Each pixel's value: the plain mean of its stratified samples drawn from the filter.
        const PixelSampler sampler(SamplePattern::Stratified, spp, 7);
        double sum = 0.0, squares = 0.0;
        for (int p = 0; p < pixels; ++p) {
            double value = 0.0;
            for (int k = 0; k < spp; ++k) value += image(f.offsetOf(sampler.sample(p, 0, k, 0)));
            value /= spp;
            sum += value;
            squares += (value - exact) * (value - exact);
        }
        const double mean = sum / pixels, noise = std::sqrt(squares / pixels);
        INFO("exact " << exact << ", mean " << mean << ", RMS error " << noise);
        CHECK(std::abs(mean - exact) < 4.0 * noise / std::sqrt(double(pixels)));
        if (kind == FilterKind::Box) boxNoise = noise;
        else CHECK(noise <= 1.05 * boxNoise);
        CHECK(noise > 0.0);
    }
}
