// The sky a render sees, built once per render from the scene's sky description: the physical atmosphere's
// tables (tracer/sky/atmosphere.h) or the simple gradient and flat skies. Everything it returns is in the
// renderers' units, where a white surface of albedo a facing a sun of irradiance E has radiance a E.
#pragma once

#include "tracer/sky/atmosphere.h"
#include "tracer/sky/sky_description.h"
#include "tracer/sampling/warps.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace terracast {

// The sun that lights a physical sky: unit direction towards it and its irradiance (colour times intensity).
struct SkySun {
    glm::dvec3 direction{0.0, 0.0, 1.0};
    glm::vec3 irradiance{1.0f};
};

// Point i of n in [0, 1)^2 for sky-visibility rays: a rank-1 lattice (x stratified, y stepping by the golden
// ratio) shifted by `shift` (a random point per pixel and sample), so that even a few rays spread over the
// hemisphere once warped to cosine-weighted directions.
glm::dvec2 skyVisibilityPoint(int i, int n, const glm::dvec2& shift);

// The open share of the hemisphere about the unit normal `n`, from `count` cosine-weighted directions spread by
// skyVisibilityPoint with `shift`; `blocked(dir)` traces one sky-visibility ray and says whether it is stopped.
template <class Blocked>
float openSkyFraction(const glm::dvec3& n, int count, const glm::dvec2& shift, Blocked&& blocked) {
    const Frame frame = Frame::around(n);
    int open = 0;
    for (int i = 0; i < count; ++i)
        open += !blocked(frame.toWorld(squareToCosineHemisphere(skyVisibilityPoint(i, count, shift))));
    return float(open) / float(count);
}

// The sky seen along a unit direction: a gradient from a pale horizon to a deeper zenith.
glm::vec3 gradientSky(const glm::dvec3& dir);

// The transmittance table of an atmosphere, shared by every render in the process that uses the same haze.
std::shared_ptr<const TransmittanceTable> sharedTransmittanceTable(const AtmosphereParameters& parameters);

class Sky {
public:
    // `sun` lights the physical sky (none: a sky at night); `viewerAltitudeM` places the camera above sea level.
    Sky(const SkyDescription& description, const std::optional<SkySun>& sun, double viewerAltitudeM);

    SkyKind kind() const { return d_.kind; }
    const SkyDescription& description() const { return d_; }

    // Radiance arriving from the sky along a unit direction (the sun's disc excluded). Below the physical
    // horizon this is the Earth's lit ground seen through the air, not the sky.
    glm::vec3 radiance(const glm::dvec3& dir) const;
    // The irradiance a sun of `irradiance` (as a scene states it) delivers at an altitude: reddened by the air
    // in front of it with the physical sky (white when the sun stands at the zenith over sea level), unchanged
    // otherwise.
    glm::vec3 sunlight(const glm::vec3& irradiance, const glm::dvec3& toSun, double altitudeM) const;
    double viewerAltitudeM() const { return viewerAltitudeM_; }
    // What the viewer sees of a surface of radiance `surface` at `distanceM` along `dir`: dimmed by the air and
    // with the light the air scatters in added (aerial perspective). Unchanged unless enabled.
    glm::vec3 throughAir(const glm::vec3& surface, const glm::dvec3& dir, double distanceM) const;
    // The two terms of throughAir: the air's transmittance and the light it scatters in (1 and 0 unless enabled).
    void air(const glm::dvec3& dir, double distanceM, glm::vec3& transmittance, glm::vec3& inscattered) const;
    bool aerialPerspective() const { return tables_ && d_.aerialPerspective; }

    // Sky light on a surface of normal z-component `normalZ` with the whole sky open: the cosine-weighted mean
    // radiance of the upper hemisphere, times the ambient scale, fading on tilted surfaces (half on a wall).
    glm::vec3 ambient(double normalZ) const { return ambientScale_ * float(0.5 + 0.5 * normalZ) * hemisphereMean_; }
    // Sky light on a surface of unit normal `n` with the whole sky open. An environment image is lit from every
    // side differently: the cosine-weighted mean of its radiance over the hemisphere about n, from a table over
    // normal directions. The other skies depend on n.z alone (ambient(n.z)).
    glm::vec3 ambient(const glm::dvec3& n) const;
    // The ambient scale alone (sky light = scale x mean radiance of the open sky directions).
    float ambientScale() const { return ambientScale_; }

private:
    void buildIrradianceTable();

    SkyDescription d_;
    double viewerAltitudeM_ = 0.0;
    std::shared_ptr<const TransmittanceTable> transmittance_;
    std::shared_ptr<const SkyTables> tables_;
    glm::vec3 skyScale_{0.0f};      // physical: pi x white balance x the sun's irradiance
    glm::vec3 whiteBalance_{1.0f};  // physical: 1 / transmittance of a zenith sun at sea level
    float ambientScale_ = 0.0f;
    glm::vec3 hemisphereMean_{0.0f};
    // Image: the cosine-weighted mean radiance about each normal of a kIrradianceWidth x kIrradianceHeight
    // equirectangular grid of normals (the environment's own layout).
    static constexpr int kIrradianceWidth = 64, kIrradianceHeight = 32;
    std::vector<glm::vec3> irradiance_;
};

}  // namespace terracast
