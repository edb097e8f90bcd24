#include "tracer/sky/clear_sky.h"

#include "tracer/core/angles.h"

#include <algorithm>
#include <cmath>

namespace terracast {

double extraterrestrialIrradiance(double dayOfYear, double solarConstant) {
    // Perihelion near January 3: the phase 0.048869 rad is 2.84 days of the 365.25-day year; the amplitude is
    // twice the orbit's eccentricity (Suri and Hofierka 2004, eq. 2).
    return solarConstant * (1.0 + 0.03344 * std::cos(2.0 * kPi * dayOfYear / 365.25 - 0.048869));
}

double relativeAirMass(double elevationRad, double heightM) {
    const double h = elevationRad;
    // Refraction raises the sun near the horizon (ESRA's correction, radians), then Kasten and Young's (1989)
    // air mass, whose second term takes the elevation in degrees; thinner air with height by the pressure ratio.
    const double refraction = 0.061359 * (0.1594 + h * (1.123 + 0.065656 * h)) / (1.0 + h * (28.9344 + 277.3971 * h));
    const double apparent = h + refraction;
    const double pressureRatio = std::exp(-heightM / 8434.5);
    return pressureRatio / (std::sin(apparent) + 0.50572 * std::pow(degrees(apparent) + 6.07995, -1.6364));
}

double rayleighOpticalThickness(double m) {
    if (m <= 20.0) return 1.0 / (6.6296 + m * (1.7513 + m * (-0.1202 + m * (0.0065 - m * 0.00013))));
    return 1.0 / (10.4 + 0.718 * m);
}

ClearSkySun clearSkySun(const ClearSky& sky, double g0, double elevationRad, double azimuthRad) {
    ClearSkySun sun;
    sun.g0 = g0;
    sun.elevationRad = elevationRad;
    sun.azimuthRad = azimuthRad;
    if (!(elevationRad > 0.0)) return sun;
    sun.sinElevation = std::sin(elevationRad);
    sun.seaLevelAirMass = relativeAirMass(elevationRad, 0.0);
    // Diffuse on the horizontal: the transmission at zenith Tn times the sun-elevation function Fd, whose
    // coefficients are quadratics in the Linke factor (Rigollier et al. 2000, eqs. 23-27).
    const double tl = sky.linkeTurbidity, sinH = sun.sinElevation;
    const double tn = -0.015843 + tl * (0.030543 + 0.0003797 * tl);
    const double a1Raw = 0.26463 + tl * (-0.061581 + 0.0031408 * tl);
    const double a1 = a1Raw * tn < 0.0022 ? 0.0022 / tn : a1Raw;
    const double a2 = 2.04020 + tl * (0.018945 - 0.011161 * tl);
    const double a3 = -1.3025 + tl * (0.039231 + 0.0085079 * tl);
    sun.diffuseHorizontal = g0 * tn * (a1 + sinH * (a2 + a3 * sinH));
    return sun;
}

ClearSkySurface clearSkySurface(double slopeRad, double aspectRad, double heightM) {
    ClearSkySurface s;
    s.slopeRad = slopeRad;
    s.aspectRad = aspectRad;
    s.pressureRatio = std::exp(-heightM / 8434.5);
    s.sinSlope = std::sin(slopeRad);
    const double cosSlope = std::cos(slopeRad);
    s.skyView = 0.5 * (1.0 + cosSlope);
    s.groundView = 0.5 * (1.0 - cosSlope);
    const double halfSin = std::sin(0.5 * slopeRad);
    s.fg = s.sinSlope - slopeRad * cosSlope - kPi * halfSin * halfSin;
    return s;
}

Irradiance clearSkyIrradiance(const ClearSky& sky, const ClearSkySun& sun, const ClearSkySurface& surface,
                              double cosIncidence, bool shadowed) {
    Irradiance out;
    if (!(sun.elevationRad > 0.0)) return out;
    // Beam: the normal irradiance through the air mass (thinner with height by the pressure ratio), then on the
    // horizontal and on the surface.
    const double m = sun.seaLevelAirMass * surface.pressureRatio;
    const double beamNormal = sun.g0 * std::exp(-0.8662 * sky.linkeTurbidity * m * rayleighOpticalThickness(m));
    const double beamHorizontal = beamNormal * sun.sinElevation;
    const bool sunOnFace = !shadowed && cosIncidence > 0.0;
    if (sunOnFace) out.beam = beamNormal * cosIncidence;
    const double diffuseHorizontal = sun.diffuseHorizontal;
    if (!(surface.slopeRad > 0.0)) {
        out.diffuse = diffuseHorizontal;
        return out;
    }
    // Muneer's sloped sky: an isotropic part seen through the slope's view of the sky, a circumsolar part in the
    // sun's direction weighted by the beam's share Kb, and a horizon-brightening term through Fg.
    const double kb = beamNormal / sun.g0;  // the horizontal beam over the horizontal extraterrestrial light
    double fx = 0.0;
    if (!sunOnFace) {
        fx = surface.skyView + 0.252271 * surface.fg;
    } else {
        const double n = 0.00263 - kb * (0.712 + 0.6883 * kb);
        const double isotropic = (surface.skyView + n * surface.fg) * (1.0 - kb);
        if (sun.elevationRad >= 0.1) {
            fx = isotropic + kb * cosIncidence / sun.sinElevation;
        } else {
            // A low sun: the circumsolar term from the slope's facing, without dividing by a vanishing sin h.
            const double azimuthGap = std::remainder(sun.azimuthRad - surface.aspectRad, 2.0 * kPi);
            fx = isotropic + kb * surface.sinSlope * std::cos(azimuthGap) / (0.1 - 0.008 * sun.elevationRad);
        }
    }
    out.diffuse = diffuseHorizontal * fx;
    // The ground in front of a slope reflects the global horizontal light through the slope's view of the ground;
    // that ground is taken to be lit as the point itself is (r.sun's convention), so no beam when it is not.
    const double groundLight = (sunOnFace ? beamHorizontal : 0.0) + diffuseHorizontal;
    out.reflected = sky.albedo * groundLight * surface.groundView;
    return out;
}

Irradiance clearSkyIrradiance(const ClearSky& sky, double g0, const SunOnSurface& at) {
    return clearSkyIrradiance(sky, clearSkySun(sky, g0, at.elevationRad, at.azimuthRad),
                              clearSkySurface(at.slopeRad, at.aspectRad, at.heightM), at.cosIncidence, at.shadowed);
}

}  // namespace terracast
