#include "heightfield/horizon.h"

#include "heightfield/height_tile.h"

#include <algorithm>
#include <cmath>

namespace terracast {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// How a walk reads the grid: heights, cell validity and the pyramid's block maxima, each exactly as the grid's
// own at, cellValid and blockMaxM return them. A whole grid's reader reads its arrays; a tiled grid's keeps the
// tile of the last cell it read, so that it asks the grid's per-thread memo only when the walk enters another
// tile (docs/architecture.md, "Tiled grids").
struct WholeGridReader {
    const HeightGrid& g;
    HeightGrid::PyramidView pyramid = g.pyramidView();
    float at(int64_t i, int64_t j) const { return g.at(i, j); }
    bool cellValid(int64_t i, int64_t j) const { return g.wholeCellValid(i, j); }
    double blockMaxM(int k, int64_t bi, int64_t bj) const { return pyramid.blockMaxM(k, bi, bj); }
};

struct TiledGridReader {
    const HeightGrid& g;
    HeightGrid::PyramidView pyramid = g.pyramidView();  // the levels above the tiles'
    const HeightTile* tile = nullptr;
    int64_t x0 = 1, x1 = 0, y0 = 1, y1 = 0;  // the current tile's cells, inclusive

    const HeightTile& cellTile(int64_t i, int64_t j) {
        if (i < x0 || i > x1 || j < y0 || j > y1) [[unlikely]] {
            tile = &g.tileOfCell(i, j);
            x0 = tile->firstX();
            y0 = tile->firstY();
            x1 = x0 + tile->verticesX() - 2;
            y1 = y0 + tile->verticesY() - 2;
        }
        return *tile;
    }
    // A vertex from the current tile when it holds it (a tile holds its cells' far edges too).
    float at(int64_t i, int64_t j) {
        if (i < x0 || i > x1 + 1 || j < y0 || j > y1 + 1) [[unlikely]]
            return cellTile(std::min(i, g.cellsX() - 1), std::min(j, g.cellsY() - 1)).at(i, j);
        return tile->at(i, j);
    }
    bool cellValid(int64_t i, int64_t j) { return cellTile(i, j).cellValid(i, j); }
    double blockMaxM(int k, int64_t bi, int64_t bj) {
        if (k > g.tileLevels()) return pyramid.blockMaxM(k, bi, bj);
        return pyramid.decode(cellTile(bi << k, bj << k).maxCode(k, bi, bj));
    }
};

// One horizon walk. The line runs through grid coordinates u(t) = x0 + t du, v(t) = y0 + t dv (in vertex
// indices; a vertex's own for the map products, any point for an observer), t in horizontal metres; a point at
// distance t and height h has the slope (h - z0 - k t^2) / t. `onSurface` says that (x0, y0, z0) lies on the
// surface, so that the limit t -> 0 is the surface's slope there; above it the limit is -infinity.
template <class Reader>
class HorizonWalk {
public:
    HorizonWalk(Reader& g, double x0, double y0, double z0, bool onSurface, double du, double dv,
                bool triangles, const HorizonSearch& s, double floor)
        : g_(g), x0_(x0), y0_(y0), du_(du), dv_(dv), invDu_(du != 0.0 ? 1.0 / du : 0.0),
          invDv_(dv != 0.0 ? 1.0 / dv : 0.0), z0_(z0), k_(s.dropPerSquareM), onSurface_(onSurface),
          onLineX_(x0 == std::floor(x0)), onLineY_(y0 == std::floor(y0)), triangles_(triangles), best_(floor) {}

    double best() const { return best_; }
    double bestDistance() const { return bestT_; }
    // Starts the supremum at a known surface point's slope (a lower bound of it), at distance t.
    void seed(double t, double slope) {
        if (slope > best_) {
            best_ = slope;
            bestT_ = t;
        }
    }

    // The parameter at which the line crosses the grid line x = c (y = c), through the reciprocal: every crossing
    // comes from these two functions, so the walk's steps and block exits agree on the order of crossings.
    double atX(int64_t c) const { return du_ != 0.0 ? (double(c) - x0_) * invDu_ : kInf; }
    double atY(int64_t c) const { return dv_ != 0.0 ? (double(c) - y0_) * invDv_ : kInf; }
    // The exit parameter of cell column ci (row cj): where the line crosses the cell's far grid line.
    double exitX(int64_t ci) const { return atX(du_ > 0.0 ? ci + 1 : ci); }
    double exitY(int64_t cj) const { return atY(dv_ > 0.0 ? cj + 1 : cj); }

    // False when no point between distances t > 0 and tFar with a height up to `bound` can raise the horizon: each
    // is at least t away, at most tFar, and dropped by at least k t^2 (k tFar^2 for a negative k).
    bool canRaise(double bound, double t, double tFar) const {
        const double d = k_ >= 0.0 ? t : tFar;
        return bound - z0_ - k_ * d * d > best_ * (best_ >= 0.0 ? t : tFar);
    }

    // The point at distance t > 0 with surface height h (a division only when it raises the horizon).
    void consider(double t, double h) {
        const double rise = h - z0_ - k_ * t * t;
        if (rise > best_ * t && rise / t > best_) {
            best_ = rise / t;
            bestT_ = t;
        }
    }

    // A stretch [ta, tb] over which the surface height along the line is h(t) = hA + slope (t - ta) + c (t - ta)^2,
    // evaluated exactly by `at`. The slope's supremum over the stretch is at an end or where its derivative
    // vanishes: with H(t) = alpha + beta t + gamma t^2 the surface less the vertex and the drop, d(H / t) / dt =
    // (gamma t^2 - alpha) / t^2 vanishes at t^2 = alpha / gamma, a maximum only when gamma < 0 (and so alpha < 0;
    // with gamma > 0 it is a minimum). At ta = 0 (the vertex itself, hA = z0) the limit is the slope in t.
    template <class At>
    void stretch(double ta, double tb, double hA, double slope, double c, At&& at) {
        if (ta == 0.0) {
            if (onSurface_) seed(0.0, slope);
        } else if (ta != lastEnd_) {
            consider(ta, hA);
        }  // else the stretch before ended here, at the same point
        consider(tb, at(tb));
        lastEnd_ = tb;
        const double gamma = c - k_;
        if (gamma < 0.0) {
            // ta^2 < alpha / gamma < tb^2, multiplied through by gamma < 0: no division unless the maximum is inside.
            const double alpha = hA - z0_ - slope * ta + c * ta * ta;
            if (alpha < gamma * ta * ta && alpha > gamma * tb * tb) {
                const double ts = std::sqrt(alpha / gamma);
                if (ts > ta && ts < tb) consider(ts, at(ts));
            }
        }
    }

    // True when the line runs along a grid line (du or dv zero, from a point on that grid line).
    bool alongGridLine() const { return (du_ == 0.0 && onLineX_) || (dv_ == 0.0 && onLineY_); }

    // The surface of cell (ci, cj) over [ta, tb] (tb > ta). Along a grid line the surface is the edge between the
    // line's two vertices, linear in both methods.
    void solveCell(int64_t ci, int64_t cj, double ta, double tb) {
        if (alongGridLine()) {
            // The edge's vertices: (x0, cj) to (x0, cj + 1) along a north-south line, (ci, y0) to (ci + 1, y0)
            // east-west.
            const bool northSouth = du_ == 0.0 && onLineX_;
            const int64_t li = int64_t(x0_), lj = int64_t(y0_);
            const double hLo = northSouth ? g_.at(li, cj) : g_.at(ci, lj);
            const double hHi = northSouth ? g_.at(li, cj + 1) : g_.at(ci + 1, lj);
            const double s0 = northSouth ? y0_ - double(cj) : x0_ - double(ci), ds = northSouth ? dv_ : du_;
            auto at = [&](double t) { return hLo + (hHi - hLo) * std::clamp(s0 + t * ds, 0.0, 1.0); };
            stretch(ta, tb, at(ta), (hHi - hLo) * ds, 0.0, at);
            return;
        }
        const double h00 = g_.at(ci, cj), h10 = g_.at(ci + 1, cj), h01 = g_.at(ci, cj + 1), h11 = g_.at(ci + 1, cj + 1);
        // Both surfaces stay within the corners' range: a cell whose highest corner cannot raise the horizon is
        // passed without solving it (the start cell, at ta = 0, always is solved: its slope counts).
        if (ta > 0.0 && !canRaise(std::max(std::max(h00, h10), std::max(h01, h11)), ta, tb)) return;
        const double u0 = x0_ - double(ci), v0 = y0_ - double(cj);  // the origin in the cell's frame
        auto uAt = [&](double t) { return std::clamp(u0 + t * du_, 0.0, 1.0); };
        auto vAt = [&](double t) { return std::clamp(v0 + t * dv_, 0.0, 1.0); };
        if (!triangles_) {
            // h = a + b u + c v + d u v (docs/architecture.md, "Cell intersectors"); along the line it is quadratic
            // in t with second-order coefficient d du dv.
            const double b = h10 - h00, c = h01 - h00, d = h00 - h10 - h01 + h11;
            auto at = [&](double t) {
                const double u = uAt(t), v = vAt(t);
                return h00 + b * u + c * v + d * u * v;
            };
            const double ua = uAt(ta), va = vAt(ta);
            stretch(ta, tb, at(ta), (b + d * va) * du_ + (c + d * ua) * dv_, d * du_ * dv_, at);
            return;
        }
        // Two planes split by the diagonal u + v = 1 (from (1, 0) to (0, 1)); the line crosses it at most once.
        auto lower = [&](double t) { return h00 + (h10 - h00) * uAt(t) + (h01 - h00) * vAt(t); };
        auto upper = [&](double t) { return h11 + (h11 - h01) * (uAt(t) - 1.0) + (h11 - h10) * (vAt(t) - 1.0); };
        const double lowerSlope = (h10 - h00) * du_ + (h01 - h00) * dv_;
        const double upperSlope = (h11 - h01) * du_ + (h11 - h10) * dv_;
        double tDiag = kInf;
        if (du_ + dv_ != 0.0) tDiag = (1.0 - u0 - v0) / (du_ + dv_);
        auto piece = [&](double a, double b) {
            const double mid = 0.5 * (a + b);
            if (uAt(mid) + vAt(mid) < 1.0) stretch(a, b, lower(a), lowerSlope, 0.0, lower);
            else stretch(a, b, upper(a), upperSlope, 0.0, upper);
        };
        if (tDiag > ta && tDiag < tb) {
            piece(ta, tDiag);
            piece(tDiag, tb);
        } else {
            piece(ta, tb);
        }
    }

private:
    Reader& g_;
    double x0_, y0_;
    double du_, dv_, invDu_, invDv_;
    double z0_, k_;
    bool onSurface_, onLineX_, onLineY_;
    bool triangles_;
    double best_;
    double lastEnd_ = -1.0;  // where the last stretch solved ended
    double bestT_ = 0.0;     // the distance of the point that gave best_
};

// The walk behind horizonTangent and horizonAbove: the supremum of the slopes, or `floor` when none exceeds it;
// with `stopAbove`, it ends as soon as one does.
// The origin is (x0, y0) in vertex indices at height z0, on the surface or above it.
template <class Reader>
double walkOver(const HeightGrid& g, Reader& reader, double x0, double y0, double z0, bool onSurface, double dirX,
                double dirY, CellMethod method, const HorizonSearch& search, HorizonCounters* counters, double floor,
                bool stopAbove, double hintM, double* distanceM) {
    if (method == CellMethod::Nearest) throw GridError("the horizon walk needs a surface through the vertices, not nearest");
    const double norm = std::hypot(dirX, dirY);
    if (!(norm > 0.0)) return floor;
    double du = dirX / norm / g.cellSizeXM(), dv = dirY / norm / g.cellSizeYM();
    // A direction within rounding of a grid line (azimuth 90 gives cos(pi / 2), about 6e-17, for y) runs along it.
    if (std::abs(du) < 1e-12 * std::abs(dv)) du = 0.0;
    if (std::abs(dv) < 1e-12 * std::abs(du)) dv = 0.0;
    HorizonWalk<Reader> walk(reader, x0, y0, z0, onSurface, du, dv, method == CellMethod::Triangles, search, floor);
    if (hintM > 1e-3 * std::min(g.cellSizeXM(), g.cellSizeYM()) && hintM <= search.maxDistanceM) {
        // The surface point at the hint's distance along the line, when a valid cell holds it: its slope is a lower
        // bound of the supremum, from which the walk starts (and so skips more). A thousandth of a cell out at
        // least, so that the rounding of h - z0 stays small against the distance; and lowered by a billionth, so
        // that the walk still solves the cell the point lies in and returns its own value, as without a hint.
        const double u = x0 + hintM * du, v = y0 + hintM * dv;
        if (u >= 0.0 && v >= 0.0 && u <= double(g.cellsX()) && v <= double(g.cellsY())) {
            const int64_t ci = std::min(int64_t(u), g.cellsX() - 1), cj = std::min(int64_t(v), g.cellsY() - 1);
            if (reader.cellValid(ci, cj)) {
                const double fu = u - double(ci), fv = v - double(cj);
                const double h00 = reader.at(ci, cj), h10 = reader.at(ci + 1, cj), h01 = reader.at(ci, cj + 1),
                             h11 = reader.at(ci + 1, cj + 1);
                double h = 0.0;
                if (method != CellMethod::Triangles)
                    h = h00 + (h10 - h00) * fu + (h01 - h00) * fv + (h00 - h10 - h01 + h11) * fu * fv;
                else if (fu + fv <= 1.0)
                    h = h00 + (h10 - h00) * fu + (h01 - h00) * fv;
                else
                    h = h11 + (h11 - h01) * (fu - 1.0) + (h11 - h10) * (fv - 1.0);
                const double slope = (h - z0 - search.dropPerSquareM * hintM * hintM) / hintM;
                // Lowered past the rounding of h - z0 (a few ulps of the heights, over the distance) as well.
                const double margin = 1e-9 * (1.0 + std::abs(slope)) +
                                      16.0 * std::numeric_limits<double>::epsilon() * (std::abs(h) + std::abs(z0)) / hintM;
                walk.seed(hintM, slope - margin);
            }
        }
    }

    // The cell the line leaves the origin over: from a vertex (or a grid line), the one the direction points
    // into; along a grid line, the column (row) on the line's east (north) side, or its west (south) side on the
    // grid's last line, standing for both. From inside a cell, that cell.
    const int64_t nx = g.cellsX(), ny = g.cellsY();
    const bool onLineX = x0 == std::floor(x0), onLineY = y0 == std::floor(y0);
    const int64_t i = int64_t(std::floor(x0)), j = int64_t(std::floor(y0));
    int64_t ci = !onLineX ? std::min(i, nx - 1) : du > 0.0 ? i : du < 0.0 ? i - 1 : std::min(i, nx - 1);
    int64_t cj = !onLineY ? std::min(j, ny - 1) : dv > 0.0 ? j : dv < 0.0 ? j - 1 : std::min(j, ny - 1);
    const int64_t stepI = du > 0.0 ? 1 : du < 0.0 ? -1 : 0, stepJ = dv > 0.0 ? 1 : dv < 0.0 ? -1 : 0;
    auto inGrid = [&](int64_t a, int64_t b) { return a >= 0 && b >= 0 && a < nx && b < ny; };
    // Along a grid line a stretch has surface when the cell on either side is valid.
    auto hasSurface = [&](int64_t a, int64_t b) {
        if (reader.cellValid(a, b)) return true;
        if (du == 0.0 && onLineX && i > 0 && i < nx && a == i) return reader.cellValid(i - 1, b);
        if (dv == 0.0 && onLineY && j > 0 && j < ny && b == j) return reader.cellValid(a, j - 1);
        return false;
    };
    // Where the line leaves the grid (or the search radius), from the same crossing parameters as the cells' exits.
    const double tEnd = std::min(search.maxDistanceM,
                                 std::min(du > 0.0 ? walk.atX(nx) : du < 0.0 ? walk.atX(0) : kInf,
                                          dv > 0.0 ? walk.atY(ny) : dv < 0.0 ? walk.atY(0) : kInf));
    const double top = g.maxHeightM();
    const int levels = g.pyramidLevels();
    auto cannotRaise = [&](double bound, double t, double tFar) { return !walk.canRaise(bound, t, tFar); };
    double t = 0.0;
    int level = 0;
    int64_t visited = 0, skipped = 0;
    while (inGrid(ci, cj) && t < tEnd) {
        if (t > 0.0) {
            if (cannotRaise(top, t, tEnd)) break;
            // The largest block around the cell (at most one level above the last) that cannot raise the horizon.
            bool skip = false;
            double tOut = 0.0;
            int lv = std::min(level + 1, levels);
            for (; lv >= 1; --lv) {
                const int64_t bi = ci >> lv, bj = cj >> lv;
                const double txb = walk.atX(du > 0.0 ? (bi + 1) << lv : bi << lv);
                const double tyb = walk.atY(dv > 0.0 ? (bj + 1) << lv : bj << lv);
                tOut = std::min(txb, tyb);
                if (tOut > t && cannotRaise(reader.blockMaxM(lv, bi, bj), t, std::min(tOut, tEnd))) {
                    skip = true;
                    // The cell the line is in just past the block: across the side it leaves by, and along the
                    // other axis the one whose stretch holds tOut (from the same exit parameters as a cell step).
                    if (txb <= tyb) ci = du > 0.0 ? (bi + 1) << lv : (bi << lv) - 1;
                    else if (du != 0.0) {
                        ci = std::clamp<int64_t>(int64_t(std::floor(x0 + tOut * du)), bi << lv, ((bi + 1) << lv) - 1);
                        while (walk.exitX(ci) <= tOut) ci += stepI;
                        while (walk.exitX(ci - stepI) > tOut) ci -= stepI;
                    }
                    if (tyb <= txb) cj = dv > 0.0 ? (bj + 1) << lv : (bj << lv) - 1;
                    else if (dv != 0.0) {
                        cj = std::clamp<int64_t>(int64_t(std::floor(y0 + tOut * dv)), bj << lv, ((bj + 1) << lv) - 1);
                        while (walk.exitY(cj) <= tOut) cj += stepJ;
                        while (walk.exitY(cj - stepJ) > tOut) cj -= stepJ;
                    }
                    break;
                }
            }
            if (skip) {
                ++skipped;
                level = lv;
                t = tOut;
                continue;
            }
            level = 0;
        }
        const double tx = walk.exitX(ci), ty = walk.exitY(cj);
        const double tNext = std::min(tx, ty);
        if (hasSurface(ci, cj)) {
            walk.solveCell(ci, cj, t, std::min(tNext, tEnd));
            ++visited;
        }
        if (std::abs(tx - ty) * (std::abs(du) + std::abs(dv)) <= 1e-9 && tNext <= tEnd) {
            // Through a corner, or within 1e-9 of a cell of it (a diagonal azimuth whose sine and cosine differ in
            // the last bit): the vertex counts when any of its four cells is valid, though the line may cross only
            // holes or the sliver of a cell beside it.
            const int64_t vi = du > 0.0 ? ci + 1 : ci, vj = dv > 0.0 ? cj + 1 : cj;
            bool onSurface = false;
            for (int64_t b = vj - 1; b <= vj && !onSurface; ++b)
                for (int64_t a = vi - 1; a <= vi && !onSurface; ++a) onSurface = inGrid(a, b) && reader.cellValid(a, b);
            if (onSurface) walk.consider(tNext, reader.at(vi, vj));
        }
        if (stopAbove && walk.best() > floor) break;
        if (tx <= ty) ci += stepI;
        if (ty <= tx) cj += stepJ;
        t = tNext;
    }
    if (counters) {
        counters->cellsVisited += visited;
        counters->blocksSkipped += skipped;
    }
    if (distanceM) *distanceM = walk.bestDistance();
    return walk.best();
}

// The walk behind horizonTangent and horizonAbove, through the reader of the grid's kind.
double walkHorizon(const HeightGrid& g, double x0, double y0, double z0, bool onSurface, double dirX, double dirY,
                   CellMethod method, const HorizonSearch& search, HorizonCounters* counters, double floor,
                   bool stopAbove, double hintM = 0.0, double* distanceM = nullptr) {
    if (g.tiled()) {
        TiledGridReader reader{g};
        return walkOver(g, reader, x0, y0, z0, onSurface, dirX, dirY, method, search, counters, floor, stopAbove,
                        hintM, distanceM);
    }
    WholeGridReader reader{g};
    return walkOver(g, reader, x0, y0, z0, onSurface, dirX, dirY, method, search, counters, floor, stopAbove, hintM,
                    distanceM);
}

}  // namespace

double horizonTangent(const HeightGrid& g, int64_t i, int64_t j, double dirX, double dirY, CellMethod method,
                      const HorizonSearch& search, HorizonCounters* counters) {
    return walkHorizon(g, double(i), double(j), g.at(i, j), true, dirX, dirY, method, search, counters, -kInf, false);
}

HorizonPoint horizonPoint(const HeightGrid& g, int64_t i, int64_t j, double dirX, double dirY, CellMethod method,
                          const HorizonSearch& search, double hintDistanceM, HorizonCounters* counters) {
    HorizonPoint p;
    p.tangent = walkHorizon(g, double(i), double(j), g.at(i, j), true, dirX, dirY, method, search, counters, -kInf,
                            false, hintDistanceM, &p.distanceM);
    return p;
}

bool horizonAbove(const HeightGrid& g, int64_t i, int64_t j, double dirX, double dirY, double tangent,
                  CellMethod method, const HorizonSearch& search, HorizonCounters* counters) {
    return walkHorizon(g, double(i), double(j), g.at(i, j), true, dirX, dirY, method, search, counters, tangent,
                       true) > tangent;
}

double horizonTangentFrom(const HeightGrid& g, double xM, double yM, double zM, double dirX, double dirY,
                          CellMethod method, const HorizonSearch& search, HorizonCounters* counters) {
    const double x0 = std::clamp(xM * g.cellsPerMetreX(), 0.0, double(g.cellsX()));
    const double y0 = std::clamp(yM * g.cellsPerMetreY(), 0.0, double(g.cellsY()));
    return walkHorizon(g, x0, y0, zM, false, dirX, dirY, method, search, counters, -kInf, false);
}

}  // namespace terracast
