// Pixel reconstruction filters and the per-pixel weighted average that uses them.
//
// How samples reach pixels: each pixel keeps its own samples. A pixel's N sample positions lie in the
// filter's support, the square [-radius, radius]^2 around the pixel's centre (radius up to one pixel, so
// neighbouring pixels' supports overlap but no sample is shared), drawn with a density proportional to the
// filter (importance sampling of the filter, Cook 1986, "Stochastic sampling in computer graphics"; pbrt-v4
// does the same with its FilterSampler): each sample then carries the same weight, and the pixel's value is
// their plain mean, an estimate of the filtered image with the noise of a plain average rather than that of
// weights that vary from sample to sample. Nothing splats into neighbouring pixels, so pixels can be
// rendered in any order on any thread without locks.
#pragma once

#include "tracer/sampling/film.h"

#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace terracast {

enum class FilterKind {
    Box,       // constant over the support: a plain average
    Tent,      // linear fall-off to zero at the radius (separable: a pyramid)
    Gaussian,  // exp(-alpha x^2), shifted down to reach zero at the radius (separable)
};

// Parses "box", "tent" or "gaussian".
// Every filter, in the order lists and messages show them.
std::span<const FilterKind> filterKinds();
std::optional<FilterKind> parseFilterKind(std::string_view name);
const char* filterKindName(FilterKind kind);
// The names parseFilterKind accepts, comma-separated, for messages.
const char* filterKindList();

// A separable filter f(x, y) = f1(x) f1(y), normalised so that its integral over the support is 1.
//   box:      f1(x) = 1 / (2 r)
//   tent:     f1(x) = (r - |x|) / r^2
//   Gaussian: f1(x) = (exp(-alpha x^2) - exp(-alpha r^2)) / G with G its integral over [-r, r]; alpha = 2
//             per square pixel is a standard deviation of half a pixel before the shift (as pbrt's
//             Gaussian filter, which subtracts the value at the radius so the filter has no step there).
// Every filter is zero at and outside the radius (the box: outside only).
struct PixelFilter {
    FilterKind kind = FilterKind::Box;
    double radius = 0.5;  // half-width of the support, pixels, in (0, 1]
    double alpha = 2.0;   // Gaussian fall-off, per square pixel (unused by box and tent)

    // The usual settings of each kind: box 0.5 (the pixel itself), tent and Gaussian 1 pixel.
    static PixelFilter defaults(FilterKind kind);

    // A one-line description of what is wrong with the settings, or none.
    std::optional<std::string> problem() const;

    // The filter at an offset (pixels) from the pixel's centre.
    double evaluate(glm::dvec2 offset) const { return evaluate1D(offset.x) * evaluate1D(offset.y); }
    double evaluate1D(double x) const;

    // The offset (pixels) from the pixel's centre of a sample at u in [0, 1)^2, drawn with density equal to
    // the filter: each axis by the inverse of the 1D filter's cumulative distribution (exact for box and tent,
    // solved to 1e-12 of a pixel for the Gaussian). Monotonic in each coordinate of u, so stratified points
    // stay stratified. A sample so drawn has weight 1: its value enters the pixel's plain mean.
    glm::dvec2 offsetOf(glm::dvec2 u) const { return {sample1D(u.x), sample1D(u.y)}; }
    double sample1D(double u) const;

    // The filter's cumulative distribution along one axis: the integral of evaluate1D from -radius to x.
    double cumulative1D(double x) const;
};

// The weighted samples of one pixel.
struct PixelAccumulator {
    glm::dvec3 weightedSum{0.0};  // sum of w_i L_i
    double weightSum = 0.0;       // sum of w_i
    int samples = 0;              // samples added, whatever their weight

    void add(const glm::vec3& radiance, double weight) {
        weightedSum += weight * glm::dvec3(radiance);
        weightSum += weight;
        ++samples;
    }
    // The weighted mean; black when no sample carried weight.
    glm::vec3 value() const { return weightSum > 0.0 ? glm::vec3(weightedSum / weightSum) : glm::vec3(0.0f); }
};

// A film of pixel accumulators. add() touches one pixel only, so threads working on different pixels never
// meet.
class AccumulationFilm {
public:
    AccumulationFilm(int width, int height, PixelFilter filter);

    int width() const { return width_; }
    int height() const { return height_; }
    const PixelFilter& filter() const { return filter_; }

    // A sample of pixel (x, y) at `offset` pixels from its centre, weighted by the filter there.
    void add(int x, int y, glm::dvec2 offset, const glm::vec3& radiance) {
        at(x, y).add(radiance, filter_.evaluate(offset));
    }
    PixelAccumulator& at(int x, int y) { return pixels_[index(x, y)]; }
    const PixelAccumulator& at(int x, int y) const { return pixels_[index(x, y)]; }

    // Every pixel's weighted mean.
    Film resolve() const;

private:
    size_t index(int x, int y) const { return size_t(y) * size_t(width_) + size_t(x); }

    int width_;
    int height_;
    PixelFilter filter_;
    std::vector<PixelAccumulator> pixels_;
};

}  // namespace terracast
