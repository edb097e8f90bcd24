// A cheap clock for timing many short intervals (render --verbose): the processor's time-stamp counter where there
// is one (x86-64: about 10 ns a read here, against 25 for the steady clock), else the steady clock in
// nanoseconds. Ticks become seconds through a rate measured over the timed work itself (TickRate).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>

#if defined(__x86_64__) || defined(_M_X64)
#include <x86intrin.h>
#endif

namespace terracast {

inline uint64_t readTicks() {
#if defined(__x86_64__) || defined(_M_X64)
    return __rdtsc();
#else
    return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::steady_clock::now().time_since_epoch())
                        .count());
#endif
}

// What two back-to-back reads measure: the part of a read that an interval timed between two reads includes,
// subtracted from each (the least of many pairs).
uint64_t tickReadCost();

// The ticks since `start` (a readTicks()), less `readCost` (tickReadCost()): what the timed work itself took.
inline uint64_t ticksSince(uint64_t start, uint64_t readCost) {
    const uint64_t spent = readTicks() - start;
    return spent - std::min(spent, readCost);
}

// Ticks per second over a stretch of work: started when made, measured when asked (the counter of an x86-64
// processor of this century runs at a constant rate; the stretch should last a good fraction of a second).
class TickRate {
public:
    TickRate() : ticks0_(readTicks()), time0_(std::chrono::steady_clock::now()) {}
    double ticksPerSecond() const {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - time0_).count();
        const double ticks = double(readTicks() - ticks0_);
        return seconds > 0.0 && ticks > 0.0 ? ticks / seconds : 1e9;
    }

private:
    uint64_t ticks0_;
    std::chrono::steady_clock::time_point time0_;
};

}  // namespace terracast
