// What every command of the `terracast` executable shares: typed option parsers (sizes, pairs, byte counts,
// named values), the DEM options, the listener that prints a job's lines on stdout and stderr, and the
// wrapper that turns a job's exceptions into one error line and an exit code.
#pragma once

#include "tracer/core/errors.h"
#include "tracer/core/listener.h"
#include "tracer/terrain/dem_pipeline.h"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace terracast::cli {

// A subcommand and what runs it once the command line is parsed; the runner returns the exit code.
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};
using Commands = std::vector<Command>;

// Each family of commands adds its subcommands to `app` and their runners to `commands`.
void addInfoCommand(CLI::App& app, Commands& commands);
void addRenderCommand(CLI::App& app, Commands& commands);
void addMapCommands(CLI::App& app, Commands& commands);
void addMeasureCommands(CLI::App& app, Commands& commands);
void addSceneCommand(CLI::App& app, Commands& commands);
void addBenchCommand(CLI::App& app, Commands& commands);

// `text` on one line: newlines, tabs and other control characters escaped (a file name may hold them).
std::string oneLine(std::string_view text);

// Runs a job: 0 when it returns, 2 with one line for bad input (InputError, GridError), 130 when interrupted,
// 1 for any other failure.
int guarded(const std::function<void()>& job);

// Prints a job's report on stdout, warnings always, notes unless `quiet`, and, when stderr is a terminal,
// status lines, and progress (percentage, rays per second, time left) unless `quiet`.
class ConsoleListener {
public:
    explicit ConsoleListener(bool quiet);
    ~ConsoleListener();
    const RunListener& listener() const { return listener_; }

private:
    struct Progress;
    std::unique_ptr<Progress> progress_;
    RunListener listener_;
};

// The option parsers: each returns nothing on malformed text.
std::optional<double> parseByteCount(const std::string& text);         // "512M", "8G", "1.5T", "1000000"
bool parseSize(const std::string& text, int& width, int& height);      // "WxH", positive, at most 65536
bool parsePair(const std::string& text, double& a, double& b);         // "A,B", finite

// Throws InputError "OPTION: expected ..., found 'TEXT'" unless `text` parses.
void parseSizeOption(const std::string& text, int& width, int& height);
void parseSunOption(const std::string& text, double& azimuthDeg, double& elevationDeg);
SurfaceMethod parseMethodOption(const std::string& text, const char* option = "--method");
// A value named by its enumeration's own parser (a sample pattern, a filter); `list` names the choices.
template <class E>
E parseNamedOption(const std::string& text, const char* option, std::optional<E> (*parse)(std::string_view),
                   const char* list) {
    if (const auto value = parse(text)) return *value;
    throw InputError(option + std::string(": expected one of ") + list + ", found '" + text + "'");
}
std::optional<PinholeCamera> parseCameraOption(const std::string& text, bool fisheye = false);  // empty text: none
UtcInstant parseSunTimeOption(const std::string& text);
// X,Y pixel indices.
void parsePixelOption(const std::string& text, const char* option, int& x, int& y);

// Validators whose messages say what was expected and what was found.
CLI::Validator finiteNumber();        // any finite number (no nan, inf, or overflow such as 1e999)
CLI::Validator positiveNumber();      // a finite number above 0
CLI::Validator nonNegativeInteger(int64_t max = 2147483647);  // a whole number from 0 to max
CLI::Validator numberRange(double lo, double hi, const char* what);  // "expected WHAT from LO to HI"
// Adds finiteNumber to every floating-point option of `app` and its subcommands, and nonNegativeInteger (up to
// 2^53) to every unsigned one, which would otherwise take -1 as 2^64 - 1.
void checkNumberOptions(CLI::App& app);

// --max-memory SIZE into `bytes`.
void addMaxMemoryOption(CLI::App& cmd, double& bytes, const std::string& help);
// The DEM argument and the options of every command that reads one.
void addDemOptions(CLI::App& cmd, DemSource& dem);

}  // namespace terracast::cli
