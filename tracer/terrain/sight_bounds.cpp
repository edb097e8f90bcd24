#include "tracer/terrain/sight_bounds.h"

#include "heightfield/large_buffer.h"
#include "tracer/core/parallel.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace terracast {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Relative margin by which intervals of columns and of keys are widened against rounding.
constexpr double kEps = 1e-9;
// Level 0 holds rings [0, 8); level k >= 1 rings [8 * 2^(k-1), 8 * 2^k).
constexpr int64_t kFirstRings = 8;
// Cells nearer than kFinerRings rings are bounded from above by kSplit x kSplit sub-squares each (bilinear
// surface). The sub-squares' corners are computed in double from float corners: their rounding is far below
// the tolerance, which is doubled there all the same.
constexpr double kFinerRings = 2.0;
constexpr int kSplit = 16;
constexpr double kSubTolerance = 2.0;
// Rings are kRingCells cells wide. Level 0 has kWedges0 wedges, level k kWedges0 * 2^k but never fewer than
// kLeastWedges (near the eye the surface's slope changes with direction faster than with distance); both are
// powers of two, so that each wedge of a level lies within one wedge of the level below. A key step of 1 / W
// turns the direction by at most 8 / W radians (the key changes half as fast with angle on the diagonals as
// on the axes), so at the far end of level k, 8 * 2^k rings out, a wedge is at most 64 / kWedges0 rings wide.
// These were chosen on the White Mountains tile at 90 and 30 m from a summit and a valley (docs/maps.md):
// narrower rings and wedges settle more lines but cost more to build than they save.
constexpr double kRingCells = 4.0;
// From this many rings out, blocks of 2 x 2 cells are bounded as one (8: 0.1 s less than none on the 30 m
// summit run of docs/maps.md; 4 and 16 no better).
constexpr double kBlockRings = 8.0;
constexpr int64_t kWedges0 = 32;
constexpr int64_t kLeastWedges = 256;

int64_t wedgesAt(int64_t k) { return std::max(kLeastWedges, kWedges0 << k); }

// The nearest and farthest |t| over [a0, a1].
struct Span {
    double nearM, farM;
};
Span spanOf(double a0, double a1) { return {a0 > 0.0 ? a0 : a1 < 0.0 ? -a1 : 0.0, std::max(std::abs(a0), std::abs(a1))}; }

// The nearest and farthest horizontal distance from the eye of a box with spans x and y, rounded outwards so that
// the box is never placed in a ring it does not reach.
Span distancesOf(Span x, Span y) {
    return {std::sqrt(x.nearM * x.nearM + y.nearM * y.nearM) * (1.0 - 1e-12),
            std::sqrt(x.farM * x.farM + y.farM * y.farM) * (1.0 + 1e-12)};
}

// A float at least (at most) v: float(v) moved outwards by more than its rounding.
float roundUp(double v) { return std::isfinite(v) ? float(v + std::abs(v) * 0x1p-22 + 1e-30) : float(v); }
float roundDown(double v) { return std::isfinite(v) ? float(v - std::abs(v) * 0x1p-22 - 1e-30) : float(v); }

int64_t levelCount(int64_t rings) {
    return rings <= kFirstRings ? 1 : int64_t(std::bit_width(uint64_t((rings - 1) >> 3))) + 1;
}
int64_t levelFirstRing(int64_t k) { return k == 0 ? 0 : kFirstRings << (k - 1); }

double farthestCornerM(const HeightGrid& g, double ex, double ey) {
    const double fx = std::max(std::abs(ex), std::abs(g.extentXM() - ex));
    const double fy = std::max(std::abs(ey), std::abs(g.extentYM() - ey));
    return std::hypot(fx, fy);
}

}  // namespace

double SightBounds::bytesFor(const HeightGrid& g, double eyeXM, double eyeYM) {
    const double ringM = kRingCells * std::min(g.cellSizeXM(), g.cellSizeYM());
    const int64_t rings = int64_t(farthestCornerM(g, eyeXM, eyeYM) / ringM) + 1;
    double entries = 0.0;
    for (int64_t k = 0, n = levelCount(rings); k < n; ++k) {
        const int64_t a = levelFirstRing(k), b = std::min(rings, k + 1 < n ? levelFirstRing(k + 1) : rings);
        entries += double(b - a) * double(wedgesAt(k));
    }
    return 3.0 * sizeof(float) * entries;  // both tables, and the upper one again while it is turned
}

SightBounds::SightBounds(const HeightGrid& grid, const glm::dvec3& eye, double toleranceM, bool bilinear, int threads)
    : grid_(grid), eye_(eye), toleranceM_(toleranceM), bilinear_(bilinear) {
    ringM_ = kRingCells * std::min(grid.cellSizeXM(), grid.cellSizeYM());
    perRing_ = 1.0 / ringM_;
    rings_ = int64_t(farthestCornerM(grid, eye.x, eye.y) / ringM_) + 1;
    const int64_t n = levelCount(rings_);
    levels_.resize(size_t(n));
    for (int64_t k = 0; k < n; ++k) {
        Level& l = levels_[size_t(k)];
        l.ring0 = levelFirstRing(k);
        l.rings = std::min(rings_, k + 1 < n ? levelFirstRing(k + 1) : rings_) - l.ring0;
        l.wedges = wedgesAt(k);
        l.highest = largeVector<float>(size_t(l.rings * l.wedges), -std::numeric_limits<float>::infinity());
        l.lowest = largeVector<float>(size_t(l.rings * l.wedges), std::numeric_limits<float>::infinity());
    }
    // Annuli of about equal area, each filled by one task: a task writes its own rings only.
    const int64_t chunks = std::min<int64_t>(rings_, 64);
    std::vector<int64_t> edge(size_t(chunks) + 1);
    for (int64_t c = 0; c <= chunks; ++c)
        edge[size_t(c)] = std::min(rings_, int64_t(std::ceil(double(rings_) * std::sqrt(double(c) / double(chunks)))));
    edge.back() = rings_;
    parallelForTiles(1, int(chunks), 1, threads, [&](int, int c0, int, int c1) {
        for (int c = c0; c < c1; ++c)
            if (edge[size_t(c)] < edge[size_t(c) + 1]) addCells(edge[size_t(c)], edge[size_t(c) + 1]);
    });
    runningMaxima();
}

void SightBounds::addCells(int64_t ringA, int64_t ringB) {
    const HeightGrid& g = grid_;
    const double cx = g.cellSizeXM(), cy = g.cellSizeYM();
    const double ex = eye_.x, ey = eye_.y, ez = eye_.z, tol = toleranceM_;
    const double inner = double(ringA) * ringM_, outer = double(ringB) * ringM_;
    // The keys and heights of two rows of vertices over the columns at hand.
    std::vector<double> keyLow, keyHigh;
    std::vector<float> zLow, zHigh;
    // Cells [ia, ib) of row j.
    const auto addRun = [&](int64_t j, int64_t ia, int64_t ib) {
        if (ia >= ib) return;
        const double ay0 = double(j) * cy - ey, ay1 = double(j + 1) * cy - ey;
        const Span y = spanOf(ay0, ay1);
        const size_t n = size_t(ib - ia) + 1;
        keyLow.resize(n);
        keyHigh.resize(n);
        zLow.resize(n);
        zHigh.resize(n);
        for (size_t k = 0; k < n; ++k) {
            const int64_t i = ia + int64_t(k);
            const double ax = double(i) * cx - ex;
            keyLow[k] = azimuthKey(ax, ay0);
            keyHigh[k] = azimuthKey(ax, ay1);
            zLow[k] = g.at(i, j);
            zHigh[k] = g.at(i, j + 1);
        }
        // A cell across the +x axis from the eye spans keys near 1 and near 0.
        const bool axisRow = ay0 <= 0.0 && ay1 >= 0.0;
        for (int64_t i = ia; i < ib; ++i) {
            const size_t k = size_t(i - ia);
            const double ax0 = double(i) * cx - ex, ax1 = double(i + 1) * cx - ex;
            const Span x = spanOf(ax0, ax1), d = distancesOf(x, y);
            const double minD = d.nearM, maxD = d.farM;
            const int64_t r0 = int64_t(minD / ringM_), r1 = std::min(rings_ - 1, int64_t(maxD / ringM_));
            if (r1 < ringA || r0 >= ringB) continue;
            // The slope range of the cell's surface, widened by the tolerance.
            double hi = kInf, lo = -kInf;
            const bool valid = g.wholeCellValid(i, j);
            if (valid) {
                const double z00 = zLow[k], z10 = zLow[k + 1], z01 = zHigh[k], z11 = zHigh[k + 1];
                const double zMax = std::max({z00, z10, z01, z11}), zMin = std::min({z00, z10, z01, z11});
                const double up = zMax + tol - ez, down = zMin - tol - ez;
                hi = up > 0.0 ? (minD > 0.0 ? up / minD : kInf) : up / maxD;
                lo = down >= 0.0 ? down / maxD : (minD > 0.0 ? down / minD : -kInf);
            }
            if (valid && bilinear_ && minD < kFinerRings * ringM_) {
                // Near the eye a whole cell's range is too coarse (its corner under the eye is far higher than
                // its far corners, and it spans many directions): its sub-squares bound it from above, each
                // placed on its own.
                placeNearCell(ringA, ringB, ax0, ay0, zLow[k], zLow[k + 1], zHigh[k], zHigh[k + 1]);
                hi = -kInf;
            }
            const double keys[4] = {keyLow[k], keyLow[k + 1], keyHigh[k], keyHigh[k + 1]};
            place(ringA, ringB, r0, r1, x.nearM == 0.0 && y.nearM == 0.0, axisRow && ax1 > 0.0, keys, valid, roundUp(hi),
                  roundDown(lo));
        }
    };
    // The columns of a band of rows [ya, yb) (metres from the eye) that reach rings [ringA, ringB): [i0, skip0)
    // and [skip1, i1). False when none does.
    const auto columns = [&](double ya, double yb, int64_t& i0, int64_t& i1, int64_t& skip0, int64_t& skip1) {
        const auto [nearY, farY] = spanOf(ya, yb);
        // A band is passed over only when all its cells start at `outer` or beyond, their nearest distance
        // rounded down as below.
        if (nearY * (1.0 - 1e-9) >= outer) return false;
        // Cells nearer than `outer`: an interval of columns around the eye.
        const double sOut = std::sqrt(std::max(0.0, outer * outer - nearY * nearY)) * (1.0 + kEps) + kEps;
        i0 = std::max<int64_t>(0, int64_t(std::floor((ex - sOut) / cx)) - 1);
        i1 = std::min<int64_t>(g.cellsX(), int64_t(std::ceil((ex + sOut) / cx)) + 1);
        // Cells entirely nearer than `inner` are skipped: an interval inside the first.
        skip0 = i1;
        skip1 = i1;
        if (farY < inner) {
            const double sIn = std::sqrt(inner * inner - farY * farY) * (1.0 - kEps) - kEps;
            if (sIn > 0.0) {
                skip0 = std::clamp<int64_t>(int64_t(std::ceil((ex - sIn) / cx)) + 1, i0, i1);
                skip1 = std::clamp<int64_t>(int64_t(std::floor((ex + sIn) / cx)) - 1, skip0, i1);
            }
        }
        return true;
    };
    // Far from the eye, blocks of 2 x 2 valid cells are bounded as one (their corners' range over their extent):
    // a quarter of the work, and bounds hardly looser where a block is a small part of its distance.
    const double blockFrom = kBlockRings * ringM_;
    const auto addBlocks = [&](int64_t j, int64_t ia, int64_t ib) {
        const double ay0 = double(j) * cy - ey, ay2 = double(j + 2) * cy - ey;
        const Span y = spanOf(ay0, ay2);
        const bool axisBand = ay0 <= 0.0 && ay2 >= 0.0;
        for (int64_t i = ia; i < ib; i += 2) {
            if (i + 2 > ib) {
                addRun(j, i, ib);
                addRun(j + 1, i, ib);
                break;
            }
            if (!g.wholeCellValid(i, j) || !g.wholeCellValid(i + 1, j) || !g.wholeCellValid(i, j + 1) ||
                !g.wholeCellValid(i + 1, j + 1)) {
                addRun(j, i, i + 2);
                addRun(j + 1, i, i + 2);
                continue;
            }
            const double ax0 = double(i) * cx - ex, ax2 = double(i + 2) * cx - ex;
            const Span d = distancesOf(spanOf(ax0, ax2), y);
            const double minD = d.nearM, maxD = d.farM;
            const int64_t r0 = int64_t(minD / ringM_), r1 = std::min(rings_ - 1, int64_t(maxD / ringM_));
            if (r1 < ringA || r0 >= ringB) continue;
            double zMax = -kInf, zMin = kInf;
            for (int64_t b = j; b <= j + 2; ++b)
                for (int64_t a = i; a <= i + 2; ++a) {
                    const double z = g.at(a, b);
                    zMax = std::max(zMax, z);
                    zMin = std::min(zMin, z);
                }
            const double up = zMax + tol - ez, down = zMin - tol - ez;
            const double hi = up > 0.0 ? up / minD : up / maxD;
            const double lo = down >= 0.0 ? down / maxD : down / minD;
            const double keys[4] = {azimuthKey(ax0, ay0), azimuthKey(ax2, ay0), azimuthKey(ax0, ay2), azimuthKey(ax2, ay2)};
            place(ringA, ringB, r0, r1, false, axisBand && ax2 > 0.0, keys, true, roundUp(hi), roundDown(lo));
        }
    };
    // The cells [ia, ib) of rows j and j + 1: near the eye one by one, beyond blockFrom by blocks.
    const auto addPair = [&](int64_t j, int64_t ia, int64_t ib) {
        if (ia >= ib) return;
        const double ay0 = double(j) * cy - ey, ay2 = double(j + 2) * cy - ey;
        const double nearY = spanOf(ay0, ay2).nearM;
        // Blocks wholly farther than blockFrom: beyond [n0, n1) (all columns when the band is).
        int64_t n0 = ia, n1 = ia;
        if (nearY < blockFrom) {
            const double xNear = std::sqrt(blockFrom * blockFrom - nearY * nearY);
            n0 = std::clamp<int64_t>(int64_t(std::floor((ex - xNear) / cx)) - 1, ia, ib) & ~int64_t(1);
            n1 = std::clamp<int64_t>((int64_t(std::ceil((ex + xNear) / cx)) + 2) & ~int64_t(1), n0, ib);
            n0 = std::max(n0, ia);
        }
        addBlocks(j, ia, n0);
        addRun(j, n0, n1);
        addRun(j + 1, n0, n1);
        addBlocks(j, n1, ib);
    };
    // Every task must cut the cells into the same blocks, so that the task holding a block's nearest ring
    // places its upper bound: blocks start at even columns of even rows whatever the task's columns are.
    const auto even = [](int64_t i) { return i & ~int64_t(1); };
    int64_t i0 = 0, i1 = 0, skip0 = 0, skip1 = 0;
    int64_t j = 0;
    for (; j + 1 < g.cellsY(); j += 2)
        if (columns(double(j) * cy - ey, double(j + 2) * cy - ey, i0, i1, skip0, skip1)) {
            i0 = even(i0);
            i1 = std::min(g.cellsX(), even(i1 + 1));
            skip0 = std::min(even(skip0 + 1), i1);
            skip1 = std::max(even(skip1), skip0);
            addPair(j, i0, skip0);
            addPair(j, skip1, i1);
        }
    if (j < g.cellsY() && columns(double(j) * cy - ey, double(j + 1) * cy - ey, i0, i1, skip0, skip1)) {
        addRun(j, i0, skip0);
        addRun(j, skip1, i1);
    }
}

void SightBounds::place(int64_t ringA, int64_t ringB, int64_t r0, int64_t r1, bool all, bool wraps,
                        const double keys[4], bool withHigh, float hi, float lo) {
    if (r0 == r1 && !all && !wraps && r0 >= ringA && r0 < ringB) {
        // The common case, a cell within one ring away from the +x axis.
        Level& l = levels_[size_t(levelOfRing(r0))];
        const double k0 = std::min(std::min(keys[0], keys[1]), std::min(keys[2], keys[3])) - kEps;
        const double k1 = std::max(std::max(keys[0], keys[1]), std::max(keys[2], keys[3])) + kEps;
        const double wedges = double(l.wedges);
        const int64_t w0 = int64_t(std::floor(k0 * wedges)), w1 = int64_t(std::floor(k1 * wedges));
        if (w0 >= 0 && w1 < l.wedges) {
            float* hiRow = l.highest.data() + (r0 - l.ring0) * l.wedges;
            float* loRow = l.lowest.data() + (r0 - l.ring0) * l.wedges;
            for (int64_t w = w0; w <= w1; ++w) {
                if (withHigh) hiRow[w] = std::max(hiRow[w], hi);
                loRow[w] = std::min(loRow[w], lo);
            }
            return;
        }
    }
    // The directions spanned, as keys; across the +x axis from the eye they run from near 1 to near 0.
    double k0 = 0.0, k1 = 1.0;
    if (!all) {
        k0 = kInf;
        k1 = -kInf;
        for (int c = 0; c < 4; ++c) {
            const double q = wraps && keys[c] > 0.5 ? keys[c] - 1.0 : keys[c];
            k0 = std::min(k0, q);
            k1 = std::max(k1, q);
        }
        k0 -= kEps;
        k1 += kEps;
    }
    int level = -1;
    int64_t w0 = 0, w1 = 0, wedges = 0;
    for (int64_t r = std::max(r0, ringA); r <= std::min(r1, ringB - 1); ++r) {
        if (levelOfRing(r) != level) {
            level = levelOfRing(r);
            wedges = levels_[size_t(level)].wedges;
            w0 = int64_t(std::floor(k0 * double(wedges)));
            w1 = int64_t(std::floor(k1 * double(wedges)));
            if (all || w1 - w0 >= wedges - 1) {
                w0 = 0;
                w1 = wedges - 1;
            }
        }
        Level& l = levels_[size_t(level)];
        float* hiRow = l.highest.data() + (r - l.ring0) * wedges;
        float* loRow = l.lowest.data() + (r - l.ring0) * wedges;
        for (int64_t w = w0; w <= w1; ++w) {
            const int64_t c = w < 0 ? w + wedges : w >= wedges ? w - wedges : w;
            if (withHigh && r == r0) hiRow[c] = std::max(hiRow[c], hi);
            loRow[c] = std::min(loRow[c], lo);
        }
    }
}

void SightBounds::placeNearCell(int64_t ringA, int64_t ringB, double ax0, double ay0, double z00, double z10,
                                double z01, double z11) {
    // The bilinear patch over each sub-square lies within the sub-square's own corners.
    const double cx = grid_.cellSizeXM(), cy = grid_.cellSizeYM(), ez = eye_.z;
    const auto z = [&](double u, double v) { return (z00 * (1.0 - u) + z10 * u) * (1.0 - v) + (z01 * (1.0 - u) + z11 * u) * v; };
    for (int b = 0; b < kSplit; ++b)
        for (int a = 0; a < kSplit; ++a) {
            const double u0 = double(a) / kSplit, u1 = double(a + 1) / kSplit;
            const double v0 = double(b) / kSplit, v1 = double(b + 1) / kSplit;
            const double top = std::max({z(u0, v0), z(u1, v0), z(u0, v1), z(u1, v1)});
            const double bx0 = ax0 + u0 * cx, bx1 = ax0 + u1 * cx, by0 = ay0 + v0 * cy, by1 = ay0 + v1 * cy;
            const Span x = spanOf(bx0, bx1), y = spanOf(by0, by1), d = distancesOf(x, y);
            const double minD = d.nearM, maxD = d.farM;
            const int64_t r0 = int64_t(minD / ringM_);
            if (r0 < ringA || r0 >= ringB) continue;  // its upper bound goes to ring r0 only
            const double up = top + kSubTolerance * toleranceM_ - ez;
            const double hi = up > 0.0 ? (minD > 0.0 ? up / minD : kInf) : up / maxD;
            const double keys[4] = {azimuthKey(bx0, by0), azimuthKey(bx1, by0), azimuthKey(bx0, by1), azimuthKey(bx1, by1)};
            place(ringA, ringB, r0, r0, x.nearM == 0.0 && y.nearM == 0.0, bx1 > 0.0 && by0 <= 0.0 && by1 >= 0.0, keys, true,
                  roundUp(hi), std::numeric_limits<float>::infinity());
        }
}

void SightBounds::runningMaxima() {
    // Filled ring by ring ([ring][wedge]: a row of cells meets neighbouring wedges), the running maxima taken
    // outwards ring by ring; then the upper bounds turned to [wedge][ring], where clearBefore searches.
    const float unknown = -std::numeric_limits<float>::infinity();
    for (size_t k = 0; k < levels_.size(); ++k) {
        Level& l = levels_[k];
        const Level* parent = k > 0 ? &levels_[k - 1] : nullptr;
        for (int64_t r = 0; r < l.rings; ++r) {
            float* hi = l.highest.data() + r * l.wedges;
            float* lo = l.lowest.data() + r * l.wedges;
            // A region no cell reached has no bound from below.
            for (int64_t w = 0; w < l.wedges; ++w)
                if (lo[w] == std::numeric_limits<float>::infinity()) lo[w] = unknown;
            if (r > 0) {
                for (int64_t w = 0; w < l.wedges; ++w) {
                    hi[w] = std::max(hi[w], hi[w - l.wedges]);
                    lo[w] = std::max(lo[w], lo[w - l.wedges]);
                }
            } else if (parent) {
                // The previous level's last ring, whose wedges each hold two of these.
                const float* loLast = parent->lowest.data() + (parent->rings - 1) * parent->wedges;
                const int shift = parent->wedges == l.wedges ? 0 : 1;
                for (int64_t w = 0; w < l.wedges; ++w) {
                    hi[w] = std::max(hi[w], parent->highest[size_t((w >> shift) * parent->rings + parent->rings - 1)]);
                    lo[w] = std::max(lo[w], loLast[w >> shift]);
                }
            }
        }
        // This level's upper bounds by wedge (its parent, already turned, was read that way above).
        std::vector<float> byWedge = largeVector<float>(l.highest.size());
        constexpr int64_t kBlock = 64;
        for (int64_t r0 = 0; r0 < l.rings; r0 += kBlock)
            for (int64_t w0 = 0; w0 < l.wedges; w0 += kBlock)
                for (int64_t r = r0; r < std::min(l.rings, r0 + kBlock); ++r)
                    for (int64_t w = w0; w < std::min(l.wedges, w0 + kBlock); ++w)
                        byWedge[size_t(w * l.rings + r)] = l.highest[size_t(r * l.wedges + w)];
        l.highest = std::move(byWedge);
    }
}

double SightBounds::clearBefore(double key, double slope) const {
    for (const Level& l : levels_) {
        const int64_t w = std::min(l.wedges - 1, int64_t(key * double(l.wedges)));
        const float* column = l.highest.data() + w * l.rings;
        if (!(column[l.rings - 1] < slope)) {
            // The first ring whose running maximum reaches the line's slope: the cells that start before it
            // are all below the line.
            const float* first = std::partition_point(column, column + l.rings, [slope](float v) { return v < slope; });
            return double(l.ring0 + (first - column)) * ringM_;
        }
    }
    return kInf;
}

}  // namespace terracast
