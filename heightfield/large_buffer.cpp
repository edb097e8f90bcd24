#include "heightfield/large_buffer.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace terracast {
namespace {

LargeBufferAdvisor installedAdvisor = nullptr;

// Below this an array spans too few huge pages for the advice to matter.
constexpr size_t kLargeBytes = size_t(4) << 20;

// Ranges smaller than this are touched on the calling thread: starting a thread costs about as much as the
// faults of a few MiB.
constexpr size_t kParallelTouchBytes = size_t(8) << 20;
// The smallest page: one write per page faults each in, whatever size the kernel backs the range with.
constexpr size_t kPageBytes = 4096;

void touchPages(volatile unsigned char* data, size_t bytes) {
    for (size_t k = 0; k < bytes; k += kPageBytes) data[k] = 0;
}

std::atomic<int> arrayPassLimit{0};

}  // namespace

void setArrayPassThreads(int threads) { arrayPassLimit.store(std::max(threads, 0)); }

int arrayPassThreads() {
    if (const int limit = arrayPassLimit.load(); limit > 0) return limit;
    // hardware_concurrency reads a file under /sys on Linux: asked once.
    static const int hardwareThreads = int(std::max(1u, std::thread::hardware_concurrency()));
    return hardwareThreads;
}

void touchLargeBuffer(void* data, size_t bytes) {
    if (!data || bytes < kParallelTouchBytes) return;
    const size_t threads = std::min(size_t(arrayPassThreads()), bytes / kParallelTouchBytes * 2);
    if (threads <= 1) return;
    auto* bytesAt = static_cast<volatile unsigned char*>(data);
    // Slices on page boundaries, each thread touching its own pages.
    const size_t pages = (bytes + kPageBytes - 1) / kPageBytes;
    auto slice = [&](size_t t) {
        const size_t p0 = pages * t / threads, p1 = pages * (t + 1) / threads;
        touchPages(bytesAt + p0 * kPageBytes, std::min(bytes, p1 * kPageBytes) - p0 * kPageBytes);
    };
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(slice, t);
    slice(0);
    for (auto& thread : pool) thread.join();
}

void setLargeBufferAdvisor(LargeBufferAdvisor advisor) { installedAdvisor = advisor; }

void adviseLargeBuffer(void* data, size_t bytes) {
    if (installedAdvisor && data && bytes >= kLargeBytes) installedAdvisor(data, bytes);
}

}  // namespace terracast
