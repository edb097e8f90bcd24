#include "cli/cli_support.h"

#include "loaders/image_io.h"

#include "heightfield/height_grid.h"
#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/ranks.h"
#include "tracer/core/text.h"

#include <fmt/core.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstdlib>

namespace terracast::cli {

std::string oneLine(std::string_view text) { return escapeControls(text); }

namespace {

// Prints a failure's line; in a launch of several ranks, names the rank and ends every rank with `code` (the
// others would wait for this one's tiles).
int fail(int code, const std::string& line) {
    fmt::print(stderr, "terracast: {}{}\n", ranks::prefix(), line);
    if (ranks::size() > 1) ranks::abortAll(code);
    return code;
}

}  // namespace

int guarded(const std::function<void()>& job) {
    try {
        job();
        return 0;
    } catch (const Cancelled&) {
        return fail(130, "interrupted; no output written");
    } catch (const InputError& e) {
        return fail(2, "error: " + oneLine(e.what()));
    } catch (const GridError& e) {
        return fail(2, "error: " + oneLine(e.what()));
    } catch (const std::bad_alloc&) {
        return fail(1, "error: out of memory");
    } catch (const std::exception& e) {
        return fail(1, "error: " + oneLine(e.what()));
    }
}

// Progress on stderr when it is a terminal: percentage, rays per second and time left; and status lines.
struct ConsoleListener::Progress {
    bool terminal = isatty(fileno(stderr)) != 0;
    bool dirty = false;
    std::string detail;  // appended to the progress line
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last{};

    void update(double fraction, int64_t rays) {
        const auto now = std::chrono::steady_clock::now();
        if (fraction < 1.0 && now - last < std::chrono::milliseconds(200)) return;
        last = now;
        const double elapsed = std::chrono::duration<double>(now - start).count();
        const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
        fmt::print(stderr, "\rrender {:5.1f}%  {:.2f} Mrays/s  ETA {:.0f} s{}{}   ", 100.0 * fraction,
                   elapsed > 0.0 ? double(rays) / elapsed * 1e-6 : 0.0, eta, detail.empty() ? "" : "  ", detail);
        dirty = true;
    }
    void status(const std::string& text) {
        if (text.empty()) {
            if (dirty) fmt::print(stderr, "\r{:100}\r", "");
            dirty = false;
            return;
        }
        fmt::print(stderr, "\r{}{:30}", text, "");
        dirty = true;
    }
    // Clears the progress line, so what follows starts at the left margin.
    void finish() {
        if (dirty) fmt::print(stderr, "\r{:100}\r", "");
        dirty = false;
    }
};

ConsoleListener::ConsoleListener(bool quiet) : progress_(std::make_unique<Progress>()) {
    // In a launch of several ranks the leader speaks for all; the others say only why they fail (guarded).
    if (!ranks::leader()) return;
    Progress* p = progress_.get();
    listener_.output = [p](const std::string& text) {
        p->finish();
        std::fputs(text.c_str(), stdout);
        std::fflush(stdout);
    };
    listener_.warning = [p](const std::string& line) {
        p->finish();
        fmt::print(stderr, "terracast: warning: {}\n", oneLine(line));
    };
    if (!quiet)
        listener_.note = [p](const std::string& line) {
            p->finish();
            fmt::print(stderr, "terracast: {}\n", line);
        };
    if (p->terminal) {
        listener_.step = [p](const std::string& text) { p->status(text); };
        if (!quiet) {
            listener_.progress = [p](double fraction, int64_t rays) { p->update(fraction, rays); };
            listener_.detail = [p](const std::string& words) { p->detail = words; };
        }
    }
}

ConsoleListener::~ConsoleListener() { progress_->finish(); }

std::optional<double> parseByteCount(const std::string& text) {
    try {
        size_t used = 0;
        double v = std::stod(text, &used);
        std::string unit = text.substr(used);
        if (unit.size() > 1 || !std::isfinite(v) || !(v > 0.0)) return std::nullopt;
        if (!unit.empty()) {
            const std::string units = "KMGT";
            const auto k = units.find(char(std::toupper(static_cast<unsigned char>(unit[0]))));
            if (k == std::string::npos) return std::nullopt;
            v *= std::pow(1024.0, double(k + 1));
        }
        return v;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

bool parseSize(const std::string& text, int& width, int& height) {
    const auto x = text.find_first_of("xX");
    if (x == std::string::npos) return false;
    try {
        size_t a = 0, b = 0;
        const long w = std::stol(text.substr(0, x), &a);
        const long h = std::stol(text.substr(x + 1), &b);
        if (a != x || b != text.size() - x - 1 || w <= 0 || h <= 0 || w > 65536 || h > 65536) return false;
        width = int(w);
        height = int(h);
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

bool parsePair(const std::string& text, double& a, double& b) {
    const auto comma = text.find(',');
    if (comma == std::string::npos) return false;
    try {
        size_t na = 0, nb = 0;
        const double x = std::stod(text.substr(0, comma), &na);
        const double y = std::stod(text.substr(comma + 1), &nb);
        if (na != comma || nb != text.size() - comma - 1 || !std::isfinite(x) || !std::isfinite(y)) return false;
        a = x;
        b = y;
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

void parseSizeOption(const std::string& text, int& width, int& height) {
    if (!parseSize(text, width, height))
        throw InputError(fmt::format("--size: expected WxH with whole numbers from 1 to 65536, found '{}'", oneLine(text)));
}

void parseSunOption(const std::string& text, double& azimuthDeg, double& elevationDeg) {
    if (!parsePair(text, azimuthDeg, elevationDeg))
        throw InputError(fmt::format("--sun: expected AZ,EL in degrees, found '{}'", text));
}

SurfaceMethod parseMethodOption(const std::string& text, const char* option) {
    return parseNamedOption(text, option, parseSurfaceMethod, surfaceMethodList());
}

std::optional<PinholeCamera> parseCameraOption(const std::string& text, bool fisheye) {
    if (text.empty()) return std::nullopt;
    PinholeCamera camera;
    if (auto err = parseCamera(text, camera, fisheye)) throw InputError("--camera: " + *err);
    return camera;
}

UtcInstant parseSunTimeOption(const std::string& text) {
    std::string why;
    const auto utc = parseIsoTime(text, why);
    if (!utc)
        throw InputError(fmt::format("--sun-time: expected an ISO 8601 time such as 2026-06-21T19:30Z, found '{}' ({})",
                                     text, why));
    return *utc;
}

void parsePixelOption(const std::string& text, const char* option, int& x, int& y) {
    double px = 0, py = 0;
    if (!parsePair(text, px, py) || px != std::floor(px) || py != std::floor(py))
        throw InputError(fmt::format("{}: expected X,Y pixel indices, found '{}'", option, text));
    x = int(px);
    y = int(py);
}

namespace {

// `text` as a number when all of it is one (nothing for text that is not), overflow giving infinity.
std::optional<double> numberIn(const std::string& text) {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size()) return std::nullopt;
    return v;
}

}  // namespace

CLI::Validator finiteNumber() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            const auto v = numberIn(text);
            if (v && !std::isfinite(*v)) return "expected a finite number, found '" + oneLine(text) + "'";
            return {};  // anything else is the option's own parser's to refuse
        },
        "", "finite");
}

CLI::Validator positiveNumber() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            const auto v = numberIn(text);
            if (!v || !std::isfinite(*v) || !(*v > 0.0))
                return "expected a finite number above 0, found '" + oneLine(text) + "'";
            return {};
        },
        "", "positive");
}

CLI::Validator nonNegativeInteger(int64_t max) {
    return CLI::Validator(
        [max](std::string& text) -> std::string {
            const auto v = numberIn(text);
            if (!v || !(*v >= 0.0) || *v != std::floor(*v) || *v > double(max))
                return fmt::format("expected a whole number from 0 to {}, found '{}'", max, oneLine(text));
            return {};
        },
        "", "non-negative");
}

CLI::Validator numberRange(double lo, double hi, const char* what) {
    return CLI::Validator(
        [lo, hi, what](std::string& text) -> std::string {
            const auto v = numberIn(text);
            if (!v || !(*v >= lo && *v <= hi))
                return fmt::format("expected {} from {:g} to {:g}, found '{}'", what, lo, hi, oneLine(text));
            return {};
        },
        "", "range");
}

void checkNumberOptions(CLI::App& app) {
    for (CLI::Option* option : app.get_options()) {
        if (option->get_type_name() == "FLOAT") option->check(finiteNumber());
        if (option->get_type_name() == "UINT") option->check(nonNegativeInteger(int64_t(1) << 53));
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) checkNumberOptions(*sub);
}

void addMaxMemoryOption(CLI::App& cmd, double& bytes, const std::string& help) {
    cmd.add_option_function<std::string>(
        "--max-memory",
        [&bytes](const std::string& text) {
            const auto parsed = parseByteCount(text);
            if (!parsed)
                throw CLI::ValidationError("--max-memory", "expected a size such as 512M or 8G, found '" + text + "'");
            bytes = *parsed;
        },
        help);
}

void addDemOptions(CLI::App& cmd, DemSource& dem) {
    addMaxMemoryOption(cmd, dem.maxMemoryBytes,
                       "Refuse jobs estimated to need more memory than this, e.g. 8G (default: 80% of physical memory)");
    cmd.add_option("DEM", dem.path, "Elevation raster: GeoTIFF, SRTM .hgt, any GDAL raster, or a PNG height map")
        ->required();
    cmd.add_option_function<std::string>(
        "--tile-cache",
        [&dem](const std::string& text) {
            const auto parsed = parseByteCount(text);
            if (!parsed || *parsed < 1.0)
                throw CLI::ValidationError("--tile-cache", "expected a size such as 256M or 2G, found '" + text + "'");
            dem.tileCacheBytes = *parsed;
        },
        "Hold the DEM as tiles read on demand, keeping at most this much of them, e.g. 256M (default: whole in "
        "memory when it fits in --max-memory, tiles otherwise)");
    cmd.add_flag("--tile-store", dem.tileStore,
                 "Held as tiles: keep them decoded in DEM.terracast-tiles (2 bytes a vertex for 16-bit heights, else 4) "
                 "and read them from there in later runs instead of decoding the DEM again");
    cmd.add_option("--cell-size", dem.imageCellSizeM, "PNG height maps: metres between samples (default 1)")
        ->check(positiveNumber());
    cmd.add_option("--height-scale", dem.imageHeightScale,
                   "PNG height maps: metres per stored unit, 0..255 or 0..65535 (default 1)")
        ->check(positiveNumber());
}

}  // namespace terracast::cli
