#include "tracer/sampling/filters.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace terracast {

namespace {
constexpr std::pair<FilterKind, const char*> kFilterNames[] = {
    {FilterKind::Box, "box"},
    {FilterKind::Tent, "tent"},
    {FilterKind::Gaussian, "gaussian"},
};

// The integral of exp(-alpha x^2) - exp(-alpha r^2) over [-r, r].
double gaussianIntegral(double radius, double alpha) {
    return std::sqrt(glm::pi<double>() / alpha) * std::erf(std::sqrt(alpha) * radius) - 2.0 * radius * std::exp(-alpha * radius * radius);
}

// The truncated Gaussian's terms that do not depend on x, and its density, distribution and inverse distribution
// along one axis: the same expressions, to the bit, as PixelFilter::evaluate1D and cumulative1D.
struct GaussianTerms {
    GaussianTerms() = default;
    GaussianTerms(double radius, double alpha)
        : r(radius), alpha(alpha), k(std::sqrt(alpha)), half(0.5 * std::sqrt(glm::pi<double>() / alpha)),
          erfKr(std::erf(k * radius)), expR(std::exp(-alpha * radius * radius)),
          integral(gaussianIntegral(radius, alpha)) {}

    double density(double x) const {
        const double a = std::abs(x);
        return a > r ? 0.0 : std::max(0.0, std::exp(-alpha * a * a) - expR) / integral;
    }
    double distribution(double x) const {
        const double c = std::clamp(x, -r, r);
        return std::clamp((half * (std::erf(k * c) + erfKr) - expR * (c + r)) / integral, 0.0, 1.0);
    }
    // The x where the distribution reaches u, to 1e-12: Newton's method from x, kept inside a shrinking bracket
    // (a bisection step whenever Newton's would leave it); the distribution is smooth and increasing inside the
    // support.
    double inverse(double u, double x) const {
        double lo = -r, hi = r;
        for (int n = 0; n < 64; ++n) {
            const double g = distribution(x) - u;
            if (g < 0.0) lo = x;
            else hi = x;
            const double f = density(x);
            double next = f > 0.0 ? x - g / f : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            if (std::abs(next - x) < 1e-12) return next;
            x = next;
        }
        return x;
    }

    double r = 1.0, alpha = 2.0, k = 0.0, half = 0.0, erfKr = 0.0, expR = 0.0, integral = 1.0;
};
}  // namespace

std::span<const FilterKind> filterKinds() {
    static constexpr FilterKind kAll[] = {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian};
    static_assert(std::size(kAll) == std::size(kFilterNames));
    return kAll;
}

std::optional<FilterKind> parseFilterKind(std::string_view name) {
    for (const auto& [kind, text] : kFilterNames)
        if (name == text) return kind;
    return std::nullopt;
}

const char* filterKindName(FilterKind kind) {
    for (const auto& [k, text] : kFilterNames)
        if (k == kind) return text;
    return "unknown";
}

const char* filterKindList() { return "box, tent, gaussian"; }

PixelFilter PixelFilter::defaults(FilterKind kind) {
    PixelFilter f;
    f.kind = kind;
    f.radius = kind == FilterKind::Box ? 0.5 : 1.0;
    return f;
}

std::optional<std::string> PixelFilter::problem() const {
    if (!(radius > 0.0 && radius <= 1.0))
        return "filter radius: expected a value in (0, 1] pixels, found " + std::to_string(radius);
    if (kind == FilterKind::Gaussian && !(alpha > 0.0 && std::isfinite(alpha)))
        return "Gaussian filter alpha: expected a positive value, found " + std::to_string(alpha);
    return std::nullopt;
}

double PixelFilter::evaluate1D(double x) const {
    const double a = std::abs(x);
    if (a > radius) return 0.0;
    switch (kind) {
    case FilterKind::Box: return 0.5 / radius;
    case FilterKind::Tent: return (radius - a) / (radius * radius);
    case FilterKind::Gaussian:
        return std::max(0.0, std::exp(-alpha * a * a) - std::exp(-alpha * radius * radius)) /
               gaussianIntegral(radius, alpha);
    }
    return 0.0;
}

double PixelFilter::cumulative1D(double x) const {
    const double r = radius, c = std::clamp(x, -r, r);
    switch (kind) {
    case FilterKind::Box: return (c + r) / (2.0 * r);
    case FilterKind::Tent: {
        const double s = (r - std::abs(c)) / r;  // the tail beyond |c| holds s^2 / 2
        return c <= 0.0 ? 0.5 * s * s : 1.0 - 0.5 * s * s;
    }
    case FilterKind::Gaussian: {
        const double k = std::sqrt(alpha), half = 0.5 * std::sqrt(glm::pi<double>() / alpha);
        const double area = half * (std::erf(k * c) + std::erf(k * r)) - std::exp(-alpha * r * r) * (c + r);
        return std::clamp(area / gaussianIntegral(r, alpha), 0.0, 1.0);
    }
    }
    return 0.0;
}

double PixelFilter::sample1D(double u) const {
    const double r = radius;
    switch (kind) {
    case FilterKind::Box: return (2.0 * u - 1.0) * r;
    case FilterKind::Tent:
        // Inverting the two quadratic halves of the cumulative distribution.
        return u < 0.5 ? r * (std::sqrt(2.0 * u) - 1.0) : r * (1.0 - std::sqrt(2.0 - 2.0 * u));
    case FilterKind::Gaussian: {
        // A table per thread, made again when the filter changes: the filter's constant terms, and its inverse
        // distribution at 256 steps of u, from which Newton's method starts (one or two steps left to take).
        struct InverseTable {
            double radius = 0.0, alpha = 0.0;
            GaussianTerms terms;
            std::array<double, 257> x{};
        };
        thread_local InverseTable table;
        if (table.radius != r || table.alpha != alpha) {
            table.radius = r;
            table.alpha = alpha;
            table.terms = GaussianTerms(r, alpha);
            for (size_t k = 0; k < table.x.size(); ++k)
                table.x[k] = k == 0 ? -r : k + 1 == table.x.size() ? r : table.terms.inverse(double(k) / 256.0, 0.0);
        }
        const double at = (u > 0.0 ? std::min(u, 1.0) : 0.0) * 256.0;  // NaN as 0
        const size_t k = std::min<size_t>(size_t(at), 255);
        return table.terms.inverse(u, table.x[k] + (at - double(k)) * (table.x[k + 1] - table.x[k]));
    }
    }
    return 0.0;
}

AccumulationFilm::AccumulationFilm(int width, int height, PixelFilter filter)
    : width_(width), height_(height), filter_(filter), pixels_(size_t(width) * size_t(height)) {}

Film AccumulationFilm::resolve() const {
    Film film(width_, height_);
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) film.set(x, y, at(x, y).value());
    return film;
}

}  // namespace terracast
