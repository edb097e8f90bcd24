#include "tracer/core/resources.h"

#include <sys/resource.h>
#include <unistd.h>

namespace terracast {

double defaultMemoryLimitBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return 64.0 * 1024.0 * 1024.0 * 1024.0;
    return 0.8 * double(pages) * double(pageSize);
}

double memoryLimitBytes(double maxBytes) { return maxBytes > 0.0 ? maxBytes : defaultMemoryLimitBytes(); }

double peakResidentBytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) * 1024.0;
}

}  // namespace terracast
