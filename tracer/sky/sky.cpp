#include "tracer/sky/sky.h"

#include "tracer/core/ranks.h"

#include "tracer/core/angles.h"

#include "tracer/sampling/warps.h"

#include <algorithm>
#include <cmath>
#include <deque>
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
    // Ranks sharing the work all build the table together (sharedSkyTables below says why).
    if (!entry || ranks::sharingWork()) entry = std::make_shared<const TransmittanceTable>(parameters);
    return entry;
}

namespace {

// The sky's tables for one atmosphere, viewer altitude and sun. The last two made are kept: a scene's single
// pixel traces (tracePixel, `scene --debug-pixel`) each make a Sky for the same viewer and sun, and building
// the tables (a few tens of milliseconds) would dwarf tracing the pixel.
std::shared_ptr<const SkyTables> sharedSkyTables(const std::shared_ptr<const TransmittanceTable>& transmittance,
                                                 double viewerAltitudeM, const glm::dvec3& sun) {
    struct Entry {
        const TransmittanceTable* transmittance;
        double altitudeM;
        glm::dvec3 sun;
        std::shared_ptr<const SkyTables> tables;
    };
    static std::mutex mutex;
    static std::deque<Entry> recent;
    std::lock_guard lock(mutex);
    // Ranks sharing the work all build the tables together: none may take them from its own history instead.
    if (!ranks::sharingWork())
        for (const Entry& e : recent)
            if (e.transmittance == transmittance.get() && e.altitudeM == viewerAltitudeM && e.sun == sun) return e.tables;
    auto tables = std::make_shared<const SkyTables>(transmittance, viewerAltitudeM, sun);
    recent.push_front({transmittance.get(), viewerAltitudeM, sun, tables});
    if (recent.size() > 2) recent.pop_back();
    return tables;
}

}  // namespace

Sky::Sky(const SkyDescription& description, const std::optional<SkySun>& sun, double viewerAltitudeM)
    : d_(description), viewerAltitudeM_(viewerAltitudeM) {
    if (d_.kind == SkyKind::Physical) {
        AtmosphereParameters a;
        a.haze = d_.haze;
        transmittance_ = sharedTransmittanceTable(a);
        const glm::dvec3 zenith = transmittance_->toTop(a.earthRadiusM, 1.0);
        whiteBalance_ = glm::vec3(1.0 / zenith);
        if (sun) {
            tables_ = sharedSkyTables(transmittance_, viewerAltitudeM, sun->direction);
            skyScale_ = float(kPi) * whiteBalance_ * sun->irradiance;
        }
    }
    ambientScale_ = d_.kind == SkyKind::None ? 0.0f : d_.ambientScale();
    if (d_.kind == SkyKind::Image && d_.image) buildIrradianceTable();
    // The cosine-weighted mean radiance of the upper hemisphere, on a 16 x 16 stratified grid.
    glm::dvec3 sum(0.0);
    constexpr int n = 16;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) sum += glm::dvec3(radiance(squareToCosineHemisphere({(i + 0.5) / n, (j + 0.5) / n})));
    hemisphereMean_ = glm::vec3(sum / double(n * n));
}

void Sky::buildIrradianceTable() {
    // For each normal n of the table, the sum over the picture's pixels of radiance x max(0, n . direction) x the
    // pixel's solid angle, over pi: the irradiance over pi, which times a diffuse albedo is the light the surface
    // sends back. Summing pixels rather than sampling directions keeps a small bright sun from aliasing. The
    // picture is first averaged down to at most 256 x 128 (block means keep its energy).
    const EnvironmentImage& image = *d_.image;
    const int bx = std::max(1, (image.width + 255) / 256), by = std::max(1, (image.height + 127) / 128);
    const int w = (image.width + bx - 1) / bx, h = (image.height + by - 1) / by;
    std::vector<glm::dvec3> dirs, weighted;  // per coarse pixel: direction, radiance x solid angle / pi
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            glm::dvec3 sum(0.0);
            int count = 0;
            for (int y = j * by; y < std::min((j + 1) * by, image.height); ++y)
                for (int x = i * bx; x < std::min((i + 1) * bx, image.width); ++x, ++count) {
                    const size_t k = (size_t(y) * size_t(image.width) + size_t(x)) * 3;
                    sum += glm::dvec3(image.rgb[k], image.rgb[k + 1], image.rgb[k + 2]);
                }
            // The block's centre and extent in the picture (the last block may be narrower).
            const double x0 = double(i * bx), x1 = double(std::min((i + 1) * bx, image.width));
            const double y0 = double(j * by), y1 = double(std::min((j + 1) * by, image.height));
            const double u = 0.5 * (x0 + x1) / image.width + d_.rotationDeg / 360.0;
            const double theta0 = y0 / image.height * kPi, theta1 = y1 / image.height * kPi;
            const double azimuth = (u - 0.5) * 2.0 * kPi, theta = 0.5 * (theta0 + theta1);
            const double solidAngle = (x1 - x0) / image.width * 2.0 * kPi * (std::cos(theta0) - std::cos(theta1));
            dirs.push_back({std::sin(theta) * std::sin(azimuth), std::sin(theta) * std::cos(azimuth), std::cos(theta)});
            weighted.push_back(double(d_.intensity) * sum / double(count) * solidAngle / kPi);
        }
    irradiance_.assign(size_t(kIrradianceWidth) * kIrradianceHeight, glm::vec3(0.0f));
    for (int j = 0; j < kIrradianceHeight; ++j)
        for (int i = 0; i < kIrradianceWidth; ++i) {
            const double azimuth = ((i + 0.5) / kIrradianceWidth - 0.5) * 2.0 * kPi;
            const double fromZenith = (j + 0.5) / kIrradianceHeight * kPi;
            const glm::dvec3 normal{std::sin(fromZenith) * std::sin(azimuth), std::sin(fromZenith) * std::cos(azimuth),
                                    std::cos(fromZenith)};
            glm::dvec3 e(0.0);
            for (size_t p = 0; p < dirs.size(); ++p) e += std::max(0.0, glm::dot(normal, dirs[p])) * weighted[p];
            irradiance_[size_t(j) * kIrradianceWidth + size_t(i)] = glm::vec3(e);
        }
}

glm::vec3 Sky::ambient(const glm::dvec3& n) const {
    if (irradiance_.empty()) return ambient(n.z);
    // The table's layout is the environment's (environmentCoordinates) over world normals: the image's rotation
    // was applied when it was built.
    return ambientScale_ * sampleLatLong(kIrradianceWidth, kIrradianceHeight, environmentCoordinates(n), [&](int i, int j) {
               return irradiance_[size_t(j) * kIrradianceWidth + size_t(i)];
           });
}

glm::vec3 Sky::radiance(const glm::dvec3& dir) const {
    switch (d_.kind) {
    case SkyKind::Image:
        return d_.image ? d_.intensity * environmentRadiance(*d_.image, dir, d_.rotationDeg) : glm::vec3(0.0f);
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
