// A clear-sky atmosphere by single scattering (Nishita, Sirai, Tadamura, Nakamae 1993, "Display of the Earth
// taking into account atmospheric scattering"): Rayleigh and Mie scattering in an exponential atmosphere over
// a spherical Earth, with the constants of Bruneton's reference implementation (Bruneton 2017, "A qualitative
// and quantitative evaluation of 8 clear sky models", and his precomputed atmospheric scattering code).
// Ozone absorption and multiple scattering are left out.
//
// Frames: a point is given by its radius r from the Earth's centre, a direction by mu, the cosine of its angle
// to the local zenith. Radiances are for a sun of unit irradiance at the top of the atmosphere, per channel.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <vector>

namespace terracast {

struct AtmosphereParameters {
    double earthRadiusM = 6360e3;
    double topRadiusM = 6420e3;
    // Rayleigh scattering at sea level at 680, 550 and 440 nm (red, green, blue), per metre; no absorption.
    glm::dvec3 rayleighScattering{5.802e-6, 13.558e-6, 33.100e-6};
    double rayleighScaleHeightM = 8000.0;
    // Mie (aerosol) scattering and extinction at sea level, per metre, grey.
    double mieScattering = 4.0e-6;
    double mieExtinction = 4.44e-6;
    double mieScaleHeightM = 1200.0;
    double mieG = 0.8;                 // Henyey-Greenstein asymmetry
    double haze = 1.0;                 // multiplies Mie scattering and extinction (turbidity knob)
    double sunAngularRadius = 0.004675;  // radians
    double groundAlbedo = 0.1;         // the Earth below the horizon, beyond any modelled terrain

    // Extinction per metre at an altitude (metres above the Earth's surface).
    glm::dvec3 extinctionAt(double altitudeM) const;
};

// Rayleigh phase function, 3 (1 + nu^2) / (16 pi), nu the cosine of the scattering angle.
double rayleighPhase(double nu);
// Henyey-Greenstein phase function (1 - g^2) / (4 pi (1 + g^2 - 2 g nu)^1.5).
double henyeyGreensteinPhase(double nu, double g);

// Distance from radius r along direction mu to the top of the atmosphere (r inside it).
double distanceToTop(const AtmosphereParameters& a, double r, double mu);
// Whether the ray from radius r along mu meets the ground (the Earth's sphere).
bool rayHitsGround(const AtmosphereParameters& a, double r, double mu);

// Optical depth per channel from radius r along mu to the top of the atmosphere, by Simpson's rule with `steps`
// intervals (the reference, in double precision). Rays that hit the ground are integrated to the top anyway.
glm::dvec3 opticalDepthToTop(const AtmosphereParameters& a, double r, double mu, int steps);

// Transmittance to the top of the atmosphere, tabulated over (r, mu) for rays that do not meet the ground, with
// Bruneton's parameterisation (distance to the top between its bounds, and rho = sqrt(r^2 - R^2)); the table
// holds optical depth, so interpolation errors are relative errors of the transmittance.
class TransmittanceTable {
public:
    static constexpr int kMuSize = 512;
    static constexpr int kRSize = 128;

    explicit TransmittanceTable(const AtmosphereParameters& a);

    // Transmittance from radius r along mu to the top; zero when the ray meets the ground.
    glm::dvec3 toTop(double r, double mu) const;
    // Transmittance of sunlight reaching radius r from a sun at mu, with the sun's disc partly below the
    // horizon fading it out (the disc's angular radius).
    glm::dvec3 sunlight(double r, double muSun) const;
    const AtmosphereParameters& parameters() const { return a_; }

private:
    glm::dvec3 opticalDepth(double r, double mu) const;
    AtmosphereParameters a_;
    std::vector<glm::vec3> depth_;  // kRSize rows of kMuSize optical depths
};

// Single-scattered light along a view ray, split by scatterer and without the phase functions, which depend
// only on the angle to the sun: radiance = rayleigh * betaR * P_R(nu) + mie * betaMs * P_M(nu) (+ ground).
struct Inscatter {
    glm::dvec3 rayleigh{0.0};  // integral of transmittance * Rayleigh density * sunlight transmittance
    glm::dvec3 mie{0.0};
    glm::dvec3 transmittance{1.0};  // from the viewer to the end of the segment
};

// Brute-force single scattering for a viewer `altitudeM` above the ground looking along the unit direction
// `view` (z up) with the sun along `sun`: the segment to the top of the atmosphere, the ground, or `maxDistanceM`,
// integrated with `steps` midpoint intervals and sunlight transmittance integrated directly at every step
// (no tables). Returns the radiance, including the lit ground below the horizon when the ray reaches it.
glm::dvec3 referenceRadiance(const AtmosphereParameters& a, double altitudeM, const glm::dvec3& view,
                             const glm::dvec3& sun, int steps, double maxDistanceM = 1e30);

// The sky for one viewer altitude and one sun direction, tabulated once: sky radiance per view direction
// (above the horizon, and the ground with its haze below it, in separate tables so neither blurs into the
// other) and the aerial perspective per view direction and distance.
class SkyTables {
public:
    // `sun` is the unit direction towards the sun. Filling the tables takes a few tens of milliseconds.
    SkyTables(std::shared_ptr<const TransmittanceTable> transmittance, double viewerAltitudeM, const glm::dvec3& sun);

    // Radiance along a unit direction (z up) for a sun of unit irradiance at the top of the atmosphere.
    glm::vec3 radiance(const glm::dvec3& dir) const;
    // Light added by the air between the viewer and a point `distanceM` away along `dir`, and the transmittance
    // of that segment: seen radiance = transmittance * surface radiance + inscattered.
    void aerial(const glm::dvec3& dir, double distanceM, glm::vec3& transmittance, glm::vec3& inscattered) const;

    double viewerAltitudeM() const { return altitudeM_; }
    // The elevation angle (radians, negative) of the viewer's horizon on the spherical Earth.
    double horizonElevation() const { return horizonElevation_; }

    static constexpr int kAzimuthSize = 64;    // by the cosine of the azimuth from the sun's (the sky is symmetric)
    static constexpr int kSkyRows = 64;        // horizon to zenith
    static constexpr int kGroundRows = 32;     // nadir to horizon
    static constexpr int kAerialAzimuth = 32;
    static constexpr int kAerialRows = 64;     // nadir to zenith
    static constexpr int kAerialSlices = 32;   // distances, quadratic up to kAerialMaxM
    static constexpr double kAerialMaxM = 300e3;

private:
    struct Texel {
        glm::vec3 rayleigh, mie, extra;  // extra: ground radiance (ground table) or optical depth (aerial)
    };
    glm::vec3 combine(const Texel& t, double nu) const;
    void angles(const glm::dvec3& dir, double& column, double& z, double& nu) const;
    double zOfRow(double row, bool ground, int rows) const;
    double rowOfZ(double z, bool ground, int rows) const;
    Texel march(const glm::dvec3& view, double maxDistanceM, int steps, std::vector<Texel>* slices) const;

    std::shared_ptr<const TransmittanceTable> t_;
    AtmosphereParameters a_;
    double altitudeM_, r_;
    glm::dvec3 sun_;
    glm::dvec2 sunFlat_;        // the sun's azimuth as a horizontal unit vector
    double horizonElevation_;
    double horizonZ_;
    std::vector<Texel> sky_, ground_, aerial_;
};

}  // namespace terracast
