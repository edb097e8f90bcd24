#include "tracer/core/huge_pages.h"

#include "heightfield/large_buffer.h"

#include <algorithm>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace terracast {
namespace {

// Below this the faults of a first touch cost about what starting a thread does.
constexpr size_t kFaultInBytes = size_t(8) << 20;

// Faults the whole pages of [data, data + bytes) in, writable, on arrayPassThreads() threads (MADV_POPULATE_WRITE,
// Linux 5.14): the kernel zeroes each page, and on a virtual machine the host provides it, about 2 ms a MiB of
// memory the process has not used before on the machine of docs/bench.md, and those faults run in parallel.
// Nothing is written through the array. An older kernel refuses the advice and the thread that fills the array
// takes the faults, as without it.
void faultIn(void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    constexpr uintptr_t kPage = 4096;
    const int threads = arrayPassThreads();
    if (bytes < kFaultInBytes || threads <= 1) return;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kPage - 1) & ~(kPage - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kPage - 1);
    if (end <= begin) return;
    const int64_t pages = int64_t((end - begin) / kPage);
    runInSlices(pages, std::min<int64_t>(threads, int64_t(bytes / kFaultInBytes) * 2), [&](int64_t p0, int64_t p1) {
        if (p1 > p0) ::madvise(reinterpret_cast<void*>(begin + uintptr_t(p0) * kPage), size_t(p1 - p0) * kPage,
                               MADV_POPULATE_WRITE);
    });
#else
    (void)data;
    (void)bytes;
#endif
}

#if defined(__linux__) && defined(MADV_HUGEPAGE)
// madvise needs page-aligned ranges, and only whole 2 MiB extents can become huge pages: the advice covers the
// aligned 2 MiB extents inside the array. A refusal (an old kernel) leaves the memory as it was.
void adviseHugePages(void* data, size_t bytes) {
    constexpr uintptr_t kHuge = uintptr_t(2) << 20;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
    faultIn(data, bytes);
}
#endif

}  // namespace

void useHugePagesForLargeBuffers() {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    setLargeBufferAdvisor(adviseHugePages);
#endif
}

}  // namespace terracast
