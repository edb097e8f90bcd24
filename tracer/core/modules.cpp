#include "tracer/core/modules.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace terracast {

std::string modulePath(const char* env, const std::string& builtPath) {
    if (const char* value = std::getenv(env); value && *value) return value;
    std::error_code ec;
    if (std::filesystem::exists(builtPath, ec)) return builtPath;
    const std::string name = std::filesystem::path(builtPath).filename().string();
    const std::filesystem::path installed = std::filesystem::path(TERRACAST_MODULE_INSTALL_DIR) / name;
    if (std::filesystem::exists(installed, ec)) return installed.string();
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? name : (self.parent_path() / name).string();
}

void* moduleEntry(const std::string& path, const char* entry, const std::string& what, const char* env, bool global) {
    void* module = dlopen(path.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
    if (!module) {
        const char* why = dlerror();
        throw std::runtime_error("cannot load the " + what + " module " + path + " (" + (why ? why : "unknown") +
                                 "); set " + env + " to its path");
    }
    void* function = dlsym(module, entry);
    if (!function) throw std::runtime_error("the " + what + " module " + path + " has no " + entry + " entry");
    return function;  // the module stays loaded for the life of the process
}

}  // namespace terracast
