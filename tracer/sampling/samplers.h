// Sample patterns in the unit square and on the sphere, and the per-pixel sampler that hands a renderer
// sample k of N for any pixel. Everything is a pure function of (pattern, count, seed, pixel, sample index,
// dimension), so pictures do not depend on thread count or tile order.
#pragma once

#include "tracer/sampling/rng.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace terracast {

// How the N samples of a pixel (or of a light, or a lens) are spread over the unit square.
enum class SamplePattern {
    Regular,        // a regular grid: N rounded to the nearest square; aliases on regular detail
    Random,         // independent uniform points: unbiased, clumps and holes, error ~ N^-1/2
    Stratified,     // jittered: one uniform point in each cell of a grid of N strata
    Poisson,        // Poisson disk (blue noise) by Bridson's algorithm, precomputed and shifted per pixel
    BestCandidate,  // Mitchell's best-candidate points, precomputed and shifted per pixel
};

// Parses "regular", "random", "stratified", "poisson" or "best-candidate".
// Every pattern, in the order lists and messages show them.
std::span<const SamplePattern> samplePatterns();
std::optional<SamplePattern> parseSamplePattern(std::string_view name);
const char* samplePatternName(SamplePattern pattern);
// The names parseSamplePattern accepts, comma-separated, for messages.
const char* samplePatternList();

// ---- Regular, random and stratified patterns -------------------------------------------------------------

// The side of the regular grid used for a request of n samples: the nearest integer to sqrt(n), at least 1,
// so a regular pattern has side^2 points (n = 2 gives 1, n = 3 gives 4, n = 10 gives 9).
int regularGridSide(int n);
// Points at the centres of a regularGridSide(n)^2 grid, row by row from y = 0.
std::vector<glm::dvec2> regularPattern(int n);

// n independent uniform points.
std::vector<glm::dvec2> randomPattern(int n, uint64_t seed);

// The strata of a jittered pattern of n points: `columns` x `rows` = n exactly, with rows the largest
// divisor of n not above sqrt(n). Square n gives a square grid, n = 8 gives 4 x 2, n = 12 gives 4 x 3; a prime
// n degenerates into n vertical strips (still one point per stratum, but stratified along x only), so
// counts with a near-square factorisation are the better choice.
struct StrataLayout {
    int columns = 1;  // strata along x
    int rows = 1;     // strata along y
};
StrataLayout strataLayout(int n);
// One uniform point in each stratum; point k lies in column k % columns, row k / columns.
std::vector<glm::dvec2> stratifiedPattern(int n, uint64_t seed);

// ---- Poisson disk ----------------------------------------------------------------------------------------

struct PoissonDiskOptions {
    double radius = 0.05;    // minimum distance between points, in units of the square's side; (0, 0.5]
    bool toroidal = false;   // distances wrap around the square's edges, so copies of the tile join seamlessly
    int candidates = 30;     // Bridson's k: attempts around an active point before it is retired
    uint64_t seed = 1;
};

// A Poisson disk pattern in [0, 1)^2 by Bridson's algorithm (2007, "Fast Poisson disk sampling in arbitrary
// dimensions"): a background grid of cells r / sqrt(2) wide holds at most one point each, so checking a
// candidate against its neighbours costs O(1) and the whole pattern O(N). New points are drawn in the annulus
// [r, 2r] around a random active point; an active point that yields none in k attempts is retired. No two
// points are closer than r (in the toroidal metric when toroidal), and the algorithm stops only when every
// point has been retired, which leaves few gaps wider than about r.
std::vector<glm::dvec2> poissonDiskPattern(const PoissonDiskOptions& options);

// The radius for which poissonDiskPattern gives about n points (calibrated on this implementation; the
// expected count is within a few percent of n for n >= 64).
double poissonDiskRadiusForCount(int n, bool toroidal);

// Exactly n Poisson disk points: the radius is adjusted over a few runs until one returns n points; if none
// does, the smallest run with more than n points is thinned by removing points at random (the minimum
// distance still holds; small gaps appear where points were removed).
std::vector<glm::dvec2> poissonDiskPatternWithCount(int n, uint64_t seed, bool toroidal);

// ---- Mitchell's best candidate ---------------------------------------------------------------------------

// Mitchell's best-candidate algorithm (1991, "Spectrally optimal sampling for distribution ray tracing"):
// each new point is the one, among quality x (points so far) uniform candidates, farthest from the points
// already placed. Every prefix of the result is itself well spread, so a renderer may stop early. Not a
// maximal Poisson disk set, but close to blue noise. Nearest-point queries use a uniform grid, so the cost
// is about quality x n^2 / 2 distance tests rather than quality x n^3 / 6.

// n points in [0, 1)^2, with toroidal distances so that the pattern tiles.
std::vector<glm::dvec2> bestCandidatePattern(int n, uint64_t seed, int quality = 10);

// n unit directions in the cap within theta_max of +z (cosThetaMax = -1: the whole sphere, 0: the
// hemisphere; rotate them with Frame::around). Candidates are uniform by solid angle and compared by chord
// length, which orders pairs exactly as the angle between them does.
std::vector<glm::dvec3> bestCandidateDirections(int n, double cosThetaMax, uint64_t seed, int quality = 10);

// ---- Per-pixel samples -----------------------------------------------------------------------------------

// A pseudo-random permutation of [0, n) chosen by `key`: returns the image of i < n. Built from invertible
// steps on the smallest power-of-two range holding n (xor with the key, multiplication by an odd constant,
// xor-shift), repeated until the value falls below n ("cycle walking", Black and Rogaway 2002); the idea
// follows Kensler 2013 ("Correlated multi-jittered sampling"). O(1) expected time, no tables.
uint32_t permuteIndex(uint32_t i, uint32_t n, uint64_t key);

// Sample k of N for any pixel, for any number of independent 2D (or 1D) sample dimensions.
//  - Dimension 0 is meant for the position in the pixel, 1 for the lens, 2 for a light, and so on. Sample k
//    takes point k of the pattern in dimension 0; every other dimension visits the N points in its own
//    per-pixel random order (permuteIndex), so the stratum of the lens sample does not follow the stratum of
//    the film sample.
//  - Regular and stratified points are computed directly from k (regular points are the same in every
//    pixel, which is what makes them alias). Random points hash (seed, pixel, k, dimension).
//  - Poisson and best-candidate sets are computed once, in the toroidal square, and every pixel and
//    dimension sees them moved by its own random toroidal shift (Cranley and Patterson 1976, "Randomization
//    of number theoretic methods for multiple integration"), which keeps their spacing, decorrelates pixels
//    and makes each pixel's estimate unbiased.
// Thread-safe: every method is const and allocation-free.
class PixelSampler {
public:
    // With `spreadPrefixes`, dimension 0 too visits the points in a per-pixel random order, so that the first
    // m < N samples of a pixel (all that an adaptive pixel may take) lie all over the pixel: taken in the
    // pattern's own order, the first m regular or stratified points fill a band along the pixel's top. A pixel
    // that takes all N samples sees the same points either way.
    PixelSampler(SamplePattern pattern, int samplesPerPixel, uint64_t seed, bool spreadPrefixes = false);

    SamplePattern pattern() const { return pattern_; }
    // The samples each pixel gets: the request, or the nearest square for the regular pattern.
    int samplesPerPixel() const { return count_; }
    uint64_t seed() const { return seed_; }

    // Sample k >= 0 of pixel (px, py) in 2D dimension `dimension`, in [0, 1)^2. k runs from 0 to
    // samplesPerPixel() - 1 for one full pattern; an adaptive renderer may go on: sample k >= N belongs to
    // round k / N, a new copy of the pattern with its own random shift and order.
    glm::dvec2 sample(int64_t px, int64_t py, int k, uint32_t dimension = 0) const;
    // A value in [0, 1) for 1D dimension `dimension` (such as the shutter time). Uniform random for the
    // random pattern; jittered in 1D for the others: sample k gets its own stratum of width 1 / N, strata
    // taken in a per-pixel random order.
    double sample1D(int64_t px, int64_t py, int k, uint32_t dimension = 0) const;

    // The precomputed points (Poisson and best-candidate only; empty otherwise).
    const std::vector<glm::dvec2>& points() const { return points_; }

private:
    RandomStream roundStream(int64_t px, int64_t py, int k) const;
    uint32_t orderOf(const RandomStream& round, int k, uint64_t dimensionKey) const;

    SamplePattern pattern_;
    int count_;
    uint64_t seed_;
    StrataLayout layout_;
    std::vector<glm::dvec2> points_;
    bool spreadPrefixes_ = false;
};

}  // namespace terracast
