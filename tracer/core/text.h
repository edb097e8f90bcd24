// Small text helpers every layer uses: a path's lower-cased extension and a byte count for people.
#pragma once

#include <string>

namespace terracast {

// The extension of a path, lower-cased, with its dot (".tif"); empty when there is none.
std::string lowerExtension(const std::string& path);

// A byte count in binary units with one decimal: "512.0 B", "1.5 GiB".
std::string humanBytes(double bytes);

}  // namespace terracast
