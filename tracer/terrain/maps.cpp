#include "tracer/terrain/maps.h"
#include "tracer/terrain/vertex_loop.h"

#include "heightfield/horizon.h"
#include "tracer/core/angles.h"

#include "tracer/sampling/rng.h"
#include "tracer/sampling/warps.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terracast {

namespace vertex_maps {

bool vertexOnSurface(const HeightGrid& g, int64_t i, int64_t j) {
    if (!g.vertexValid(i, j)) return false;
    for (int64_t cj = j - 1; cj <= j; ++cj)
        for (int64_t ci = i - 1; ci <= i; ++ci)
            if (ci >= 0 && cj >= 0 && ci < g.cellsX() && cj < g.cellsY() && g.cellValid(ci, cj)) return true;
    return false;
}

glm::dvec3 vertexNormal(const HeightGrid& g, int64_t i, int64_t j) {
    glm::dvec3 sum(0.0);
    for (int64_t cj = j - 1; cj <= j; ++cj)
        for (int64_t ci = i - 1; ci <= i; ++ci) {
            if (ci < 0 || cj < 0 || ci >= g.cellsX() || cj >= g.cellsY() || !g.cellValid(ci, cj)) continue;
            const double h00 = g.at(ci, cj), h10 = g.at(ci + 1, cj), h01 = g.at(ci, cj + 1), h11 = g.at(ci + 1, cj + 1);
            const double u = double(i - ci), v = double(j - cj), d = h00 - h10 - h01 + h11;
            const double dhdu = h10 - h00 + d * v, dhdv = h01 - h00 + d * u;
            sum += glm::normalize(glm::dvec3(-dhdu / g.cellSizeXM(), -dhdv / g.cellSizeYM(), 1.0));
        }
    return glm::normalize(sum);
}

}  // namespace vertex_maps

using namespace vertex_maps;

namespace {

// Horizons along one azimuth for the vertices of a row, west to east: each walk starts from the surface where the
// vertex to its west found its horizon (horizonPoint's hint), which lets it skip more; same answers.
class HorizonChain {
public:
    HorizonChain(const HeightGrid& g, double azimuthRad, CellMethod method, const HorizonSearch& search)
        : g_(g), dirX_(std::sin(azimuthRad)), dirY_(std::cos(azimuthRad)), method_(method), search_(search) {}
    // The tangent at vertex (i, j); `restart` forgets the last vertex.
    double tangent(int64_t i, int64_t j, bool restart) {
        // The west neighbour's horizon point, seen along this vertex's line: one cell further east.
        const double hint = restart || !(lastDistanceM_ > 0.0) ? 0.0 : lastDistanceM_ - g_.cellSizeXM() * dirX_;
        const HorizonPoint p = horizonPoint(g_, i, j, dirX_, dirY_, method_, search_, hint);
        lastDistanceM_ = p.distanceM;
        return p.tangent;
    }
    void skip() { lastDistanceM_ = 0.0; }

private:
    const HeightGrid& g_;
    double dirX_, dirY_;
    CellMethod method_;
    HorizonSearch search_;
    double lastDistanceM_ = 0.0;
};

// The surface point at vertex (i, j), or none for a vertex that belongs to no valid cell.
std::optional<HeightFieldHit> vertexPoint(const HeightGrid& g, int64_t i, int64_t j, CellMethod method) {
    if (!g.vertexValid(i, j)) return std::nullopt;
    return surfacePointAt(g, double(i) * g.cellSizeXM(), double(j) * g.cellSizeYM(), method);
}

// The flat squares of `nearest` put no surface at a vertex; the other methods pass through every vertex.
bool exactAtVertices(CellMethod method) { return method != CellMethod::Nearest; }

// The horizon elevation angle (radians) towards an azimuth from a point whose blocked directions form one
// interval from -90 degrees up (a height field has no overhangs): bisection on `blocked(direction)` to
// `toleranceRad`; -pi/2 when nothing blocks even the lowest direction tested.
template <class Blocked>
double bisectHorizon(double azimuthRad, double toleranceRad, Blocked&& blocked) {
    double lo = -0.5 * kPi, hi = 0.5 * kPi;
    if (!blocked(directionFromRadians(azimuthRad, lo + 1e-9))) return lo;
    while (hi - lo > toleranceRad) {
        const double mid = 0.5 * (lo + hi);
        if (blocked(directionFromRadians(azimuthRad, mid))) lo = mid;
        else hi = mid;
    }
    return hi;
}

// The ray z(t) = h(vertex) + t dz leaves vertex (i, j) over cell (ci, cj), whose corner it is, with the
// horizontal step (du, dv) in cells per unit of t. With f(t) = z(t) - h(t) the ray's height over the cell's
// surface along the way, f(0) = 0 and:
//  - bilinear patch: f(t) = t s - t^2 q with s = dz - (b + d v0) du - (c + d u0) dv, q = d du dv (the patch
//    h = a + b u + c v + d u v seen from its corner (u0, v0); docs/architecture.md, "Cell intersectors");
//  - two triangles: f is linear in each triangle, s its slope in the triangle the ray starts in.
// The ray is blocked inside the cell when it starts below the surface (s < 0, or s = 0 with q > 0) or when it
// is below it where it leaves the cell, at tExit (f is concave or piecewise linear with one kink, so a dip
// inside the cell shows at its exit).
bool blockedInStartCell(const HeightGrid& g, int64_t i, int64_t j, int64_t ci, int64_t cj, double du, double dv,
                        double dz, double tExit, CellMethod method) {
    const double h00 = g.at(ci, cj), h10 = g.at(ci + 1, cj), h01 = g.at(ci, cj + 1), h11 = g.at(ci + 1, cj + 1);
    const double u0 = double(i - ci), v0 = double(j - cj);
    const double z0 = g.at(i, j);
    const double u1 = u0 + tExit * du, v1 = v0 + tExit * dv;  // where the ray leaves the cell
    double s = 0.0, q = 0.0, hExit = 0.0;
    if (method == CellMethod::Triangles) {
        // The diagonal runs from (1, 0) to (0, 1); below it (u + v < 1) the lower triangle's plane, above it the
        // upper one's. A ray leaving (1, 0) or (0, 1) starts in the triangle its step points into.
        const bool upperStart = u0 + v0 > 1.0 || (u0 + v0 == 1.0 && du + dv > 0.0);
        s = dz - (upperStart ? (h11 - h01) * du + (h11 - h10) * dv : (h10 - h00) * du + (h01 - h00) * dv);
        hExit = u1 + v1 <= 1.0 ? h00 + (h10 - h00) * u1 + (h01 - h00) * v1
                               : h11 + (h11 - h01) * (u1 - 1.0) + (h11 - h10) * (v1 - 1.0);
    } else {
        const double b = h10 - h00, c = h01 - h00, d = h00 - h10 - h01 + h11;
        s = dz - (b + d * v0) * du - (c + d * u0) * dv;
        q = d * du * dv;
        hExit = h00 + b * u1 + c * v1 + d * u1 * v1;
    }
    if (s < 0.0 || (s == 0.0 && q > 0.0)) return true;
    return z0 + tExit * dz < hExit;
}

// True when the horizontal path of `ray` from t = t0 on, to where it leaves the grid's footprint, crosses a valid
// cell (a 2D DDA over the cells, Amanatides and Woo 1987). Below the grid's lowest height, that cell's surface is
// above the ray.
bool crossesValidCell(const HeightGrid& g, const Ray& ray, double t0) {
    const double du = ray.dir.x / g.cellSizeXM(), dv = ray.dir.y / g.cellSizeYM();
    double u = (ray.origin.x + t0 * ray.dir.x) / g.cellSizeXM(), v = (ray.origin.y + t0 * ray.dir.y) / g.cellSizeYM();
    const double nu = double(g.cellsX()), nv = double(g.cellsY());
    if (u < 0.0 || v < 0.0 || u > nu || v > nv) return false;
    // The cell the path enters: on a boundary, the one the direction points into.
    int64_t ci = std::clamp<int64_t>(int64_t(std::floor(u)) - (du < 0.0 && u == std::floor(u) ? 1 : 0), 0, g.cellsX() - 1);
    int64_t cj = std::clamp<int64_t>(int64_t(std::floor(v)) - (dv < 0.0 && v == std::floor(v) ? 1 : 0), 0, g.cellsY() - 1);
    const int64_t stepI = du > 0.0 ? 1 : -1, stepJ = dv > 0.0 ? 1 : -1;
    while (ci >= 0 && cj >= 0 && ci < g.cellsX() && cj < g.cellsY()) {
        if (g.cellValid(ci, cj)) return true;
        // Distance (in t) to the next vertical and horizontal grid line, from the integer cell index.
        const double tu = du != 0.0 ? (double(ci + (du > 0.0 ? 1 : 0)) - u) / du : kInfinity;
        const double tv = dv != 0.0 ? (double(cj + (dv > 0.0 ? 1 : 0)) - v) / dv : kInfinity;
        const double t = std::min(tu, tv);
        if (!(t < kInfinity)) return false;
        u += t * du;
        v += t * dv;
        if (tu <= tv) ci += stepI;
        if (tv <= tu) cj += stepJ;
    }
    return false;
}

}  // namespace

bool blockedFromVertex(const HeightGrid& g, int64_t i, int64_t j, const glm::dvec3& dir, CellMethod method) {
    double du = dir.x / g.cellSizeXM(), dv = dir.y / g.cellSizeYM();
    // A direction within rounding of a grid line (azimuth 90 gives cos(pi / 2), about 6e-17, for y) runs along it.
    if (std::abs(du) < 1e-12 * std::abs(dv)) du = 0.0;
    if (std::abs(dv) < 1e-12 * std::abs(du)) dv = 0.0;
    if (du == 0.0 && dv == 0.0) return dir.z <= 0.0;  // straight up is free; straight down is into the ground
    // The cell the direction leaves the vertex over; along a grid line, the valid ones of the two beside it
    // (the surface along their shared edge is the same line in both).
    const int64_t ciLo = du > 0.0 ? i : i - 1, ciHi = du < 0.0 ? i - 1 : i;
    const int64_t cjLo = dv > 0.0 ? j : j - 1, cjHi = dv < 0.0 ? j - 1 : j;
    const double tExit = std::min(du != 0.0 ? 1.0 / std::abs(du) : kInfinity, dv != 0.0 ? 1.0 / std::abs(dv) : kInfinity);
    bool overSurface = false;
    for (int64_t cj = cjLo; cj <= cjHi && !overSurface; ++cj)
        for (int64_t ci = ciLo; ci <= ciHi && !overSurface; ++ci)
            if (ci >= 0 && cj >= 0 && ci < g.cellsX() && cj < g.cellsY() && g.cellValid(ci, cj)) {
                if (blockedInStartCell(g, i, j, ci, cj, du, dv, dir.z, tExit, method)) return true;
                overSurface = true;  // along an edge, both cells give the same answer
            }
    // Past the starting cell the walk decides, from the vertex itself: no offset skips any terrain. Over a hole
    // (or off the grid) the walk starts a billionth of a cell from the vertex, past the vertex's own point on
    // the cells beside it, so that terrain right beyond the hole is not skipped.
    const glm::dvec3 origin{double(i) * g.cellSizeXM(), double(j) * g.cellSizeYM(), double(g.at(i, j))};
    const Ray ray{origin, glm::normalize(glm::dvec3(du * g.cellSizeXM(), dv * g.cellSizeYM(), dir.z))};
    const double start = overSurface ? tExit : 1e-9 * std::min(g.cellSizeXM(), g.cellSizeYM());
    if (occluded(g, ray, {start, kInfinity}, method)) return true;
    // The walk traces the grid's box of heights. A ray that sinks below the lowest height (through a hole) is
    // under the surface of any valid cell it passes afterwards: blocked, as the horizon's definition wants.
    if (ray.dir.z >= 0.0) return false;
    const double tBottom = std::max(start, (double(g.minHeightM()) - origin.z) / ray.dir.z);
    return crossesValidCell(g, ray, tBottom * (1.0 + 1e-12) + 1e-12);
}

std::optional<HeightFieldHit> surfacePointAt(const HeightGrid& grid, double xM, double yM, CellMethod method) {
    const double top = double(grid.maxHeightM()) + 1.0 + 1e-3 * std::abs(double(grid.maxHeightM()));
    return intersect(grid, Ray{{xM, yM, top}, {0.0, 0.0, -1.0}}, {0.0, kInfinity}, method);
}


bool blockedFrom(const HeightGrid& grid, const HeightFieldHit& at, const glm::dvec3& dir, CellMethod method) {
    // A direction at or below the local tangent plane is blocked by the surface itself.
    if (glm::dot(at.normal, dir) <= 0.0) return true;
    return occluded(grid, Ray{spawnOrigin(at, dir), dir}, {0.0, kInfinity}, method);
}

namespace {

// A map product's question at vertex (i, j): does the terrain block a direction? From the vertex itself for
// the methods whose surface passes through the vertices (a horizon walk that ends at the first point above the
// direction); from the surface point under the vertex for nearest (an occlusion walk).
class VertexView {
public:
    VertexView(const HeightGrid& g, int64_t i, int64_t j, CellMethod method) : g_(g), i_(i), j_(j), method_(method) {
        if (exactAtVertices(method)) {
            onSurface_ = vertexOnSurface(g, i, j);
        } else {
            probe_ = vertexPoint(g, i, j, method);
            onSurface_ = probe_.has_value();
        }
    }
    // False for a vertex that is a corner of no valid cell: the map has no value there.
    bool onSurface() const { return onSurface_; }
    bool blocked(const glm::dvec3& dir, const HorizonSearch& search = {}) const {
        if (probe_) return blockedFrom(g_, *probe_, dir, method_);
        const double across = std::hypot(dir.x, dir.y);
        if (!(across > 0.0)) return dir.z <= 0.0;  // straight up is free; straight down is into the ground
        if (dir.z > 0.0) return horizonAbove(g_, i_, j_, dir.x, dir.y, dir.z / across, method_, search);
        // At or below the horizontal: blocked by the terrain as above, and where no surface lies that way at all
        // (past the DEM's edge) by the unknown ground beyond, taken as a horizon at 0 degrees.
        const double horizon = horizonTangent(g_, i_, j_, dir.x, dir.y, method_, search);
        return std::isinf(horizon) || horizon > dir.z / across;
    }

private:
    const HeightGrid& g_;
    int64_t i_, j_;
    CellMethod method_;
    bool onSurface_ = false;
    std::optional<HeightFieldHit> probe_;
};

}  // namespace

MapRaster shadowMask(const HeightGrid& grid, double azimuthRad, double elevationRad, CellMethod method,
                     double sunRadiusRad, int samples, int threads, const HorizonSearch& search,
                     const MapProgress& progress, const VertexWindow& window) {
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
    return perVertex(grid, window, threads, progress, int64_t(dirs.size()), [&](int64_t i, int64_t j) {
        const VertexView vertex(grid, i, j, method);
        if (!vertex.onSurface()) return kNaN;
        int blocked = 0;
        for (const auto& d : dirs) blocked += vertex.blocked(d, search);
        return float(double(blocked) / double(dirs.size()));
    });
}

MapRaster shadowMasks(const HeightGrid& grid, const std::vector<glm::dvec2>& sunsRad, CellMethod method, int threads,
                      const HorizonSearch& search, const MapProgress& progress, const VertexWindow& window) {
    std::vector<glm::dvec3> dirs;
    for (const glm::dvec2& sun : sunsRad) dirs.push_back(directionFromRadians(sun.x, sun.y));
    const int n = int(dirs.size());
    return perVertexBands(grid, window, n, threads, progress, n, [&](int64_t i, int64_t j, float* out) {
        const VertexView vertex(grid, i, j, method);
        if (!vertex.onSurface()) return;
        for (int k = 0; k < n; ++k) out[k] = vertex.blocked(dirs[size_t(k)], search) ? 1.0f : 0.0f;
    });
}

MapRaster horizonMaps(const HeightGrid& grid, const std::vector<double>& azimuthsRad, CellMethod method, int threads,
                      const HorizonSearch& search, const MapProgress& progress, const VertexWindow& window) {
    const int n = int(azimuthsRad.size());
    if (!exactAtVertices(method))
        return perVertexBands(grid, window, n, threads, progress, n, [&](int64_t i, int64_t j, float* out) {
            // Nearest has no surface at the vertex: bisection over occlusion from the surface point under it.
            const VertexView vertex(grid, i, j, method);
            if (!vertex.onSurface()) return;
            for (int k = 0; k < n; ++k)
                out[k] = float(degrees(bisectHorizon(azimuthsRad[size_t(k)], 1e-7,
                                                     [&](const glm::dvec3& d) { return vertex.blocked(d); })));
        });
    // One chain per azimuth and row (the rows' chains live in the row loop's thread).
    return perVertexRows(grid, window, n, threads, progress, n,
                         [&](int64_t i, int64_t j, float* out, bool chainStart, bool rowStart) {
        thread_local std::vector<HorizonChain> chains;
        if (rowStart) {
            chains.clear();
            for (double az : azimuthsRad) chains.emplace_back(grid, az, method, search);
        }
        if (!vertexOnSurface(grid, i, j)) {
            for (auto& c : chains) c.skip();
            return;
        }
        for (int k = 0; k < n; ++k) out[k] = float(degrees(std::atan(chains[size_t(k)].tangent(i, j, chainStart))));
    });
}

MapRaster horizonMap(const HeightGrid& grid, double azimuthRad, CellMethod method, int threads,
                     const HorizonSearch& search, const MapProgress& progress) {
    return horizonMaps(grid, {azimuthRad}, method, threads, search, progress);
}

std::function<MapRaster(const VertexWindow&, const MapProgress&)> skyViewMaker(const HeightGrid& grid, const SkyViewSettings& s) {
    if (!exactAtVertices(s.method)) throw GridError("sky-view factor and openness need a surface through the vertices, not nearest");
    if (s.directions < 1) throw GridError("sky-view factor: at least one direction is needed");
    // The terrain upside down, for the lowest elevation angles of the negative openness.
    HeightTransform upsideDown;
    upsideDown.upsideDown = true;
    const auto below = std::make_shared<const HeightGrid>(grid.transformed(upsideDown));
    HorizonSearch belowSearch = s.search;
    belowSearch.dropPerSquareM = -s.search.dropPerSquareM;  // the earth's drop lifts the upside-down terrain
    std::vector<double> azimuths;
    for (int k = 0; k < s.directions; ++k) azimuths.push_back(2.0 * kPi * double(k) / double(s.directions));
    const int64_t n = int64_t(azimuths.size());
    return [&grid, s, below, belowSearch, azimuths, n](const VertexWindow& window, const MapProgress& progress) {
    return perVertexRows(grid, window, 3, s.threads, progress, 2 * n,
                         [&](int64_t i, int64_t j, float* out, bool chainStart, bool rowStart) {
        // Per direction, a chain over the terrain and one over the terrain upside down.
        thread_local std::vector<HorizonChain> up, down;
        if (rowStart) {
            up.clear();
            down.clear();
            for (double az : azimuths) {
                up.emplace_back(grid, az, s.method, s.search);
                down.emplace_back(*below, az, s.method, belowSearch);
            }
        }
        if (!vertexOnSurface(grid, i, j)) {
            for (auto& c : up) c.skip();
            for (auto& c : down) c.skip();
            return;
        }
        double sinSum = 0.0, above = 0.0, under = 0.0;
        int seen = 0;
        for (int64_t k = 0; k < n; ++k) {
            const double t = up[size_t(k)].tangent(i, j, chainStart);
            const double lowest = down[size_t(k)].tangent(i, j, chainStart);
            if (std::isinf(t)) continue;  // no surface that way: an open sky, and no openness term
            const double g = std::atan(t);
            sinSum += std::sin(std::max(0.0, g));
            above += 90.0 - degrees(g);
            under += 90.0 - degrees(std::atan(lowest));
            ++seen;
        }
        out[0] = float(1.0 - sinSum / double(n));
        if (seen > 0) {
            out[1] = float(above / seen);
            out[2] = float(under / seen);
        }
    });
    };
}

MapRaster skyView(const HeightGrid& grid, const SkyViewSettings& s) { return skyViewMaker(grid, s)(s.window, s.progress); }

VertexWindow VertexWindow::within(const HeightGrid& grid) const {
    if (whole()) return {0, 0, grid.width(), grid.height()};
    if (i0 < 0 || j0 < 0 || i1 > grid.width() || j1 > grid.height() || i1 <= i0 || j1 <= j0)
        throw std::invalid_argument("VertexWindow: [" + std::to_string(i0) + ", " + std::to_string(i1) + ") x [" +
                                    std::to_string(j0) + ", " + std::to_string(j1) + ") is not within a " +
                                    std::to_string(grid.width()) + " x " + std::to_string(grid.height()) + " grid");
    return *this;
}

namespace {

// The top-down view's light at one surface point (renderMapView, mapViewMaker): Lambert sun with cast shadows,
// sky visibility from cosine-weighted directions keyed by the pixel (px, py) (counter-based random numbers: the
// same picture for any thread count and any tiling), blended with a plain hillshade. At a vertex (`vertex`
// set) directions are tested as `shadow` tests them; elsewhere from the surface point `hit`.
struct MapShade {
    glm::vec3 colour{0.0f};
    int64_t shadowRays = 0;
    int64_t skyRays = 0;
};

MapShade shadeMapPoint(const HeightGrid& grid, const MapViewSettings& s, const glm::dvec3& toSun, int64_t px,
                       int64_t py, const glm::dvec3& point, const glm::dvec3& normal, const VertexView* vertex,
                       const HeightFieldHit* hit) {
    MapShade out;
    const double lambert = std::max(0.0, glm::dot(normal, toSun));
    double lit = toSun.z > 0.0 ? 1.0 : 0.0;
    if (s.castShadows && lambert > 0.0) {
        // At a vertex as `shadow` decides (a sun below the horizontal can light a peak); elsewhere the sun must
        // also be above the horizontal.
        ++out.shadowRays;
        if (vertex) lit = vertex->blocked(toSun) ? 0.0 : 1.0;
        else if (blockedFrom(grid, *hit, toSun, s.method)) lit = 0.0;
    }
    double sky = 1.0;
    if (s.skySamples > 0) {
        const RandomStream random(s.seed, uint64_t(px), uint64_t(py));
        const Frame frame = Frame::around(normal);
        int open = 0;
        for (int k = 0; k < s.skySamples; ++k) {
            const glm::dvec3 d = frame.toWorld(squareToCosineHemisphere(random.uniform2(2 * uint64_t(k))));
            // Sky directions take the occlusion walk from the vertex (the same verdicts but where a direction
            // passes exactly through a vertex between holes), which is faster.
            open += vertex ? !blockedFromVertex(grid, px, grid.height() - 1 - py, d, s.method)
                           : !blockedFrom(grid, *hit, d, s.method);
        }
        out.skyRays += s.skySamples;
        sky = double(open) / double(s.skySamples);
    }
    const glm::vec3 albedo =
        s.colourRamp ? elevationAlbedo(point.z, grid.minHeightM(), grid.maxHeightM()) : glm::vec3(0.8f);
    const double shade = double(s.sun.intensity) * lambert * lit + double(s.ambient) * sky;
    const double plain = double(s.sun.intensity) * lambert + double(s.ambient);
    const double value = (1.0 - s.hillshadeBlend) * shade + s.hillshadeBlend * plain;
    out.colour = albedo * float(value);
    return out;
}

}  // namespace

MapImage renderMapView(const HeightGrid& grid, const MapViewSettings& s) {
    const int w = std::max(1, int(std::lround(double(grid.width()) * s.scale)));
    const int h = std::max(1, int(std::lround(double(grid.height()) * s.scale)));
    MapImage image;
    image.film = Film(w, h);
    image.covered.assign(size_t(w) * size_t(h), 0);
    const glm::dvec3 toSun = s.sun.direction();
    // The raster spans the samples' footprint: from half a cell west of vertex 0 to half a cell east of the last.
    const double stepX = double(grid.width()) * grid.cellSizeXM() / w, stepY = double(grid.height()) * grid.cellSizeYM() / h;
    const double x0 = -0.5 * grid.cellSizeXM(), yTop = (double(grid.height()) - 0.5) * grid.cellSizeYM();
    const bool atVertices = w == grid.width() && h == grid.height();
    std::atomic<int64_t> shadowRays{0}, skyRays{0}, done{0};
    std::mutex progressMutex;
    parallelForTiles(w, h, 32, s.threads, [&](int tx0, int ty0, int tx1, int ty1) {
        int64_t nShadow = 0, nSky = 0;
        for (int py = ty0; py < ty1; ++py)
            for (int px = tx0; px < tx1; ++px) {
                // The surface at the pixel: its point, normal and a test of directions.
                glm::dvec3 point, normal;
                std::optional<HeightFieldHit> hit;
                std::optional<VertexView> vertex;
                if (atVertices && exactAtVertices(s.method)) {
                    const int64_t i = px, j = grid.height() - 1 - py;
                    if (!vertexOnSurface(grid, i, j)) continue;
                    vertex.emplace(grid, i, j, s.method);
                    point = {double(i) * grid.cellSizeXM(), double(j) * grid.cellSizeYM(), double(grid.at(i, j))};
                    normal = vertexNormal(grid, i, j);
                } else {
                    const double x = std::clamp(x0 + (px + 0.5) * stepX, 0.0, grid.extentXM());
                    const double y = std::clamp(yTop - (py + 0.5) * stepY, 0.0, grid.extentYM());
                    hit = surfacePointAt(grid, x, y, s.method);
                    if (!hit) continue;
                    point = hit->pointM;
                    normal = hit->normal;
                }
                image.covered[size_t(py) * size_t(w) + size_t(px)] = 1;
                const MapShade shade = shadeMapPoint(grid, s, toSun, px, py, point, normal,
                                                     vertex ? &*vertex : nullptr, hit ? &*hit : nullptr);
                nShadow += shade.shadowRays;
                nSky += shade.skyRays;
                image.film.set(px, py, shade.colour);
            }
        shadowRays += nShadow;
        skyRays += nSky;
        const int64_t now = done += int64_t(tx1 - tx0) * (ty1 - ty0);
        if (s.progress) {
            std::lock_guard lock(progressMutex);
            s.progress(double(now) / (double(w) * double(h)), shadowRays.load() + skyRays.load());
        }
    });
    image.shadowRays = shadowRays;
    image.skyRays = skyRays;
    return image;
}

std::function<MapRaster(const VertexWindow&, const MapProgress&)> mapViewMaker(const HeightGrid& grid,
                                                                               const MapViewSettings& s) {
    if (!exactAtVertices(s.method))
        throw GridError("the map view on the DEM's own grid needs a surface through the vertices, not nearest");
    return [&grid, s](const VertexWindow& window, const MapProgress& progress) {
        const glm::dvec3 toSun = s.sun.direction();
        // Rays vary per vertex (no sun ray where the surface faces away): counted, and reported as counted.
        std::atomic<int64_t> rays{0};
        MapProgress counted;
        if (progress) counted = [&](double f, int64_t) { progress(f, rays.load()); };
        return perVertexBands(grid, window, 4, s.threads, counted, 0, [&](int64_t i, int64_t j, float* out) {
            out[0] = out[1] = out[2] = out[3] = 0.0f;
            if (!vertexOnSurface(grid, i, j)) return;
            const VertexView vertex(grid, i, j, s.method);
            const glm::dvec3 point{double(i) * grid.cellSizeXM(), double(j) * grid.cellSizeYM(), double(grid.at(i, j))};
            // The pixel renderMapView gives this vertex at scale 1: column i, row height - 1 - j from the north.
            const MapShade shade = shadeMapPoint(grid, s, toSun, i, grid.height() - 1 - j, point,
                                                 vertexNormal(grid, i, j), &vertex, nullptr);
            rays += shade.shadowRays + shade.skyRays;
            for (int b = 0; b < 3; ++b) out[b] = shade.colour[b];
            out[3] = 1.0f;
        });
    };
}

}  // namespace terracast
