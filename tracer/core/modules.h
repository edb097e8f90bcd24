// Modules of this build that the executable opens only when a run needs them (the image codec, MPI), so that
// the runs without pictures or mpirun never load their libraries (docs/architecture.md, "Start-up").
#pragma once

#include <string>

namespace terracast {

// Where a module is: the environment variable `env` when it is set, else `builtPath` (the build's own) when it
// is still there, else the file of that name where `cmake --install` puts it (lib/terracast under the configured
// prefix), else beside the executable.
std::string modulePath(const char* env, const std::string& builtPath);

// Opens the module at `path` (its symbols global for the libraries it opens in turn when `global`) and returns
// its function `entry`, which stays valid for the life of the process. Throws std::runtime_error: "cannot load
// the WHAT module PATH (reason); set ENV to its path", or "the WHAT module PATH has no ENTRY entry".
void* moduleEntry(const std::string& path, const char* entry, const std::string& what, const char* env, bool global);

}  // namespace terracast
