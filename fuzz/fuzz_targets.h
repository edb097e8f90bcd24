// The bodies of the libFuzzer targets, as plain functions: the fuzz executables call them on generated
// inputs and the test suite replays every input kept in tests/fuzz/regressions/ through them.
//
// Each body returns normally for any input the code under test handles as documented (a result, or an
// InputError of one line for bad input) and throws FuzzFailure when it catches the code breaking a promise;
// anything else (a crash, a sanitizer report, another exception escaping) is a finding too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>

namespace terracast::fuzz {

// A broken property found by a fuzz body.
class FuzzFailure : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

// The scene-file parser on arbitrary text: it returns a scene or throws a one-line InputError.
void sceneFile(const uint8_t* data, size_t size);

// DEM loading on arbitrary bytes: the first byte picks the route (GDAL from an in-memory file, or a PNG file
// read by OpenImageIO), the rest is the file. Loading returns a grid with finite heights and at least one
// valid cell, or throws a one-line InputError naming the file.
void demLoader(const uint8_t* data, size_t size);

// The float bilinear cell intersector against the long-double one on a cell and a ray segment decoded from
// the bytes: a crossing is never missed, a hit lies on the segment, and well-conditioned roots agree.
void cellIntersector(const uint8_t* data, size_t size);

}  // namespace terracast::fuzz
