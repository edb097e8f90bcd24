#include "tracer/core/ticks.h"

#include <algorithm>
#include <limits>

namespace terracast {

uint64_t tickReadCost() {
    static const uint64_t cost = [] {
        uint64_t least = std::numeric_limits<uint64_t>::max();
        for (int k = 0; k < 1000; ++k) {
            const uint64_t a = readTicks();
            const uint64_t b = readTicks();
            least = std::min(least, b - a);
        }
        return least;
    }();
    return cost;
}

}  // namespace terracast
