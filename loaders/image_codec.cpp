#include "loaders/image_codec.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>

#ifdef TERRACAST_IMAGE_CODEC_LINKED
extern "C" const terracast::image_codec::Api* terracastImageCodec();
#endif

namespace terracast::image_codec {

namespace {

#ifdef TERRACAST_IMAGE_CODEC_LINKED
// Sanitized builds link the codec in (loaders/CMakeLists.txt says why).
const Api* load() { return terracastImageCodec(); }
#else
// Where the module is: TERRACAST_IMAGE_CODEC, else the build's own (when it is still there), else beside the
// executable.
std::string modulePath() {
    if (const char* env = std::getenv("TERRACAST_IMAGE_CODEC"); env && *env) return env;
    std::error_code ec;
    if (std::filesystem::exists(TERRACAST_IMAGE_CODEC_PATH, ec)) return TERRACAST_IMAGE_CODEC_PATH;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string name = std::filesystem::path(TERRACAST_IMAGE_CODEC_PATH).filename().string();
    return ec ? name : (self.parent_path() / name).string();
}

const Api* load() {
    const std::string path = modulePath();
    void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!module) {
        const char* why = dlerror();
        throw std::runtime_error("cannot load the image codec module " + path + " (" + (why ? why : "unknown") +
                                 "); set TERRACAST_IMAGE_CODEC to its path");
    }
    using Entry = const Api* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(module, "terracastImageCodec"));
    if (!entry) throw std::runtime_error("the image codec module " + path + " has no terracastImageCodec entry");
    return entry();  // the module stays loaded for the life of the process
}
#endif

}  // namespace

const Api& api() {
    static std::once_flag once;
    static const Api* loaded = nullptr;
    std::call_once(once, [] { loaded = load(); });
    return *loaded;
}

}  // namespace terracast::image_codec
