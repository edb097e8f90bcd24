// The machine's memory as the memory guard sees it: the default limit and the process's peak so far.
#pragma once

namespace terracast {

// 80 % of physical memory (64 GiB when the system does not say).
double defaultMemoryLimitBytes();
// `maxBytes` when positive (a --max-memory value), else the default limit.
double memoryLimitBytes(double maxBytes);
// The most resident memory this process has held so far.
double peakResidentBytes();
// The resident memory this process holds now (libraries, everything allocated and touched).
double currentResidentBytes();

}  // namespace terracast
