#include "cli/commands.h"

#include "tracer/core/angles.h"

#include "cli/height_png.h"

#include "loaders/dem_loader.h"
#include "tracer/core/errors.h"
#include "loaders/image_io.h"
#include "loaders/crs.h"
#include "loaders/raster_writer.h"
#include "loaders/scene_assets.h"
#include "loaders/scene_file.h"
#include "heightfield/fractal_terrain.h"
#include "tracer/measure/accuracy.h"
#include "tracer/measure/bench.h"
#include "tracer/core/cancel.h"
#include "tracer/measure/compare.h"
#include "tracer/terrain/maps.h"
#include "tracer/scene/scene_renderer.h"
#include "tracer/terrain/terrain_renderer.h"

#include <fmt/core.h>

#include <sys/resource.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <thread>

namespace terracast {

namespace {

// Runs a command body, mapping exceptions to one line on stderr and an exit code.
template <class Body>
int guarded(Body&& body) {
    try {
        return body();
    } catch (const Cancelled&) {
        fmt::print(stderr, "terracast: interrupted; no output written\n");
        return 130;
    } catch (const InputError& e) {
        fmt::print(stderr, "terracast: error: {}\n", e.what());
        return 2;
    } catch (const GridError& e) {
        fmt::print(stderr, "terracast: error: {}\n", e.what());
        return 2;
    } catch (const std::bad_alloc&) {
        fmt::print(stderr, "terracast: error: out of memory\n");
        return 1;
    } catch (const std::exception& e) {
        fmt::print(stderr, "terracast: error: {}\n", e.what());
        return 1;
    }
}

LoadedDem load(const DemOptions& o) {
    DemLoadOptions lo;
    lo.maxBytes = o.maxMemoryBytes;
    lo.imageCellSizeM = o.imageCellSizeM;
    lo.imageHeightScale = o.imageHeightScale;
    LoadedDem dem = loadDem(o.path, lo);
    for (const auto& w : dem.warnings) fmt::print(stderr, "terracast: warning: {}\n", w);
    return dem;
}

std::string humanBytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 4) {
        bytes /= 1024.0;
        ++u;
    }
    return fmt::format("{:.1f} {}", bytes, units[u]);
}

double peakResidentBytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) * 1024.0;
}

// The one-line summary that ends a raster command: what was written, its size, seconds and peak memory.
void printRasterSummary(const std::string& what, const std::string& path, const MapRaster& r,
                        std::chrono::steady_clock::time_point start) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(stderr, "terracast: {} {} ({} x {} vertices) in {:.2f} s, peak memory {}\n", what, path, r.width, r.height,
               seconds, humanBytes(peakResidentBytes()));
}

// Progress on stderr when it is a terminal: percentage, rays per second and time left.
class TerminalProgress {
public:
    explicit TerminalProgress(bool enabled) : enabled_(enabled && isatty(fileno(stderr))) {}
    void update(double fraction, int64_t rays) {
        if (!enabled_) return;
        const auto now = std::chrono::steady_clock::now();
        if (fraction < 1.0 && now - last_ < std::chrono::milliseconds(200)) return;
        last_ = now;
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
        fmt::print(stderr, "\rrender {:5.1f}%  {:.2f} Mrays/s  ETA {:.0f} s   ", 100.0 * fraction,
                   elapsed > 0.0 ? double(rays) / elapsed * 1e-6 : 0.0, eta);
        dirty_ = true;
    }
    // Clears the progress line, so what follows starts at the left margin.
    void finish() {
        if (dirty_) fmt::print(stderr, "\r{:60}\r", "");
        dirty_ = false;
    }
    ~TerminalProgress() { finish(); }

private:
    bool enabled_;
    bool dirty_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_{};
};


// The extension of a path, lower-cased, with its dot.
std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// Refuses an output path that names the input DEM.
void checkNotInput(const std::string& output, const std::string& input, const char* what) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(output, ec) && fs::exists(input, ec) && fs::equivalent(output, input, ec))
        throw InputError(fmt::format("{}: {} is the input DEM; refusing to overwrite it", output, what));
}

// Checks an output path before any work: it is not the input DEM, its extension is one of `allowed`, and its
// folder exists and takes a new file.
void checkOutputPath(const std::string& output, const std::string& input,
                     std::initializer_list<const char*> allowed = {".png", ".exr"}) {
    namespace fs = std::filesystem;
    checkNotInput(output, input, "output path");
    const std::string ext = lowerExtension(output);
    bool ok = false;
    std::string expected;
    for (const char* a : allowed) {
        ok = ok || ext == a;
        expected += (expected.empty() ? "" : " or ") + std::string(a);
    }
    if (!ok) throw InputError(fmt::format("{}: unsupported output format '{}' (expected {})", output, ext, expected));
    std::error_code ec;
    const fs::path dir = fs::path(output).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw InputError(fmt::format("{}: output folder '{}' does not exist", output, dir.string()));
    checkCanWrite(output);
}

// The direct cell method behind a surface method; the map commands trace the grid directly.
CellMethod directMethod(SurfaceMethod m, const char* command) {
    switch (m) {
    case SurfaceMethod::Bilinear: return CellMethod::Bilinear;
    case SurfaceMethod::BilinearDouble: return CellMethod::BilinearDouble;
    case SurfaceMethod::Triangles: return CellMethod::Triangles;
    case SurfaceMethod::Nearest: return CellMethod::Nearest;
    case SurfaceMethod::Reference: return CellMethod::Reference;
    default: break;
    }
    throw InputError(fmt::format("--method: {} traces the grid directly; expected bilinear, bilinear-double, "
                                 "triangles, nearest or reference, found '{}'",
                                 command, surfaceMethodName(m)));
}

// Writes a per-vertex map raster as a Float32 GeoTIFF on the DEM's own grid (NaN becomes nodata -9999).
void writeVertexRaster(const std::string& path, const LoadedDem& dem, const MapRaster& r, RasterType type,
                       double noData) {
    GridRaster out;
    out.width = r.width;
    out.height = r.height;
    out.values = r.values;
    out.hasNoData = true;
    out.noDataValue = noData;
    for (float& v : out.values)
        if (std::isnan(v)) v = float(noData);
    writeGeoTiff(path, out, type, dem.geo, dem.geo.originX, dem.geo.originY, sourcePixelSizeX(dem.geo),
                 sourcePixelSizeY(dem.geo));
}

// Checks the view values every rendering command shares, before any loading.
void checkViewValues(double exaggeration, double sunElevationDeg) {
    if (!(exaggeration > 0.0) || !std::isfinite(exaggeration))
        throw InputError(fmt::format("--exaggeration: expected a positive number, found {}", exaggeration));
    if (!(sunElevationDeg >= -90.0 && sunElevationDeg <= 90.0))
        throw InputError(fmt::format("--sun: elevation must lie in [-90, 90] degrees, found {}", sunElevationDeg));
}

// Refuses a job whose estimate (the grid already loaded, plus `extraBytes` still to allocate: films,
// Embree's scene) exceeds the memory limit, before allocating any of it.
void checkMemory(const DemOptions& dem, const HeightGrid& grid, double extraBytes, const std::string& what) {
    const double limit = dem.maxMemoryBytes > 0.0 ? dem.maxMemoryBytes : defaultMemoryLimitBytes();
    const double need = double(grid.memoryBytes()) + extraBytes;
    if (need > limit)
        throw InputError(fmt::format("{}: {} needs about {} ({} for the grid), more than the {} limit (--max-memory)",
                                     dem.path, what, humanBytes(need), humanBytes(double(grid.memoryBytes())),
                                     humanBytes(limit)));
}

// Embree's bytes per cell, as measured on this project's DEMs (triangle mesh peak, grid geometry).
double embreeBytesEstimate(SurfaceMethod m, const HeightGrid& grid) {
    const double cells = double(grid.validCellCount());
    if (m == SurfaceMethod::Embree) return 230.0 * cells;
    if (m == SurfaceMethod::EmbreeGrid) return 40.0 * cells;
    return 0.0;
}

// Applies the exaggeration to the loaded grid and builds the view: size, sun, camera (automatic or parsed).
TerrainRenderSettings makeView(HeightGrid& grid, int width, int height, double sunAzimuthDeg, double sunElevationDeg,
                               double exaggeration, const std::string& camera, int threads) {
    if (exaggeration != 1.0) {
        const float k = float(exaggeration);
        const double top = std::max(std::abs(double(grid.minHeightM())), std::abs(double(grid.maxHeightM())));
        if (!(k > 0.0f) || !std::isfinite(double(k) * top) || double(k) * top > 1e12)
            throw InputError(fmt::format("--exaggeration: {} makes heights of up to {:.0f} m unusable (expected a "
                                         "factor that keeps them below 1e12 m)",
                                         exaggeration, top));
        grid.scaleHeights(k);
    }
    TerrainRenderSettings s;
    s.width = width;
    s.height = height;
    s.threads = threads;
    s.sun.azimuthDeg = sunAzimuthDeg;
    s.sun.elevationDeg = sunElevationDeg;
    s.camera = autoCamera(grid, double(width) / double(height));
    if (!camera.empty())
        if (auto err = parseCamera(camera, s.camera)) throw InputError("--camera: " + *err);
    return s;
}

std::string jsonNumber(double v) {
    if (!std::isfinite(v)) return "null";
    return fmt::format("{:.6g}", v);
}

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (static_cast<unsigned char>(c) < 0x20) {
            out += fmt::format("\\u{:04x}", int(c));
            continue;
        }
        out += c;
    }
    return out + "\"";
}

std::string errorJson(const ErrorSummary& e) {
    return fmt::format("{{\"mean\": {}, \"p99\": {}, \"max\": {}}}", jsonNumber(e.mean), jsonNumber(e.p99),
                       jsonNumber(e.max));
}

}  // namespace

bool parseByteCount(const std::string& text, double& bytes) {
    try {
        size_t used = 0;
        double v = std::stod(text, &used);
        std::string unit = text.substr(used);
        if (unit.size() > 1 || !std::isfinite(v) || !(v > 0.0)) return false;
        if (!unit.empty()) {
            const std::string units = "KMGT";
            const auto k = units.find(char(std::toupper(static_cast<unsigned char>(unit[0]))));
            if (k == std::string::npos) return false;
            v *= std::pow(1024.0, double(k + 1));
        }
        bytes = v;
        return true;
    } catch (const std::exception&) {
        return false;
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

int runInfo(const InfoOptions& options) {
    return guarded([&] {
        const LoadedDem dem = load(options.dem);
        const HeightGrid& g = dem.grid;
        const double total = double(g.width()) * double(g.height());
        fmt::print("file:        {}\n", dem.path);
        fmt::print("driver:      {}\n", dem.driver);
        fmt::print("size:        {} x {} vertices ({} x {} cells)\n", g.width(), g.height(), g.cellsX(), g.cellsY());
        if (dem.geo.georeferenced) {
            fmt::print("crs:         {}{}\n", dem.geo.crsName.empty() ? "(unnamed)" : dem.geo.crsName,
                       dem.geo.geographic ? fmt::format(" (geographic, converted at latitude {:.4f})",
                                                        dem.geo.centreLatDeg)
                                          : "");
            fmt::print("origin:      {:.3f}, {:.3f} (south-west sample, CRS units)\n", dem.geo.originX, dem.geo.originY);
        } else {
            fmt::print("crs:         none (plain height map)\n");
        }
        fmt::print("cell size:   {:.3f} x {:.3f} m\n", g.cellSizeXM(), g.cellSizeYM());
        fmt::print("extent:      {:.1f} x {:.1f} m\n", g.extentXM(), g.extentYM());
        fmt::print("heights:     {:.2f} .. {:.2f} m\n", g.minHeightM(), g.maxHeightM());
        fmt::print("nodata:      {:.2f}% of vertices ({} of {}), {} valid cells\n",
                   100.0 * double(g.nodataVertexCount()) / total, g.nodataVertexCount(), int64_t(total),
                   g.validCellCount());
        fmt::print("memory:      {} for the grid; about {} to render at 1280x720\n", humanBytes(double(g.memoryBytes())),
                   humanBytes(double(g.memoryBytes()) + 1280.0 * 720.0 * 12.0));
        return 0;
    });
}

namespace {

// `render --view map`: the top-down shaded relief, as a GeoTIFF on the DEM's georeference or a PNG.
// The sky model named by --sky.
SkyKind parseSkyOption(const std::string& name) {
    if (name == "physical") return SkyKind::Physical;
    if (name == "gradient") return SkyKind::Gradient;
    if (name == "flat") return SkyKind::Flat;
    if (name == "none") return SkyKind::None;
    throw InputError(fmt::format("--sky: expected physical, gradient, flat or none, found '{}'", name));
}

// With --sun-time, the sun's azimuth and (apparent) elevation at that instant over the DEM's centre.
void applySunTime(const RenderOptions& o, const LoadedDem& dem, double& azimuthDeg, double& elevationDeg) {
    if (!o.sunTime) return;
    const std::string line = placeSunOverGrid(*o.sunTime, dem.geo, dem.grid.width(), dem.grid.height(),
                                              o.dem.path + ": --sun-time", azimuthDeg, elevationDeg);
    if (!o.quiet) fmt::print(stderr, "terracast: {}\n", line);
}

int renderMap(const RenderOptions& o) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff", ".png"});
    checkViewValues(o.exaggeration, o.sunElevationDeg);
    if (!(o.scale > 0.0 && o.scale <= 16.0)) throw InputError(fmt::format("--scale: expected (0, 16], found {}", o.scale));
    if (!(o.hillshadeBlend >= 0.0 && o.hillshadeBlend <= 1.0))
        throw InputError(fmt::format("--hillshade-blend: expected 0..1, found {}", o.hillshadeBlend));
    if (o.skySamples < -1 || o.skySamples > 4096)
        throw InputError(fmt::format("--sky-samples: expected 0..4096, found {}", o.skySamples));
    LoadedDem dem = load(o.dem);
    double sunAzimuthDeg = o.sunAzimuthDeg, sunElevationDeg = o.sunElevationDeg;
    applySunTime(o, dem, sunAzimuthDeg, sunElevationDeg);
    TerrainRenderSettings view = makeView(dem.grid, 16, 16, sunAzimuthDeg, sunElevationDeg, o.exaggeration, "", o.threads);
    MapViewSettings m;
    m.scale = o.scale;
    m.sun = view.sun;
    m.castShadows = o.castShadows;
    m.skySamples = o.skySamples < 0 ? 16 : o.skySamples;
    m.colourRamp = o.colourRamp;
    m.hillshadeBlend = o.hillshadeBlend;
    m.method = directMethod(o.method, "--view map");
    m.threads = o.threads;
    const auto start = std::chrono::steady_clock::now();
    const Film film = renderMapView(dem.grid, m);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (lowerExtension(o.output) == ".png") {
        writeImage(o.output, RgbImage{film.width, film.height, film.rgb});
    } else {
        // 8-bit sRGB in three bands, rows south first as the writer expects; pixel centres on the DEM's CRS.
        GridRaster out;
        out.width = film.width;
        out.height = film.height;
        out.bands = 3;
        out.values.resize(size_t(film.width) * size_t(film.height) * 3);
        for (int y = 0; y < film.height; ++y)
            for (int x = 0; x < film.width; ++x) {
                const glm::vec3 c = film.get(x, film.height - 1 - y);
                for (int b = 0; b < 3; ++b)
                    out.values[(size_t(y) * size_t(film.width) + size_t(x)) * 3 + size_t(b)] = 255.0f * srgbFromLinear(c[b]);
            }
        const double pxX = dem.grid.extentXM() / film.width / dem.grid.cellSizeXM() * sourcePixelSizeX(dem.geo);
        const double pxY = dem.grid.extentYM() / film.height / dem.grid.cellSizeYM() * sourcePixelSizeY(dem.geo);
        writeGeoTiff(o.output, out, RasterType::Byte, dem.geo, dem.geo.originX + 0.5 * pxX, dem.geo.originY + 0.5 * pxY,
                     pxX, pxY);
    }
    if (!o.quiet)
        fmt::print(stderr, "terracast: map {} ({}x{}, {}) in {:.2f} s; shadows {}, {} sky rays per pixel\n", o.output,
                   film.width, film.height, cellMethodName(m.method), seconds, m.castShadows ? "on" : "off",
                   m.skySamples);
    return 0;
}

}  // namespace

namespace {

// Wall-clock seconds of the phases of one perspective render, as `render` runs it.
struct RenderPhaseSeconds {
    double load = 0.0;    // reading the DEM (and, for the direct tracer, making its pyramid) and setting the view
    double build = 0.0;   // the surface: nothing more for the direct tracer, Embree's buffers and BVH
    double render = 0.0;  // tracing and shading the picture
    double write = 0.0;   // encoding and writing the picture
    double total = 0.0;   // from the first check of the options to the picture on disk
};

// `render` without --view map: checks, loads, builds, renders and writes. Throws as the commands do; fills
// `phases` when given.
void renderPerspective(const RenderOptions& o, RenderPhaseSeconds* phases) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    checkOutputPath(o.output, o.dem.path);
    checkViewValues(o.exaggeration, o.sunElevationDeg);
    if (o.skySamples < -1 || o.skySamples > 4096)
        throw InputError(fmt::format("--sky-samples: expected 0..4096, found {}", o.skySamples));
    if (!(o.haze >= 0.0 && o.haze <= 1000.0))
        throw InputError(fmt::format("--haze: expected a number in 0..1000, found {}", o.haze));
    const SkyKind sky = parseSkyOption(o.sky);
    LoadedDem dem = load(o.dem);
    HeightGrid& grid = dem.grid;
    double sunAzimuthDeg = o.sunAzimuthDeg, sunElevationDeg = o.sunElevationDeg;
    applySunTime(o, dem, sunAzimuthDeg, sunElevationDeg);
    TerrainRenderSettings s = makeView(grid, o.width, o.height, sunAzimuthDeg, sunElevationDeg, o.exaggeration,
                                       o.camera, o.threads);
    s.sky.kind = sky;
    s.sky.haze = o.haze;
    s.sky.samples = o.skySamples < 0 ? 4 : o.skySamples;
    s.seed = o.seed;
    TerminalProgress progress(!o.quiet);
    s.progress = [&](double f, int64_t rays) { progress.update(f, rays); };

    checkMemory(o.dem, grid, double(o.width) * o.height * 12.0 + embreeBytesEstimate(o.method, grid),
                fmt::format("rendering {}x{} with {}", o.width, o.height, surfaceMethodName(o.method)));
    const auto loaded = Clock::now();
    const TerrainSurface surface(grid, o.method, o.threads);
    const auto built = Clock::now();
    RenderStats stats;
    Film film = renderTerrain(grid, surface, s, &stats);
    progress.finish();
    const auto rendered = Clock::now();
    writeImage(o.output, RgbImage{film.width, film.height, std::move(film.rgb)});
    if (phases) {
        const auto written = Clock::now();
        const auto seconds = [](Clock::time_point a, Clock::time_point b) {
            return std::chrono::duration<double>(b - a).count();
        };
        phases->load = seconds(start, loaded);
        phases->build = seconds(loaded, built);
        phases->render = seconds(built, rendered);
        phases->write = seconds(rendered, written);
        phases->total = seconds(start, written);
    }
    if (!o.quiet) {
        const int64_t rays = stats.primaryRays + stats.shadowRays + stats.skyVisibilityRays;
        fmt::print(stderr,
                   "terracast: rendered {} ({}x{}, {}, {} sky) in {:.2f} s: {} primary + {} shadow + {} sky-visibility "
                   "rays, {:.2f} Mrays/s, peak memory {}\n",
                   o.output, o.width, o.height, surfaceMethodName(o.method), o.sky, stats.seconds,
                   stats.primaryRays, stats.shadowRays, stats.skyVisibilityRays,
                   stats.seconds > 0 ? double(rays) / stats.seconds * 1e-6 : 0.0,
                   humanBytes(peakResidentBytes()));
    }
}

}  // namespace

int runRender(const RenderOptions& o) {
    return guarded([&] {
        if (o.mapView) return renderMap(o);
        renderPerspective(o, nullptr);
        return 0;
    });
}

int runAccuracy(const AccuracyCommandOptions& o) {
    return guarded([&] {
        if (o.rays < 3 || o.rays > 100000000)
            throw InputError(fmt::format("--rays: expected 3 .. 100000000, found {}", o.rays));
        if (!o.json.empty()) {
            const auto dir = std::filesystem::path(o.json).parent_path();
            std::error_code ec;
            if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
                throw InputError(fmt::format("{}: output folder '{}' does not exist", o.json, dir.string()));
            checkNotInput(o.json, o.dem.path, "--json");
        }
        const LoadedDem dem = load(o.dem);
        AccuracyOptions options;
        options.rays = o.rays;
        options.seed = o.seed;
        const auto start = std::chrono::steady_clock::now();
        const AccuracyReport r = measureAccuracy(dem.grid, options);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        fmt::print("{}: {} x {} vertices, {} rays ({} camera, {} grazing, {} shadow), seed {}\n", dem.path,
                   dem.grid.width(), dem.grid.height(), r.rays, r.cameraRays, r.grazingRays, r.shadowRays, o.seed);
        fmt::print("reference: bilinear patch in long double; {} hits; {} rays ({:.3f}%) flagged ambiguous "
                   "(grazing within {:.2g} m)\n",
                   r.referenceHits, r.ambiguousRays, 100.0 * double(r.ambiguousRays) / double(r.rays),
                   r.grazingToleranceM);
        fmt::print("{:<16} {:>10} {:>11} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "method", "Mrays/s",
                   "agreement", "unamb.dis", "t mean m", "t p99 m", "t max m", "rel mean", "rel p99", "rel max");
        for (const auto& m : r.methods) {
            fmt::print("{:<16} {:>10.3f} {:>11.6f} {:>9} {:>10.3g} {:>10.3g} {:>10.3g} {:>10.3g} {:>10.3g} {:>10.3g}\n",
                       cellMethodName(m.method), m.raysPerSecond * 1e-6, double(m.agreements) / double(r.rays),
                       m.unambiguousDisagreements, m.tErrorM.mean, m.tErrorM.p99, m.tErrorM.max, m.tErrorRel.mean,
                       m.tErrorRel.p99, m.tErrorRel.max);
        }
        fmt::print(stderr, "terracast: accuracy of {} methods on {} rays each (plus the reference) in {:.2f} s, peak memory {}\n",
                   r.methods.size(), r.rays, seconds, humanBytes(peakResidentBytes()));
        if (!o.json.empty()) {
            std::string j = fmt::format(
                "{{\"dem\": {}, \"width\": {}, \"height\": {}, \"rays\": {}, \"seed\": {}, "
                "\"camera_rays\": {}, \"grazing_rays\": {}, \"shadow_rays\": {}, \"reference\": \"reference\", "
                "\"reference_hits\": {}, \"ambiguous_rays\": {}, \"grazing_tolerance_m\": {},\n \"methods\": [",
                jsonString(dem.path), dem.grid.width(), dem.grid.height(), r.rays, o.seed, r.cameraRays, r.grazingRays,
                r.shadowRays, r.referenceHits, r.ambiguousRays, jsonNumber(r.grazingToleranceM));
            for (size_t k = 0; k < r.methods.size(); ++k) {
                const auto& m = r.methods[k];
                j += fmt::format(
                    "{}\n  {{\"name\": \"{}\", \"rays_per_s\": {}, \"primary_rays_per_s\": {}, \"hit_agreement\": {}, "
                    "\"disagreements\": {}, \"unambiguous_disagreements\": {}, \"compared_hits\": {}, "
                    "\"t_error_m\": {}, \"t_error_rel\": {}}}",
                    k ? "," : "", cellMethodName(m.method), jsonNumber(m.raysPerSecond), jsonNumber(m.raysPerSecond),
                    jsonNumber(double(m.agreements) / double(r.rays)), m.disagreements, m.unambiguousDisagreements,
                    m.comparedHits, errorJson(m.tErrorM), errorJson(m.tErrorRel));
            }
            j += "\n ]}\n";
            writeTextFile(o.json, j);
        }
        return 0;
    });
}

int runCompare(const CompareCommandOptions& o) {
    return guarded([&] {
        namespace fs = std::filesystem;
        std::error_code ec;
        if (!o.json.empty()) {
            const auto dir = fs::path(o.json).parent_path();
            if (!dir.empty() && !fs::is_directory(dir, ec))
                throw InputError(fmt::format("{}: output folder '{}' does not exist", o.json, dir.string()));
            checkNotInput(o.json, o.dem.path, "--json");
        }
        checkViewValues(o.exaggeration, o.sunElevationDeg);
        LoadedDem dem = load(o.dem);
        CompareSettings cs;
        cs.methods = o.methods;
        cs.render = makeView(dem.grid, o.width, o.height, o.sunAzimuthDeg, o.sunElevationDeg, o.exaggeration, o.camera,
                             o.threads);
        {
            // Every method keeps its picture and hit distances (12 + 8 bytes per pixel) plus per-pass buffers;
            // the largest acceleration structure is alive one at a time.
            double embree = 0.0;
            for (SurfaceMethod m : cs.methods) embree = std::max(embree, embreeBytesEstimate(m, dem.grid));
            const double pixels = double(o.width) * o.height;
            checkMemory(o.dem, dem.grid, pixels * (20.0 * double(cs.methods.size() + 1) + 120.0) + embree,
                        fmt::format("comparing {} methods at {}x{}", cs.methods.size(), o.width, o.height));
        }
        // The output folder is made only once the input has loaded, so a bad input leaves nothing behind.
        if (!o.outDir.empty() && !fs::is_directory(o.outDir, ec) && !fs::create_directories(o.outDir, ec))
            throw InputError(fmt::format("--out-dir: cannot create folder '{}' ({})", o.outDir, ec.message()));

        if (isatty(fileno(stderr)))
            cs.onMethod = [](SurfaceMethod m, size_t k, size_t n) {
                fmt::print(stderr, "\rcompare: tracing {} ({} of {})          ", surfaceMethodName(m), k + 1, n);
                if (k + 1 == n) fmt::print(stderr, "\n");
            };
        const auto start = std::chrono::steady_clock::now();
        const CompareReport r = compareSurfaces(dem.grid, cs);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        fmt::print("{}: {} x {} vertices; {} x {} camera rays plus one shadow ray per lit-facing hit; reference {}\n",
                   dem.path, dem.grid.width(), dem.grid.height(), r.width, r.height, surfaceMethodName(r.reference));
        fmt::print("{:<16} {:>8} {:>11} {:>9} {:>9} {:>10} {:>10} {:>10} {:>10} {:>9} {:>8} {:>7} {:>7}\n", "method",
                   "build s", "memory", "prim M/s", "shad M/s", "agreement", "t mean m", "t p99 m", "t max m", "rmse",
                   "psnr dB", "x prim", "x shad");
        for (const auto& m : r.methods)
            fmt::print("{:<16} {:>8.3f} {:>11} {:>9.3f} {:>9.3f} {:>10.6f} {:>10.3g} {:>10.3g} {:>10.3g} {:>9.5f} {:>8.1f} "
                       "{:>7.2f} {:>7.2f}\n",
                       surfaceMethodName(m.method), m.buildSeconds, humanBytes(double(m.memoryBytes)),
                       m.primaryRaysPerSecond * 1e-6, m.shadowRaysPerSecond * 1e-6, m.hitAgreement, m.tErrorM.mean,
                       m.tErrorM.p99, m.tErrorM.max, m.imageRmse, m.imagePsnrDb, m.ratioToEmbreePrimary,
                       m.ratioToEmbreeShadow);
        fmt::print("({:.1f} s in all, peak memory {}; x prim / x shad: rays per second over embree's, this run)\n",
                   seconds, humanBytes(peakResidentBytes()));

        if (!o.outDir.empty()) {
            const MethodComparison* ref = nullptr;
            for (const auto& m : r.methods)
                if (m.method == r.reference) ref = &m;
            for (const auto& m : r.methods) {
                const std::string name = surfaceMethodName(m.method);
                writeImage((fs::path(o.outDir) / (name + ".png")).string(), RgbImage{m.image.width, m.image.height, m.image.rgb});
                if (&m == ref) continue;
                const Film heat = differenceHeatMap(m, *ref);
                writeImage((fs::path(o.outDir) / ("diff-" + name + ".png")).string(), RgbImage{heat.width, heat.height, heat.rgb});
            }
            writeTextFile((fs::path(o.outDir) / "tradeoff.svg").string(), tradeoffSvg(r));
        }
        // The report goes last: its presence says the run completed.
        if (!o.json.empty()) {
            std::string j = fmt::format("{{\"dem\": {}, \"width\": {}, \"height\": {}, \"image_width\": {}, "
                                        "\"image_height\": {}, \"rays\": {}, \"reference\": \"{}\",\n \"methods\": [",
                                        jsonString(dem.path), dem.grid.width(), dem.grid.height(), r.width, r.height,
                                        r.rays, surfaceMethodName(r.reference));
            for (size_t k = 0; k < r.methods.size(); ++k) {
                const auto& m = r.methods[k];
                j += fmt::format(
                    "{}\n  {{\"name\": \"{}\", \"build_s\": {}, \"memory_bytes\": {}, \"primary_rays\": {}, "
                    "\"shadow_rays\": {}, \"primary_rays_per_s\": {}, \"shadow_rays_per_s\": {}, \"hit_agreement\": {}, "
                    "\"t_error_m\": {}, \"t_error_rel\": {}, \"image_rmse\": {}, \"image_psnr_db\": {}, "
                    "\"ratio_to_embree\": {{\"primary\": {}, \"shadow\": {}}}}}",
                    k ? "," : "", surfaceMethodName(m.method), jsonNumber(m.buildSeconds), m.memoryBytes, m.primaryRays,
                    m.shadowRays, jsonNumber(m.primaryRaysPerSecond), jsonNumber(m.shadowRaysPerSecond),
                    jsonNumber(m.hitAgreement), errorJson(m.tErrorM), errorJson(m.tErrorRel), jsonNumber(m.imageRmse),
                    // identical images have infinite PSNR; JSON has no infinity, so it is capped at 999 dB
                    jsonNumber(std::min(m.imagePsnrDb, 999.0)), jsonNumber(m.ratioToEmbreePrimary),
                    jsonNumber(m.ratioToEmbreeShadow));
            }
            j += "\n ]}\n";
            writeTextFile(o.json, j);
        }
        return 0;
    });
}

int runShadow(const ShadowOptions& o) {
    return guarded([&] {
        checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
        checkViewValues(1.0, o.sunElevationDeg);
        if (!(o.sunSizeDeg >= 0.0 && o.sunSizeDeg < 30.0))
            throw InputError(fmt::format("--sun-size: expected degrees in [0, 30), found {}", o.sunSizeDeg));
        const CellMethod method = directMethod(o.method, "shadow");
        const LoadedDem dem = load(o.dem);
        const auto start = std::chrono::steady_clock::now();
        const MapRaster mask = shadowMask(dem.grid, radians(o.sunAzimuthDeg),
                                          radians(o.sunElevationDeg), method,
                                          radians(0.5 * o.sunSizeDeg), 16, o.threads);
        writeVertexRaster(o.output, dem, mask, RasterType::Float32, -9999.0);
        printRasterSummary("shadow mask", o.output, mask, start);
        return 0;
    });
}

int runHorizon(const HorizonOptions& o) {
    return guarded([&] {
        checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
        const CellMethod method = directMethod(o.method, "horizon");
        const LoadedDem dem = load(o.dem);
        const auto start = std::chrono::steady_clock::now();
        const MapRaster horizon = horizonMap(dem.grid, radians(o.azimuthDeg), method, o.threads);
        writeVertexRaster(o.output, dem, horizon, RasterType::Float32, -9999.0);
        printRasterSummary("horizon angles", o.output, horizon, start);
        return 0;
    });
}

int runViewshed(const ViewshedOptions& o) {
    return guarded([&] {
        checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
        if (!std::isfinite(o.observerHeightM) || !std::isfinite(o.targetHeightM) || !std::isfinite(o.curvatureCoeff))
            throw InputError("--observer-height, --target-height and --curvature-coeff must be finite numbers");
        ViewshedSettings s;
        s.method = directMethod(o.method, "viewshed");
        const LoadedDem dem = load(o.dem);
        double x = o.observerX, y = o.observerY;
        if (o.lonLat) lonLatToSource(dem.geo, o.observerX, o.observerY, x, y);
        sourceToLocal(dem, x, y, s.observerXM, s.observerYM);
        if (s.observerXM < 0.0 || s.observerYM < 0.0 || s.observerXM > dem.grid.extentXM() ||
            s.observerYM > dem.grid.extentYM())
            throw InputError(fmt::format("--observer: {}, {} lies outside the DEM (x {:.3f} .. {:.3f}, y {:.3f} .. {:.3f} "
                                         "in its CRS)",
                                         o.observerX, o.observerY, dem.geo.originX,
                                         dem.geo.originX + dem.grid.cellsX() * sourcePixelSizeX(dem.geo),
                                         dem.geo.originY, dem.geo.originY + dem.grid.cellsY() * sourcePixelSizeY(dem.geo)));
        s.observerHeightM = o.observerHeightM;
        s.targetHeightM = o.targetHeightM;
        s.curvatureCoeff = o.curvatureCoeff;
        s.threads = o.threads;
        const auto start = std::chrono::steady_clock::now();
        const MapRaster vis = viewshed(dem.grid, s);
        writeVertexRaster(o.output, dem, vis, RasterType::Byte, 255.0);
        printRasterSummary("viewshed", o.output, vis, start);
        return 0;
    });
}

namespace {

std::string vecText(const glm::dvec3& v) { return fmt::format("({:.3f}, {:.3f}, {:.3f})", v.x, v.y, v.z); }

// One pixel's ray tree, one ray per line, indented by depth.
void printRayTree(int x, int y, const std::vector<RayRecord>& tree) {
    fmt::print("ray tree of pixel {},{} ({} rays)\n", x, y, tree.size());
    for (const RayRecord& r : tree) {
        fmt::print("{:{}}{} from {} dir {} -> {}", "", 2 * r.depth, rayKindName(r.kind), vecText(r.origin),
                   vecText(r.dir), r.hit);
        if (std::isfinite(r.t) && r.kind != RayKind::Shadow) fmt::print(" at {:.4g} m", r.t);
        // A shadow ray's record holds the fraction of the light that gets through, not weighted radiance.
        fmt::print("  weight ({:.3g}, {:.3g}, {:.3g}) {} ({:.4g}, {:.4g}, {:.4g})\n", r.weight.r, r.weight.g, r.weight.b,
                   r.kind == RayKind::Shadow ? "transmittance" : "contribution", r.contribution.r, r.contribution.g,
                   r.contribution.b);
    }
}

}  // namespace

int runScene(const SceneCommandOptions& o) {
    return guarded([&] {
        SceneDescription d = loadSceneFile(o.path);
        RenderDescription& r = d.render;
        if (!o.output.empty()) r.output = o.output;
        if (o.width > 0) r.width = o.width;
        if (o.height > 0) r.height = o.height;
        if (o.samples > 0) r.samples = o.samples;
        if (o.threads >= 0) r.threads = o.threads;
        if (o.seed >= 0) r.seed = uint64_t(o.seed);
        if (o.method)
            for (auto& obj : d.objects) obj.method = *o.method;
        if (o.sampler) r.sampler = *o.sampler;
        if (o.filter) r.filter = *o.filter;
        if (o.adaptive && !(o.adaptiveError > 0.0))
            throw InputError(fmt::format("--adaptive: expected an error > 0, found {}", o.adaptiveError));
        if (o.focusPixel && d.camera.kind != CameraKind::ThinLens)
            throw InputError(o.path + ": --focus needs a thin-lens camera (type = \"thin-lens\" in [camera])");
        if (o.focusPixel && (o.focusX < 0 || o.focusY < 0 || o.focusX >= r.width || o.focusY >= r.height))
            throw InputError(fmt::format("--focus: expected a pixel inside {}x{}, found {},{}", r.width, r.height,
                                         o.focusX, o.focusY));
        // With --debug-pixel only an output named on the command line is rendered, never the file's own.
        const bool writesImage = !o.debugPixel || !o.output.empty();
        if (r.output.empty() && writesImage)
            throw InputError(o.path + ": no output image: give -o OUT or set output in [render]");
        if (o.debugPixel && (o.debugX < 0 || o.debugY < 0 || o.debugX >= r.width || o.debugY >= r.height))
            throw InputError(fmt::format("--debug-pixel: expected a pixel inside {}x{}, found {},{}", r.width, r.height,
                                         o.debugX, o.debugY));
        if (writesImage) {
            checkOutputPath(r.output, o.path);
            for (const auto& obj : d.objects)
                if (obj.kind == ObjectKind::HeightField) checkNotInput(r.output, obj.filePath, "output path");
        }

        const double limit = o.maxMemoryBytes > 0.0 ? o.maxMemoryBytes : defaultMemoryLimitBytes();
        const LoadedSceneAssets loaded = loadSceneAssets(d, limit);
        for (const auto& w : loaded.warnings) fmt::print(stderr, "terracast: warning: {}\n", w);
        for (const auto& line : placeTimedSuns(d, loaded))
            if (!o.quiet) fmt::print(stderr, "terracast: {}\n", line);
        double embreeBytes = 0.0;
        for (size_t k = 0, g = 0; k < d.objects.size(); ++k)
            if (d.objects[k].kind == ObjectKind::HeightField)
                embreeBytes += embreeBytesEstimate(d.objects[k].method, *loaded.assets.grids[g++]);
        const double need = loaded.bytes + embreeBytes + double(r.width) * r.height * 12.0;
        if (need > limit)
            throw InputError(fmt::format("{}: rendering {}x{} needs about {}, more than the {} limit (--max-memory)",
                                         o.path, r.width, r.height, humanBytes(need), humanBytes(limit)));

        const Scene scene(d, loaded.assets);
        const double aspect = double(r.width) / double(r.height);
        SceneCamera camera = makeSceneCamera(scene, d.camera, aspect);
        if (o.focusPixel) {
            const auto focus = focusDistanceAt(scene, camera, o.focusX, o.focusY, r.width, r.height);
            if (!focus)
                throw InputError(fmt::format("--focus: pixel {},{} sees the sky; pick a pixel on an object", o.focusX,
                                             o.focusY));
            d.camera.focusDistanceM = *focus;
            camera = makeSceneCamera(scene, d.camera, aspect);
            if (!o.quiet) fmt::print(stderr, "terracast: focus distance {:.2f} m (pixel {},{})\n", *focus, o.focusX, o.focusY);
        }
        SceneRenderSettings s;
        s.width = r.width;
        s.height = r.height;
        s.samples = r.samples;
        s.maxDepth = r.maxDepth;
        s.minWeight = r.minWeight;
        s.seed = r.seed;
        s.threads = r.threads;
        s.exposure = r.exposure;
        s.pattern = r.sampler;
        s.filter = PixelFilter::defaults(r.filter);
        s.adaptive = o.adaptive;
        if (o.adaptive) {
            s.rule.maxSamples = std::max(r.samples, 2);
            s.rule.minSamples = std::min(s.rule.minSamples, s.rule.maxSamples);
            s.rule.absoluteError = o.adaptiveError;
        }

        if (o.debugPixel) {
            std::vector<RayRecord> tree;
            const glm::vec3 v = tracePixel(scene, camera, s, o.debugX, o.debugY, &tree);
            printRayTree(o.debugX, o.debugY, tree);
            fmt::print("pixel value ({:.4g}, {:.4g}, {:.4g})\n", v.r, v.g, v.b);
            if (!writesImage) return 0;
        }

        TerminalProgress progress(!o.quiet);
        s.progress = [&](double f, int64_t rays) { progress.update(f, rays); };
        SceneRayStats stats;
        Film film = renderScene(scene, camera, s, &stats);
        progress.finish();
        writeImage(r.output, RgbImage{film.width, film.height, std::move(film.rgb)});
        if (!o.quiet)
            fmt::print(stderr,
                       "terracast: rendered {} ({}x{}, {} spp{}) in {:.2f} s: {} primary, {} shadow, {} reflection, {} "
                       "refraction, {} sky-visibility rays ({} reached the sky), {:.2f} Mrays/s, peak memory {}\n",
                       r.output, r.width, r.height,
                       s.adaptive ? fmt::format("{:.1f}", double(stats.samples) / (double(r.width) * r.height))
                                  : std::to_string(std::max(1, s.samples)),
                       s.adaptive ? fmt::format(" on average, adaptive up to {}", s.rule.maxSamples) : "", stats.seconds, stats.primary, stats.shadow,
                       stats.reflection, stats.refraction, stats.skyVisibility, stats.skyRays,
                       stats.seconds > 0 ? double(stats.total()) / stats.seconds * 1e-6 : 0.0,
                       humanBytes(peakResidentBytes()));
        return 0;
    });
}

namespace {

// One grid of `bench`: a synthetic fractal of some size, or a DEM file.
struct BenchJob {
    std::string name;   // as reported: "synthetic-513" or the file's name (no folder: reports name no machine paths)
    int64_t size = 0;   // synthetic: vertices per side; 0 for a file
    std::string path;   // file: the DEM
    bool integer = false;  // synthetic: heights in whole metres, so the grid is held as int16
};

// Parses "513,2049,8193" into sizes of 2^n + 1 vertices from 3 to 65537.
std::vector<int64_t> parseBenchSizes(const std::string& text) {
    std::vector<int64_t> sizes;
    std::stringstream in(text);
    std::string item;
    const auto bad = [&] {
        return InputError(fmt::format("--sizes: expected comma-separated grid sizes of 2^n + 1 vertices from 3 to "
                                      "65537 (such as 513,2049,8193), found '{}'",
                                      text));
    };
    while (std::getline(in, item, ',')) {
        size_t used = 0;
        int64_t v = 0;
        try {
            v = std::stoll(item, &used);
        } catch (const std::exception&) {
            throw bad();
        }
        if (used != item.size() || !isFractalTerrainSize(v) || v > 65537) throw bad();
        sizes.push_back(v);
    }
    if (sizes.empty() || (!text.empty() && text.back() == ',')) throw bad();
    return sizes;
}

// Parses "bilinear,triangles" into bench methods, in report order; embree is always measured (the ratios'
// reference).
std::vector<BenchMethod> parseBenchMethods(const std::string& text) {
    std::vector<bool> wanted(benchMethods().size(), false);
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        const auto m = parseBenchMethod(item);
        if (!m)
            throw InputError(fmt::format("--methods: expected a comma-separated list of bilinear, bilinear-flat, "
                                         "triangles, embree, embree-grid, found '{}'",
                                         item));
        wanted[size_t(std::find(benchMethods().begin(), benchMethods().end(), *m) - benchMethods().begin())] = true;
    }
    if (text.empty() || text.back() == ',')
        throw InputError(fmt::format("--methods: expected a comma-separated list of methods, found '{}'", text));
    std::vector<BenchMethod> methods;
    for (size_t k = 0; k < wanted.size(); ++k)
        if (wanted[k] || benchMethods()[k] == BenchMethod::Embree) methods.push_back(benchMethods()[k]);
    return methods;
}

// The DEMs `bench --real` adds: the GDAL rasters of a folder (GeoTIFF, SRTM .hgt), by name. PNG height maps
// are left out: they carry no cell size or height scale.
std::vector<std::string> benchRealDems(const std::string& dir) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(fmt::format("--data: '{}' is not a folder", dir));
    std::vector<std::string> paths;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string ext = lowerExtension(e.path().string());
        if (e.is_regular_file(ec) && (ext == ".tif" || ext == ".tiff" || ext == ".hgt")) paths.push_back(e.path().string());
    }
    std::sort(paths.begin(), paths.end());
    if (paths.empty()) throw InputError(fmt::format("--data: no GeoTIFF or .hgt DEM in '{}'", dir));
    return paths;
}

std::string benchRatioJson(double primary, double shadow) {
    return fmt::format("{{\"primary\": {}, \"shadow\": {}}}", jsonNumber(primary), jsonNumber(shadow));
}

// A method the memory guard left out, as the JSON reports it.
std::string skippedMethodJson(BenchMethod method, double neededBytes) {
    return fmt::format("{{\"name\": \"{}\", \"skipped\": true, \"memory_needed_bytes\": {}}}",
                       benchMethodName(method), jsonNumber(neededBytes));
}

// One grid's object in the bench report: the DESIGN section 8 shape, with the corner camera at the most
// threads as each method's headline numbers and every pass listed under "passes".
std::string benchGridJson(const BenchJob& job, const BenchGridResult& r, const BenchSettings& s) {
    // The agreement's reference: the first method that was measured (a skipped one has no hits).
    const char* reference = "";
    for (const auto& m : r.methods)
        if (!m.skipped) {
            reference = benchMethodName(m.method);
            break;
        }
    std::string j = fmt::format("{{\"dem\": {}, \"synthetic\": {}, \"width\": {}, \"height\": {}, \"cells\": {}, "
                                "\"image_width\": {}, \"image_height\": {}, \"rays\": {}, \"reference\": \"{}\", "
                                "\"skipped\": false,\n  \"methods\": [",
                                jsonString(job.name), job.size > 0 ? "true" : "false", r.width, r.height, r.cells,
                                s.width, s.height, int64_t(s.width) * s.height, reference);
    for (size_t k = 0; k < r.methods.size(); ++k) {
        const auto& m = r.methods[k];
        j += k ? "," : "";
        if (m.skipped) {
            j += "\n   " + skippedMethodJson(m.method, m.neededBytes);
            continue;
        }
        const BenchPass* head = nullptr;
        for (const auto& p : m.passes)
            if (p.camera == BenchCamera::Corner && (!head || p.threads > head->threads)) head = &p;
        if (!head && !m.passes.empty()) head = &m.passes.front();
        const BenchPass none{};
        if (!head) head = &none;
        j += fmt::format("\n   {{\"name\": \"{}\", \"skipped\": false, \"build_s\": {}, \"memory_bytes\": {}, "
                         "\"peak_memory_bytes\": {}, \"bytes_per_cell\": {}, \"peak_bytes_per_cell\": {}, "
                         "\"hit_agreement\": {}, \"threads\": {}, \"primary_rays_per_s\": {}, \"shadow_rays_per_s\": {}, "
                         "\"ratio_to_embree\": {},\n    \"passes\": [",
                         benchMethodName(m.method), jsonNumber(m.buildSeconds), m.memoryBytes, m.peakMemoryBytes,
                         jsonNumber(m.bytesPerCell), jsonNumber(m.peakBytesPerCell), jsonNumber(m.hitAgreement),
                         head->threads, jsonNumber(head->primaryRaysPerSecond), jsonNumber(head->shadowRaysPerSecond),
                         benchRatioJson(head->ratioToEmbreePrimary, head->ratioToEmbreeShadow));
        for (size_t q = 0; q < m.passes.size(); ++q) {
            const auto& p = m.passes[q];
            j += fmt::format("{}\n     {{\"camera\": \"{}\", \"threads\": {}, \"primary_rays\": {}, \"shadow_rays\": {}, "
                             "\"primary_rays_per_s\": {}, \"shadow_rays_per_s\": {}, \"ratio_to_embree\": {}}}",
                             q ? "," : "", benchCameraName(p.camera), p.threads, p.primaryRays, p.shadowRays,
                             jsonNumber(p.primaryRaysPerSecond), jsonNumber(p.shadowRaysPerSecond),
                             benchRatioJson(p.ratioToEmbreePrimary, p.ratioToEmbreeShadow));
        }
        j += "]}";
    }
    return j + "]}";
}

// The processor's model name from /proc/cpuinfo, or empty where there is none.
std::string cpuModelName() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon == std::string::npos) break;
            const auto first = line.find_first_not_of(" \t", colon + 1);
            return first == std::string::npos ? std::string() : line.substr(first);
        }
    return {};
}

// Refuses, before any work, an output file whose folder does not exist.
void checkOutputFolder(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto dir = fs::path(path).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw InputError(fmt::format("{}: output folder '{}' does not exist", path, dir.string()));
}

// A folder of its own under the system's temporary folder, removed with all it holds on destruction.
class ScratchFolder {
public:
    ScratchFolder() {
        std::string pattern = (std::filesystem::temp_directory_path() / "terracast-bench-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a temporary folder under " + pattern);
        path_ = pattern;
    }
    ~ScratchFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

// `bench --file-to-picture`: the whole `render FILE.png` job with one method.
struct FileToPictureRun {
    BenchMethod method = BenchMethod::Bilinear;
    bool skipped = false;       // estimated over --max-memory; nothing below is measured
    double neededBytes = 0.0;   // when skipped
    RenderPhaseSeconds seconds;
    int64_t pictureBytes = 0;   // the PNG written
    int pictureWidth = 0;       // as read back
    int pictureHeight = 0;
};

struct FileToPictureResult {
    std::string name;                  // "synthetic-8193"
    int64_t size = 0;                  // vertices per side
    bool skipped = false;              // the height map itself would not fit; nothing below is measured
    double neededBytes = 0.0;
    double makeSeconds = 0.0;          // the fractal grid
    double heightMapSeconds = 0.0;     // encoding and writing the 16-bit PNG
    int64_t heightMapBytes = 0;
    int threads = 1;
    RenderOptions render;              // as run, less the paths
    std::vector<FileToPictureRun> runs;
    double totalRatio = std::numeric_limits<double>::quiet_NaN();          // total(embree) / total(bilinear)
    double pictureMeanAbsDiff = std::numeric_limits<double>::quiet_NaN();  // 8-bit levels, over all channels
};

// Makes the fractal grid of `size`, writes it as a 16-bit PNG height map into a scratch folder, then runs
// `render` on it as a user would (--cell-size 30 --size 1024x768 --threads N) with bilinear and with embree,
// each picture written into the same folder; reads both pictures back to compare them, then removes the folder.
FileToPictureResult fileToPicture(int64_t size, uint64_t seed, int threads, double maxMemoryBytes, double limit,
                                  const std::function<void(const std::string&)>& onStep) {
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    FileToPictureResult out;
    out.name = fmt::format("synthetic-{}", size);
    out.size = size;
    out.threads = threads;
    out.render.dem.imageCellSizeM = 30.0;
    out.render.dem.maxMemoryBytes = maxMemoryBytes;
    out.render.width = 1024;
    out.render.height = 768;
    out.render.threads = threads;
    out.render.quiet = true;
    const BenchMethod methods[] = {BenchMethod::Bilinear, BenchMethod::Embree};
    for (BenchMethod m : methods) {
        FileToPictureRun run;
        run.method = m;
        out.runs.push_back(run);
    }

    // While the height map is made: the grid, its scanlines and their deflated copy (at most about as big).
    const double vertices = double(size) * double(size);
    const double mapNeed = double(fractalTerrainBytes(size)) + 4.1 * vertices;
    if (mapNeed > limit) {
        out.skipped = true;
        out.neededBytes = mapNeed;
        return out;
    }
    ScratchFolder scratch;
    const std::string heightMap = (scratch.path() / "height.png").string();
    {
        if (onStep) onStep("making the grid");
        const auto made = Clock::now();
        FractalTerrainOptions fo;
        fo.size = size;
        fo.seed = seed;
        const HeightGrid grid = fractalTerrain(fo);
        out.makeSeconds = since(made);
        // What render will hold: the grid as loaded (as big as this one), the loader's 16-bit samples, the
        // film, and Embree's scene.
        for (auto& run : out.runs) {
            const double need = double(grid.memoryBytes()) + 2.0 * vertices + double(out.render.width) *
                                out.render.height * 12.0 + embreeBytesEstimate(benchSurfaceMethod(run.method), grid);
            if (need > limit) {
                run.skipped = true;
                run.neededBytes = need;
            }
        }
        if (onStep) onStep("writing the 16-bit PNG height map");
        const auto written = Clock::now();
        const std::string png = encodeHeightPng16(grid);
        writeFileAtomically(heightMap, png);
        out.heightMapSeconds = since(written);
        out.heightMapBytes = int64_t(png.size());
    }

    std::vector<RgbImage> pictures;
    for (auto& run : out.runs) {
        if (run.skipped) continue;
        if (onStep) onStep(fmt::format("render {} with {}", std::filesystem::path(heightMap).filename().string(),
                                       benchMethodName(run.method)));
        RenderOptions ro = out.render;
        ro.dem.path = heightMap;
        ro.output = (scratch.path() / (std::string(benchMethodName(run.method)) + ".png")).string();
        ro.method = benchSurfaceMethod(run.method);
        renderPerspective(ro, &run.seconds);
        run.pictureBytes = int64_t(std::filesystem::file_size(ro.output));
        pictures.push_back(readImage(ro.output));
        run.pictureWidth = pictures.back().width;
        run.pictureHeight = pictures.back().height;
    }
    if (!out.runs[0].skipped && !out.runs[1].skipped) {
        out.totalRatio = out.runs[1].seconds.total / out.runs[0].seconds.total;
        const RgbImage& a = pictures[0];
        const RgbImage& b = pictures[1];
        if (a.width == b.width && a.height == b.height && !a.rgb.empty()) {
            // The 8-bit sRGB levels the PNGs store.
            const auto level = [](float v) { return std::lround(255.0f * srgbFromLinear(v)); };
            double sum = 0.0;
            for (size_t k = 0; k < a.rgb.size(); ++k) sum += double(std::labs(level(a.rgb[k]) - level(b.rgb[k])));
            out.pictureMeanAbsDiff = sum / double(a.rgb.size());
        }
    }
    return out;
}

std::string fileToPictureJson(const FileToPictureResult& f) {
    std::string j = fmt::format("{{\"dem\": {}, \"width\": {}, \"height\": {}, \"cell_size_m\": {}, \"skipped\": {}",
                                jsonString(f.name), f.size, f.size, jsonNumber(f.render.dem.imageCellSizeM),
                                f.skipped ? "true" : "false");
    if (f.skipped) return j + fmt::format(", \"memory_needed_bytes\": {}, \"methods\": []}}", jsonNumber(f.neededBytes));
    j += fmt::format(", \"make_s\": {}, \"height_map_write_s\": {}, \"height_map_bytes\": {}, \"image_width\": {}, "
                     "\"image_height\": {}, \"threads\": {}, \"sky\": {}, \"sky_samples\": {},\n  \"methods\": [",
                     jsonNumber(f.makeSeconds), jsonNumber(f.heightMapSeconds), f.heightMapBytes, f.render.width,
                     f.render.height, f.threads, jsonString(f.render.sky), f.render.skySamples < 0 ? 4 : f.render.skySamples);
    for (size_t k = 0; k < f.runs.size(); ++k) {
        const auto& r = f.runs[k];
        j += k ? ",\n   " : "\n   ";
        if (r.skipped) {
            j += skippedMethodJson(r.method, r.neededBytes);
            continue;
        }
        j += fmt::format("{{\"name\": \"{}\", \"skipped\": false, \"load_s\": {}, \"build_s\": {}, \"render_s\": {}, "
                         "\"write_s\": {}, \"total_s\": {}, \"picture_bytes\": {}, \"picture_width\": {}, "
                         "\"picture_height\": {}}}",
                         benchMethodName(r.method), jsonNumber(r.seconds.load), jsonNumber(r.seconds.build),
                         jsonNumber(r.seconds.render), jsonNumber(r.seconds.write), jsonNumber(r.seconds.total),
                         r.pictureBytes, r.pictureWidth, r.pictureHeight);
    }
    return j + fmt::format("],\n  \"total_ratio_embree_to_bilinear\": {}, \"picture_mean_abs_diff\": {}}}",
                           jsonNumber(f.totalRatio), jsonNumber(f.pictureMeanAbsDiff));
}

void printFileToPicture(const FileToPictureResult& f, double limit) {
    if (f.skipped) {
        fmt::print("\nfile to picture ({}): skipped: making the height map needs about {}, more than the {} limit "
                   "(--max-memory)\n",
                   f.name, humanBytes(f.neededBytes), humanBytes(limit));
        return;
    }
    const RenderOptions& r = f.render;
    fmt::print("\nfile to picture: {} made in {:.2f} s, written as a 16-bit PNG height map ({}) in {:.2f} s; then "
               "`render FILE.png --cell-size {:g} --size {}x{} --threads {} --method M -o OUT.png` (sun {:g},{:g}, "
               "shadows, {} sky, {} sky rays per hit)\n",
               f.name, f.makeSeconds, humanBytes(double(f.heightMapBytes)), f.heightMapSeconds, r.dem.imageCellSizeM,
               r.width, r.height, f.threads, r.sunAzimuthDeg, r.sunElevationDeg, r.sky,
               r.skySamples < 0 ? 4 : r.skySamples);
    fmt::print("{:<14} {:>8} {:>8} {:>8} {:>8} {:>8}\n", "method", "load s", "build s", "render s", "write s", "total s");
    for (const auto& run : f.runs) {
        if (run.skipped) {
            fmt::print("{:<14} skipped: needs about {}, more than the {} limit (--max-memory)\n",
                       benchMethodName(run.method), humanBytes(run.neededBytes), humanBytes(limit));
            continue;
        }
        fmt::print("{:<14} {:>8.3f} {:>8.3f} {:>8.3f} {:>8.3f} {:>8.3f}\n", benchMethodName(run.method),
                   run.seconds.load, run.seconds.build, run.seconds.render, run.seconds.write, run.seconds.total);
    }
    if (std::isfinite(f.totalRatio))
        fmt::print("total embree / bilinear: {:.2f}; the two pictures differ by {:.2f} of 255 on average (8-bit sRGB)\n",
                   f.totalRatio, f.pictureMeanAbsDiff);
}

}  // namespace

int runBench(const BenchCommandOptions& o) {
    return guarded([&] {
        std::vector<int64_t> sizes = parseBenchSizes(o.sizes);
        if (o.large && std::find(sizes.begin(), sizes.end(), int64_t(32769)) == sizes.end()) sizes.push_back(32769);
        if (o.threads < 0) throw InputError(fmt::format("--threads: expected 0 (all cores) or more, found {}", o.threads));
        if (!o.json.empty()) checkOutputFolder(o.json);
        if (!o.svg.empty()) checkOutputFolder(o.svg);
        std::vector<BenchJob> jobs;
        // The --large grid has whole-metre heights and so int16 storage: 2.7 bytes per cell instead of 4.7.
        for (int64_t size : sizes)
            jobs.push_back({fmt::format("synthetic-{}", size), size, "", o.large && size == 32769});
        if (o.real)
            for (const auto& path : benchRealDems(o.dataDir.empty() ? std::string(TERRACAST_DATA_DIR) : o.dataDir))
                jobs.push_back({std::filesystem::path(path).filename().string(), 0, path});

        const int hardware = std::max(1, int(std::thread::hardware_concurrency()));
        const int most = o.threads > 0 ? o.threads : hardware;
        BenchSettings settings;
        if (!o.methods.empty()) settings.methods = parseBenchMethods(o.methods);
        settings.threadCounts = most > 1 ? std::vector<int>{1, most} : std::vector<int>{1};
        settings.repeat = o.repeat;
        settings.bands = o.bands;
        const double limit = o.maxMemoryBytes > 0.0 ? o.maxMemoryBytes : defaultMemoryLimitBytes();
        // Per pixel while a pass runs: its hits, directions, shadow verdicts, picture and hit distances, plus
        // the first method's hit distances kept for the agreement.
        const double passBytes = double(settings.width) * settings.height *
                                 double(sizeof(std::optional<HeightFieldHit>) + sizeof(glm::dvec3) + 1 + 12 + 8 + 8);
        const bool terminal = isatty(fileno(stderr));
        const char* kernels = kernelIsaName(kernelIsa());
        const std::string cpu = cpuModelName();
        const std::string machine = fmt::format("{}{} hardware thread{}", cpu.empty() ? "" : cpu + ", ", hardware,
                                                hardware == 1 ? "" : "s");

        fmt::print("terracast bench: {} x {} camera rays per view (corner: south-west, 30 degrees down; grazing: above "
                   "the highest peak, 8 degrees down), sun at azimuth {:g}, elevation {:g} degrees, one shadow ray per "
                   "hit facing it; {} thread{} ({}); FTZ/DAZ on for every method; direct kernels: {}; {} trace{} per "
                   "pass after one untimed, in {} band{} of rows, each band taken in turn with the other methods in "
                   "alternating order; a pass's time is the sum of each band's fastest\n",
                   settings.width, settings.height, settings.sunAzimuthDeg, settings.sunElevationDeg,
                   most > 1 ? fmt::format("1 and {}", most) : "1", most > 1 ? "s" : "", machine,
                   kernels, settings.repeat, settings.repeat == 1 ? "" : "s", settings.bands,
                   settings.bands == 1 ? "" : "s");
        std::string json = fmt::format("{{\"image_width\": {}, \"image_height\": {}, \"sun_azimuth_deg\": {}, "
                                       "\"sun_elevation_deg\": {}, \"cpu\": {}, \"hardware_threads\": {}, "
                                       "\"kernels\": {}, \"threads\": [{}], \"repeat\": {}, \"bands\": {},\n \"grids\": [",
                                       settings.width, settings.height, jsonNumber(settings.sunAzimuthDeg),
                                       jsonNumber(settings.sunElevationDeg), jsonString(cpu), hardware,
                                       jsonString(kernels),
                                       most > 1 ? fmt::format("1, {}", most) : "1", settings.repeat, settings.bands);
        std::vector<BenchGridResult> plotted;  // the synthetic grids measured, for --svg
        const auto start = std::chrono::steady_clock::now();
        for (size_t g = 0; g < jobs.size(); ++g) {
            const BenchJob& job = jobs[g];
            json += g ? ",\n " : "\n ";
            if (job.size > 0) {
                // The grid alone (its heights and the pyramid) must fit with one pass's buffers, and while it is
                // made, with the float heights it is generated in.
                const double gridBytes = double(fractalTerrainBytes(job.size, job.integer));
                const double need =
                    std::max(gridBytes + passBytes, gridBytes + (job.integer ? 4.0 * double(job.size) * double(job.size) : 0.0));
                if (need > limit) {
                    fmt::print("\n{} ({} x {} vertices): skipped: needs about {} (grid {}), more than the {} limit "
                               "(--max-memory)\n",
                               job.name, job.size, job.size, humanBytes(need),
                               humanBytes(gridBytes), humanBytes(limit));
                    json += fmt::format("{{\"dem\": {}, \"synthetic\": true, \"width\": {}, \"height\": {}, \"cells\": {}, "
                                        "\"skipped\": true, \"memory_needed_bytes\": {}, \"methods\": []}}",
                                        jsonString(job.name), job.size, job.size, (job.size - 1) * (job.size - 1),
                                        jsonNumber(need));
                    continue;
                }
            }
            if (terminal) fmt::print(stderr, "\rbench: {}: making the grid{:30}", job.name, "");
            const auto made = std::chrono::steady_clock::now();
            HeightGrid grid;
            if (job.size > 0) {
                FractalTerrainOptions fo;
                fo.size = job.size;
                fo.seed = o.seed;
                fo.integerHeights = job.integer;
                grid = fractalTerrain(fo);
            } else {
                DemOptions dem;
                dem.path = job.path;
                dem.maxMemoryBytes = o.maxMemoryBytes;
                grid = std::move(load(dem).grid);
            }
            const double makeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - made).count();

            settings.refuse = [&](BenchMethod m) -> std::optional<double> {
                const double need = double(grid.memoryBytes()) + passBytes + embreeBytesEstimate(benchSurfaceMethod(m), grid);
                if (need > limit) return need;
                return std::nullopt;
            };
            if (terminal)
                settings.onStep = [&](const std::string& step) {
                    fmt::print(stderr, "\rbench: {} ({} of {}): {}{:20}", job.name, g + 1, jobs.size(), step, "");
                };
            const BenchGridResult r = benchGrid(grid, settings);
            if (terminal) fmt::print(stderr, "\r{:100}\r", "");

            fmt::print("\n{} ({} x {} vertices, {} cells of {:.4g} x {:.4g} m, heights {:.0f} to {:.0f} m; {} in {:.2f} s)\n",
                       job.name, grid.width(), grid.height(), r.cells, grid.cellSizeXM(), grid.cellSizeYM(),
                       grid.minHeightM(), grid.maxHeightM(), job.size > 0 ? "made" : "loaded", makeSeconds);
            fmt::print("{:<14} {:>8} {:>8} {:>8} {:>9}  {:<8} {:>3} {:>10} {:>10} {:>7} {:>7}\n", "method", "build s",
                       "B/cell", "peak B", "agreement", "camera", "thr", "prim Mr/s", "shad Mr/s", "x prim", "x shad");
            for (const auto& m : r.methods) {
                if (m.skipped) {
                    fmt::print("{:<14} skipped: needs about {}, more than the {} limit (--max-memory)\n",
                               benchMethodName(m.method), humanBytes(m.neededBytes), humanBytes(limit));
                    continue;
                }
                for (size_t q = 0; q < m.passes.size(); ++q) {
                    const auto& p = m.passes[q];
                    const std::string head =
                        q == 0 ? fmt::format("{:<14} {:>8.3f} {:>8.1f} {:>8.1f} {:>9.6f}", benchMethodName(m.method),
                                             m.buildSeconds, m.bytesPerCell, m.peakBytesPerCell, m.hitAgreement)
                               : fmt::format("{:<14} {:>8} {:>8} {:>8} {:>9}", "", "", "", "", "");
                    fmt::print("{}  {:<8} {:>3} {:>10.3f} {:>10.3f} {:>7.2f} {:>7.2f}\n", head, benchCameraName(p.camera),
                               p.threads, p.primaryRaysPerSecond * 1e-6, p.shadowRaysPerSecond * 1e-6,
                               p.ratioToEmbreePrimary, p.ratioToEmbreeShadow);
                }
            }
            json += benchGridJson(job, r, settings);
            if (job.size > 0) plotted.push_back(r);
        }
        json += "\n ],\n \"file_to_picture\": ";
        if (o.fileToPicture) {
            const int64_t largest = *std::max_element(sizes.begin(), sizes.end());
            std::function<void(const std::string&)> onStep;
            if (terminal)
                onStep = [&](const std::string& step) {
                    fmt::print(stderr, "\rbench: file to picture, synthetic-{}: {}{:30}", largest, step, "");
                };
            const FileToPictureResult f = fileToPicture(largest, o.seed, most, o.maxMemoryBytes, limit, onStep);
            if (terminal) fmt::print(stderr, "\r{:100}\r", "");
            printFileToPicture(f, limit);
            json += fileToPictureJson(f);
        } else {
            json += "null";
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        fmt::print("\n({:.1f} s in all, peak memory {}; agreement: share of corner-camera rays with {}'s hit/miss "
                   "verdict; x prim / x shad: rays per second over embree's in the same pass)\n",
                   seconds, humanBytes(peakResidentBytes()),
                   settings.methods.empty() ? "" : benchMethodName(settings.methods.front()));
        if (!o.svg.empty()) {
            std::sort(plotted.begin(), plotted.end(),
                      [](const BenchGridResult& a, const BenchGridResult& b) { return a.width < b.width; });
            writeTextFile(o.svg, benchRatesSvg(plotted, machine));
        }
        // The report goes last: its presence says the run completed.
        if (!o.json.empty()) writeTextFile(o.json, json + "}\n");
        return 0;
    });
}

}  // namespace terracast
