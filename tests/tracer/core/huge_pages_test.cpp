// Large arrays are offered to the advisor before they are filled, and the executable's advisor makes Linux back
// them with transparent huge pages where the kernel leaves that to the program ("madvise", Debian's default).
#include "heightfield/height_grid.h"
#include "heightfield/large_buffer.h"
#include "tracer/core/huge_pages.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>
#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
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

// A field of the mapping that holds `address` in /proc/self/smaps ("AnonHugePages", "Rss"), in KiB; -1 if none.
int64_t smapsKiB(const void* address, const std::string& field) {
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
        if (inside && line.rfind(field + ":", 0) == 0) return std::stoll(line.substr(field.size() + 1));
    }
    return -1;
}

// The kibibytes of huge pages backing the mapping that holds `address`.
int64_t hugePagesKiB(const void* address) { return smapsKiB(address, "AnonHugePages"); }

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

TEST_CASE("Large buffers: the executable's advisor faults a large array in on the array-pass threads, writing nothing",
          "[core]") {
    if (terracast::testing::kSanitizedBuild) return;  // the sanitizer's allocator places the memory
    const size_t bytes = size_t(32) << 20;
    auto fresh = [&] {
        void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        REQUIRE(p != MAP_FAILED);
        return static_cast<unsigned char*>(p);
    };
    {
        // Kernels before 5.14 have no MADV_POPULATE_WRITE: the advisor then leaves the faults to the filler.
        unsigned char* probe = fresh();
        const bool populates = ::madvise(probe, 4096, MADV_POPULATE_WRITE) == 0;
        ::munmap(probe, bytes);
        if (!populates) return;
    }
    // Resident pages of [p, p + bytes), page by page (mincore), so that neighbouring mappings do not count.
    auto residentPages = [&](unsigned char* p) {
        std::vector<unsigned char> vec(bytes / 4096);
        REQUIRE(::mincore(p, bytes, vec.data()) == 0);
        return std::count_if(vec.begin(), vec.end(), [](unsigned char v) { return (v & 1) != 0; });
    };
    useHugePagesForLargeBuffers();
    setArrayPassThreads(2);
    unsigned char* two = fresh();
    adviseLargeBuffer(two + 5, bytes - 4096);  // off page boundaries, as a vector's storage may be
    const auto twoPages = residentPages(two);
    // With one thread there is nothing to share: the filling thread takes the faults itself.
    setArrayPassThreads(1);
    unsigned char* one = fresh();
    adviseLargeBuffer(one + 5, bytes - 4096);
    const auto onePages = residentPages(one);
    setArrayPassThreads(0);
    setLargeBufferAdvisor(nullptr);
    INFO("resident after the advice: " << twoPages << " pages on two threads, " << onePages << " on one, of "
                                       << bytes / 4096);
    // The whole pages inside the range (all but the first and the last two) are resident, and hold zeros.
    CHECK(twoPages >= std::ptrdiff_t(bytes / 4096) - 3);
    CHECK(onePages == 0);
    CHECK(std::all_of(two, two + bytes, [](unsigned char c) { return c == 0; }));
    ::munmap(two, bytes);
    ::munmap(one, bytes);
}

TEST_CASE("Large buffers: slices cover a range once, on as many threads as asked", "[core]") {
    for (const auto& [n, slices] : std::vector<std::pair<int64_t, int64_t>>{{1000, 1}, {1000, 3}, {7, 5}, {3, 8}, {0, 4}}) {
        INFO(n << " items in " << slices << " slices");
        std::vector<std::atomic<int>> seen(static_cast<size_t>(n));
        std::mutex mutex;
        std::set<std::thread::id> threads;
        int64_t parts = 0;
        runInSlices(n, slices, [&](int64_t a, int64_t b) {
            for (int64_t k = a; k < b; ++k) ++seen[size_t(k)];
            std::lock_guard lock(mutex);
            threads.insert(std::this_thread::get_id());
            ++parts;
        });
        CHECK(std::all_of(seen.begin(), seen.end(), [](const std::atomic<int>& c) { return c.load() == 1; }));
        CHECK(parts == std::min(slices, std::max<int64_t>(n, 1)));
        CHECK(int64_t(threads.size()) == parts);
    }
}

TEST_CASE("Large buffers: a command's thread count bounds the passes over whole arrays", "[core]") {
    const int all = arrayPassThreads();
    CHECK(all >= 1);
    setArrayPassThreads(1);
    CHECK(arrayPassThreads() == 1);
    setArrayPassThreads(3);
    CHECK(arrayPassThreads() == 3);
    setArrayPassThreads(0);  // back to all cores
    CHECK(arrayPassThreads() == all);
}
