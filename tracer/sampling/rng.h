// Counter-based random numbers: every value is a hash of where it is used (seed, pixel, sample index,
// dimension), never the next state of a shared generator, so a picture does not depend on how many threads
// drew it or in which order its tiles ran.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

namespace terracast {

// SplitMix64's output function (Steele, Lea, Flood 2014, "Fast splittable pseudorandom number generators",
// with Stafford's "Mix13" constants): a bijection on 64-bit words in which every input bit flips about half
// of the output bits.
constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// The 64-bit golden ratio, SplitMix64's counter increment (odd, so consecutive counters never repeat).
inline constexpr uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ull;

// The top 53 bits of a word as a double in [0, 1): a multiple of 2^-53, never 1.
constexpr double unitDoubleFromBits(uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }

// The top 24 bits of a word as a float in [0, 1): a multiple of 2^-24, never 1 (converting the double
// above to float could round up to 1).
constexpr float unitFloatFromBits(uint64_t bits) { return float(bits >> 40) * 0x1.0p-24f; }

// A stream of random values keyed by (seed, pixel x, pixel y, sample index). Value number d of the stream
// (its "dimension") is SplitMix64 at counter d from a start hashed out of the key, so any value can be read
// directly with uniform(d), or in order with next(). Two streams that differ in any key component are
// unrelated. Copying a stream copies its position.
class RandomStream {
public:
    explicit constexpr RandomStream(uint64_t seed, int64_t px = 0, int64_t py = 0, uint64_t sampleIndex = 0)
        : start_(keyOf(seed, px, py, sampleIndex)) {}

    // Random bits of dimension d.
    constexpr uint64_t bits(uint64_t dimension) const { return mix64(start_ + (dimension + 1) * kGoldenGamma); }
    // Uniform in [0, 1) for dimension d.
    constexpr double uniform(uint64_t dimension) const { return unitDoubleFromBits(bits(dimension)); }
    constexpr float uniformFloat(uint64_t dimension) const { return unitFloatFromBits(bits(dimension)); }
    // A point uniform in [0, 1)^2 made of dimensions d and d + 1.
    glm::dvec2 uniform2(uint64_t dimension) const { return {uniform(dimension), uniform(dimension + 1)}; }

    // The value at the stream's position, then the position moves one dimension on.
    constexpr uint64_t nextBits() { return bits(position_++); }
    constexpr double next() { return unitDoubleFromBits(nextBits()); }
    constexpr float nextFloat() { return unitFloatFromBits(nextBits()); }
    glm::dvec2 next2() {
        const double x = next();
        return {x, next()};
    }
    // Uniform integer in [0, n) for n >= 1, by the high word of a 64 x 64-bit product (Lemire 2019, "Fast
    // random integer generation in an interval"; the bias, at most n / 2^64, is far below anything a
    // renderer could see).
    constexpr uint64_t nextIndex(uint64_t n) {
        return uint64_t((static_cast<unsigned __int128>(nextBits()) * n) >> 64);
    }

    constexpr uint64_t position() const { return position_; }

private:
    // Each key component is folded in through a full mix so that neighbouring pixels, samples and seeds
    // (which differ in a few low bits) give unrelated starts.
    static constexpr uint64_t keyOf(uint64_t seed, int64_t px, int64_t py, uint64_t sampleIndex) {
        uint64_t h = mix64(seed ^ 0x5851f42d4c957f2dull);
        h = mix64((h + kGoldenGamma) ^ uint64_t(px));
        h = mix64((h + kGoldenGamma) ^ uint64_t(py));
        return mix64((h + kGoldenGamma) ^ sampleIndex);
    }

    uint64_t start_;
    uint64_t position_ = 0;
};

}  // namespace terracast
