// Cooperative cancellation: a process-wide flag that long loops check between tiles.
#pragma once

#include <atomic>
#include <stdexcept>

namespace terracast {

// Thrown by a loop that stopped because cancellation was requested.
class Cancelled : public std::runtime_error {
public:
    Cancelled() : std::runtime_error("interrupted") {}
};

// The flag; setting it (from a signal handler too: the store is lock-free) asks running loops to stop.
inline std::atomic<bool>& cancelFlag() {
    static std::atomic<bool> flag{false};
    return flag;
}

// How many ExitOnCancel scopes are open; read by the signal handler (the load is lock-free).
inline std::atomic<int>& exitOnCancelDepth() {
    static std::atomic<int> depth{0};
    return depth;
}

// While one lives, an interrupt ends the process at once with exit code 130 instead of waiting for a loop to
// look at the flag: for reads that can block inside a library (GDAL opening a pipe, a network path that never
// answers, a decoder) before any output or temporary file exists. The executable's signal handler honours it.
class ExitOnCancel {
public:
    ExitOnCancel() { exitOnCancelDepth().fetch_add(1); }
    ~ExitOnCancel() { exitOnCancelDepth().fetch_sub(1); }
    ExitOnCancel(const ExitOnCancel&) = delete;
    ExitOnCancel& operator=(const ExitOnCancel&) = delete;
};

// Inside an ExitOnCancel scope, a stretch that writes a file: while one lives an interrupt only sets the flag
// (the enclosing work stops at its next check), so that the write's temporary file is removed or renamed.
class DeferExitOnCancel {
public:
    DeferExitOnCancel() : saved_(exitOnCancelDepth().exchange(0)) {}
    ~DeferExitOnCancel() { exitOnCancelDepth().fetch_add(saved_); }
    DeferExitOnCancel(const DeferExitOnCancel&) = delete;
    DeferExitOnCancel& operator=(const DeferExitOnCancel&) = delete;

private:
    int saved_;
};

// Throws Cancelled when cancellation was requested.
inline void throwIfCancelled() {
    if (cancelFlag().load(std::memory_order_relaxed)) throw Cancelled();
}

}  // namespace terracast
