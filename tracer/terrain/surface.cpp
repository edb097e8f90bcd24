#include "tracer/terrain/surface.h"

#include "heightfield/coarser_grid.h"
#include "heightfield/shading_normals.h"
#include "tracer/core/ranks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace terracast {

namespace {
// Coarser grids a level of detail builds at most (a grid of 2^17 cells a side would need 17).
constexpr size_t kMaxDetailLevels = 16;
}  // namespace

TerrainSurface::TerrainSurface(const HeightGrid& grid, SurfaceMethod method, int threads, Traversal traversal)
    : grid_(grid), method_(method), cell_(directCellMethod(method).value_or(CellMethod::Bilinear)), traversal_(traversal),
      threads_(threads) {
    if (method == SurfaceMethod::Embree)
        embree_ = std::make_unique<EmbreeTerrain>(grid, EmbreeLayout::TriangleMesh, threads);
    if (method == SurfaceMethod::EmbreeGrid) embree_ = std::make_unique<EmbreeTerrain>(grid, EmbreeLayout::Grid, threads);
}

void TerrainSurface::setLevelOfDetail(const LevelOfDetail& lod) {
    if (embree_) throw std::invalid_argument("a level of detail is for the direct tracer's methods, not Embree's");
    if (!(lod.radiansPerPixel > 0.0) || !(lod.pixels > 0.0) || !std::isfinite(lod.radiansPerPixel * lod.pixels) ||
        !std::isfinite(lod.eyeM.x + lod.eyeM.y + lod.eyeM.z))
        throw std::invalid_argument("a level of detail needs a positive, finite pixel angle and pixel count");
    // A cell of size c at distance d spans about c / (d * radiansPerPixel) pixels: level k + 1 takes over where
    // level k's cells span fewer than `pixels`. Levels stop at a grid of 2 x 2 cells.
    // A grid held as tiles keeps in memory only the levels from `first` on, the first whose grids (together about
    // 4/3 of its own bytes) fit in the tile cache's budget; it is made by reading every tile once (or taken from
    // where the tile source kept it). The fine grid's tiles serve the levels before it, which therefore begins
    // where level first - 1 would have ended. The ranks of a launch take the leader's choice, so that their parts
    // of a picture are traced on the same levels.
    int first = 1;
    if (grid_.tiled()) {
        const double budget = double(grid_.tileSource()->cacheBudgetBytes());
        const auto coarser = coarserVertexCount;
        int64_t w = grid_.width(), h = grid_.height();
        if (w >= 3 && h >= 3) {
            w = coarser(w);
            h = coarser(h);
            while (4.0 / 3.0 * coarseGridBytes(w, h) > budget && w >= 3 && h >= 3 && first < int(kMaxDetailLevels)) {
                w = coarser(w);
                h = coarser(h);
                ++first;
            }
        }
    }
    ranks::broadcast(&first, sizeof first);
    // Built aside, so that a failure (a tile that cannot be read) leaves the surface as it was.
    std::vector<std::unique_ptr<HeightGrid>> coarse;
    std::vector<double> fromM;
    float low = grid_.minHeightM(), high = grid_.maxHeightM();
    const HeightGrid* finer = &grid_;
    double finerCellM = std::min(grid_.cellSizeXM(), grid_.cellSizeYM()) * double(int64_t(1) << (first - 1));
    while (finer->width() >= 3 && finer->height() >= 3 && coarse.size() < kMaxDetailLevels) {
        fromM.push_back(finerCellM / (lod.radiansPerPixel * lod.pixels));
        coarse.push_back(std::make_unique<HeightGrid>(finer == &grid_ && grid_.tiled() ? coarserGrid(grid_, first, threads_)
                                                                                       : coarserGrid(*finer)));
        finer = coarse.back().get();
        finerCellM = std::min(finer->cellSizeXM(), finer->cellSizeYM());
        low = std::min(low, finer->minHeightM());
        high = std::max(high, finer->maxHeightM());
    }
    // Every level's surface lies in this box (a pad of a few cells of the finest grid for the rounding).
    const double pad = 4.0 * std::max(grid_.cellSizeXM(), grid_.cellSizeYM());
    const double zPad = 1e-3 * (1.0 + std::max(std::abs(double(low)), std::abs(double(high))));
    boxLo_ = {-pad, -pad, double(low) - zPad};
    boxHi_ = {std::max(grid_.extentXM(), finer->extentXM()) + pad, std::max(grid_.extentYM(), finer->extentYM()) + pad,
              double(high) + zPad};
    coarse_ = std::move(coarse);
    fromM_ = std::move(fromM);
    eye_ = lod.eyeM;
    firstDetailLevel_ = first;
}

glm::dvec3 TerrainSurface::smoothNormalAt(const HeightFieldHit& hit) const {
    if (!coarse_.empty()) {
        const double dist = glm::length(hit.pointM - eye_);
        if (const int k = levelAt(dist); k > 0) {
            const HeightFieldHit at = inCellsOf(level(k), hit);
            return smoothNormal(level(k), at.cellX, at.cellY, at.u, at.v);
        }
    }
    return smoothNormal(grid_, hit.cellX, hit.cellY, hit.u, hit.v);
}

size_t TerrainSurface::detailBytes() const {
    size_t bytes = 0;
    for (const auto& g : coarse_) bytes += g->memoryBytes();
    return bytes;
}

template <class Visit>
bool TerrainSurface::byLevel(const Ray& ray, Interval interval, Visit&& visit) const {
    if (!(interval.lo <= interval.hi)) return false;
    // Only the stretch inside the box of every level's surface can meet one: the grid's extent widened by the
    // coarsest level's overhang (half its cell past the far edges) and its range of heights.
    {
        const glm::dvec3 lo = boxLo_ - ray.origin, hi = boxHi_ - ray.origin;
        double t0 = interval.lo, t1 = interval.hi;
        for (int a = 0; a < 3; ++a) {
            const double inv = 1.0 / ray.dir[a];
            double ta = lo[a] * inv, tb = hi[a] * inv;
            if (ta > tb) std::swap(ta, tb);
            if (std::isnan(ta) || std::isnan(tb)) {
                if (lo[a] > 0.0 || hi[a] < 0.0) return false;  // parallel to the slab, outside it
                continue;
            }
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (!(t0 <= t1)) return false;
        // The stretch before the box holds nothing: the walk may start at the box, on its level.
        interval.lo = std::max(interval.lo, t0 - 1e-9 * (1.0 + std::abs(t0)));
        interval.hi = std::min(interval.hi, t1 + 1e-9 * (1.0 + std::abs(t1)));
    }
    // Where the ray's distance from the eye crosses each level's start: |o + t d - e|^2 = D^2, a quadratic whose
    // distance is convex in t, so each D cuts the ray at most twice.
    const glm::dvec3 oe = ray.origin - eye_;
    const double a = glm::dot(ray.dir, ray.dir), b = 2.0 * glm::dot(ray.dir, oe), c0 = glm::dot(oe, oe);
    double cuts[2 * kMaxDetailLevels + 2];  // each level's start cuts a ray at most twice
    int n = 0;
    cuts[n++] = interval.lo;
    for (const double d : fromM_) {
        const double c = c0 - d * d, disc = b * b - 4.0 * a * c;
        if (!(disc > 0.0) || !(a > 0.0)) continue;
        const double root = std::sqrt(disc);
        // Both roots without cancellation.
        const double q = -0.5 * (b + std::copysign(root, b));
        for (const double t : {q / a, q != 0.0 ? c / q : -b / (2.0 * a)})
            if (t > interval.lo && t < interval.hi) cuts[n++] = t;
    }
    std::sort(cuts + 1, cuts + n);
    cuts[n++] = interval.hi;
    for (int k = 0; k + 1 < n; ++k) {
        const double lo = cuts[k], hi = cuts[k + 1];
        if (!(hi > lo) && n > 2) continue;  // an empty stretch, unless it is the whole interval
        // The level of the stretch, from a point inside it (beyond the last cut when it reaches infinity).
        const double mid = std::isfinite(hi) ? 0.5 * (lo + hi) : lo + std::max(1.0, std::abs(lo));
        const double dist = glm::length(oe + mid * ray.dir);
        const int levelIndex = levelAt(dist);
        if (visit(levelIndex, Interval{lo, hi})) return true;
    }
    return false;
}

HeightFieldHit TerrainSurface::inCellsOf(const HeightGrid& g, HeightFieldHit hit) {
    const double x = hit.pointM.x * g.cellsPerMetreX(), y = hit.pointM.y * g.cellsPerMetreY();
    hit.cellX = std::clamp<int64_t>(int64_t(std::floor(x)), 0, g.cellsX() - 1);
    hit.cellY = std::clamp<int64_t>(int64_t(std::floor(y)), 0, g.cellsY() - 1);
    hit.u = std::clamp(x - double(hit.cellX), 0.0, 1.0);
    hit.v = std::clamp(y - double(hit.cellY), 0.0, 1.0);
    return hit;
}

int TerrainSurface::levelAt(double distanceM) const {
    return int(std::upper_bound(fromM_.begin(), fromM_.end(), distanceM) - fromM_.begin());
}

std::optional<HeightFieldHit> TerrainSurface::underLevel(int k, const Ray& ray, double t) const {
    const HeightGrid& g = level(k);
    const glm::dvec3 p = ray.origin + t * ray.dir;
    if (!(p.z < double(g.maxHeightM()))) return std::nullopt;
    const double x = p.x * g.cellsPerMetreX(), y = p.y * g.cellsPerMetreY();
    if (!(x >= 0.0 && y >= 0.0 && x <= double(g.cellsX()) && y <= double(g.cellsY()))) return std::nullopt;
    const int64_t i = std::min<int64_t>(int64_t(x), g.cellsX() - 1), j = std::min<int64_t>(int64_t(y), g.cellsY() - 1);
    if (!g.cellValid(i, j)) return std::nullopt;
    const double u = x - double(i), v = y - double(j);
    const double z00 = g.at(i, j), z10 = g.at(i + 1, j), z01 = g.at(i, j + 1), z11 = g.at(i + 1, j + 1);
    const double z = (1 - v) * ((1 - u) * z00 + u * z10) + v * ((1 - u) * z01 + u * z11);
    if (!(p.z < z)) return std::nullopt;
    HeightFieldHit hit;
    hit.t = t;
    hit.pointM = {p.x, p.y, z};
    const double dzdx = ((1 - v) * (z10 - z00) + v * (z11 - z01)) * g.cellsPerMetreX();
    const double dzdy = ((1 - u) * (z01 - z00) + u * (z11 - z10)) * g.cellsPerMetreY();
    hit.normal = glm::normalize(glm::dvec3(-dzdx, -dzdy, 1.0));
    hit.errorM = 1e-6 * (1.0 + std::abs(z));
    return inFineCells(hit);
}

std::optional<HeightFieldHit> TerrainSurface::intersect(const Ray& ray, Interval interval) const {
    if (embree_) return embree_->intersect(ray, interval);
    if (coarse_.empty()) return terracast::intersect(grid_, ray, interval, cell_, nullptr, traversal_);
    return intersectLevels(ray, interval, false);
}

std::optional<HeightFieldHit> TerrainSurface::intersectLevels(const Ray& ray, Interval interval, bool fromSwitch) const {
    std::optional<HeightFieldHit> hit;
    byLevel(ray, interval, [&](int k, Interval stretch) {
        // A ray that passes onto a coarser (or finer) level under its surface meets it where it passes.
        if ((fromSwitch || stretch.lo > interval.lo) && (hit = underLevel(k, ray, stretch.lo))) return true;
        hit = terracast::intersect(level(k), ray, stretch, cell_, nullptr, traversal_);
        if (hit && k > 0) hit = inFineCells(*hit);
        return hit.has_value();
    });
    return hit;
}

void TerrainSurface::intersectBundle(std::span<const Ray> rays, Interval interval,
                                     std::span<std::optional<HeightFieldHit>> hits) const {
    const size_t n = std::min(rays.size(), hits.size());
    if (embree_) {
        for (size_t k = 0; k < n; ++k) hits[k] = embree_->intersect(rays[k], interval);
        return;
    }
    if (coarse_.empty() || n == 0) return terracast::intersectBundle(grid_, rays, interval, cell_, hits, nullptr, traversal_);
    // The bundle's shared proof on the fine grid up to where the first ray leaves it, when they all start on it
    // (camera rays from the eye); each ray then goes on alone from there.
    // Where each ray passes from the fine grid to a coarser one (infinity when it never does).
    thread_local std::vector<double> switchAt;
    switchAt.assign(n, kInfinity);
    double fineEnd = interval.hi;
    bool fineFirst = true;
    for (size_t k = 0; k < n && fineFirst; ++k) {
        int stretches = 0;
        byLevel(rays[k], interval, [&](int level, Interval stretch) {
            if (stretches++ == 0) {
                fineFirst = level == 0;
                switchAt[k] = stretch.hi;
                return false;
            }
            return true;  // a second stretch: the first one's end is a switch
        });
        if (stretches < 2) switchAt[k] = kInfinity;
        fineEnd = std::min(fineEnd, switchAt[k]);
    }
    double from = interval.lo;
    if (fineFirst && fineEnd > interval.lo) {
        terracast::intersectBundle(grid_, rays.first(n), {interval.lo, fineEnd}, cell_, hits.first(n), nullptr, traversal_);
        from = fineEnd;
    } else {
        for (size_t k = 0; k < n; ++k) hits[k].reset();
    }
    // Rays go on alone; the test for lying under the next level's surface only where the ray switches there.
    if (from < interval.hi)
        for (size_t k = 0; k < n; ++k)
            if (!hits[k]) hits[k] = intersectLevels(rays[k], {from, interval.hi}, fineFirst && from == switchAt[k]);
}

bool TerrainSurface::occluded(const Ray& ray, Interval interval) const {
    if (embree_) return embree_->occluded(ray, interval);
    if (coarse_.empty()) return terracast::occluded(grid_, ray, interval, cell_, nullptr, traversal_);
    // The whole ray on the level of where it starts: occlusion rays leave a hit (shadow and sky-visibility rays)
    // and test the surface they left; cutting them where they cross levels costs a walk's set-up per stretch.
    const glm::dvec3 start = ray.origin + std::max(interval.lo, 0.0) * ray.dir;
    return terracast::occluded(level(levelAt(glm::length(start - eye_))), ray, interval, cell_, nullptr, traversal_);
}

int64_t TerrainSurface::memoryBytes() const {
    if (embree_) return embree_->memoryBytes();
    int64_t bytes = int64_t(grid_.memoryBytes());
    for (const auto& g : coarse_) bytes += int64_t(g->memoryBytes());
    return bytes;
}

int64_t TerrainSurface::peakMemoryBytes() const {
    if (embree_) return embree_->peakMemoryBytes();
    return int64_t(grid_.memoryBytes());
}

}  // namespace terracast
