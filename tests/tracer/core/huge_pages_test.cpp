// Large arrays are offered to the advisor before they are filled, and the executable's advisor makes Linux back
// them with transparent huge pages where the kernel leaves that to the program ("madvise", Debian's default).
#include "heightfield/height_grid.h"
#include "heightfield/large_buffer.h"
#include "tracer/core/huge_pages.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace terracast;

namespace {

struct Offer {
    uintptr_t begin = 0, end = 0;
};
std::vector<Offer> offers;
void record(void* data, size_t bytes) {
    offers.push_back({reinterpret_cast<uintptr_t>(data), reinterpret_cast<uintptr_t>(data) + bytes});
}

// The kernel's transparent huge page mode: "always", "madvise" or "never" (the bracketed word), or "" when the
// kernel has none.
std::string hugePageMode() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string text;
    std::getline(in, text);
    const size_t open = text.find('['), close = text.find(']');
    return open == std::string::npos || close == std::string::npos ? "" : text.substr(open + 1, close - open - 1);
}

// The kibibytes of huge pages backing the mapping that holds `address`, from /proc/self/smaps.
int64_t hugePagesKiB(const void* address) {
    const auto a = reinterpret_cast<uintptr_t>(address);
    std::ifstream in("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(in, line)) {
        // A mapping's first line starts "lo-hi perms ..."; its fields follow as "Name:   value kB".
        const size_t dash = line.find('-'), space = line.find(' ');
        if (dash != std::string::npos && space != std::string::npos && dash < space &&
            line.find(':') > space) {
            const uintptr_t lo = std::stoull(line.substr(0, dash), nullptr, 16);
            const uintptr_t hi = std::stoull(line.substr(dash + 1, space - dash - 1), nullptr, 16);
            inside = a >= lo && a < hi;
            continue;
        }
        if (inside && line.rfind("AnonHugePages:", 0) == 0) return std::stoll(line.substr(14));
    }
    return -1;
}

}  // namespace

TEST_CASE("Large buffers: a grid's codes are offered to the advisor whole", "[core]") {
    offers.clear();
    setLargeBufferAdvisor(record);
    const int64_t n = 2049;
    std::vector<float> heights(size_t(n * n));
    for (size_t k = 0; k < heights.size(); ++k) heights[k] = float(k % 977);
    const HeightGrid grid(n, n, 10.0, 10.0, heights);
    setLargeBufferAdvisor(nullptr);
    REQUIRE(grid.storage() == HeightStorage::Int16);
    // Some offer covers the codes' 8 MiB.
    const size_t codeBytes = size_t(n * n) * sizeof(int16_t);
    bool covered = false;
    for (const Offer& o : offers) covered = covered || o.end - o.begin >= codeBytes;
    CHECK(covered);
}

TEST_CASE("Large buffers: the executable's advisor gets transparent huge pages where the kernel allows them",
          "[core]") {
    const std::string mode = hugePageMode();
    if (mode != "madvise" && mode != "always") return;  // no huge pages to be had
    if (terracast::testing::kSanitizedBuild) return;       // the sanitizer's allocator places the memory
    useHugePagesForLargeBuffers();
    const std::vector<float> big = largeVector<float>((size_t(64) << 20) / sizeof(float), 1.0f);  // 64 MiB
    setLargeBufferAdvisor(nullptr);
    const int64_t kib = hugePagesKiB(big.data() + big.size() / 2);
    INFO("transparent huge pages: " << mode << "; " << kib << " KiB of huge pages in the array's mapping");
    // At least half of the array: the kernel may fall back to small pages where it finds no free 2 MiB block.
    CHECK(kib >= 32 * 1024);
}

TEST_CASE("Large buffers: the parallel first touch writes a zero in every page of its range and nowhere else",
          "[core]") {
    // 24 MiB, above the size the touch splits over threads; the range starts and ends off page boundaries.
    std::vector<uint8_t> bytes(size_t(24) << 20, uint8_t(0xAB));
    const size_t begin = 4096 * 3 + 5, end = bytes.size() - 4096 * 2 - 7;
    touchLargeBuffer(bytes.data() + begin, end - begin);
    size_t outsideChanged = 0, zeros = 0, pagesWithoutZero = 0;
    for (size_t k = 0; k < bytes.size(); ++k) {
        if (k < begin || k >= end) outsideChanged += bytes[k] != 0xAB;
        else zeros += bytes[k] == 0;
    }
    // Every 4096-byte window of the range holds a written byte: no page is left for the filling thread.
    for (size_t w = begin; w + 4096 <= end; w += 4096) {
        bool any = false;
        for (size_t k = w; k < w + 4096; ++k) any = any || bytes[k] == 0;
        pagesWithoutZero += !any;
    }
    CHECK(outsideChanged == 0);
    CHECK(pagesWithoutZero == 0);
    CHECK(zeros == (end - begin + 4095) / 4096);
    // And a large vector still holds its value everywhere once filled.
    const std::vector<int16_t> codes = largeVector<int16_t>(size_t(12) << 20, int16_t(-7));
    CHECK(std::count(codes.begin(), codes.end(), int16_t(-7)) == std::ptrdiff_t(codes.size()));
}

TEST_CASE("Large buffers: a command's thread count bounds the passes over whole arrays", "[core]") {
    const int all = arrayPassThreads();
    CHECK(all >= 1);
    setArrayPassThreads(1);
    CHECK(arrayPassThreads() == 1);
    // On one thread there is no first touch to share: the thread that fills the array takes the faults itself.
    std::vector<uint8_t> bytes(size_t(16) << 20, uint8_t(0xAB));
    touchLargeBuffer(bytes.data(), bytes.size());
    CHECK(std::count(bytes.begin(), bytes.end(), uint8_t(0)) == 0);
    setArrayPassThreads(3);
    CHECK(arrayPassThreads() == 3);
    touchLargeBuffer(bytes.data(), bytes.size());
    CHECK(size_t(std::count(bytes.begin(), bytes.end(), uint8_t(0))) == bytes.size() / 4096);
    setArrayPassThreads(0);  // back to all cores
    CHECK(arrayPassThreads() == all);
}
