// Tile arrays come from pooled chunks: a dropped tile's arrays are handed to the next tile of the same size
// instead of fresh pages, across threads, and what is in use is counted back to where it was.
#include "heightfield/tile_memory.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <set>
#include <thread>
#include <vector>

using namespace terracast;

TEST_CASE("Tile memory: released arrays are reused for the same size, and counted", "[heightfield][tiles]") {
    if (testing::kSanitizedBuild) {
        // Under AddressSanitizer every array comes from operator new, so that its bounds are checked.
        void* p = allocateTileMemory(1000);
        std::memset(p, 1, 1000);
        releaseTileMemory(p, 1000);
        return;
    }
    const TileMemoryStats before = tileMemoryStats();
    // A full int16 tile's codes: 257 x 257 samples.
    const size_t codes = 257 * 257 * sizeof(int16_t);
    std::vector<void*> held;
    for (int k = 0; k < 70; ++k) {  // 9.5 MB: more than a chunk holds
        held.push_back(allocateTileMemory(codes));
        std::memset(held.back(), k, codes);  // writable to the last byte
    }
    CHECK(tileMemoryStats().bytesInUse - before.bytesInUse >= 70 * codes);
    CHECK(tileMemoryStats().bytesInUse - before.bytesInUse < 70 * (codes + 4096));
    // More than one chunk's worth: a new chunk was taken, and the arrays are page aligned.
    CHECK(tileMemoryStats().chunkBytes > before.chunkBytes);
    for (void* p : held) CHECK(reinterpret_cast<uintptr_t>(p) % 4096 == 0);
    // Distinct, non-overlapping arrays.
    std::set<uintptr_t> starts;
    for (void* p : held) starts.insert(reinterpret_cast<uintptr_t>(p));
    REQUIRE(starts.size() == held.size());
    for (auto it = starts.begin(); std::next(it) != starts.end(); ++it) CHECK(*std::next(it) - *it >= codes);
    // Released, then asked for again: the same memory, no new chunk.
    const std::set<void*> released(held.begin(), held.end());
    for (void* p : held) releaseTileMemory(p, codes);
    CHECK(tileMemoryStats().bytesInUse == before.bytesInUse);
    const size_t chunks = tileMemoryStats().chunkBytes;
    std::vector<void*> again;
    for (int k = 0; k < 70; ++k) again.push_back(allocateTileMemory(codes - 100));  // same pages
    for (void* p : again) CHECK(released.count(p) == 1);
    CHECK(tileMemoryStats().chunkBytes == chunks);
    // From other threads at once: each gets its own arrays.
    std::vector<std::thread> threads;
    std::vector<std::vector<void*>> got(4);
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int k = 0; k < 25; ++k) {
                void* p = allocateTileMemory(50000);
                std::memset(p, t, 50000);
                got[size_t(t)].push_back(p);
            }
        });
    for (auto& thread : threads) thread.join();
    std::set<void*> all;
    for (const auto& g : got) all.insert(g.begin(), g.end());
    CHECK(all.size() == 100);
    for (const auto& g : got)
        for (void* p : g) releaseTileMemory(p, 50000);
    for (void* p : again) releaseTileMemory(p, codes - 100);
    CHECK(tileMemoryStats().bytesInUse == before.bytesInUse);
    // Arrays too large for a chunk's quarter come from operator new, and are not counted.
    void* big = allocateTileMemory(size_t(3) << 20);
    CHECK(tileMemoryStats().bytesInUse == before.bytesInUse);
    releaseTileMemory(big, size_t(3) << 20);
}
