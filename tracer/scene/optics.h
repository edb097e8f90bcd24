// Reflection, refraction, Fresnel and absorption: the optics of the Whitted recursion.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace terracast {

// Mirror direction of `d` about the unit normal `n` (either side).
inline glm::dvec3 reflect(const glm::dvec3& d, const glm::dvec3& n) { return d - 2.0 * glm::dot(d, n) * n; }

// Refraction of the unit direction `d` through a surface with unit normal `n` facing the incoming side
// (dot(d, n) < 0), from index `etaFrom` into `etaTo`, by Snell's law. None under total internal reflection.
inline std::optional<glm::dvec3> refract(const glm::dvec3& d, const glm::dvec3& n, double etaFrom, double etaTo) {
    const double eta = etaFrom / etaTo;
    const double cosI = -glm::dot(d, n);
    const double sin2T = eta * eta * std::max(0.0, 1.0 - cosI * cosI);
    if (sin2T >= 1.0) return std::nullopt;
    const double cosT = std::sqrt(1.0 - sin2T);
    return glm::normalize(eta * d + (eta * cosI - cosT) * n);
}

// Schlick's approximation of the Fresnel reflectance (Schlick 1994, "An inexpensive BRDF model for
// physically-based rendering"): R0 + (1 - R0)(1 - cos)^5 with R0 = ((n1 - n2) / (n1 + n2))^2. `cosI` is the
// cosine on the incoming side; when leaving the denser medium the cosine of the transmitted angle is used, and
// total internal reflection gives 1.
inline double fresnelSchlick(double cosI, double etaFrom, double etaTo) {
    if (etaFrom == etaTo) return 0.0;  // no interface (the formula itself would leave (1 - cos)^5)
    double c = std::clamp(cosI, 0.0, 1.0);
    if (etaFrom > etaTo) {
        const double eta = etaFrom / etaTo;
        const double sin2T = eta * eta * (1.0 - c * c);
        if (sin2T >= 1.0) return 1.0;
        c = std::sqrt(1.0 - sin2T);
    }
    const double r0 = ((etaFrom - etaTo) / (etaFrom + etaTo)) * ((etaFrom - etaTo) / (etaFrom + etaTo));
    const double m = 1.0 - c;
    return r0 + (1.0 - r0) * m * m * m * m * m;
}

// The exact Fresnel reflectance of unpolarised light at a dielectric interface: the mean of the s- and
// p-polarised reflectances from the Fresnel equations (Born and Wolf, "Principles of Optics", section 1.5).
inline double fresnelDielectric(double cosI, double etaFrom, double etaTo) {
    const double c = std::clamp(cosI, 0.0, 1.0);
    const double eta = etaFrom / etaTo;
    const double sin2T = eta * eta * (1.0 - c * c);
    if (sin2T >= 1.0) return 1.0;
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rs = (etaFrom * c - etaTo * cosT) / (etaFrom * c + etaTo * cosT);
    const double rp = (etaTo * c - etaFrom * cosT) / (etaTo * c + etaFrom * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

// The critical angle of total internal reflection (radians) leaving a medium of index `etaFrom` into `etaTo`.
inline double criticalAngle(double etaFrom, double etaTo) { return std::asin(std::min(1.0, etaTo / etaFrom)); }

// Beer-Lambert transmittance exp(-sigma s) over `distanceM` metres of a medium with absorption `sigma` per metre.
inline glm::vec3 beerLambert(const glm::vec3& sigmaPerM, double distanceM) {
    return {float(std::exp(-double(sigmaPerM.r) * distanceM)), float(std::exp(-double(sigmaPerM.g) * distanceM)),
            float(std::exp(-double(sigmaPerM.b) * distanceM))};
}

}  // namespace terracast
