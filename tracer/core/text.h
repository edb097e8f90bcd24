// Small text helpers every layer uses: a path's lower-cased extension and a byte count for people.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace terracast {

// The extension of a path, lower-cased, with its dot (".tif"); empty when there is none.
std::string lowerExtension(const std::string& path);

// `text` on one line: newlines, tabs and other control characters escaped (\n, \t, \x1b), and cut at a UTF-8
// boundary after `maxBytes` bytes with "..." (no cut by default). File names in messages may hold any byte.
std::string escapeControls(std::string_view text, size_t maxBytes = std::string_view::npos);

// A byte count in binary units with one decimal: "512.0 B", "1.5 GiB".
std::string humanBytes(double bytes);

}  // namespace terracast
