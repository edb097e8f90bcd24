// Large arrays: a grid's height codes and pyramid, a loader's whole-raster buffers. Each is allocated by
// largeVector(), which reserves its memory, offers it to the process's advisor before anything touches it, then
// fills it. The advisor is a hook so that this layer stays free of system headers: the executable installs one
// (tracer/core/huge_pages.h) that asks Linux to back the memory with transparent huge pages, which makes the
// first touch of a 300 MB buffer one fault per 2 MiB rather than per 4 KiB (docs/architecture.md, "Memory").
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

namespace terracast {

// Called with the bytes of each large array before it is first written.
using LargeBufferAdvisor = void (*)(void* data, size_t bytes);

// Installs `advisor` for every later largeVector() (nullptr: none). Not thread-safe: call it once at start-up.
void setLargeBufferAdvisor(LargeBufferAdvisor advisor);

// Offers [data, data + bytes) to the advisor when one is installed and the range is large (a few MiB or more).
void adviseLargeBuffer(void* data, size_t bytes);

// The threads that passes over whole arrays in this layer take (building a grid's codes, flags and pyramid, and
// the first touch below): all cores unless a command limits them, as its --threads does. 0 = all cores.
void setArrayPassThreads(int threads);
// The count in force, at least 1.
int arrayPassThreads();

// Writes one byte of every page of [data, data + bytes), on several threads when the range is large, so that
// the page faults of a large array's first touch (the kernel zeroing each page and, on a virtual machine, the
// host providing it: about 2 ms a MiB on the machine of docs/bench.md) are taken on arrayPassThreads() threads
// rather than on the one thread that fills the array (docs/architecture.md, "Memory"). The bytes written are zeros; whatever
// fills the range afterwards overwrites them.
void touchLargeBuffer(void* data, size_t bytes);

// A vector of `n` copies of `value`, its memory offered to the advisor before it is filled.
template <class T>
std::vector<T> largeVector(size_t n, const T& value = T{}) {
    static_assert(std::is_trivially_copyable_v<T>, "largeVector touches the storage before it holds elements");
    std::vector<T> v;
    v.reserve(n);
    adviseLargeBuffer(v.data(), n * sizeof(T));
    touchLargeBuffer(v.data(), n * sizeof(T));
    v.assign(n, value);
    return v;
}

}  // namespace terracast
