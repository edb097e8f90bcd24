// Small text helpers every layer uses: a path's lower-cased extension, escaped control characters, near misses
// for misspelt names, and a byte count for people.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace terracast {

// The extension of a path, lower-cased, with its dot (".tif"); empty when there is none.
std::string lowerExtension(const std::string& path);

// `text` on one line: newlines, tabs and other control characters escaped (\n, \t, \x1b), and cut at a UTF-8
// boundary after `maxBytes` bytes with "..." (no cut by default). File names in messages may hold any byte.
std::string escapeControls(std::string_view text, size_t maxBytes = std::string_view::npos);

// Optimal string alignment distance (Levenshtein's edits plus adjacent transpositions, after Damerau 1964),
// ignoring ASCII case.
size_t editDistance(std::string_view a, std::string_view b);

// Words longer than this get no near-miss suggestion (the edit distance costs the product of the lengths).
constexpr size_t kNearMissMaxLength = 64;

// The candidate closest to `word` if it is close enough to be a slip of the keyboard: one edit for words of
// up to four letters, two up to eight, three beyond. Ties go to the earlier candidate.
std::optional<std::string> nearMiss(std::string_view word, std::span<const std::string> candidates);

// A byte count in binary units with one decimal: "512.0 B", "1.5 GiB".
std::string humanBytes(double bytes);

}  // namespace terracast
