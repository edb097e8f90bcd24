// Pixel filters: unit integral, symmetry, support; the weighted per-pixel average built on them.
#include "tracer/sampling/filters.h"
#include "tracer/sampling/rng.h"

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
