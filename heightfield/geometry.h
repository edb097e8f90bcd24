// Rays and parameter intervals shared by the height-field core and the tracer.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <limits>

namespace terracast {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A closed range [lo, hi] of ray parameters; empty when lo > hi.
struct Interval {
    double lo = 0.0;               // first accepted ray parameter
    double hi = kInfinity;         // last accepted ray parameter

    bool empty() const { return !(lo <= hi); }
    bool contains(double t) const { return lo <= t && t <= hi; }
    Interval intersect(Interval other) const { return {std::max(lo, other.lo), std::min(hi, other.hi)}; }
};

// A ray in a local metric frame (x east, y north, z up, metres). The direction need not be unit length;
// ray parameters then scale with it.
struct Ray {
    glm::dvec3 origin{0.0};        // metres, local frame
    glm::dvec3 dir{0.0, 0.0, -1.0};  // any non-zero length
    double time = 0.0;             // shutter time, for moving geometry

    glm::dvec3 at(double t) const { return origin + t * dir; }
};

}  // namespace terracast
