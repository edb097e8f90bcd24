#include "tracer/sampling/samplers.h"

#include "tracer/sampling/rng.h"
#include "tracer/sampling/warps.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace terracast {

namespace {

constexpr std::pair<SamplePattern, const char*> kPatternNames[] = {
    {SamplePattern::Regular, "regular"},
    {SamplePattern::Random, "random"},
    {SamplePattern::Stratified, "stratified"},
    {SamplePattern::Poisson, "poisson"},
    {SamplePattern::BestCandidate, "best-candidate"},
};

// Sample indices no real sample uses, counting down from the top: the pixel-level values of each round of N
// samples (shifts, permutation keys) live there.
constexpr uint64_t kPixelLevelIndex = ~0ull;
// Stream dimensions of the per-pixel values, in blocks of four per sample dimension.
constexpr uint64_t kShiftDimension = 0;   // + 4 d: the Cranley-Patterson shift (two values)
constexpr uint64_t kOrderDimension = 2;   // + 4 d: the key of the visiting order
// 1D dimensions are keyed apart from the 2D ones, in the per-sample and in the pixel-level streams.
constexpr uint64_t kOneDimensionalKey = 0x1d1d1d1dull << 32;

void requirePositive(int n, const char* what) {
    if (n < 1) throw std::invalid_argument(std::string(what) + ": the sample count must be at least 1, found " +
                                           std::to_string(n));
}

// x mod 1 in [0, 1), also for x slightly below 0 or at 1 after a shift.
double wrapUnit(double x) {
    const double w = x - std::floor(x);
    return w < 1.0 ? w : 0.0;
}

// Difference a - b in the torus [0, 1): the shortest of the wrapped differences, in [-0.5, 0.5].
double torusDelta(double a, double b) {
    const double d = a - b;
    return d - std::round(d);
}

// ---- Nearest-point grid ----------------------------------------------------------------------------------
// Points in a cube split into side^D cells; the nearest stored point to a query is found by visiting rings of
// cells (Chebyshev distance s = 0, 1, 2, ... from the query's cell) until the next ring cannot hold anything
// closer than the best found. With about one point per cell that is O(1) cells per query.
template <int D>
class NearestGrid {
public:
    using Vec = glm::vec<D, double>;

    NearestGrid(Vec lo, double extent, int side, bool periodic)
        : lo_(lo), extent_(extent), side_(std::max(1, side)), periodic_(periodic) {
        size_t cells = 1;
        for (int a = 0; a < D; ++a) cells *= size_t(side_);
        cells_.resize(cells);
    }

    void insert(const Vec& p) { cells_[cellIndex(cellOf(p))].push_back(p); }

    // Squared distance from q to the nearest stored point (infinity when empty). Stops early, returning a
    // value below `enough2`, as soon as a point that close is found: the caller only needs to know that.
    double nearest2(const Vec& q, double enough2) const {
        const glm::vec<D, int> home = cellOf(q);
        const double cell = extent_ / side_;
        const int lastRing = periodic_ ? side_ / 2 : side_ - 1;
        double best2 = std::numeric_limits<double>::infinity();
        for (int s = 0; s <= lastRing; ++s) {
            visitRing(home, s, [&](const std::vector<Vec>& points) {
                for (const Vec& p : points) best2 = std::min(best2, distance2(p, q));
            });
            if (best2 < enough2) return best2;
            // Any cell of ring s + 1 is at least s whole cells away from q along some axis.
            const double bound = double(s) * cell;
            if (best2 <= bound * bound) break;
        }
        return best2;
    }

private:
    glm::vec<D, int> cellOf(const Vec& p) const {
        glm::vec<D, int> c;
        for (int a = 0; a < D; ++a)
            c[a] = std::clamp(int(std::floor((p[a] - lo_[a]) / extent_ * side_)), 0, side_ - 1);
        return c;
    }
    size_t cellIndex(const glm::vec<D, int>& c) const {
        size_t k = 0;
        for (int a = D - 1; a >= 0; --a) k = k * size_t(side_) + size_t(c[a]);
        return k;
    }
    double distance2(const Vec& p, const Vec& q) const {
        double d2 = 0.0;
        for (int a = 0; a < D; ++a) {
            const double d = periodic_ ? torusDelta(p[a] / extent_, q[a] / extent_) * extent_ : p[a] - q[a];
            d2 += d * d;
        }
        return d2;
    }
    // Calls f(points) for every cell whose largest per-axis offset from `home` is exactly s.
    template <class F>
    void visitRing(const glm::vec<D, int>& home, int s, F&& f) const {
        glm::vec<D, int> off(-s);
        while (true) {
            int chebyshev = 0;
            for (int a = 0; a < D; ++a) chebyshev = std::max(chebyshev, std::abs(off[a]));
            if (chebyshev == s) {
                glm::vec<D, int> c = home + off;
                bool inside = true;
                for (int a = 0; a < D; ++a) {
                    if (periodic_) c[a] = ((c[a] % side_) + side_) % side_;
                    else inside = inside && c[a] >= 0 && c[a] < side_;
                }
                if (inside) f(cells_[cellIndex(c)]);
            }
            int a = 0;
            while (a < D && off[a] == s) off[a++] = -s;
            if (a == D) return;
            ++off[a];
        }
    }

    Vec lo_;
    double extent_;
    int side_;
    bool periodic_;
    std::vector<std::vector<Vec>> cells_;
};

// Mitchell's loop: point i is the best of quality * i candidates, the one farthest from the points so far.
// Candidates that come closer to a placed point than the best candidate's distance are dropped as soon as
// that is known.
template <int D, class Draw>
std::vector<glm::vec<D, double>> bestCandidate(int n, int quality, NearestGrid<D>& grid, Draw&& draw) {
    std::vector<glm::vec<D, double>> points;
    points.reserve(size_t(n));
    for (int i = 0; i < n; ++i) {
        glm::vec<D, double> best = draw();
        double best2 = -1.0;
        const int candidates = std::max(1, quality * i);
        for (int c = 0; c < candidates && i > 0; ++c) {
            const glm::vec<D, double> q = c == 0 ? best : draw();
            const double d2 = grid.nearest2(q, best2);
            if (d2 > best2) {
                best2 = d2;
                best = q;
            }
        }
        grid.insert(best);
        points.push_back(best);
    }
    return points;
}

// A point uniform by area in the annulus 1/2 <= |p| < 1, by rejection from the square [-1, 1)^2 (59 % of
// draws land in it): cheaper than a square root, a sine and a cosine per point.
glm::dvec2 annulusPoint(RandomStream& stream) {
    while (true) {
        const glm::dvec2 p = 2.0 * stream.next2() - 1.0;
        const double d2 = glm::dot(p, p);
        if (d2 >= 0.25 && d2 < 1.0) return p;
    }
}

// Point k of a jittered pattern, from its stratum and a jitter in [0, 1)^2.
glm::dvec2 stratifiedPoint(int k, StrataLayout layout, glm::dvec2 jitter) {
    const int column = k % layout.columns, row = k / layout.columns;
    return {(column + jitter.x) / layout.columns, (row + jitter.y) / layout.rows};
}

glm::dvec2 regularPoint(int k, int side) {
    return {(k % side + 0.5) / side, (k / side + 0.5) / side};
}

}  // namespace

std::span<const SamplePattern> samplePatterns() {
    static constexpr SamplePattern kAll[] = {SamplePattern::Regular, SamplePattern::Random, SamplePattern::Stratified,
                                             SamplePattern::Poisson, SamplePattern::BestCandidate};
    static_assert(std::size(kAll) == std::size(kPatternNames));
    return kAll;
}

std::optional<SamplePattern> parseSamplePattern(std::string_view name) {
    for (const auto& [pattern, text] : kPatternNames)
        if (name == text) return pattern;
    return std::nullopt;
}

const char* samplePatternName(SamplePattern pattern) {
    for (const auto& [p, text] : kPatternNames)
        if (p == pattern) return text;
    return "unknown";
}

const char* samplePatternList() {
    static const std::string list = [] {
        std::string s;
        for (const auto& [pattern, text] : kPatternNames) s += (s.empty() ? "" : ", ") + std::string(text);
        return s;
    }();
    return list.c_str();
}

// ---- Regular, random, stratified ---------------------------------------------------------------------------

int regularGridSide(int n) { return std::max(1, int(std::lround(std::sqrt(double(std::max(n, 0)))))); }

std::vector<glm::dvec2> regularPattern(int n) {
    const int side = regularGridSide(n);
    std::vector<glm::dvec2> points(size_t(side) * size_t(side));
    for (int k = 0; k < side * side; ++k) points[size_t(k)] = regularPoint(k, side);
    return points;
}

std::vector<glm::dvec2> randomPattern(int n, uint64_t seed) {
    RandomStream stream(seed);
    std::vector<glm::dvec2> points(size_t(std::max(n, 0)));
    for (auto& p : points) p = stream.next2();
    return points;
}

StrataLayout strataLayout(int n) {
    requirePositive(n, "stratified pattern");
    int rows = int(std::sqrt(double(n)));
    while (rows * rows > n) --rows;
    while (n % rows != 0) --rows;
    return {n / rows, rows};
}

std::vector<glm::dvec2> stratifiedPattern(int n, uint64_t seed) {
    const StrataLayout layout = strataLayout(n);
    RandomStream stream(seed);
    std::vector<glm::dvec2> points(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) points[size_t(k)] = stratifiedPoint(k, layout, stream.next2());
    return points;
}

// ---- Poisson disk --------------------------------------------------------------------------------------------

std::vector<glm::dvec2> poissonDiskPattern(const PoissonDiskOptions& o) {
    if (!(o.radius > 0.0 && o.radius <= 0.5))
        throw std::invalid_argument("Poisson disk radius must be in (0, 0.5], found " + std::to_string(o.radius));
    const double r = o.radius, r2 = r * r;
    // Cells at most r / sqrt(2) wide, so a cell's diagonal is below r and it can hold one point only; an
    // integer number of cells per side, so the toroidal grid wraps exactly.
    const int side = int(std::ceil(std::sqrt(2.0) / r));
    const double cell = 1.0 / side;
    const int reach = int(std::ceil(r / cell));  // cells to search each way for a neighbour within r
    std::vector<int32_t> grid(size_t(side) * size_t(side), -1);
    const auto cellOf = [&](double x) { return std::min(int(x * side), side - 1); };

    std::vector<glm::dvec2> points;
    std::vector<int32_t> active;
    RandomStream stream(o.seed, 0, 0, 0x9015504ull);

    // The neighbouring cells' rows and columns, wrapped in the torus; -1 outside the open square.
    std::vector<int> columns(size_t(2 * reach + 1)), rows(size_t(2 * reach + 1));
    const auto neighbours = [&](int c, std::vector<int>& out) {
        for (int d = -reach; d <= reach; ++d) {
            int g = c + d;
            if (o.toroidal) g = g < 0 ? g + side : g >= side ? g - side : g;
            else if (g < 0 || g >= side) g = -1;
            out[size_t(d + reach)] = g;
        }
    };
    const auto conflicts = [&](int32_t k, glm::dvec2 q) {
        if (k < 0) return false;
        const glm::dvec2 p = points[size_t(k)];
        const glm::dvec2 d = o.toroidal ? glm::dvec2(torusDelta(p.x, q.x), torusDelta(p.y, q.y)) : p - q;
        return glm::dot(d, d) < r2;
    };
    const auto farEnough = [&](glm::dvec2 q) {
        const int cx = cellOf(q.x), cy = cellOf(q.y);
        // The candidate's own cell first: when a point sits there (the usual way to fail), nothing else is read.
        if (grid[size_t(cy) * size_t(side) + size_t(cx)] >= 0) return false;
        neighbours(cx, columns);
        neighbours(cy, rows);
        for (int gy : rows) {
            if (gy < 0) continue;
            for (int gx : columns)
                if (gx >= 0 && conflicts(grid[size_t(gy) * size_t(side) + size_t(gx)], q)) return false;
        }
        return true;
    };
    const auto emit = [&](glm::dvec2 p) {
        grid[size_t(cellOf(p.y)) * size_t(side) + size_t(cellOf(p.x))] = int32_t(points.size());
        active.push_back(int32_t(points.size()));
        points.push_back(p);
    };

    emit(stream.next2());
    while (!active.empty()) {
        const size_t j = size_t(stream.nextIndex(active.size()));
        const glm::dvec2 centre = points[size_t(active[j])];
        bool found = false;
        for (int attempt = 0; attempt < o.candidates && !found; ++attempt) {
            glm::dvec2 q = centre + 2.0 * r * annulusPoint(stream);
            if (o.toroidal) q = {wrapUnit(q.x), wrapUnit(q.y)};
            else if (q.x < 0.0 || q.y < 0.0 || q.x >= 1.0 || q.y >= 1.0) continue;
            if (farEnough(q)) {
                emit(q);
                found = true;
            }
        }
        if (!found) {
            active[j] = active.back();
            active.pop_back();
        }
    }
    return points;
}

double poissonDiskRadiusForCount(int n, bool toroidal) {
    requirePositive(n, "Poisson disk pattern");
    // Measured over 20 runs each for r = 0.01 .. 0.2: this implementation packs 0.615 / r^2 points into the
    // unit torus (fewer than random dart throwing's jamming limit, about 0.70 / r^2). In the open square,
    // points crowd along the edges, which hold about 0.62 / r more.
    constexpr double kDensity = 0.615, kEdge = 0.62;
    if (toroidal) return std::min(0.5, std::sqrt(kDensity / n));
    // Solve kDensity / r^2 + kEdge / r = n for 1 / r.
    const double invR = (-kEdge + std::sqrt(kEdge * kEdge + 4.0 * kDensity * n)) / (2.0 * kDensity);
    return std::min(0.5, 1.0 / invR);
}

std::vector<glm::dvec2> poissonDiskPatternWithCount(int n, uint64_t seed, bool toroidal) {
    requirePositive(n, "Poisson disk pattern");
    double radius = poissonDiskRadiusForCount(n, toroidal);
    std::vector<glm::dvec2> bestAbove;
    constexpr int kAttempts = 24;
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
        PoissonDiskOptions o;
        o.radius = radius;
        o.toroidal = toroidal;
        o.seed = mix64(seed + uint64_t(attempt) * kGoldenGamma);
        std::vector<glm::dvec2> points = poissonDiskPattern(o);
        const int count = int(points.size());
        if (count == n) return points;
        if (count > n && (bestAbove.empty() || points.size() < bestAbove.size())) bestAbove = std::move(points);
        // The count goes as 1 / r^2; a damped step, since counts also scatter from run to run.
        radius = std::min(0.5, radius * std::pow(double(count) / n, 0.35));
    }
    // No run reached n (unlikely but possible for tiny n): halve the radius until one does.
    for (double r = 0.5 * radius; int(bestAbove.size()) < n; r *= 0.5) {
        PoissonDiskOptions o;
        o.radius = r;
        o.toroidal = toroidal;
        o.seed = seed;
        bestAbove = poissonDiskPattern(o);
    }
    // Thin at random down to n points.
    RandomStream stream(seed, 0, 0, 0x7415ull);
    while (int(bestAbove.size()) > n) {
        const size_t k = size_t(stream.nextIndex(bestAbove.size()));
        bestAbove[k] = bestAbove.back();
        bestAbove.pop_back();
    }
    return bestAbove;
}

// ---- Best candidate --------------------------------------------------------------------------------------------

std::vector<glm::dvec2> bestCandidatePattern(int n, uint64_t seed, int quality) {
    requirePositive(n, "best-candidate pattern");
    NearestGrid<2> grid(glm::dvec2(0.0), 1.0, int(std::sqrt(double(n))), true);
    RandomStream stream(seed, 0, 0, 0xbe57ull);
    return bestCandidate<2>(n, quality, grid, [&] { return stream.next2(); });
}

std::vector<glm::dvec3> bestCandidateDirections(int n, double cosThetaMax, uint64_t seed, int quality) {
    requirePositive(n, "best-candidate directions");
    cosThetaMax = std::clamp(cosThetaMax, -1.0, 1.0);
    // The cap's bounding box around +z, split into cells about one expected spacing wide (capped, since the
    // cells fill a volume while the points lie on a surface).
    const double sinMax = cosThetaMax <= 0.0 ? 1.0 : std::sqrt((1.0 - cosThetaMax) * (1.0 + cosThetaMax));
    const double extent = std::max({2.0 * sinMax, 1.0 - cosThetaMax, 1e-12});
    const double spacing = std::sqrt(2.0 * glm::pi<double>() * (1.0 - cosThetaMax) / n);
    const int side = std::clamp(int(std::ceil(extent / std::max(spacing, 1e-12))), 1, 64);
    NearestGrid<3> grid(glm::dvec3(-sinMax, -sinMax, cosThetaMax), extent, side, false);
    RandomStream stream(seed, 0, 0, 0xd1ec7ull);
    return bestCandidate<3>(n, quality, grid, [&] { return squareToUniformCone(stream.next2(), cosThetaMax); });
}

// ---- Per-pixel samples ---------------------------------------------------------------------------------------

uint32_t permuteIndex(uint32_t i, uint32_t n, uint64_t key) {
    if (n <= 1) return 0;
    uint32_t mask = n - 1;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    const int bits = std::popcount(mask);
    const int half = std::max(1, bits / 2), third = std::max(1, bits / 3);
    const uint64_t k1 = mix64(key), k2 = mix64(k1 + kGoldenGamma);
    const uint32_t a = uint32_t(k1), b = uint32_t(k1 >> 32), c = uint32_t(k2), d = uint32_t(k2 >> 32) | 1u;
    // Every step maps [0, mask] onto itself one to one: xor and addition with a constant, multiplication by an
    // odd number modulo a power of two, and x ^ (x >> s).
    do {
        i ^= a & mask;
        i = (i * 0x9e3779b1u) & mask;
        i ^= i >> half;
        i = (i + b) & mask;
        i = (i * d) & mask;
        i ^= i >> third;
        i ^= c & mask;
        i = (i * 0x85ebca6bu) & mask;
        i ^= i >> half;
    } while (i >= n);
    return i;
}

PixelSampler::PixelSampler(SamplePattern pattern, int samplesPerPixel, uint64_t seed, bool spreadPrefixes)
    : pattern_(pattern), count_(samplesPerPixel), seed_(seed), spreadPrefixes_(spreadPrefixes) {
    requirePositive(samplesPerPixel, "pixel sampler");
    switch (pattern) {
    case SamplePattern::Regular: count_ = regularGridSide(samplesPerPixel) * regularGridSide(samplesPerPixel); break;
    case SamplePattern::Stratified: layout_ = strataLayout(samplesPerPixel); break;
    case SamplePattern::Poisson: points_ = poissonDiskPatternWithCount(samplesPerPixel, seed, true); break;
    case SamplePattern::BestCandidate: points_ = bestCandidatePattern(samplesPerPixel, seed); break;
    case SamplePattern::Random: break;
    }
}

// The pixel-level stream of one round of N samples: it holds the round's shifts and visiting orders.
RandomStream PixelSampler::roundStream(int64_t px, int64_t py, int k) const {
    return RandomStream(seed_, px, py, kPixelLevelIndex - uint64_t(k / count_));
}

// The pattern point that sample k visits in a dimension: k itself in dimension 0, else its image under the
// dimension's permutation for this pixel and round.
uint32_t PixelSampler::orderOf(const RandomStream& round, int k, uint64_t dimensionKey) const {
    const uint32_t i = uint32_t(k % count_);
    if (dimensionKey == 0) return i;
    return permuteIndex(i, uint32_t(count_), round.bits(dimensionKey));
}

glm::dvec2 PixelSampler::sample(int64_t px, int64_t py, int k, uint32_t dimension) const {
    const RandomStream sampleStream(seed_, px, py, uint64_t(k));
    if (pattern_ == SamplePattern::Random) return sampleStream.uniform2(2 * uint64_t(dimension));
    const RandomStream round = roundStream(px, py, k);
    const uint64_t slot = 4 * uint64_t(dimension);
    // In dimension 0, point k as generated, or with spread prefixes the points in a per-pixel random order (every
    // other dimension's order is random anyway). Best-candidate points are spread at every prefix already.
    const bool asGenerated = dimension == 0 && (!spreadPrefixes_ || pattern_ == SamplePattern::BestCandidate);
    const uint32_t index = orderOf(round, k, asGenerated ? 0 : slot + kOrderDimension);
    switch (pattern_) {
    case SamplePattern::Regular: return regularPoint(int(index), regularGridSide(count_));
    case SamplePattern::Stratified:
        return stratifiedPoint(int(index), layout_, sampleStream.uniform2(2 * uint64_t(dimension)));
    case SamplePattern::Poisson:
    case SamplePattern::BestCandidate: {
        const glm::dvec2 p = points_[index];
        const glm::dvec2 shift = round.uniform2(slot + kShiftDimension);
        return {wrapUnit(p.x + shift.x), wrapUnit(p.y + shift.y)};
    }
    case SamplePattern::Random: break;
    }
    return {0.0, 0.0};
}

double PixelSampler::sample1D(int64_t px, int64_t py, int k, uint32_t dimension) const {
    const uint64_t key = kOneDimensionalKey + uint64_t(dimension);
    const RandomStream sampleStream(seed_, px, py, uint64_t(k));
    if (pattern_ == SamplePattern::Random) return sampleStream.uniform(key);
    const uint32_t stratum = orderOf(roundStream(px, py, k), k, key);
    return std::min((stratum + sampleStream.uniform(key)) / count_, std::nextafter(1.0, 0.0));
}

}  // namespace terracast
