#include "tracer/core/ranks.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>

extern "C" {
struct TerracastRanksApi {
    int (*init)(int*, int*);
    void (*barrier)();
    void (*broadcast)(void*, size_t);
    void (*sumInt64)(int64_t*, size_t);
    void (*sumFloatsToLeader)(float*, size_t);
    void (*resetTasks)();
    int64_t (*nextTask)();
    void (*abortAll)(int);
    void (*finalize)();
};
}

namespace terracast::ranks {

namespace {

const TerracastRanksApi* api = nullptr;  // set by start() in a launch
int myRank = 0, rankCount = 1;
std::atomic<int64_t> localTasks{0};
bool finished = false;

// Where the module is: TERRACAST_MPI_MODULE, else the build's own (when it is still there), else beside the
// executable.
std::string modulePath() {
    if (const char* env = std::getenv("TERRACAST_MPI_MODULE"); env && *env) return env;
    std::error_code ec;
    if (std::filesystem::exists(TERRACAST_MPI_MODULE_PATH, ec)) return TERRACAST_MPI_MODULE_PATH;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string name = std::filesystem::path(TERRACAST_MPI_MODULE_PATH).filename().string();
    return ec ? name : (self.parent_path() / name).string();
}

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
        const std::string path = modulePath();
        // Global: Open MPI opens its own components, which look for its symbols in the process.
        void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
        if (!module) {
            const char* why = dlerror();
            throw std::runtime_error("cannot load the MPI module " + path + " (" + (why ? why : "unknown") +
                                     "); set TERRACAST_MPI_MODULE to its path");
        }
        using Entry = const TerracastRanksApi* (*)();
        const auto entry = reinterpret_cast<Entry>(dlsym(module, "terracastRanks"));
        if (!entry) throw std::runtime_error("the MPI module " + path + " has no terracastRanks entry");
        const TerracastRanksApi* loaded = entry();
        if (loaded->init(&myRank, &rankCount) != 0) throw std::runtime_error("MPI did not start");
        api = loaded;
    });
}

int rank() { return myRank; }
int size() { return rankCount; }

void barrier() {
    if (many()) api->barrier();
}

void broadcast(void* data, size_t bytes) {
    if (many()) api->broadcast(data, bytes);
}

void sum(int64_t* values, size_t count) {
    if (many()) api->sumInt64(values, count);
}

void sumToLeader(float* values, size_t count) {
    if (many()) api->sumFloatsToLeader(values, count);
}

void resetTasks() {
    if (many()) api->resetTasks();
    else localTasks = 0;
}

int64_t nextTask() { return many() ? api->nextTask() : localTasks++; }

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
