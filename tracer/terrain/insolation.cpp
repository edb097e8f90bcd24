#include "tracer/terrain/insolation.h"

#include "heightfield/traversal.h"
#include "tracer/core/angles.h"
#include "tracer/terrain/vertex_loop.h"

#include <algorithm>
#include <cmath>

namespace terracast {

using namespace vertex_maps;

MapRaster insolationMap(const HeightGrid& grid, const InsolationSettings& s) {
    if (s.method == CellMethod::Nearest)
        throw GridError("insolation needs a surface through the vertices (bilinear or triangles), not nearest");
    // Only the steps with the sun up matter; their directions and model inputs are the same for every vertex.
    struct Step {
        ClearSkySun model;  // the clear-sky model's share of the step, computed once
        double hours;
        glm::dvec3 toSun;   // unit, apparent
        double tangent;     // the apparent elevation's slope, for the shadow walk
    };
    std::vector<Step> steps;
    for (const SunStep& sun : s.steps) {
        if (!(sun.elevationRad > 0.0) || !(sun.hours > 0.0)) continue;
        steps.push_back({clearSkySun(s.sky, sun.extraterrestrial, sun.elevationRad, sun.azimuthRad), sun.hours,
                         directionFromRadians(sun.azimuthRad, sun.apparentElevationRad),
                         std::tan(sun.apparentElevationRad)});
    }
    const int64_t walksPerVertex = int64_t(steps.size());
    return perVertexBands(grid, kInsolationBands, s.threads, s.progress, walksPerVertex,
                          [&](int64_t i, int64_t j, float* out) {
        if (!vertexOnSurface(grid, i, j)) return;
        const glm::dvec3 n = vertexNormal(grid, i, j);
        // The way the surface faces (downhill), clockwise from north.
        const ClearSkySurface surface =
            clearSkySurface(std::acos(std::clamp(n.z, -1.0, 1.0)), std::atan2(n.x, n.y), grid.at(i, j));
        double beam = 0.0, diffuse = 0.0, reflected = 0.0, sunshine = 0.0;
        for (const Step& step : steps) {
            const double cosIncidence = glm::dot(n, step.toSun);
            // The walk only where the surface faces the sun: facing away, the beam is lost anyway and the model
            // treats the two alike.
            const bool shadowed =
                cosIncidence > 0.0 && horizonAbove(grid, i, j, step.toSun.x, step.toSun.y, step.tangent, s.method, s.search);
            const Irradiance e = clearSkyIrradiance(s.sky, step.model, surface, cosIncidence, shadowed);
            beam += e.beam * step.hours;
            diffuse += e.diffuse * step.hours;
            reflected += e.reflected * step.hours;
            if (e.beam > 0.0) sunshine += step.hours;
        }
        out[kBeamBand] = float(beam);
        out[kDiffuseBand] = float(diffuse);
        out[kReflectedBand] = float(reflected);
        out[kGlobalBand] = float(beam + diffuse + reflected);
        out[kSunshineBand] = float(sunshine);
    });
}

}  // namespace terracast
