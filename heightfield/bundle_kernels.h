// The bundle kernels: the proof that a bundle of rays from one origin clears the terrain up to a distance, and
// the bundle trace built on it. Not a header of its own: traversal.cpp includes it right after
// traversal_kernels.h, inside the same two namespaces (baseline and AVX2), and it uses that file's walk and
// trace; it therefore includes nothing and holds no pragma once.

// A horizontal distance R (metres) from `origin` such that every ray of `rays` (all leaving `origin`, none
// vertical) passes above every cell, by more than the margin trace skips cells with, at each point whose
// horizontal distance from the origin is below R. Proved with the pyramid on whole stretches [r, r + step) at
// once: over such a stretch no ray lies lower than origin.z + sMin * r or origin.z + sMin * (r + step), sMin
// being the bundle's lowest slope (rise per horizontal metre), and every ray's footprint lies in the box
// that the extreme unit horizontal directions span between the two distances. The stretch is proved when the
// blocks covering that box all lie below that height; the step doubles after a proof and halves after a
// failure, down to half a cell.
double bundleFreeDistanceM(const HeightGrid& g, const glm::dvec3& origin, std::span<const Ray> rays) {
    const int levels = g.pyramidLevels();
    if (levels == 0 || rays.empty()) return 0.0;
    double sMin = kInfinity;
    glm::dvec2 uLo{kInfinity}, uHi{-kInfinity};
    for (const Ray& r : rays) {
        const double h = std::sqrt(r.dir.x * r.dir.x + r.dir.y * r.dir.y);
        const glm::dvec2 u{r.dir.x / h, r.dir.y / h};
        sMin = std::min(sMin, r.dir.z / h);
        uLo = glm::min(uLo, u);
        uHi = glm::max(uHi, u);
    }
    if (!std::isfinite(sMin + uLo.x + uLo.y + uHi.x + uHi.y)) return 0.0;

    // The slack covers, with room to spare, everything trace's own cell and block tests allow for: its skip
    // margin at float precision (the widest of the methods) or the grazing tolerance, one pyramid code step,
    // the rounding of decoded heights and that of the rays' heights (added per stretch below).
    const double heightScale = std::max(std::abs(g.minHeightM()), std::abs(g.maxHeightM()));
    const double floatEps = double(std::numeric_limits<float>::epsilon());
    const double margin = std::max(cellSkipMargin(floatEps, heightScale, origin.z), grazingToleranceM(g));
    const HeightGrid::PyramidView pyramid = g.pyramidView();
    const double slack = 2.0 * margin + pyramid.scale + 0x1p-20 * (heightScale + pyramid.scale);

    const double cellM = std::min(g.cellSizeXM(), g.cellSizeYM());
    const double extentX = g.extentXM(), extentY = g.extentYM();
    const double farX = std::max(std::abs(origin.x), std::abs(origin.x - extentX));
    const double farY = std::max(std::abs(origin.y), std::abs(origin.y - extentY));
    const double rEnd = std::hypot(farX, farY) + 2.0 * cellM;
    const int64_t cellsX = g.cellsX(), cellsY = g.cellsY();

    // True when every block covering the cells under the box [lo, hi] (metres) lies below zLimit. The box is
    // widened by a sixteenth of a cell, far more than the rounding of its corners and of the rays' own cell
    // coordinates, so a point on a cell boundary counts in both cells. The blocks are taken at the finest level
    // on which the cells span at most three blocks per axis.
    auto blocksBelow = [&](glm::dvec2 lo, glm::dvec2 hi, double zLimit) {
        auto cellRange = [](double a, double b, double perMetre, int64_t cells, int64_t& c0, int64_t& c1) {
            const double x0 = a * perMetre, x1 = b * perMetre;
            const double pad = 0x1p-4 + 0x1p-40 * std::max(std::abs(x0), std::abs(x1));
            const double last = double(cells - 1);
            if (!(x1 + pad >= 0.0 && x0 - pad < double(cells))) return false;
            c0 = static_cast<int64_t>(std::clamp(x0 - pad, 0.0, last));
            c1 = static_cast<int64_t>(std::clamp(x1 + pad, 0.0, last));
            return true;
        };
        int64_t cx0 = 0, cx1 = 0, cy0 = 0, cy1 = 0;
        if (!cellRange(lo.x, hi.x, g.cellsPerMetreX(), cellsX, cx0, cx1) ||
            !cellRange(lo.y, hi.y, g.cellsPerMetreY(), cellsY, cy0, cy1))
            return true;  // no cell under the box
        int k = 1;
        while (k < levels && (((cx1 >> k) - (cx0 >> k)) > 2 || ((cy1 >> k) - (cy0 >> k)) > 2)) ++k;
        for (int64_t bj = cy0 >> k; bj <= (cy1 >> k); ++bj)
            for (int64_t bi = cx0 >> k; bi <= (cx1 >> k); ++bi)
                if (!((TERRACAST_TILED_KERNELS ? g.blockMaxM(k, bi, bj) : pyramid.blockMaxM(k, bi, bj)) < zLimit))
                    return false;
        return true;
    };

    // Nothing is met before the footprint reaches the grid's rectangle, nor while every ray is still above
    // the highest block; the proof starts there (both distances are lowered past their rounding).
    const glm::dvec2 o{origin.x, origin.y};
    const double outsideX = std::max({0.0, -origin.x, origin.x - extentX});
    const double outsideY = std::max({0.0, -origin.y, origin.y - extentY});
    double r = std::max(0.0, std::sqrt(outsideX * outsideX + outsideY * outsideY) - 2.0 * cellM);
    const double topClearance = origin.z - (double(g.maxHeightM()) + 2.0 * slack) - 0x1p-40 * std::abs(origin.z);
    if (sMin < 0.0 && topClearance > 0.0) r = std::max(r, topClearance / -sMin * (1.0 - 0x1p-30));
    double step = 16.0 * cellM;
    for (int guard = 0; r < rEnd && guard < 256; ++guard) {
        const double rb = r + step;
        const double zLow = origin.z + std::min(sMin * r, sMin * rb);
        const double zLimit = zLow - slack - 0x1p-40 * (std::abs(origin.z) + std::abs(sMin) * rb);
        const bool free = zLimit > g.maxHeightM() ||
                          blocksBelow(o + glm::min(r * uLo, rb * uLo), o + glm::max(r * uHi, rb * uHi), zLimit);
        if (free) {
            r = rb;
            step *= 2.0;
        } else if (step <= 0.5 * cellM) {
            break;
        } else {
            step *= 0.5;
        }
    }
    return r;
}


// intersectBundle's work (see traversal.h).
void traceBundle(const HeightGrid& grid, std::span<const Ray> rays, Interval interval, CellMethod method,
                 std::span<std::optional<HeightFieldHit>> hits, TraceCounters* counters, Traversal traversal) {
    const size_t n = std::min(rays.size(), hits.size());
    if (n == 0) return;
    const glm::dvec3 origin = rays[0].origin;
    bool sameOrigin = true, noneVertical = true;
    for (size_t k = 0; k < n; ++k) {
        sameOrigin = sameOrigin && rays[k].origin == origin;
        noneVertical = noneVertical && (rays[k].dir.x != 0.0 || rays[k].dir.y != 0.0);
    }
    const bool shared = traversal == Traversal::Pyramid && n > 1 && sameOrigin && noneVertical;
    // The proof covers the rays ahead of the origin only: an interval reaching behind it walks from its start.
    const double freeM = shared && interval.lo >= 0.0 ? bundleFreeDistanceM(grid, origin, rays.first(n)) : 0.0;
    // Rays from a shared origin are first tested against the grid's box, relative to that origin, widened by a
    // cell on each side, by ten times the vertical padding trace clips with, and by 2^-30 of the origin's
    // magnitude: far more than this test's rounding. A ray that misses it has no hit, and trace would have
    // walked nothing and counted nothing; camera rays towards the sky or past the grid's sides cost a few
    // products instead of trace's setup. A NaN bound never rejects; rays this test rejects for infinite values
    // trace rejects too.
    const double padM = 0x1p-30 * (std::abs(origin.x) + std::abs(origin.y) + std::abs(origin.z));
    const double zPadM = 10.0 * zSlabPadM(grid) + padM;
    const glm::dvec3 boxLo =
        glm::dvec3(-grid.cellSizeXM() - padM, -grid.cellSizeYM() - padM, double(grid.minHeightM()) - zPadM) - origin;
    const glm::dvec3 boxHi = glm::dvec3(grid.extentXM() + grid.cellSizeXM() + padM,
                                        grid.extentYM() + grid.cellSizeYM() + padM,
                                        double(grid.maxHeightM()) + zPadM) - origin;
    auto missesBox = [&](const glm::dvec3& d) {
        const glm::dvec3 inv = 1.0 / d;
        const glm::dvec3 a = boxLo * inv, b = boxHi * inv;
        const double ta = std::max({interval.lo, std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)});
        const double tb = std::min({interval.hi, std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)});
        return ta > tb;
    };
    const bool traced = withMethod(grid, method, [&]<class Real, Shape shape>(const auto& at) {
        for (size_t k = 0; k < n; ++k) {
            const glm::dvec3& d = rays[k].dir;
            if (sameOrigin && missesBox(d)) {
                hits[k].reset();
                continue;
            }
            // The parameter where ray k reaches the horizontal distance freeM, lowered past its rounding.
            const double freeUntil =
                freeM > 0.0 ? freeM / std::sqrt(d.x * d.x + d.y * d.y) * (1.0 - 0x1p-40) : -kInfinity;
            // Constructed in place (optional<HeightFieldHit> is trivially destructible), so storing the hit does
            // not first branch on whatever the slot held.
            std::construct_at(&hits[k], std::in_place);
            if (!traceSign<Real, shape>(grid, at, rays[k], interval, false, counters, traversal, &*hits[k],
                                        freeUntil))
                hits[k].reset();
        }
        return true;
    });
    if (!traced)  // not a method: no hits, as intersect gives
        for (size_t k = 0; k < n; ++k) hits[k].reset();
}

