// libFuzzer entry point for the cell intersector target; the body is terracast::fuzz::cellIntersector (fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    terracast::fuzz::cellIntersector(data, size);
    return 0;
}
