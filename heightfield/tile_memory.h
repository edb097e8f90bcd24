// Memory for the arrays of a tiled grid's tiles (docs/architecture.md, "Tiled grids"). A tiled job makes and
// drops thousands of arrays of a few hundred KiB as its cache turns over. Taken from the system, each would be
// fresh pages, faulted in one 4 KiB page at a time on first touch: a fifth of a tiled render's time when its
// tiles all fit. Here they are carved from chunks of 8 MiB offered to the large-buffer advisor (huge pages,
// large_buffer.h), and the arrays of a dropped tile are reused by the next of the same size. The memory is kept
// for reuse until the process ends: for each array size, the most arrays of that size held at once.
// Thread-safe.
#pragma once

#include <cstddef>
#include <new>
#include <utility>

namespace terracast {

// `bytes` of memory aligned for any array element, and its release (the same `bytes`).
void* allocateTileMemory(size_t bytes);
void releaseTileMemory(void* data, size_t bytes) noexcept;

// What allocateTileMemory holds: chunks taken from the system, and of them the bytes in arrays now.
struct TileMemoryStats {
    size_t chunkBytes = 0;
    size_t bytesInUse = 0;
};
TileMemoryStats tileMemoryStats();

// An allocator for tile arrays through allocateTileMemory, which also leaves elements uninitialised on resize:
// every element of a tile's arrays is written once when the tile is made.
template <class T>
struct TileAllocator {
    using value_type = T;
    TileAllocator() = default;
    template <class U>
    TileAllocator(const TileAllocator<U>&) noexcept {}
    T* allocate(size_t n) { return static_cast<T*>(allocateTileMemory(n * sizeof(T))); }
    void deallocate(T* p, size_t n) noexcept { releaseTileMemory(p, n * sizeof(T)); }
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    template <class U>
    bool operator==(const TileAllocator<U>&) const noexcept {
        return true;
    }
};

}  // namespace terracast
