#include "loaders/image_codec.h"

#include "tracer/core/modules.h"

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
const Api* load() {
    using Entry = const Api* (*)();
    const auto entry = reinterpret_cast<Entry>(moduleEntry(modulePath("TERRACAST_IMAGE_CODEC", TERRACAST_IMAGE_CODEC_PATH),
                                                           "terracastImageCodec", "image codec", "TERRACAST_IMAGE_CODEC",
                                                           false));
    return entry();
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
