// The processes of one run (docs/architecture.md, "Ranks"): this process alone, or the ranks of an MPI launch
// (`mpirun -n K terracast ...`). MPI lives in a module of its own (libterracast_mpi.so, Open MPI), opened only
// when the environment shows that mpirun started the process, so a run without mpirun never loads it and
// behaves as one rank of one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace terracast::ranks {

// True when an MPI launcher started this process (Open MPI's, or any PMI / PMIx one).
bool launchedByMpi();

// Joins the launch's ranks (MPI_Init through the module) when launchedByMpi(), else does nothing; once per
// process. Throws std::runtime_error when the module cannot be loaded or MPI cannot start.
void start();

// This process's rank and the number of ranks (0 and 1 without a launch).
int rank();
int size();
inline bool leader() { return rank() == 0; }
// The ranks of the launch on this machine, which share its memory: from the launcher's environment (Open MPI's
// OMPI_COMM_WORLD_LOCAL_SIZE, MPICH's MPI_LOCALNRANKS), else size().
int sizeOnThisMachine();

// Collective operations: every rank must call them, in the same order.
void barrier();
// Rank `root`'s `bytes` bytes at `data` on every rank (the leader's by default).
void broadcast(void* data, size_t bytes, int root = 0);
// Sums `count` values over the ranks, in place on every rank.
void sum(int64_t* values, size_t count);
// Sums `count` floats over the ranks into the leader's array (the others' arrays are left as they were).
void sumToLeader(float* values, size_t count);
// Sums `count` floats over the ranks, in place on every rank.
void sumFloats(float* values, size_t count);

// While one of these is alive on every rank, the constructions that can split their work over the ranks do
// (the physical sky's tables: each rank fills a share of the entries, then the shares are summed on every rank,
// which gives every rank the whole tables, each entry as one process computes it). Every rank must then construct
// the same things, in the same order: only code that all ranks run alike opens one. Without ranks it changes
// nothing.
class SharedWork {
public:
    SharedWork();
    ~SharedWork();
    SharedWork(const SharedWork&) = delete;
    SharedWork& operator=(const SharedWork&) = delete;
};
// True inside a SharedWork of a launch of more than one rank.
bool sharingWork();
// This rank's share of work split k mod K: inside a SharedWork, the entries k with k mod size() = rank(); else all.
struct WorkShare {
    bool shared = false;
    int rank = 0, stride = 1;
    bool mine(int64_t k) const { return k % stride == rank; }
};
WorkShare workShare();

// The tasks of one job, 0 .. spanEnds.back() - 1, handed out over the ranks (the dynamic load balancing of tiles
// and picture blocks), cut into spans: span s ends (exclusive) at spanEnds[s]. With one span per rank, each rank
// takes the tasks of its own span in order first, then helps with the others' (r + 1, r + 2, ... round), taking
// their next tasks first come first served: a rank keeps to its part of the work (a part of the picture, which
// reads a part of the DEM) while it lasts, and the load still balances at the end. With any other number of
// spans, one shared count, first come first served. Every task goes to exactly one rank; next() returns
// spanEnds.back() once none is left. Making one is collective under ranks (the shared counts start again); one
// thread per rank calls next(). Without ranks the tasks come in order from a count of the object's own.
class SpanTasks {
public:
    explicit SpanTasks(std::vector<int64_t> spanEnds);
    int64_t next();

    // The hand-out itself, for one rank of spanEnds.size(), from shared counts that fetchAdd(s) reads and
    // advances by one; `cursor` (the rank's own span to begin with) and `spent` (0) are the rank's place.
    static int64_t next(const std::vector<int64_t>& spanEnds, int& cursor, int& spent,
                        const std::function<int64_t(int)>& fetchAdd);

private:
    std::vector<int64_t> spanEnds_;
    int cursor_ = 0, spent_ = 0;
    std::atomic<int64_t> local_{0};
};

// Ends every rank of the launch with `code` (MPI_Abort): after a failure on one rank, the others must not wait
// for it. Without a launch it only exits.
[[noreturn]] void abortAll(int code);

// Leaves MPI (MPI_Finalize) when start() joined it.
void finish();

// "rank R of K: " in a launch of more than one rank, else "".
std::string prefix();

}  // namespace terracast::ranks
