#include "tracer/core/ranks.h"

#include "tracer/core/modules.h"
#include "tracer/core/ranks_api.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

namespace terracast::ranks {

namespace {

const TerracastRanksApi* api = nullptr;  // set by start() in a launch
int myRank = 0, rankCount = 1;
bool finished = false;

bool many() { return api != nullptr && rankCount > 1; }

}  // namespace

bool launchedByMpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
        if (const char* v = std::getenv(name); v && *v) return true;
    return false;
}

void start() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (!launchedByMpi()) return;
        // Global: Open MPI opens its own components, which look for its symbols in the process.
        using Entry = const TerracastRanksApi* (*)();
        const auto entry = reinterpret_cast<Entry>(moduleEntry(modulePath("TERRACAST_MPI_MODULE", TERRACAST_MPI_MODULE_PATH),
                                                               "terracastRanks", "MPI", "TERRACAST_MPI_MODULE", true));
        const TerracastRanksApi* loaded = entry();
        if (loaded->version != TERRACAST_RANKS_API_VERSION)
            throw std::runtime_error("the MPI module is from another build of terracast (its interface is version " +
                                     std::to_string(loaded->version) + ", this program's " +
                                     std::to_string(TERRACAST_RANKS_API_VERSION) + "); set TERRACAST_MPI_MODULE to "
                                     "the module built with it");
        if (loaded->init(&myRank, &rankCount) != 0) throw std::runtime_error("MPI did not start");
        api = loaded;
    });
}

int rank() { return myRank; }
int size() { return rankCount; }

int sizeOnThisMachine() {
    for (const char* name : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"}) {
        const char* value = std::getenv(name);
        if (value == nullptr) continue;
        char* end = nullptr;
        const long n = std::strtol(value, &end, 10);
        if (end != value && *end == '\0' && n >= 1 && n <= rankCount) return int(n);
    }
    return rankCount;
}

void barrier() {
    if (many()) api->barrier();
}

void broadcast(void* data, size_t bytes, int root) {
    if (many()) api->broadcast(data, bytes, root);
}

void sum(int64_t* values, size_t count) {
    if (many()) api->sumInt64(values, count);
}

void sumToLeader(float* values, size_t count) {
    if (many()) api->sumFloatsToLeader(values, count);
}

void sumFloats(float* values, size_t count) {
    if (many()) api->sumFloats(values, count);
}

namespace {
// The collectives of a shared construction run on the thread that opened the scope.
thread_local int sharedWorkDepth = 0;
}  // namespace

SharedWork::SharedWork() { ++sharedWorkDepth; }
SharedWork::~SharedWork() { --sharedWorkDepth; }
bool sharingWork() { return many() && sharedWorkDepth > 0; }

WorkShare workShare() {
    if (!sharingWork()) return {};
    return {true, myRank, rankCount};
}

SpanTasks::SpanTasks(std::vector<int64_t> spanEnds) : spanEnds_(std::move(spanEnds)), cursor_(myRank) {
    if (many()) api->resetTasks();
}

int64_t SpanTasks::next() {
    if (spanEnds_.empty()) return 0;
    if (!many()) return std::min(local_++, spanEnds_.back());
    if (int(spanEnds_.size()) != rankCount) return std::min(api->nextTask(0), spanEnds_.back());
    return next(spanEnds_, cursor_, spent_, [](int s) { return api->nextTask(s); });
}

int64_t SpanTasks::next(const std::vector<int64_t>& spanEnds, int& cursor, int& spent,
                        const std::function<int64_t(int)>& fetchAdd) {
    const int spans = int(spanEnds.size());
    while (spent < spans) {
        const int s = cursor;
        const int64_t begin = s == 0 ? 0 : spanEnds[size_t(s - 1)];
        const int64_t task = begin + fetchAdd(s);
        if (task < spanEnds[size_t(s)]) return task;
        ++spent;
        cursor = (cursor + 1) % spans;
    }
    return spanEnds.empty() ? 0 : spanEnds.back();
}

void abortAll(int code) {
    if (many()) api->abortAll(code);
    std::_Exit(code);
}

void finish() {
    if (api != nullptr && !finished) {
        finished = true;
        api->finalize();
    }
}

std::string prefix() {
    return rankCount > 1 ? "rank " + std::to_string(myRank) + " of " + std::to_string(rankCount) + ": " : "";
}

}  // namespace terracast::ranks
