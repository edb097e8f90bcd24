#include "heightfield/tile_memory.h"

#include "heightfield/large_buffer.h"

#include <cstdlib>
#include <mutex>
#include <unordered_map>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define TERRACAST_TILE_MEMORY_FROM_NEW 1  // AddressSanitizer checks each array's bounds only on its own allocations
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TERRACAST_TILE_MEMORY_FROM_NEW 1
#endif
#endif

namespace terracast {
namespace {

constexpr size_t kChunkBytes = size_t(8) << 20;  // large enough for the advisor (large_buffer.cpp)
constexpr size_t kChunkAlignment = size_t(2) << 20;  // a huge page
constexpr size_t kPage = 4096;  // arrays take whole pages, so sizes repeat and reuse finds them
constexpr size_t kLargest = kChunkBytes / 4;  // larger arrays come from operator new

struct Pool {
    std::mutex mutex;
    std::unordered_map<size_t, std::vector<void*>> free;  // by rounded size
    std::vector<char*> chunks;  // every chunk taken (kept reachable, for leak checkers)
    char* chunk = nullptr;  // the chunk being carved
    size_t used = 0;        // of it
    TileMemoryStats stats;
};

Pool& pool() {
    static Pool* p = new Pool;  // never destroyed: tiles may be released during static destruction
    return *p;
}

size_t rounded(size_t bytes) { return (bytes + kPage - 1) / kPage * kPage; }

}  // namespace

void* allocateTileMemory(size_t bytes) {
#ifndef TERRACAST_TILE_MEMORY_FROM_NEW
    if (bytes > 0 && bytes <= kLargest) {
        const size_t size = rounded(bytes);
        Pool& p = pool();
        std::lock_guard lock(p.mutex);
        p.stats.bytesInUse += size;
        if (auto it = p.free.find(size); it != p.free.end() && !it->second.empty()) {
            void* data = it->second.back();
            it->second.pop_back();
            return data;
        }
        if (p.chunk == nullptr || p.used + size > kChunkBytes) {
            // The tail of the last chunk is left unused (less than one array).
            p.chunk = static_cast<char*>(std::aligned_alloc(kChunkAlignment, kChunkBytes));
            if (p.chunk == nullptr) {
                p.stats.bytesInUse -= size;
                throw std::bad_alloc();
            }
            try {
                p.chunks.push_back(p.chunk);
            } catch (...) {
                std::free(p.chunk);
                p.chunk = nullptr;
                p.stats.bytesInUse -= size;
                throw;
            }
            adviseLargeBuffer(p.chunk, kChunkBytes);
            p.used = 0;
            p.stats.chunkBytes += kChunkBytes;
        }
        void* data = p.chunk + p.used;
        p.used += size;
        return data;
    }
#endif
    return ::operator new(bytes);
}

void releaseTileMemory(void* data, size_t bytes) noexcept {
    if (data == nullptr) return;
#ifndef TERRACAST_TILE_MEMORY_FROM_NEW
    if (bytes > 0 && bytes <= kLargest) {
        const size_t size = rounded(bytes);
        Pool& p = pool();
        std::lock_guard lock(p.mutex);
        p.stats.bytesInUse -= size;
        try {
            p.free[size].push_back(data);
        } catch (...) {
            // Without room to remember it the array is lost to reuse, not to correctness.
        }
        return;
    }
#endif
    ::operator delete(data);
}

TileMemoryStats tileMemoryStats() {
    Pool& p = pool();
    std::lock_guard lock(p.mutex);
    return p.stats;
}

}  // namespace terracast
