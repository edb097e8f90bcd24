// terracast: ray tracing of terrain height fields. Parses the command line into options structs and calls
// one library function per subcommand.
#include "cli/commands.h"

#include "tracer/core/cancel.h"

#include <CLI/CLI.hpp>
#include <csignal>
#include <fmt/core.h>

#include <cmath>
#include <string>

using namespace terracast;

namespace {

void addDemOptions(CLI::App& cmd, DemOptions& dem) {
    cmd.add_option_function<std::string>(
        "--max-memory",
        [&dem](const std::string& text) {
            if (!parseByteCount(text, dem.maxMemoryBytes))
                throw CLI::ValidationError("--max-memory", "expected a size such as 512M or 8G, found '" + text + "'");
        },
        "Refuse jobs estimated to need more memory than this, e.g. 8G (default: 80% of physical memory)");
    cmd.add_option("DEM", dem.path, "Elevation raster: GeoTIFF, SRTM .hgt, any GDAL raster, or a PNG height map")
        ->required();
    cmd.add_option("--cell-size", dem.imageCellSizeM, "PNG height maps: metres between samples (default 1)")
        ->check(CLI::PositiveNumber);
    cmd.add_option("--height-scale", dem.imageHeightScale,
                   "PNG height maps: metres per stored unit, 0..255 or 0..65535 (default 1)")
        ->check(CLI::PositiveNumber);
}

// The option parsers below print one error line and return false on malformed input.

bool parseSunOption(const std::string& sun, double& azimuthDeg, double& elevationDeg) {
    if (parsePair(sun, azimuthDeg, elevationDeg)) return true;
    fmt::print(stderr, "terracast: error: --sun: expected AZ,EL in degrees, found '{}'\n", sun);
    return false;
}

// A named value of an option (a method, sample pattern or filter), or one error line naming the choices.
template <class E>
bool parseNamedOption(const std::string& text, const char* option, std::optional<E> (*parse)(std::string_view),
                      const char* list, std::optional<E>& value) {
    value = parse(text);
    if (!value) fmt::print(stderr, "terracast: error: {}: expected one of {}, found '{}'\n", option, list, text);
    return value.has_value();
}

bool parseMethodOption(const std::string& name, SurfaceMethod& method) {
    if (const auto m = parseSurfaceMethod(name)) {
        method = *m;
        return true;
    }
    fmt::print(stderr, "terracast: error: --method: expected one of {}, found '{}'\n", surfaceMethodList(), name);
    return false;
}

// The --size and --sun texts shared by render and compare.
bool parseViewOptions(const std::string& size, const std::string& sun, int& width, int& height, double& azimuthDeg,
                      double& elevationDeg) {
    if (!parseSize(size, width, height)) {
        fmt::print(stderr, "terracast: error: --size: expected WxH with positive integers, found '{}'\n", size);
        return false;
    }
    return parseSunOption(sun, azimuthDeg, elevationDeg);
}

}  // namespace

// SIGINT and SIGTERM ask the running command to stop between tiles; outputs are written only at the end
// (through a temporary file), so nothing partial is left.
extern "C" void onInterrupt(int) { cancelFlag().store(true); }

int main(int argc, char** argv) {
    cancelFlag().store(false);  // made before the handlers, so a signal never initialises it
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
    CLI::App app{"terracast: ray tracing of terrain height fields, exact or triangulated"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "terracast 0.1.0");

    InfoOptions info;
    auto* infoCmd = app.add_subcommand("info", "Describe a DEM: size, CRS, cell size, heights, nodata, memory");
    addDemOptions(*infoCmd, info.dem);

    SceneCommandOptions scene;
    std::string debugPixel, sceneSize, focusPixel, sceneMethod, sceneSampler, sceneFilter;
    auto* sceneCmd = app.add_subcommand("scene", "Render a TOML scene: terrain, spheres, boxes, polygons, water, mirrors, glass");
    sceneCmd->add_option("SCENE", scene.path, "Scene file (TOML); see docs/scene-format.md")->required();
    sceneCmd->add_option("-o,--output", scene.output, "Output image .png or .exr (overrides render.output)");
    sceneCmd->add_option("--size", sceneSize, "Image size WxH (overrides render.width and render.height)");
    sceneCmd->add_option("--spp", scene.samples, "Samples per pixel (overrides render.samples)")->check(CLI::Range(1, 65536));
    sceneCmd->add_option("--threads", scene.threads, "Worker threads, 0 = all cores")->check(CLI::NonNegativeNumber);
    sceneCmd->add_option("--seed", scene.seed, "Random seed (overrides render.seed)")->check(CLI::NonNegativeNumber);
    sceneCmd->add_option("--method", sceneMethod, "Height-field method for every terrain (overrides the file)");
    sceneCmd->add_option("--debug-pixel", debugPixel, "Print the ray tree of pixel X,Y (and render only with -o)");
    sceneCmd->add_option("--sampler", sceneSampler, "Sample pattern: regular, random, stratified, poisson, best-candidate");
    sceneCmd->add_option("--filter", sceneFilter, "Pixel filter: box, tent, gaussian");
    sceneCmd->add_option("--focus", focusPixel, "Thin lens: focus on what pixel X,Y sees");
    auto* adaptiveOpt = sceneCmd->add_option("--adaptive", scene.adaptiveError,
                                             "Adaptive sampling up to --spp samples, until the standard error of a "
                                             "pixel's luminance is below this (e.g. 0.002)");
    sceneCmd->add_option_function<std::string>(
        "--max-memory",
        [&scene](const std::string& text) {
            if (!parseByteCount(text, scene.maxMemoryBytes))
                throw CLI::ValidationError("--max-memory", "expected a size such as 512M or 8G, found '" + text + "'");
        },
        "Refuse scenes estimated to need more memory than this (default: 80% of physical memory)");
    sceneCmd->add_flag("-q,--quiet", scene.quiet, "No progress or summary on stderr");

    RenderOptions render;
    std::string size = "1280x720", sun = "315,35", method = "bilinear";
    auto* renderCmd = app.add_subcommand("render", "Render a shaded 3D view of a DEM to PNG or EXR");
    addDemOptions(*renderCmd, render.dem);
    renderCmd->add_option("-o,--output", render.output, "Output image: .png (8-bit sRGB) or .exr (linear half float)")
        ->required();
    renderCmd->add_option("--size", size, "Image size WxH in pixels (default 1280x720)");
    renderCmd->add_option("--sun", sun, "Sun azimuth,elevation in degrees, azimuth clockwise from north (default 315,35)");
    renderCmd->add_option("--exaggeration", render.exaggeration, "Vertical exaggeration factor (default 1)");
    renderCmd->add_option("--camera", render.camera,
                          "\"eye=x,y,z look=x,y,z fov=deg\" in the DEM's local metres (origin at the south-west "
                          "sample); default: from the south-west, 30 degrees down, framing the DEM");
    renderCmd->add_option("--method", method,
                          "Surface method: bilinear, bilinear-double, triangles, nearest, reference, embree, embree-grid (default bilinear)");
    renderCmd->add_option("--threads", render.threads, "Worker threads, 0 = all cores (default 0)")
        ->check(CLI::NonNegativeNumber);
    renderCmd->add_flag("-q,--quiet", render.quiet, "No progress or summary on stderr");
    std::string view = "perspective", colour = "grey", sunTime;
    bool noShadows = false;
    renderCmd->add_option("--view", view,
                          "perspective (default), or map: top-down on the DEM's grid, written as GeoTIFF (.tif) or PNG");
    renderCmd->add_option("--scale", render.scale, "Map view: output pixels per DEM cell (default 1)");
    renderCmd->add_flag("--no-shadows", noShadows, "Map view: no cast shadows");
    renderCmd->add_option("--sky-samples", render.skySamples,
                          "Sky-visibility rays per hit (per pixel in the map view), 0 = off (default 4; map view 16)");
    renderCmd->add_option("--sky", render.sky,
                          "Sky: physical (Rayleigh and Mie scattering with aerial perspective; default), gradient, "
                          "flat or none");
    renderCmd->add_option("--haze", render.haze, "Physical sky: multiplies aerosol (Mie) scattering (default 1)");
    renderCmd->add_option("--sun-time", sunTime,
                          "Place the sun where it stands at this instant over the DEM's centre, e.g. "
                          "2026-06-21T19:30Z (instead of --sun)");
    renderCmd->add_option("--seed", render.seed, "Random seed for the sky-visibility directions (default 0)");
    renderCmd->add_option("--colour", colour, "Map view: grey (default) or ramp (by elevation)");
    renderCmd->add_option("--hillshade-blend", render.hillshadeBlend,
                          "Map view: weight of a plain hillshade without shadows or sky, 0..1 (default 0)");

    ShadowOptions shadow;
    std::string shadowSun = "315,35", shadowMethod = "bilinear";
    auto* shadowCmd = app.add_subcommand("shadow", "Sun shadow mask per DEM vertex (1 blocked, 0 lit), as GeoTIFF");
    addDemOptions(*shadowCmd, shadow.dem);
    shadowCmd->add_option("-o,--output", shadow.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
    shadowCmd->add_option("--sun", shadowSun, "Sun azimuth,elevation in degrees (default 315,35)");
    shadowCmd->add_option("--sun-size", shadow.sunSizeDeg,
                          "Sun's angular diameter in degrees; > 0 gives the blocked fraction (default 0: a point)");
    shadowCmd->add_option("--method", shadowMethod, "Direct cell method (default bilinear)");
    shadowCmd->add_option("--threads", shadow.threads, "Worker threads, 0 = all cores")->check(CLI::NonNegativeNumber);

    HorizonOptions horizon;
    std::string horizonMethod = "bilinear";
    auto* horizonCmd = app.add_subcommand("horizon", "Horizon elevation angle in degrees per DEM vertex towards an azimuth");
    addDemOptions(*horizonCmd, horizon.dem);
    horizonCmd->add_option("-o,--output", horizon.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
    horizonCmd->add_option("--azimuth", horizon.azimuthDeg, "Azimuth in degrees clockwise from north")->required();
    horizonCmd->add_option("--method", horizonMethod, "Direct cell method (default bilinear)");
    horizonCmd->add_option("--threads", horizon.threads, "Worker threads, 0 = all cores")->check(CLI::NonNegativeNumber);

    ViewshedOptions viewshedOpts;
    std::string observer, viewshedMethod = "bilinear";
    auto* viewshedCmd = app.add_subcommand("viewshed", "Visibility from an observer per DEM vertex (1 visible, 0 hidden)");
    addDemOptions(*viewshedCmd, viewshedOpts.dem);
    viewshedCmd->add_option("-o,--output", viewshedOpts.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
    viewshedCmd->add_option("--observer", observer, "Observer X,Y in the DEM's CRS (lon,lat with --lonlat)")->required();
    viewshedCmd->add_flag("--lonlat", viewshedOpts.lonLat, "The observer is WGS84 longitude,latitude");
    viewshedCmd->add_option("--observer-height", viewshedOpts.observerHeightM, "Metres above the terrain (default 1.7)");
    viewshedCmd->add_option("--target-height", viewshedOpts.targetHeightM, "Metres above the terrain (default 0)");
    viewshedCmd->add_option("--curvature-coeff", viewshedOpts.curvatureCoeff,
                            "Earth curvature and refraction, as gdal_viewshed -cc (default 0.85714; 0 = flat earth)");
    viewshedCmd->add_option("--method", viewshedMethod, "Direct cell method (default bilinear)");
    viewshedCmd->add_option("--threads", viewshedOpts.threads, "Worker threads, 0 = all cores")
        ->check(CLI::NonNegativeNumber);

    AccuracyCommandOptions accuracy;
    auto* accuracyCmd = app.add_subcommand(
        "accuracy", "Measure every cell method against the long-double reference on seeded random rays");
    addDemOptions(*accuracyCmd, accuracy.dem);
    accuracyCmd->add_option("--rays", accuracy.rays,
                            "Rays: camera-like, grazing and shadow-like in equal parts (default 100000)");
    accuracyCmd->add_option("--seed", accuracy.seed, "Random seed (default 1)");
    accuracyCmd->add_option("--json", accuracy.json, "Also write the report as JSON to this file");

    CompareCommandOptions compare;
    std::string compareSize = "640x480", compareSun = "315,35", compareMethodsText;
    auto* compareCmd = app.add_subcommand(
        "compare", "Trace the same rays with every method (direct and Embree) and report speed and error side by side");
    addDemOptions(*compareCmd, compare.dem);
    compareCmd->add_option("--size", compareSize, "Image size WxH in pixels (default 640x480)");
    compareCmd->add_option("--sun", compareSun, "Sun azimuth,elevation in degrees (default 315,35)");
    compareCmd->add_option("--exaggeration", compare.exaggeration, "Vertical exaggeration factor (default 1)");
    compareCmd->add_option("--camera", compare.camera, "As for render (default: automatic view)");
    compareCmd->add_option("--methods", compareMethodsText,
                           "Comma-separated methods (default bilinear,bilinear-double,triangles,nearest,embree,embree-grid)");
    compareCmd->add_option("--threads", compare.threads, "Worker threads, 0 = all cores (default 0)")
        ->check(CLI::NonNegativeNumber);
    compareCmd->add_option("--json", compare.json, "Write the report as JSON to this file");
    compareCmd->add_option("--out-dir", compare.outDir,
                           "Write each method's image, its difference heat map and tradeoff.svg to this folder");

    BenchCommandOptions bench;
    auto* benchCmd = app.add_subcommand(
        "bench", "Measure the direct tracer against Embree on synthetic fractal grids (and the sample DEMs)");
    benchCmd->add_option("--sizes", bench.sizes, "Synthetic grid sizes, 2^n + 1 vertices each (default 513,2049,8193)");
    benchCmd->add_option("--threads", bench.threads,
                         "Thread count measured beside 1 thread, 0 = all cores (default 0)")
        ->check(CLI::Range(0, 4096));
    benchCmd->add_option("--repeat", bench.repeat,
                         "Trace each pass this many times (default " + std::to_string(BenchSettings{}.repeat) + ")")
        ->check(CLI::Range(1, 100));
    benchCmd->add_option("--bands", bench.bands,
                         "Trace each pass in this many bands of rows, each band in turn with the other methods; a "
                         "pass's time is the sum of each band's fastest (default " +
                             std::to_string(BenchSettings{}.bands) + ")")
        ->check(CLI::Range(1, BenchSettings{}.height));
    benchCmd->add_option("--json", bench.json, "Write the report as JSON to this file");
    benchCmd->add_option("--methods", bench.methods,
                         "Methods to measure, comma-separated: bilinear, bilinear-flat, triangles, embree, embree-grid "
                         "(default all; embree is always measured, as the reference of the ratios)");
    benchCmd->add_option("--svg", bench.svg,
                         "Write an SVG chart of camera rays per second against grid size (synthetic grids, both "
                         "cameras, the most threads) to this file");
    benchCmd->add_flag("--file-to-picture", bench.fileToPicture,
                       "Also time `render FILE.png --cell-size 30 --size 1024x768` with bilinear and with embree, "
                       "from the largest synthetic grid written as a 16-bit PNG height map");
    benchCmd->add_flag("--large", bench.large, "Add a 32769 x 32769 synthetic grid (skipped when over --max-memory)");
    benchCmd->add_flag("--real", bench.real, "Add the GeoTIFF and .hgt DEMs of --data");
    benchCmd->add_option("--data", bench.dataDir, "Folder of the DEMs --real adds (default: the sample DEMs)");
    benchCmd->add_option("--seed", bench.seed, "Seed of the synthetic terrain (default 1)");
    benchCmd->add_option_function<std::string>(
        "--max-memory",
        [&bench](const std::string& text) {
            if (!parseByteCount(text, bench.maxMemoryBytes))
                throw CLI::ValidationError("--max-memory", "expected a size such as 512M or 8G, found '" + text + "'");
        },
        "Skip grids and methods estimated to need more memory than this, e.g. 8G (default: 80% of physical memory)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "terracast: error: {} (see terracast --help)\n", e.what());
        return 2;
    }

    if (*infoCmd) return runInfo(info);
    if (*shadowCmd) {
        if (!parseSunOption(shadowSun, shadow.sunAzimuthDeg, shadow.sunElevationDeg)) return 2;
        if (!parseMethodOption(shadowMethod, shadow.method)) return 2;
        return runShadow(shadow);
    }
    if (*horizonCmd) {
        if (!parseMethodOption(horizonMethod, horizon.method)) return 2;
        return runHorizon(horizon);
    }
    if (*viewshedCmd) {
        if (!parsePair(observer, viewshedOpts.observerX, viewshedOpts.observerY)) {
            fmt::print(stderr, "terracast: error: --observer: expected X,Y, found '{}'\n", observer);
            return 2;
        }
        if (!parseMethodOption(viewshedMethod, viewshedOpts.method)) return 2;
        return runViewshed(viewshedOpts);
    }
    if (*sceneCmd) {
        if (!debugPixel.empty()) {
            double dx = 0, dy = 0;
            if (!parsePair(debugPixel, dx, dy) || dx != std::floor(dx) || dy != std::floor(dy)) {
                fmt::print(stderr, "terracast: error: --debug-pixel: expected X,Y pixel indices, found '{}'\n", debugPixel);
                return 2;
            }
            scene.debugPixel = true;
            scene.debugX = int(dx);
            scene.debugY = int(dy);
        }
        if (!focusPixel.empty()) {
            double fx = 0, fy = 0;
            if (!parsePair(focusPixel, fx, fy) || fx != std::floor(fx) || fy != std::floor(fy)) {
                fmt::print(stderr, "terracast: error: --focus: expected X,Y pixel indices, found '{}'\n", focusPixel);
                return 2;
            }
            scene.focusPixel = true;
            scene.focusX = int(fx);
            scene.focusY = int(fy);
        }
        if (!sceneMethod.empty() &&
            !parseNamedOption(sceneMethod, "--method", parseSurfaceMethod, surfaceMethodList(), scene.method))
            return 2;
        if (!sceneSampler.empty() &&
            !parseNamedOption(sceneSampler, "--sampler", parseSamplePattern, samplePatternList(), scene.sampler))
            return 2;
        if (!sceneFilter.empty() &&
            !parseNamedOption(sceneFilter, "--filter", parseFilterKind, filterKindList(), scene.filter))
            return 2;
        scene.adaptive = adaptiveOpt->count() > 0;
        if (!sceneSize.empty() && !parseSize(sceneSize, scene.width, scene.height)) {
            fmt::print(stderr, "terracast: error: --size: expected WxH with positive integers, found '{}'\n", sceneSize);
            return 2;
        }
        return runScene(scene);
    }
    if (*accuracyCmd) return runAccuracy(accuracy);
    if (*compareCmd) {
        if (!parseViewOptions(compareSize, compareSun, compare.width, compare.height, compare.sunAzimuthDeg,
                              compare.sunElevationDeg))
            return 2;
        if (!compareMethodsText.empty()) {
            compare.methods.clear();
            size_t startPos = 0;
            while (startPos <= compareMethodsText.size()) {
                const size_t comma = compareMethodsText.find(',', startPos);
                const std::string name = compareMethodsText.substr(startPos, comma - startPos);
                const auto m = parseSurfaceMethod(name);
                if (!m) {
                    fmt::print(stderr, "terracast: error: --methods: expected names from {}, found '{}'\n",
                               surfaceMethodList(), name);
                    return 2;
                }
                compare.methods.push_back(*m);
                if (comma == std::string::npos) break;
                startPos = comma + 1;
            }
        }
        return runCompare(compare);
    }
    if (*benchCmd) return runBench(bench);
    if (*renderCmd) {
        if (!parseViewOptions(size, sun, render.width, render.height, render.sunAzimuthDeg, render.sunElevationDeg))
            return 2;
        if (!parseMethodOption(method, render.method)) return 2;
        if (!sunTime.empty()) {
            std::string why;
            render.sunTime = parseIsoTime(sunTime, why);
            if (!render.sunTime) {
                fmt::print(stderr, "terracast: error: --sun-time: expected an ISO 8601 time such as 2026-06-21T19:30Z, "
                                   "found '{}' ({})\n",
                           sunTime, why);
                return 2;
            }
        }
        if (view != "perspective" && view != "map") {
            fmt::print(stderr, "terracast: error: --view: expected perspective or map, found '{}'\n", view);
            return 2;
        }
        if (colour != "grey" && colour != "ramp") {
            fmt::print(stderr, "terracast: error: --colour: expected grey or ramp, found '{}'\n", colour);
            return 2;
        }
        render.mapView = view == "map";
        render.castShadows = !noShadows;
        render.colourRamp = colour == "ramp";
        return runRender(render);
    }
    return 2;
}
