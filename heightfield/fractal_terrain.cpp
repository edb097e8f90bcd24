#include "heightfield/fractal_terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace terracast {

namespace {

// SplitMix64's finaliser (Steele, Lea, Flood 2014): a well-mixed 64-bit hash of one word.
uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

// A zero-mean offset of unit standard deviation for vertex (i, j): the sum of two uniforms (a triangular
// distribution on [-sqrt 6, sqrt 6]), from a hash of the vertex and the seed.
double vertexNoise(int64_t i, int64_t j, uint64_t seed) {
    const uint64_t h = mix(mix(seed ^ 0x9e3779b97f4a7c15ULL) ^ (uint64_t(i) * 0xd6e8feb86659fd93ULL) ^
                           (uint64_t(j) * 0xa0761d6478bd642fULL + 0xe7037ed1a0b428dbULL));
    const double u1 = double(h >> 40) * 0x1p-24;               // top 24 bits
    const double u2 = double((h >> 8) & 0xffffffULL) * 0x1p-24;  // next 24 bits
    return std::sqrt(6.0) * (u1 + u2 - 1.0);
}

}  // namespace

bool isFractalTerrainSize(int64_t size) {
    if (size < 3) return false;
    const uint64_t n = uint64_t(size - 1);
    return (n & (n - 1)) == 0;
}

HeightGrid fractalTerrain(const FractalTerrainOptions& o) {
    if (!isFractalTerrainSize(o.size))
        throw GridError("fractal terrain: size must be 2^n + 1 vertices (3, 5, 9, ..., 513, 2049), found " +
                        std::to_string(o.size));
    for (double v : {o.cellSizeM, o.roughness, o.offsetAt1KmM, o.maxOffsetM})
        if (!(v > 0.0) || !std::isfinite(v))
            throw GridError("fractal terrain: cell size, roughness and offsets must be positive and finite");
    const int64_t n = o.size - 1;  // cells per side, a power of two
    const int64_t w = o.size;
    std::vector<float> h(size_t(w) * size_t(w), 0.0f);
    auto at = [&](int64_t i, int64_t j) -> float& { return h[size_t(j) * size_t(w) + size_t(i)]; };
    // The standard offset for points placed at `spanCells` from the vertices they are averaged from.
    auto offset = [&](int64_t spanCells) {
        const double km = double(spanCells) * o.cellSizeM * 1e-3;
        return std::min(o.maxOffsetM, o.offsetAt1KmM * std::pow(km, o.roughness));
    };

    const double corner = offset(n);
    for (int64_t j : {int64_t(0), n})
        for (int64_t i : {int64_t(0), n}) at(i, j) = float(corner * vertexNoise(i, j, o.seed));

    for (int64_t step = n; step > 1; step /= 2) {
        const int64_t half = step / 2;
        // Diamond step: the centre of each square from its four corners.
        const double centreOffset = offset(half);
        for (int64_t j = half; j < n; j += step)
            for (int64_t i = half; i < n; i += step) {
                const double mean = 0.25 * (double(at(i - half, j - half)) + at(i + half, j - half) +
                                            at(i - half, j + half) + at(i + half, j + half));
                at(i, j) = float(mean + centreOffset * vertexNoise(i, j, o.seed));
            }
        // Square step: the midpoint of each edge from its (up to four) neighbours at distance `half`.
        const double edgeOffset = offset(half);
        for (int64_t j = 0; j <= n; j += half)
            for (int64_t i = (j / half) % 2 == 0 ? half : 0; i <= n; i += step) {
                double sum = 0.0;
                int count = 0;
                if (i >= half) sum += at(i - half, j), ++count;
                if (i + half <= n) sum += at(i + half, j), ++count;
                if (j >= half) sum += at(i, j - half), ++count;
                if (j + half <= n) sum += at(i, j + half), ++count;
                at(i, j) = float(sum / count + edgeOffset * vertexNoise(i, j, o.seed));
            }
    }

    const float lowest = *std::min_element(h.begin(), h.end());
    for (float& v : h) v -= lowest;
    // Whole metres (all heights are >= 0 here, so no -0 appears): the grid then encodes them as int16 and
    // releases this float array, leaving 2 bytes per vertex.
    if (o.integerHeights)
        for (float& v : h) v = std::round(v);
    return HeightGrid(w, w, o.cellSizeM, o.cellSizeM, std::move(h));
}

int64_t fractalTerrainBytes(int64_t size, bool integerHeights) {
    // Heights, then the maximum pyramid's int16 levels exactly as HeightGrid builds them, with two 8-byte
    // table entries per level, and the minimum pyramid's levels 2 up (no masks: no nodata).
    const int64_t cells = size - 1;
    int64_t bytes = size * size * int64_t(integerHeights ? sizeof(int16_t) : sizeof(float));
    int64_t bx = (cells + 1) / 2, by = bx;
    bytes += bx * by * int64_t(sizeof(int16_t)) + 2 * int64_t(sizeof(int64_t));
    while (bx > 1 || by > 1) {
        bx = (bx + 1) / 2;
        by = (by + 1) / 2;
        bytes += 2 * bx * by * int64_t(sizeof(int16_t)) + 2 * int64_t(sizeof(int64_t));
    }
    return bytes;
}

}  // namespace terracast
