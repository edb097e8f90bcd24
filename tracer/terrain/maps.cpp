#include "tracer/terrain/maps.h"

#include "tracer/core/angles.h"

#include "tracer/core/parallel.h"

#include <cmath>
#include <limits>
#include <random>

namespace terracast {

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Calls f(i, j) for every vertex of the grid, in parallel tiles.
template <class F>
MapRaster perVertex(const HeightGrid& grid, int threads, F&& f) {
    MapRaster r;
    r.width = grid.width();
    r.height = grid.height();
    r.values.assign(size_t(r.width * r.height), kNaN);
    parallelForTiles(int(r.width), int(r.height), 64, threads, [&](int x0, int y0, int x1, int y1) {
        for (int j = y0; j < y1; ++j)
            for (int i = x0; i < x1; ++i) r.values[size_t(int64_t(j) * r.width + i)] = f(int64_t(i), int64_t(j));
    });
    return r;
}

// The surface point at vertex (i, j), or none for a vertex that belongs to no valid cell.
std::optional<HeightFieldHit> vertexPoint(const HeightGrid& g, int64_t i, int64_t j, CellMethod method) {
    if (!g.vertexValid(i, j)) return std::nullopt;
    return surfacePointAt(g, double(i) * g.cellSizeXM(), double(j) * g.cellSizeYM(), method);
}
}  // namespace

std::optional<HeightFieldHit> surfacePointAt(const HeightGrid& grid, double xM, double yM, CellMethod method) {
    const double top = double(grid.maxHeightM()) + 1.0 + 1e-3 * std::abs(double(grid.maxHeightM()));
    return intersect(grid, Ray{{xM, yM, top}, {0.0, 0.0, -1.0}}, {0.0, kInfinity}, method);
}


bool blockedFrom(const HeightGrid& grid, const HeightFieldHit& at, const glm::dvec3& dir, CellMethod method) {
    // A direction at or below the local tangent plane is blocked by the surface itself.
    if (glm::dot(at.normal, dir) <= 0.0) return true;
    return occluded(grid, Ray{spawnOrigin(at, dir), dir}, {0.0, kInfinity}, method);
}

double horizonAngleRad(const HeightGrid& grid, const HeightFieldHit& at, double azimuthRad, CellMethod method,
                       double toleranceRad) {
    double lo = -0.5 * kPi, hi = 0.5 * kPi;
    if (!blockedFrom(grid, at, directionFromRadians(azimuthRad, lo + 1e-9), method)) return lo;
    while (hi - lo > toleranceRad) {
        const double mid = 0.5 * (lo + hi);
        if (blockedFrom(grid, at, directionFromRadians(azimuthRad, mid), method)) lo = mid;
        else hi = mid;
    }
    return hi;
}

MapRaster shadowMask(const HeightGrid& grid, double azimuthRad, double elevationRad, CellMethod method,
                     double sunRadiusRad, int samples, int threads) {
    const glm::dvec3 centre = directionFromRadians(azimuthRad, elevationRad);
    std::vector<glm::dvec3> dirs{centre};
    if (sunRadiusRad > 0.0) {
        // Stratified directions over the sun's disc: n x n strata in (radius^2, angle).
        const int n = std::max(1, int(std::lround(std::sqrt(double(std::max(samples, 1))))));
        const glm::dvec3 a = std::abs(centre.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
        const glm::dvec3 e1 = glm::normalize(glm::cross(centre, a)), e2 = glm::cross(centre, e1);
        dirs.clear();
        for (int p = 0; p < n; ++p)
            for (int q = 0; q < n; ++q) {
                const double r = std::tan(sunRadiusRad) * std::sqrt((p + 0.5) / n), phi = 2.0 * kPi * (q + 0.5) / n;
                dirs.push_back(glm::normalize(centre + r * (std::cos(phi) * e1 + std::sin(phi) * e2)));
            }
    }
    return perVertex(grid, threads, [&](int64_t i, int64_t j) {
        const auto at = vertexPoint(grid, i, j, method);
        if (!at) return kNaN;
        int blocked = 0;
        for (const auto& d : dirs) blocked += blockedFrom(grid, *at, d, method);
        return float(double(blocked) / double(dirs.size()));
    });
}

MapRaster horizonMap(const HeightGrid& grid, double azimuthRad, CellMethod method, int threads) {
    return perVertex(grid, threads, [&](int64_t i, int64_t j) {
        const auto at = vertexPoint(grid, i, j, method);
        if (!at) return kNaN;
        return float(degrees(horizonAngleRad(grid, *at, azimuthRad, method)));
    });
}

MapRaster viewshed(const HeightGrid& grid, const ViewshedSettings& s) {
    // Earth curvature (less refraction) lowers everything by coeff * d^2 / (2 R) with distance d from the
    // observer: trace in a copy of the grid with that drop applied.
    const HeightGrid* g = &grid;
    std::optional<HeightGrid> curved;
    if (s.curvatureCoeff != 0.0) {
        std::vector<float> z = grid.copyHeights();
        std::vector<uint8_t> valid;
        if (grid.hasNodata()) {
            valid.resize(z.size());
            for (int64_t j = 0; j < grid.height(); ++j)
                for (int64_t i = 0; i < grid.width(); ++i) valid[size_t(j * grid.width() + i)] = grid.vertexValid(i, j);
        }
        for (int64_t j = 0; j < grid.height(); ++j)
            for (int64_t i = 0; i < grid.width(); ++i) {
                const double dx = double(i) * grid.cellSizeXM() - s.observerXM, dy = double(j) * grid.cellSizeYM() - s.observerYM;
                z[size_t(j * grid.width() + i)] -= float(s.curvatureCoeff * (dx * dx + dy * dy) / (2.0 * s.earthRadiusM));
            }
        curved.emplace(grid.width(), grid.height(), grid.cellSizeXM(), grid.cellSizeYM(), std::move(z), std::move(valid));
        g = &*curved;
    }
    const auto ground = surfacePointAt(*g, s.observerXM, s.observerYM, s.method);
    if (!ground)
        throw GridError("the observer at local (" + std::to_string(s.observerXM) + ", " + std::to_string(s.observerYM) +
                        ") m is not over the DEM's surface");
    const glm::dvec3 eye = ground->pointM + glm::dvec3(0.0, 0.0, s.observerHeightM);
    const double endGap = 0.01 * std::min(g->cellSizeXM(), g->cellSizeYM());
    return perVertex(*g, s.threads, [&](int64_t i, int64_t j) {
        if (!g->vertexValid(i, j)) return kNaN;
        const glm::dvec3 target{double(i) * g->cellSizeXM(), double(j) * g->cellSizeYM(),
                                double(g->at(i, j)) + s.targetHeightM};
        const glm::dvec3 d = target - eye;
        const double len = glm::length(d);
        if (len <= endGap) return 1.0f;
        // The sight line stops just short of the target, so a target on the surface does not hide itself.
        return occluded(*g, Ray{eye, d}, {0.0, 1.0 - endGap / len}, s.method) ? 0.0f : 1.0f;
    });
}

Film renderMapView(const HeightGrid& grid, const MapViewSettings& s) {
    const int w = std::max(1, int(std::lround(double(grid.cellsX()) * s.scale)));
    const int h = std::max(1, int(std::lround(double(grid.cellsY()) * s.scale)));
    Film film(w, h);
    const glm::dvec3 toSun = s.sun.direction();
    const double stepX = grid.extentXM() / w, stepY = grid.extentYM() / h;
    parallelForTiles(w, h, 32, s.threads, [&](int x0, int y0, int x1, int y1) {
        for (int py = y0; py < y1; ++py)
            for (int px = x0; px < x1; ++px) {
                const double x = (px + 0.5) * stepX, y = grid.extentYM() - (py + 0.5) * stepY;
                const auto hit = surfacePointAt(grid, x, y, s.method);
                if (!hit) {
                    film.set(px, py, glm::vec3(0.0f));
                    continue;
                }
                const double lambert = std::max(0.0, glm::dot(hit->normal, toSun));
                double lit = toSun.z > 0.0 ? 1.0 : 0.0;
                if (s.castShadows && lambert > 0.0 && blockedFrom(grid, *hit, toSun, s.method)) lit = 0.0;
                double sky = 1.0;
                if (s.skySamples > 0) {
                    // Cosine-weighted directions about the normal, seeded by pixel: the same picture for any
                    // thread count.
                    std::mt19937_64 rng(s.seed * 0x9E3779B97F4A7C15ull + uint64_t(py) * uint64_t(w) + uint64_t(px));
                    std::uniform_real_distribution<double> U(0.0, 1.0);
                    const glm::dvec3 n = hit->normal;
                    const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
                    const glm::dvec3 e1 = glm::normalize(glm::cross(n, a)), e2 = glm::cross(n, e1);
                    int open = 0;
                    for (int k = 0; k < s.skySamples; ++k) {
                        const double r = std::sqrt(U(rng)), phi = 2.0 * kPi * U(rng);
                        const glm::dvec3 d = r * std::cos(phi) * e1 + r * std::sin(phi) * e2 + std::sqrt(1.0 - r * r) * n;
                        open += !blockedFrom(grid, *hit, d, s.method);
                    }
                    sky = double(open) / double(s.skySamples);
                }
                const glm::vec3 albedo = s.colourRamp ? elevationAlbedo(hit->pointM.z, grid.minHeightM(), grid.maxHeightM())
                                                      : glm::vec3(0.8f);
                const double shade = double(s.sun.intensity) * lambert * lit + double(s.ambient) * sky;
                const double plain = double(s.sun.intensity) * lambert + double(s.ambient);
                const double value = (1.0 - s.hillshadeBlend) * shade + s.hillshadeBlend * plain;
                film.set(px, py, albedo * float(value));
            }
    });
    return film;
}

}  // namespace terracast
