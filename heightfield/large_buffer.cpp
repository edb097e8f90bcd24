#include "heightfield/large_buffer.h"

namespace terracast {
namespace {

LargeBufferAdvisor installedAdvisor = nullptr;

// Below this an array spans too few huge pages for the advice to matter.
constexpr size_t kLargeBytes = size_t(4) << 20;

}  // namespace

void setLargeBufferAdvisor(LargeBufferAdvisor advisor) { installedAdvisor = advisor; }

void adviseLargeBuffer(void* data, size_t bytes) {
    if (installedAdvisor && data && bytes >= kLargeBytes) installedAdvisor(data, bytes);
}

}  // namespace terracast
