// A thread-safe least-recently-used cache of immutable tiles, bounded in bytes: the resident part of a height
// grid too large for memory (docs/architecture.md, "Tiled grids"). Tiles are loaded on demand by a callback,
// outside the cache's lock, and handed out as shared pointers: a tile evicted while a ray still reads it stays
// alive until that ray lets go, so the bound holds for the cache's own tiles and is exceeded at most by the
// tiles the threads hold (the four each remembers here as its most recent, and the four of the grid's per-thread
// memo, which walks read through).
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace terracast {

// What the cache did so far.
struct TileCacheStats {
    int64_t hits = 0;       // requests answered from the cache (or by a load another thread was making)
    int64_t loads = 0;      // requests that loaded the tile
    int64_t evictions = 0;  // tiles dropped to stay within the budget
    size_t bytes = 0;       // bytes of the tiles held now
    size_t peakBytes = 0;   // the most ever held at once
    int64_t tiles = 0;      // tiles held now
    double loadSeconds = 0.0;  // thread time spent loading tiles
    double waitSeconds = 0.0;  // thread time spent waiting for a tile another thread was loading
};

template <class Tile>
class TileCache {
public:
    using Key = int64_t;
    using Loader = std::function<std::shared_ptr<const Tile>(Key)>;
    using Sizer = std::function<size_t(const Tile&)>;

    // `budgetBytes` bounds the bytes of the tiles held (at least one tile is always kept, whatever its size).
    // `load` makes the tile of a key (it may throw: the request that asked rethrows, and a later request tries
    // again); `bytesOf` says what a tile costs.
    TileCache(size_t budgetBytes, Loader load, Sizer bytesOf)
        : budget_(budgetBytes), load_(std::move(load)), bytesOf_(std::move(bytesOf)) {}

    TileCache(const TileCache&) = delete;
    TileCache& operator=(const TileCache&) = delete;

    // The tile of `key`, loaded when the cache does not hold it. Concurrent requests for a tile being loaded
    // wait for that one load.
    std::shared_ptr<const Tile> get(Key key) { return getLocked(key); }

    // As get, but each thread first looks among the last few tiles it got from this cache this way, without
    // the lock: for the hot paths that ask for the same tile again and again. A tile a thread remembers stays
    // alive after eviction until its slot is reused, and is made recent in the LRU order only on every 256th
    // request it answers, so the order is that of get only approximately.
    std::shared_ptr<const Tile> getRecent(Key key) {
        struct Recent {
            uint64_t cache = 0;
            Key key = 0;
            uint32_t uses = 0;
            std::shared_ptr<const Tile> tile;
        };
        thread_local std::array<Recent, 4> recent;
        Recent& slot = recent[static_cast<size_t>(key) & 3u];
        if (slot.cache == id_ && slot.key == key && ++slot.uses % 256 != 0) {
            fastHits_.fetch_add(1, std::memory_order_relaxed);
            return slot.tile;
        }
        std::shared_ptr<const Tile> tile = getLocked(key);
        slot.cache = id_;
        slot.key = key;
        slot.tile = tile;
        return tile;
    }

    // The tile of `key` if the cache holds it, without loading or counting.
    std::shared_ptr<const Tile> peek(Key key) const {
        std::lock_guard lock(mutex_);
        const auto it = entries_.find(key);
        return it == entries_.end() ? nullptr : it->second.tile;
    }

    TileCacheStats stats() const {
        std::lock_guard lock(mutex_);
        TileCacheStats s = stats_;
        s.hits += fastHits_.load(std::memory_order_relaxed);
        return s;
    }

    size_t budgetBytes() const { return budget_; }

private:
    std::shared_ptr<const Tile> getLocked(Key key) {
        std::unique_lock lock(mutex_);
        for (;;) {
            if (auto it = entries_.find(key); it != entries_.end()) {
                lru_.splice(lru_.begin(), lru_, it->second.position);
                ++stats_.hits;
                return it->second.tile;
            }
            if (!loading_.contains(key)) break;
            const auto waitStart = std::chrono::steady_clock::now();
            loaded_.wait(lock);
            stats_.waitSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - waitStart).count();
        }
        loading_.insert(key);
        lock.unlock();
        std::shared_ptr<const Tile> tile;
        std::exception_ptr failure;
        const auto loadStart = std::chrono::steady_clock::now();
        try {
            tile = load_(key);
        } catch (...) {
            failure = std::current_exception();
        }
        const double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - loadStart).count();
        lock.lock();
        stats_.loadSeconds += loadSeconds;
        loading_.erase(key);
        if (failure) {
            loaded_.notify_all();
            std::rethrow_exception(failure);
        }
        ++stats_.loads;
        const size_t bytes = bytesOf_(*tile);
        lru_.push_front(key);
        entries_.emplace(key, Entry{tile, bytes, lru_.begin()});
        stats_.bytes += bytes;
        ++stats_.tiles;
        evictBeyondBudget();
        stats_.peakBytes = std::max(stats_.peakBytes, stats_.bytes);
        loaded_.notify_all();
        return tile;
    }

    struct Entry {
        std::shared_ptr<const Tile> tile;
        size_t bytes = 0;
        typename std::list<Key>::iterator position;
    };

    // Drops the least recently used tiles until the held bytes fit the budget, keeping the newest tile.
    void evictBeyondBudget() {
        while (stats_.bytes > budget_ && lru_.size() > 1) {
            const Key victim = lru_.back();
            lru_.pop_back();
            const auto it = entries_.find(victim);
            stats_.bytes -= it->second.bytes;
            entries_.erase(it);
            --stats_.tiles;
            ++stats_.evictions;
        }
    }

    // Tells caches apart in the threads' recent tiles (never reused, unlike addresses).
    static uint64_t nextId() {
        static std::atomic<uint64_t> counter{0};
        return ++counter;
    }

    const uint64_t id_ = nextId();
    std::atomic<int64_t> fastHits_{0};
    const size_t budget_;
    const Loader load_;
    const Sizer bytesOf_;
    mutable std::mutex mutex_;
    std::condition_variable loaded_;
    std::list<Key> lru_;  // most recent first
    std::unordered_map<Key, Entry> entries_;
    std::unordered_set<Key> loading_;  // keys a thread is loading now
    TileCacheStats stats_;
};

}  // namespace terracast
