// terracast: ray tracing of terrain height fields. Parses the command line into options structs and calls
// one library function per subcommand.
#include "cli/commands.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <string>

using namespace terracast;

namespace {

void addDemOptions(CLI::App& cmd, DemOptions& dem) {
    cmd.add_option("DEM", dem.path, "Elevation raster: GeoTIFF, SRTM .hgt, any GDAL raster, or a PNG height map")
        ->required();
    cmd.add_option("--cell-size", dem.imageCellSizeM, "PNG height maps: metres between samples (default 1)")
        ->check(CLI::PositiveNumber);
    cmd.add_option("--height-scale", dem.imageHeightScale,
                   "PNG height maps: metres per stored unit, 0..255 or 0..65535 (default 1)")
        ->check(CLI::PositiveNumber);
}

// Parses the --size and --sun texts shared by render and compare; prints one line and returns false on error.
bool parseViewOptions(const std::string& size, const std::string& sun, int& width, int& height, double& azimuthDeg,
                      double& elevationDeg) {
    if (!parseSize(size, width, height)) {
        fmt::print(stderr, "terracast: error: --size: expected WxH with positive integers, found '{}'\n", size);
        return false;
    }
    if (!parsePair(sun, azimuthDeg, elevationDeg)) {
        fmt::print(stderr, "terracast: error: --sun: expected AZ,EL in degrees, found '{}'\n", sun);
        return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"terracast: ray tracing of terrain height fields, exact or triangulated"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "terracast 0.1.0");

    InfoOptions info;
    auto* infoCmd = app.add_subcommand("info", "Describe a DEM: size, CRS, cell size, heights, nodata, memory");
    addDemOptions(*infoCmd, info.dem);

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
    if (*renderCmd) {
        if (!parseViewOptions(size, sun, render.width, render.height, render.sunAzimuthDeg, render.sunElevationDeg))
            return 2;
        const auto m = parseSurfaceMethod(method);
        if (!m) {
            fmt::print(stderr, "terracast: error: --method: expected one of {}, found '{}'\n", surfaceMethodList(), method);
            return 2;
        }
        render.method = *m;
        return runRender(render);
    }
    return 2;
}
