#include "tracer/sampling/filters.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
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

AccumulationFilm::AccumulationFilm(int width, int height, PixelFilter filter)
    : width_(width), height_(height), filter_(filter), pixels_(size_t(width) * size_t(height)) {}

Film AccumulationFilm::resolve() const {
    Film film(width_, height_);
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) film.set(x, y, at(x, y).value());
    return film;
}

}  // namespace terracast
