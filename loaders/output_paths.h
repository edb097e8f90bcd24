// Checks on output paths, made before any work so that a bad path costs nothing and never leaves a partial
// file: every command that writes runs its outputs through these.
#pragma once

#include <initializer_list>
#include <string>

namespace terracast {

// Refuses (InputError) an output path that names the input file `input`, however it is spelt (links, "..", hard
// links: device and inode are compared). `what` names the output, `inputName` the input in the message.
void checkNotInput(const std::string& output, const std::string& input, const char* what,
                   const char* inputName = "the input DEM");

// Refuses an output file whose folder does not exist.
void checkOutputFolder(const std::string& path);

// Refuses an output that is the input, whose extension is not one of `allowed`, or whose folder does not exist
// or does not take a new file.
void checkOutputPath(const std::string& output, const std::string& input,
                     std::initializer_list<const char*> allowed = {".png", ".exr"},
                     const char* inputName = "the input DEM");

// Refuses a report file (--json) whose folder does not exist or that names the input.
void checkReportPath(const std::string& path, const std::string& input);

}  // namespace terracast
