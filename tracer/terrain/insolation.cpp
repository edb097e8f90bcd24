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
    const auto prepare = [&](const std::vector<SunStep>& suns) {
        std::vector<Step> steps;
        for (const SunStep& sun : suns) {
            if (!(sun.elevationRad > 0.0) || !(sun.hours > 0.0)) continue;
            steps.push_back({clearSkySun(s.sky, sun.extraterrestrial, sun.elevationRad, sun.azimuthRad), sun.hours,
                             directionFromRadians(sun.azimuthRad, sun.apparentElevationRad),
                             std::tan(sun.apparentElevationRad)});
        }
        return steps;
    };
    // One list of steps for all vertices, or one per block of the window's vertices (made here, before the
    // parallel loop); blocks count from the grid's corner, whatever the window.
    constexpr int64_t B = InsolationSettings::kSunBlock;
    const VertexWindow w = s.window.within(grid);
    const int64_t firstX = w.i0 / B, firstY = w.j0 / B;
    const int64_t blocksX = s.stepsAt ? (w.i1 - 1) / B - firstX + 1 : 1, blocksY = s.stepsAt ? (w.j1 - 1) / B - firstY + 1 : 1;
    std::vector<std::vector<Step>> blocks;
    size_t mostSteps = 0;
    for (int64_t bj = firstY; bj < firstY + blocksY; ++bj)
        for (int64_t bi = firstX; bi < firstX + blocksX; ++bi) {
            if (!s.stepsAt) {
                blocks.push_back(prepare(s.steps));
            } else {
                const double col = 0.5 * double(bi * B + std::min(grid.width(), (bi + 1) * B) - 1);
                const double row = 0.5 * double(bj * B + std::min(grid.height(), (bj + 1) * B) - 1);
                blocks.push_back(prepare(s.stepsAt(col, row)));
            }
            mostSteps = std::max(mostSteps, blocks.back().size());
        }
    const int64_t walksPerVertex = int64_t(mostSteps);
    return perVertexBands(grid, w, kInsolationBands, s.threads, s.progress, walksPerVertex,
                          [&](int64_t i, int64_t j, float* out) {
        if (!vertexOnSurface(grid, i, j)) return;
        const std::vector<Step>& steps = s.stepsAt ? blocks[size_t((j / B - firstY) * blocksX + i / B - firstX)] : blocks.front();
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
