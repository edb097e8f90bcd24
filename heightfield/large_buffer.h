// Large arrays: a grid's height codes and pyramid, a loader's whole-raster buffers. Each is allocated by
// largeVector(), which reserves its memory, offers it to the process's advisor before anything touches it, then
// fills it. The advisor is a hook so that this layer stays free of system headers: the executable installs one
// (tracer/core/huge_pages.h) that asks Linux to back the memory with transparent huge pages, which makes the
// first touch of a 300 MB buffer one fault per 2 MiB rather than per 4 KiB, and to fault it in on several
// threads (docs/architecture.md, "Memory").
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace terracast {

// Called with the bytes of each large array before it is first written.
using LargeBufferAdvisor = void (*)(void* data, size_t bytes);

// Installs `advisor` for every later largeVector() (nullptr: none). Not thread-safe: call it once at start-up.
void setLargeBufferAdvisor(LargeBufferAdvisor advisor);

// Offers [data, data + bytes) to the advisor when one is installed and the range is large (a few MiB or more).
void adviseLargeBuffer(void* data, size_t bytes);

// The threads that passes over whole arrays take (building a grid's codes, flags and pyramid, the advisor's
// faulting in below, a picture's sRGB levels): all cores unless a command limits them, as its --threads does.
// 0 = all cores.
void setArrayPassThreads(int threads);
// The count in force, at least 1.
int arrayPassThreads();

// Calls f(begin, end) once for each of `slices` contiguous parts of [0, n), the k-th [n k / slices,
// n (k + 1) / slices), each on a thread of its own (the first on the calling thread), and returns when all are
// done. A part whose thread cannot be started runs on the calling thread. f must not throw.
void runInSlices(int64_t n, int64_t slices, const std::function<void(int64_t, int64_t)>& f);

// A vector of `n` copies of `value`, its memory offered to the advisor before it is filled. The executable's
// advisor also faults the memory in on arrayPassThreads() threads (docs/architecture.md, "Memory"), so that the
// thread that fills it does not take every page fault alone.
template <class T>
std::vector<T> largeVector(size_t n, const T& value = T{}) {
    std::vector<T> v;
    v.reserve(n);
    adviseLargeBuffer(v.data(), n * sizeof(T));
    v.assign(n, value);
    return v;
}

}  // namespace terracast
