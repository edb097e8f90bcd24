// libFuzzer entry point for the scene file target; the body is terracast::fuzz::sceneFile (fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    terracast::fuzz::sceneFile(data, size);
    return 0;
}
