// What a long job tells its caller while it runs. The library never prints: the CLI turns these calls into
// lines on stdout and stderr (progress only when stderr is a terminal), and a script can collect them.
// Every member may be empty, which drops what it would receive.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace terracast {

struct RunListener {
    std::function<void(const std::string&)> output;   // the report itself (tables), as text with its newlines
    std::function<void(const std::string&)> warning;  // one line about the input that does not stop the job
    std::function<void(const std::string&)> note;     // one line saying what was done (summaries, placements)
    std::function<void(const std::string&)> step;     // the step now running, for a status line
    std::function<void(double fraction, int64_t rays)> progress;  // share of the work done, rays traced so far
    std::function<void(const std::string&)> detail;   // a few words the progress line adds (tile loads, cache hits)

    void print(const std::string& text) const { if (output) output(text); }
    void warn(const std::string& line) const { if (warning) warning(line); }
    void tell(const std::string& line) const { if (note) note(line); }
    void at(const std::string& what) const { if (step) step(what); }
    void show(const std::string& words) const { if (detail) detail(words); }
};

}  // namespace terracast
