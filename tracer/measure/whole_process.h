// Whole processes timed from outside: another program (or terracast itself) run as a child, its wall time and
// peak resident memory as the kernel accounts them, for the comparisons of `bench --file-to-picture`.
#pragma once

#include <string>
#include <vector>

namespace terracast {

struct ProcessRun {
    double seconds = 0.0;    // wall time from the spawn to the child's exit
    // The child's largest resident set, as GNU time (/usr/bin/time, Debian's time package) reports it; NaN
    // without it. The kernel's own count for a direct child (wait4's ru_maxrss) is no use here: exec carries
    // the spawning process's peak into it, so a child of a large process reads at least that process's size.
    double peakBytes = 0.0;
    int exitCode = 0;        // its exit status; 128 + N when killed by signal N
};

// Runs `argv` (argv[0] a path, or a name looked up on PATH) in `folder`, its standard output and error
// appended to `logPath`, and waits for it; through GNU time when installed, for the peak memory. Throws
// std::runtime_error when it cannot be started.
ProcessRun runTimedProcess(const std::vector<std::string>& argv, const std::string& folder, const std::string& logPath);

// The absolute path of the executable `name` on PATH, or empty when there is none.
std::string findOnPath(const std::string& name);

// The path of the running executable (/proc/self/exe), or empty where the system does not say.
std::string selfExecutablePath();

}  // namespace terracast
