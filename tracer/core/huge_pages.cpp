#include "tracer/core/huge_pages.h"

#include "heightfield/large_buffer.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace terracast {
namespace {

#if defined(__linux__) && defined(MADV_HUGEPAGE)
// madvise needs page-aligned ranges, and only whole 2 MiB extents can become huge pages: the advice covers the
// aligned 2 MiB extents inside the array. A refusal (an old kernel) leaves the memory as it was.
void adviseHugePages(void* data, size_t bytes) {
    constexpr uintptr_t kHuge = uintptr_t(2) << 20;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}
#endif

}  // namespace

void useHugePagesForLargeBuffers() {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    setLargeBufferAdvisor(adviseHugePages);
#endif
}

}  // namespace terracast
