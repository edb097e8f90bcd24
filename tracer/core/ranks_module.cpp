// The MPI side of tracer/core/ranks.h: a module built against Open MPI and opened with dlopen, so that only
// runs under mpirun load MPI. Plain C types cross the boundary.
#include "tracer/core/ranks_api.h"

#include <mpi.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace {

MPI_Win counterWindow = MPI_WIN_NULL;
int64_t* counter = nullptr;
int counters = 1;

int init(int* rank, int* size) {
    // When every rank runs on this machine (Open MPI says so in the environment mpirun gives each rank), its
    // messages go through shared memory whichever point-to-point layer carries them; the default choice among
    // them probes the network fabrics first (libfabric, UCX), which took 0.2 s of a 0.5 s launch of two ranks
    // (docs/scale.md). The plain one (ob1, over shared memory) is then asked for, unless the user chose.
    const char* worldSize = std::getenv("OMPI_COMM_WORLD_SIZE");
    const char* localSize = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    if (worldSize && localSize && std::strcmp(worldSize, localSize) == 0 && std::getenv("OMPI_MCA_pml") == nullptr)
        ::setenv("OMPI_MCA_pml", "ob1", 0);
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) return 1;
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    // The shared task counts, one per rank (tasks handed out by spans, ranks.h): int64s on rank 0, read and
    // advanced atomically by MPI_Fetch_and_op under a passive lock that every rank holds for the whole run.
    counters = *size;
    const MPI_Aint bytes = *rank == 0 ? MPI_Aint(sizeof(int64_t)) * counters : 0;
    if (MPI_Win_allocate(bytes, sizeof(int64_t), MPI_INFO_NULL, MPI_COMM_WORLD, &counter, &counterWindow) !=
        MPI_SUCCESS)
        return 2;
    if (*rank == 0)
        for (int k = 0; k < counters; ++k) counter[k] = 0;
    MPI_Win_lock_all(0, counterWindow);
    MPI_Barrier(MPI_COMM_WORLD);
    return 0;
}

void barrier() { MPI_Barrier(MPI_COMM_WORLD); }

void broadcast(void* data, size_t bytes, int root) {
    for (size_t done = 0; done < bytes;) {
        const int chunk = int(bytes - done < (size_t(1) << 30) ? bytes - done : (size_t(1) << 30));
        MPI_Bcast(static_cast<char*>(data) + done, chunk, MPI_BYTE, root, MPI_COMM_WORLD);
        done += size_t(chunk);
    }
}

void sumInt64(int64_t* values, size_t count) {
    MPI_Allreduce(MPI_IN_PLACE, values, int(count), MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
}

void sumFloatsToLeader(float* values, size_t count) {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    for (size_t done = 0; done < count;) {
        const int chunk = int(count - done < (size_t(1) << 28) ? count - done : (size_t(1) << 28));
        MPI_Reduce(rank == 0 ? MPI_IN_PLACE : values + done, rank == 0 ? values + done : nullptr, chunk, MPI_FLOAT,
                   MPI_SUM, 0, MPI_COMM_WORLD);
        done += size_t(chunk);
    }
}

void sumFloats(float* values, size_t count) {
    for (size_t done = 0; done < count;) {
        const int chunk = int(count - done < (size_t(1) << 28) ? count - done : (size_t(1) << 28));
        MPI_Allreduce(MPI_IN_PLACE, values + done, chunk, MPI_FLOAT, MPI_SUM, MPI_COMM_WORLD);
        done += size_t(chunk);
    }
}

void resetTasks() {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        const int64_t zero = 0;
        for (int k = 0; k < counters; ++k) {
            int64_t old = 0;
            MPI_Fetch_and_op(&zero, &old, MPI_INT64_T, 0, MPI_Aint(k), MPI_REPLACE, counterWindow);
        }
        MPI_Win_flush(0, counterWindow);
    }
    MPI_Barrier(MPI_COMM_WORLD);
}

int64_t nextTask(int count) {
    const int64_t one = 1;
    int64_t task = 0;
    MPI_Fetch_and_op(&one, &task, MPI_INT64_T, 0, MPI_Aint(count), MPI_SUM, counterWindow);
    MPI_Win_flush(0, counterWindow);
    return task;
}

void abortAll(int code) { MPI_Abort(MPI_COMM_WORLD, code); }

void finalize() {
    if (counterWindow != MPI_WIN_NULL) {
        MPI_Win_unlock_all(counterWindow);
        MPI_Win_free(&counterWindow);
    }
    MPI_Finalize();
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) const TerracastRanksApi* terracastRanks() {
    static const TerracastRanksApi api{TERRACAST_RANKS_API_VERSION, init, barrier, broadcast, sumInt64, sumFloatsToLeader,
                                       sumFloats, resetTasks, nextTask, abortAll, finalize};
    return &api;
}

}  // extern "C"
