// The clear-sky irradiance model of the European Solar Radiation Atlas as GRASS r.sun uses it (Rigollier, Bauer
// and Wald 2000, "On the clear sky model of the ESRA", Solar Energy 68(1); Suri and Hofierka 2004, "A new GIS-based
// solar radiation model and its application to photovoltaic assessments", Transactions in GIS 8(2)): beam and
// diffuse irradiance from the Linke turbidity factor, the diffuse light on a slope by Muneer's model (Muneer 1990,
// "Solar radiation model for Europe", Building Services Engineering Research and Technology 11(4)) and the light
// reflected by the ground around it. All irradiances in W/m^2.
#pragma once

namespace terracast {

// The atmosphere and the ground.
struct ClearSky {
    double linkeTurbidity = 3.0;   // Linke turbidity factor for an air mass of 2 (r.sun's default 3.0)
    double albedo = 0.2;           // ground reflectance for the reflected part
    double solarConstant = 1367.0; // W/m^2 at one astronomical unit
};

// The extraterrestrial irradiance normal to the beam on day `dayOfYear` (1 = January 1): the solar constant
// corrected for the Earth's distance from the sun, 1 + 0.03344 cos(2 pi day / 365.25 - 0.048869).
double extraterrestrialIrradiance(double dayOfYear, double solarConstant);

// The relative optical air mass towards a sun at geometric elevation `elevationRad` from a point `heightM` above
// sea level: Kasten and Young (1989) with the refraction correction of the ESRA model and the pressure ratio
// exp(-z / 8434.5).
double relativeAirMass(double elevationRad, double heightM);

// The Rayleigh optical thickness at air mass m (Kasten 1996, as revised for the ESRA model).
double rayleighOpticalThickness(double airMass);

// Where a surface point stands relative to the sun.
struct SunOnSurface {
    double elevationRad = 0.0;     // the sun's geometric elevation above the horizontal
    double azimuthRad = 0.0;       // the sun's azimuth, clockwise from north (in the same frame as aspectRad)
    double cosIncidence = 0.0;     // cosine of the angle between the surface normal and the sun (may be negative)
    double slopeRad = 0.0;         // the surface's inclination from the horizontal
    double aspectRad = 0.0;        // the azimuth the surface faces (downhill), clockwise from north
    double heightM = 0.0;          // above sea level
    bool shadowed = false;         // the terrain blocks the sun
};

struct Irradiance {
    double beam = 0.0;       // direct, on the surface
    double diffuse = 0.0;    // from the sky, on the surface
    double reflected = 0.0;  // from the ground around it
    double global() const { return beam + diffuse + reflected; }
};

// What the model needs of one sun position, the same for every surface point: computed once per time step.
struct ClearSkySun {
    double g0 = 0.0;                 // extraterrestrial irradiance, W/m^2
    double elevationRad = 0.0;       // geometric
    double azimuthRad = 0.0;
    double sinElevation = 0.0;
    double seaLevelAirMass = 0.0;    // relativeAirMass(elevation, 0)
    double diffuseHorizontal = 0.0;  // the sky's diffuse light on the horizontal
};
ClearSkySun clearSkySun(const ClearSky& sky, double g0, double elevationRad, double azimuthRad);

// What the model needs of one surface point, the same for every sun position.
struct ClearSkySurface {
    double slopeRad = 0.0;
    double aspectRad = 0.0;
    double pressureRatio = 1.0;      // exp(-height / 8434.5)
    double sinSlope = 0.0;
    double skyView = 1.0;            // (1 + cos slope) / 2, the slope's isotropic view of the sky
    double groundView = 0.0;         // (1 - cos slope) / 2, its view of the ground in front
    double fg = 0.0;                 // Muneer's horizon-brightening term of the slope
};
ClearSkySurface clearSkySurface(double slopeRad, double aspectRad, double heightM);

// The irradiance for a precomputed sun and surface (the same as below, without recomputing either).
Irradiance clearSkyIrradiance(const ClearSky& sky, const ClearSkySun& sun, const ClearSkySurface& surface,
                              double cosIncidence, bool shadowed);

// Clear-sky irradiance on a surface for the extraterrestrial irradiance `g0` (extraterrestrialIrradiance). Zero
// with the sun at or below the horizontal. The beam is zero where the surface faces away from the sun or the
// terrain shadows it; the sky's diffuse light then follows Muneer's model for shaded surfaces, and the ground
// around reflects no beam either (it is taken to be lit as the point is, as r.sun takes it).
Irradiance clearSkyIrradiance(const ClearSky& sky, double g0, const SunOnSurface& at);

}  // namespace terracast
