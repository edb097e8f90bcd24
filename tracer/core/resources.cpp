#include "tracer/core/resources.h"

#include <cstdio>

#include <sys/resource.h>
#include <unistd.h>

namespace terracast {

double defaultMemoryLimitBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return 64.0 * 1024.0 * 1024.0 * 1024.0;
    return 0.8 * double(pages) * double(pageSize);
}

double memoryLimitBytes(double maxBytes) { return maxBytes > 0.0 ? maxBytes : defaultMemoryLimitBytes(); }

double currentResidentBytes() {
    // /proc/self/statm: total and resident size, in pages.
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (f == nullptr) return peakResidentBytes();
    long total = 0, resident = 0;
    const bool ok = std::fscanf(f, "%ld %ld", &total, &resident) == 2;
    std::fclose(f);
    return ok ? double(resident) * double(sysconf(_SC_PAGESIZE)) : peakResidentBytes();
}

double peakResidentBytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) * 1024.0;
}

}  // namespace terracast
