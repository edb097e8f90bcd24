// libFuzzer entry point for the dem loader target; the body is terracast::fuzz::demLoader (fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

#include <cstdlib>

// Before GDAL registers its drivers: those that would fetch from the network or open other files named inside
// the input are kept out of the fuzzer's way; every driver that reads a single file stays in, but netCDF:
// libnetcdf allocates what a header claims (gigabytes) before checking it against the file, which the fuzzer's
// 2 GB allocation limit reports as running out of memory. A process gets GDAL's "not a raster" error there
// (`terracast info` on the input that found it: exit 2 with the one-line message, 54 MB at its peak); the
// parser that over-allocates is libnetcdf's, not terracast's.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ::setenv("GDAL_SKIP", "VRT WMS WMTS WCS DAAS EEDA OGCAPI PLMosaic STACTA STACIT ESRIC NGW HTTP netCDF", 0);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    terracast::fuzz::demLoader(data, size);
    return 0;
}
