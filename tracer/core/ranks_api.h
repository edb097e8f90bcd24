// The functions of the MPI module (ranks_module.cpp), as tracer/core/ranks.cpp calls them: plain C types only.
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" {
// Raised whenever the table below changes, so that a module from another build is refused rather than called
// with the wrong arguments.
#define TERRACAST_RANKS_API_VERSION 3
struct TerracastRanksApi {
    int version;                        // TERRACAST_RANKS_API_VERSION of the module's build
    int (*init)(int* rank, int* size);  // 0 when MPI started
    void (*barrier)();
    void (*broadcast)(void* data, size_t bytes, int root);
    void (*sumInt64)(int64_t* values, size_t count);
    void (*sumFloatsToLeader)(float* values, size_t count);
    void (*sumFloats)(float* values, size_t count);  // over the ranks, in place on every rank
    void (*resetTasks)();                 // every shared count back to 0 (collective)
    int64_t (*nextTask)(int count);       // shared count `count` (0 .. ranks - 1): its value, then advanced by 1
    void (*abortAll)(int code);
    void (*finalize)();
};
}
