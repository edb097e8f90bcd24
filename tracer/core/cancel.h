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

// Throws Cancelled when cancellation was requested.
inline void throwIfCancelled() {
    if (cancelFlag().load(std::memory_order_relaxed)) throw Cancelled();
}

}  // namespace terracast
