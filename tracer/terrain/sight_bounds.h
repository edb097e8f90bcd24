// Bounds on the terrain's elevation slope as seen from one eye, per azimuth wedge and distance: what lets a
// viewshed settle most sight lines without walking them (docs/architecture.md, "Viewshed").
#pragma once

#include "heightfield/height_grid.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

namespace terracast {

// A polar table around the eye (docs/architecture.md, "Viewshed"). The plane is cut into wedges of azimuth and
// rings of distance; wedges are narrower farther out (their count doubles with each doubling of distance), so a
// wedge stays at most two rings wide. For every wedge and ring the table keeps, over the valid cells that reach
// into it, the range of the slope s(P) = (z(P) - z_eye) / |P - eye|_xy that the surface can take there (from
// the cells' lowest and highest corners, widened by a height tolerance), then the running maximum of both ends
// outwards along the wedge. A sight line from the eye at slope s_line is
//   - clear of the surface by more than the tolerance over [0, clearBefore(...)) metres;
//   - under the surface by more than the tolerance somewhere within `reach` when surelySlopeBefore(...) > s_line.
// Either answer is what an exact walk of that stretch returns (the surface is a bilinear patch or two
// triangles per cell; both lie within their corners' range). Holes (cells with a nodata corner) hold no
// surface: they never bound from above and make the lower bound unknown.
class SightBounds {
public:
    // The table for `grid` (held whole in memory) seen from `eye` (local metres), bounds widened by
    // `toleranceM`, built on `threads` threads (0 = all).
    // `bilinear`: the surface is the bilinear patch (not two triangles), which allows finer bounds near the eye.
    SightBounds(const HeightGrid& grid, const glm::dvec3& eye, double toleranceM, bool bilinear, int threads);

    // The bytes the table for an eye at (eyeXM, eyeYM) would hold (for memory checks, before building it).
    static double bytesFor(const HeightGrid& grid, double eyeXM, double eyeYM);

    // The direction (dx, dy) as a position along the table's azimuths, for the two queries below.
    static double azimuthKey(double dx, double dy) {
        // The "diamond angle": monotone in the direction counter-clockwise from +x, with no trigonometry.
        double p;
        if (dy >= 0.0) p = dx >= 0.0 ? (dx + dy > 0.0 ? dy / (dx + dy) : 0.0) : 1.0 - dx / (dy - dx);
        else p = dx < 0.0 ? 2.0 - dy / (-dx - dy) : 3.0 + dx / (dx - dy);
        return 0.25 * p;
    }
    // How far from the eye (horizontally) a sight line leaving it at `slope` along the direction `key`
    // (azimuthKey) is sure to pass above the surface by more than the tolerance: over [0, result) metres;
    // +infinity when over the whole grid.
    double clearBefore(double key, double slope) const;
    // A slope that the surface exceeds by the tolerance somewhere on the first `reachM` metres along `key`,
    // over a valid cell; -infinity when none can be given.
    double surelySlopeBefore(double key, double reachM) const {
        if (!(reachM >= 0.0)) return -std::numeric_limits<double>::infinity();
        const int64_t r = std::min(rings_, int64_t(reachM * perRing_)) - 1;
        if (r < 0) return -std::numeric_limits<double>::infinity();
        const Level& l = levels_[size_t(levelOfRing(r))];
        const int64_t w = std::min(l.wedges - 1, int64_t(key * double(l.wedges)));
        return l.lowest[size_t((r - l.ring0) * l.wedges + w)];
    }


private:
    struct Level {
        int64_t ring0 = 0, rings = 0;  // the rings it covers: [ring0, ring0 + rings)
        int64_t wedges = 0;
        std::vector<float> highest;    // [wedge][ring - ring0] once built: running max of the upper bounds
        std::vector<float> lowest;     // [ring - ring0][wedge]: the same for the lower bounds
    };
    static int levelOfRing(int64_t ring) { return int(std::bit_width(uint64_t(ring >> 3))); }
    void addCells(int64_t ringA, int64_t ringB);  // cells reaching rings [ringA, ringB): writes those rings only
    void runningMaxima();
    // Bounds `hi` (on ring r0, with `withHigh`) and `lo` (on rings r0..r1) into every wedge the corner
    // directions `keys` span (all of them with `all`; across the +x axis with `wraps`), within rings [ringA, ringB).
    void place(int64_t ringA, int64_t ringB, int64_t r0, int64_t r1, bool all, bool wraps, const double keys[4],
               bool withHigh, float hi, float lo);
    // The upper bounds of a near cell (its corner at (ax0, ay0) from the eye, heights z..) by sub-squares.
    void placeNearCell(int64_t ringA, int64_t ringB, double ax0, double ay0, double z00, double z10, double z01,
                       double z11);

    const HeightGrid& grid_;
    glm::dvec3 eye_;
    double toleranceM_ = 0.0;
    bool bilinear_ = true;
    double ringM_ = 0.0;
    double perRing_ = 0.0;  // 1 / ringM_
    int64_t rings_ = 0;
    std::vector<Level> levels_;
};

}  // namespace terracast
