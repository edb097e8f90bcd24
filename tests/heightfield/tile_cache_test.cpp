// The tile cache of out-of-core grids: least recently used tiles go first, the budget holds, a failed load
// leaves nothing behind, and threads asking for one tile share a single load.
#include "heightfield/tile_cache.h"

#include <catch2/catch.hpp>

#include <atomic>
#include <map>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace terracast;

namespace {

// A tile whose content says which key it was made for.
struct FakeTile {
    int64_t key = 0;
    std::vector<int16_t> codes;
};

constexpr size_t kTileBytes = 1000;

struct Counting {
    std::atomic<int> loads{0};
    std::shared_ptr<const FakeTile> operator()(int64_t key) {
        ++loads;
        return std::make_shared<const FakeTile>(FakeTile{key, std::vector<int16_t>(8, int16_t(key))});
    }
};

size_t tileBytes(const FakeTile&) { return kTileBytes; }

}  // namespace

TEST_CASE("Tile cache: a tile is loaded once while it fits, then served from the cache", "[heightfield][tiles]") {
    Counting counting;
    TileCache<FakeTile> cache(10 * kTileBytes, [&](int64_t k) { return counting(k); }, tileBytes);
    for (int round = 0; round < 3; ++round)
        for (int64_t k = 0; k < 10; ++k) CHECK(cache.get(k)->key == k);
    CHECK(counting.loads == 10);
    const TileCacheStats s = cache.stats();
    CHECK(s.loads == 10);
    CHECK(s.hits == 20);
    CHECK(s.evictions == 0);
    CHECK(s.bytes == 10 * kTileBytes);
    CHECK(s.tiles == 10);
}

TEST_CASE("Tile cache: the least recently used tile is the one evicted", "[heightfield][tiles]") {
    Counting counting;
    TileCache<FakeTile> cache(3 * kTileBytes, [&](int64_t k) { return counting(k); }, tileBytes);
    cache.get(0);
    cache.get(1);
    cache.get(2);
    cache.get(0);  // 1 is now the least recently used
    cache.get(3);  // evicts 1
    CHECK(cache.peek(1) == nullptr);
    CHECK(cache.peek(0) != nullptr);
    CHECK(cache.peek(2) != nullptr);
    CHECK(cache.peek(3) != nullptr);
    CHECK(counting.loads == 4);
    cache.get(0);
    CHECK(counting.loads == 4);
    cache.get(1);  // loaded again; evicts 2, now the least recently used
    CHECK(counting.loads == 5);
    CHECK(cache.peek(2) == nullptr);
    CHECK(cache.stats().evictions == 2);
}

TEST_CASE("Tile cache: the held bytes never pass the budget, and a held tile outlives its eviction",
          "[heightfield][tiles]") {
    Counting counting;
    TileCache<FakeTile> cache(5 * kTileBytes, [&](int64_t k) { return counting(k); }, tileBytes);
    const auto kept = cache.get(99);
    std::mt19937 rng(3);
    for (int n = 0; n < 2000; ++n) {
        const int64_t k = int64_t(rng() % 40);
        CHECK(cache.get(k)->key == k);
        REQUIRE(cache.stats().bytes <= 5 * kTileBytes);
    }
    CHECK(cache.stats().peakBytes == 5 * kTileBytes);
    CHECK(cache.peek(99) == nullptr);
    CHECK(kept->key == 99);
    CHECK(kept->codes.at(7) == 99);
    // A tile larger than the whole budget is still served, and is then the only one held.
    TileCache<FakeTile> tight(kTileBytes / 2, [&](int64_t k) { return counting(k); }, tileBytes);
    CHECK(tight.get(1)->key == 1);
    CHECK(tight.get(2)->key == 2);
    CHECK(tight.stats().tiles == 1);
}

TEST_CASE("Tile cache: a load that throws reaches its caller, and the next request loads again",
          "[heightfield][tiles]") {
    int attempts = 0;
    TileCache<FakeTile> cache(
        4 * kTileBytes,
        [&](int64_t k) {
            if (++attempts == 1) throw std::runtime_error("read error");
            return std::make_shared<const FakeTile>(FakeTile{k, {}});
        },
        tileBytes);
    CHECK_THROWS_WITH(cache.get(7), "read error");
    CHECK(cache.stats().tiles == 0);
    CHECK(cache.get(7)->key == 7);
    CHECK(attempts == 2);
}

TEST_CASE("Tile cache: threads asking for the same tiles share one load each and always get the right tile",
          "[heightfield][tiles]") {
    std::mutex mutex;
    std::map<int64_t, int> loading;  // loads in flight per key
    std::atomic<int> overlapping{0}, loads{0};
    TileCache<FakeTile> cache(
        6 * kTileBytes,
        [&](int64_t k) {
            {
                std::lock_guard lock(mutex);
                if (++loading[k] > 1) ++overlapping;
            }
            ++loads;
            std::this_thread::sleep_for(std::chrono::microseconds(50));
            {
                std::lock_guard lock(mutex);
                --loading[k];
            }
            return std::make_shared<const FakeTile>(FakeTile{k, std::vector<int16_t>(8, int16_t(k))});
        },
        tileBytes);
    std::atomic<int> wrong{0};
    std::vector<std::thread> threads;
    constexpr int kThreads = 8, kRequests = 3000;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            std::mt19937 rng{uint32_t(t)};
            for (int n = 0; n < kRequests; ++n) {
                // Mostly a few hot tiles, sometimes a cold one.
                const int64_t k = rng() % 4 ? int64_t(rng() % 4) : int64_t(4 + rng() % 28);
                const auto tile = cache.get(k);
                if (tile->key != k || tile->codes.at(3) != int16_t(k)) ++wrong;
            }
        });
    for (auto& th : threads) th.join();
    const TileCacheStats s = cache.stats();
    CHECK(wrong == 0);
    CHECK(overlapping == 0);
    CHECK(s.loads == loads);
    CHECK(s.hits + s.loads == kThreads * kRequests);
    CHECK(s.bytes <= 6 * kTileBytes);
    CHECK(s.hits > s.loads);
}

TEST_CASE("Tile cache: a thread's recent tiles answer again without the lock, and other threads load their own",
          "[heightfield][tiles]") {
    Counting counting;
    TileCache<FakeTile> cache(1 * kTileBytes, [&](int64_t k) { return counting(k); }, tileBytes);
    const FakeTile* first = cache.getRecent(0).get();
    cache.get(1);  // evicts 0 from the cache
    CHECK(cache.peek(0) == nullptr);
    // This thread still remembers 0: the same tile, no load, counted as a hit.
    for (int n = 0; n < 100; ++n) CHECK(cache.getRecent(0).get() == first);
    CHECK(counting.loads == 2);
    CHECK(cache.stats().hits == 100);
    // Another thread remembers nothing yet: it goes to the cache, which loads 0 again.
    std::thread([&] { CHECK(cache.getRecent(0)->key == 0); }).join();
    CHECK(counting.loads == 3);
    // Every 256th request a thread could answer itself goes to the cache too, which holds 0 now: no load.
    for (int n = 0; n < 300; ++n) cache.getRecent(0);
    CHECK(cache.peek(0) != nullptr);
    CHECK(counting.loads == 3);
}
