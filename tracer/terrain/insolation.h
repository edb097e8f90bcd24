// Clear-sky insolation per vertex: the sun's beam, the sky's diffuse light and the light reflected by the ground,
// summed over a series of sun positions (a day or many), with the terrain's cast shadows from exact horizon walks
// and the ESRA clear-sky model of GRASS r.sun (tracer/sky/clear_sky.h).
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/horizon.h"
#include "tracer/sky/clear_sky.h"
#include "tracer/terrain/maps.h"

#include <glm/glm.hpp>

#include <functional>
#include <vector>

namespace terracast {

// One sun position of the series and the time it stands for.
struct SunStep {
    double azimuthRad = 0.0;            // clockwise from the grid's north
    double elevationRad = 0.0;          // geometric: the clear-sky model adds its own refraction
    double apparentElevationRad = 0.0;  // with refraction: where the light comes from (shadows, incidence)
    double extraterrestrial = 0.0;      // W/m^2 normal to the beam that day (extraterrestrialIrradiance)
    double hours = 0.0;                 // the time this position stands for
};

struct InsolationSettings {
    std::vector<SunStep> steps;         // the sun's positions for every vertex, unless stepsAt is set
    // When set: the sun's positions for each block of kSunBlock x kSunBlock vertices, as seen from the block's
    // centre (a vertex position, row 0 at the south), so that a large DEM's vertices see the sun where it stands
    // over their part of the Earth.
    std::function<std::vector<SunStep>(double col, double row)> stepsAt;
    static constexpr int64_t kSunBlock = 64;
    ClearSky sky;
    HorizonSearch search;               // radius and curvature of the shadow walks
    CellMethod method = CellMethod::Bilinear;
    int threads = 0;
    MapProgress progress;
    VertexWindow window;               // the vertices computed
};

// Band indices of insolationMap's raster.
enum InsolationBand { kBeamBand = 0, kDiffuseBand, kReflectedBand, kGlobalBand, kSunshineBand, kInsolationBands };

// Per vertex, summed over the steps: beam, diffuse, reflected and global irradiation in Wh/m^2 on the surface
// (tilted by the vertex normal, as the map view's), and the hours of direct sun (the sun above the horizontal,
// in front of the surface and not shadowed by the terrain, decided as `shadow` decides). Heights are taken as
// metres above sea level for the air mass. NaN where the vertex lies on no valid cell. For the methods through
// the vertices (throws GridError for nearest).
MapRaster insolationMap(const HeightGrid& grid, const InsolationSettings& settings);

}  // namespace terracast
