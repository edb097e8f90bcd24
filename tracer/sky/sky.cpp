#include "tracer/sky/sky.h"

#include "tracer/core/angles.h"

#include "tracer/sampling/warps.h"

#include <cmath>
#include <map>
#include <mutex>

namespace terracast {

namespace {
glm::vec3 mix(const glm::vec3& a, const glm::vec3& b, float w) { return a + (b - a) * w; }
}  // namespace

glm::vec3 gradientSky(const glm::dvec3& dir) {
    const glm::vec3 horizon{0.75f, 0.83f, 0.92f};
    const glm::vec3 zenith{0.23f, 0.42f, 0.75f};
    const glm::vec3 haze{0.62f, 0.68f, 0.76f};
    const double z = dir.z / std::max(1e-30, glm::length(dir));
    if (z < 0.0) return mix(horizon, haze, float(std::min(1.0, -z * 3.0)));
    return mix(horizon, zenith, float(std::pow(z, 0.6)));
}

glm::dvec2 skyVisibilityPoint(int i, int n, const glm::dvec2& shift) {
    const double x = (i + shift.x) / n, y = shift.y + 0.6180339887498949 * i;
    return {x, y - std::floor(y)};
}

std::shared_ptr<const TransmittanceTable> sharedTransmittanceTable(const AtmosphereParameters& parameters) {
    // Keyed by haze, the only parameter a user sets; a few entries at most.
    static std::mutex mutex;
    static std::map<double, std::shared_ptr<const TransmittanceTable>> cache;
    std::lock_guard lock(mutex);
    auto& entry = cache[parameters.haze];
    if (!entry) entry = std::make_shared<const TransmittanceTable>(parameters);
    return entry;
}

Sky::Sky(const SkyDescription& description, const std::optional<SkySun>& sun, double viewerAltitudeM)
    : d_(description), viewerAltitudeM_(viewerAltitudeM) {
    if (d_.kind == SkyKind::Physical) {
        AtmosphereParameters a;
        a.haze = d_.haze;
        transmittance_ = sharedTransmittanceTable(a);
        const glm::dvec3 zenith = transmittance_->toTop(a.earthRadiusM, 1.0);
        whiteBalance_ = glm::vec3(1.0 / zenith);
        if (sun) {
            tables_ = std::make_unique<SkyTables>(transmittance_, viewerAltitudeM, sun->direction);
            skyScale_ = float(kPi) * whiteBalance_ * sun->irradiance;
        }
    }
    ambientScale_ = d_.kind == SkyKind::None ? 0.0f : d_.ambientScale();
    // The cosine-weighted mean radiance of the upper hemisphere, on a 16 x 16 stratified grid.
    glm::dvec3 sum(0.0);
    constexpr int n = 16;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) sum += glm::dvec3(radiance(squareToCosineHemisphere({(i + 0.5) / n, (j + 0.5) / n})));
    hemisphereMean_ = glm::vec3(sum / double(n * n));
}

glm::vec3 Sky::radiance(const glm::dvec3& dir) const {
    switch (d_.kind) {
    case SkyKind::None: return glm::vec3(0.0f);
    case SkyKind::Flat: return d_.colour;
    case SkyKind::Gradient: return gradientSky(dir);
    case SkyKind::Physical: return tables_ ? skyScale_ * tables_->radiance(dir) : glm::vec3(0.0f);
    }
    return glm::vec3(0.0f);
}

glm::vec3 Sky::sunlight(const glm::vec3& irradiance, const glm::dvec3& toSun, double altitudeM) const {
    if (!transmittance_) return irradiance;
    const double r = transmittance_->parameters().earthRadiusM + std::max(0.0, altitudeM);
    return irradiance * whiteBalance_ * glm::vec3(transmittance_->sunlight(r, toSun.z));
}

glm::vec3 Sky::throughAir(const glm::vec3& surface, const glm::dvec3& dir, double distanceM) const {
    if (!aerialPerspective()) return surface;
    glm::vec3 t, in;
    air(dir, distanceM, t, in);
    return t * surface + in;
}

void Sky::air(const glm::dvec3& dir, double distanceM, glm::vec3& transmittance, glm::vec3& inscattered) const {
    transmittance = glm::vec3(1.0f);
    inscattered = glm::vec3(0.0f);
    if (!aerialPerspective()) return;
    tables_->aerial(dir, distanceM, transmittance, inscattered);
    inscattered *= skyScale_;
}

}  // namespace terracast
