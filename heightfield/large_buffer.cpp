#include "heightfield/large_buffer.h"

#include <algorithm>
#include <atomic>
#include <system_error>
#include <thread>
#include <vector>

namespace terracast {
namespace {

LargeBufferAdvisor installedAdvisor = nullptr;

// Below this an array spans too few huge pages for the advice to matter.
constexpr size_t kLargeBytes = size_t(4) << 20;

std::atomic<int> arrayPassLimit{0};

}  // namespace

void setLargeBufferAdvisor(LargeBufferAdvisor advisor) { installedAdvisor = advisor; }

void adviseLargeBuffer(void* data, size_t bytes) {
    if (installedAdvisor && data && bytes >= kLargeBytes) installedAdvisor(data, bytes);
}

void setArrayPassThreads(int threads) { arrayPassLimit.store(std::max(threads, 0)); }

int arrayPassThreads() {
    if (const int limit = arrayPassLimit.load(); limit > 0) return limit;
    // hardware_concurrency reads a file under /sys on Linux: asked once.
    static const int hardwareThreads = int(std::max(1u, std::thread::hardware_concurrency()));
    return hardwareThreads;
}

void runInSlices(int64_t n, int64_t slices, const std::function<void(int64_t, int64_t)>& f) {
    slices = std::clamp<int64_t>(slices, 1, std::max<int64_t>(n, 1));
    auto part = [&](int64_t k) { f(n * k / slices, n * (k + 1) / slices); };
    std::vector<std::thread> pool;
    pool.reserve(size_t(slices - 1));
    int64_t started = 1;
    try {
        for (; started < slices; ++started) pool.emplace_back(part, started);
    } catch (const std::system_error&) {
        // No more threads to be had: the calling thread takes the parts not started.
    }
    part(0);
    for (int64_t k = started; k < slices; ++k) part(k);
    for (auto& thread : pool) thread.join();
}

}  // namespace terracast
