// Deterministic synthetic terrain for benchmarks and tests: a fractal height field made by midpoint
// displacement (the diamond-square algorithm of Fournier, Fussell, Carpenter 1982, "Computer rendering of
// stochastic models"), with every random offset drawn from a hash of the vertex and the seed, so the same
// options give the same heights on any machine and in any evaluation order.
#pragma once

#include "heightfield/height_grid.h"

#include <cstdint>

namespace terracast {

struct FractalTerrainOptions {
    int64_t size = 513;           // vertices per side; must be 2^n + 1 with n >= 1
    uint64_t seed = 1;            // random seed
    double cellSizeM = 30.0;      // metres between samples, along x and y
    double roughness = 0.85;      // Hurst exponent: offsets shrink by 2^-roughness per halving of the step
    double offsetAt1KmM = 150.0;  // standard offset at a step of 1 km; sets the steepness of small features
    double maxOffsetM = 500.0;    // cap on the offset of long steps, so relief stays mountain-sized on big grids
    bool integerHeights = false;  // round heights to whole metres, so the grid stores them as int16 codes
};

// True when `size` is 2^n + 1 for some n >= 1 (3, 5, 9, ..., 513, 2049, ...).
bool isFractalTerrainSize(int64_t size);

// A size x size grid of fractal terrain with cell size `options.cellSizeM`. Heights are shifted so the lowest
// vertex sits at 0 m. Throws GridError when the size is not 2^n + 1 or the options are not positive and finite.
HeightGrid fractalTerrain(const FractalTerrainOptions& options);

// The bytes fractalTerrain's grid of this size holds (heights and pyramids), computed without building it.
// With integer heights the grid holds int16 codes (2 bytes per vertex) as long as its relief stays within
// 65535 m (it does with the default offsets, by a wide margin); otherwise float32 (4 bytes per vertex).
int64_t fractalTerrainBytes(int64_t size, bool integerHeights = false);

}  // namespace terracast
