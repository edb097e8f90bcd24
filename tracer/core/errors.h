// Errors raised for bad input: the CLI maps them to exit code 2.
#pragma once

#include <stdexcept>

namespace terracast {

// A user-facing error about an input (file, option or value). what() is one line that names the item,
// what was expected and what was found.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace terracast
