// `info` and `render`: option parsing into typed values; the work is demInfoReport and renderDem.
#include "cli/cli_support.h"

#include "loaders/image_io.h"
#include "tracer/core/errors.h"

#include <fmt/core.h>

#include <cstdio>

namespace terracast::cli {

void addInfoCommand(CLI::App& app, Commands& commands) {
    auto source = std::make_shared<DemSource>();
    auto* cmd = app.add_subcommand("info", "Describe a DEM: size, CRS, cell size, heights, nodata, memory");
    addDemOptions(*cmd, *source);
    commands.push_back({cmd, [source] {
                            return guarded([&] {
                                const ConsoleListener console(false);
                                const std::string report = demInfoReport(*source, console.listener());
                                console.listener().print(report);
                            });
                        }});
}

void addRenderCommand(CLI::App& app, Commands& commands) {
    struct Texts {
        DemRenderOptions options;
        std::string size = "1280x720", sun = "315,35", method = "bilinear", view = "perspective", colour;
        std::string sky = "physical", sunTime, camera, normals = "smooth", sampler, filter, background = "neutral";
        bool noShadows = false, quiet = false, noBase = false;
        CLI::Option* adaptive = nullptr;
    };
    auto t = std::make_shared<Texts>();
    DemRenderOptions& render = t->options;
    auto* cmd = app.add_subcommand("render", "Render a shaded 3D view of a DEM to PNG or EXR");
    addDemOptions(*cmd, render.dem);
    cmd->add_option("-o,--output", render.output, "Output image: .png (8-bit sRGB) or .exr (linear half float)")
        ->required();
    cmd->add_option("--size", t->size, "Image size WxH in pixels (default 1280x720)");
    cmd->add_option("--sun", t->sun, "Sun azimuth,elevation in degrees, azimuth clockwise from north (default 315,35)");
    cmd->add_option("--exaggeration", render.exaggeration, "Vertical exaggeration factor (default 1)");
    cmd->add_option("--camera", t->camera,
                    "\"eye=x,y,z look=x,y,z fov=deg\" in the DEM's local metres (origin at the south-west "
                    "sample); default: from the south-west, 30 degrees down, framing the DEM");
    cmd->add_option("--method", t->method,
                    "Surface method: bilinear, bilinear-double, triangles, nearest, reference, embree, embree-grid "
                    "(default bilinear)");
    cmd->add_option("--threads", render.threads, "Worker threads, 0 = all cores (default 0)")
        ->check(nonNegativeInteger());
    cmd->add_flag("-q,--quiet", t->quiet, "No progress or summary on stderr");
    cmd->add_flag("-v,--verbose", render.verbose,
                  "Perspective: also tell each phase's seconds (reading and decoding the DEM, its pyramid, the surface, "
                  "tracing and shading with the thread time of camera, shadow and sky-visibility rays and shading, writing)");
    cmd->add_option("--view", t->view,
                    "perspective (default); orthographic (the perspective view's direction without perspective, "
                    "spanning the DEM); panorama (360 x 180 degrees from 2 m above the DEM's centre, north in the "
                    "middle); fisheye (180 degrees from there, looking up, north at the top); or map: top-down on "
                    "the DEM's grid, written as GeoTIFF (.tif) or PNG. --camera sets the eye and look of any but map");
    cmd->add_option("--spp", render.samples, "Camera samples per pixel, anti-aliasing (default 1: the pixel's centre)")
        ->check(CLI::Range(1, 65536));
    cmd->add_option("--sampler", t->sampler,
                    "Sample pattern with --spp: regular, random, stratified (default), poisson, best-candidate");
    cmd->add_option("--filter", t->filter, "Pixel filter with --spp: box (default), tent, gaussian");
    t->adaptive = cmd->add_option("--adaptive", render.adaptiveError,
                                  "Adaptive sampling up to --spp samples, until the standard error of a "
                                  "pixel's luminance is below this (e.g. 0.002)");
    cmd->add_option("--scale", render.scale, "Map view: output pixels per DEM cell (default 1)");
    cmd->add_option("--lod", render.lodPixels,
                    "Level of detail: where a cell spans fewer than this many pixels, trace a coarser grid (every "
                    "other vertex, then every fourth, ...); faster, not exact (see compare --lod). Default: off");
    cmd->add_flag("--resume", render.resume,
                  "Map view as a GeoTIFF at scale 1: keep the output tiles an interrupted run of the same command "
                  "left in OUTPUT.partial and compute only the others");
    cmd->add_flag("--no-shadows", t->noShadows, "Map view: no cast shadows");
    cmd->add_option("--sky-samples", render.skySamples,
                    "Sky-visibility rays per hit (per pixel in the map view), 0 = off (default 4; map view 16)")
        ->check(nonNegativeInteger(4096));
    cmd->add_option("--sky", t->sky,
                    "Sky: physical (Rayleigh and Mie scattering with aerial perspective; default), gradient, "
                    "flat or none");
    cmd->add_option("--haze", render.haze, "Physical sky: multiplies aerosol (Mie) scattering (default 1)");
    cmd->add_option("--sun-time", t->sunTime,
                    "Place the sun where it stands at this instant over the DEM's centre, e.g. "
                    "2026-06-21T19:30Z (instead of --sun)");
    cmd->add_option("--normals", t->normals,
                    "Perspective: shade with smooth normals interpolated from the vertices' gradients (default), or "
                    "facet: each cell's own surface normal; hits and shadows are the same either way");
    cmd->add_option("--seed", render.seed, "Random seed for the sky-visibility directions (default 0)");
    cmd->add_option("--colour", t->colour,
                    "Terrain colour: ramp (by elevation; the default in perspective), grey (the map view's default), "
                    "or in perspective a colour as #rrggbb (sRGB)");
    cmd->add_option("--drape", render.drape,
                    "Perspective: colour the terrain with this image (any raster GDAL reads, RGB or grey), warped "
                    "onto the DEM's grid through both georeferences (or stretched over it when either has none)");
    cmd->add_flag("--no-base", t->noBase,
                  "Perspective: no solid base (by default the DEM stands on walls from its edges down to a floor)");
    cmd->add_option("--background", t->background,
                    "Perspective: what rays that meet nothing show: neutral (grey, the default), sky (the sky model, "
                    "its horizon colour below the horizon) or ground (the sky model's Earth below the horizon)");
    cmd->add_option("--hillshade-blend", render.hillshadeBlend,
                    "Map view: weight of a plain hillshade without shadows or sky, 0..1 (default 0)");
    commands.push_back({cmd, [t] {
                            return guarded([&] {
                                DemRenderOptions& r = t->options;
                                parseSizeOption(t->size, r.width, r.height);
                                parseSunOption(t->sun, r.sunAzimuthDeg, r.sunElevationDeg);
                                r.method = parseMethodOption(t->method);
                                if (!t->sunTime.empty()) r.sunTime = parseSunTimeOption(t->sunTime);
                                if (t->view == "perspective") r.cameraKind = CameraKind::Pinhole;
                                else if (t->view == "orthographic") r.cameraKind = CameraKind::Orthographic;
                                else if (t->view == "panorama") r.cameraKind = CameraKind::Panorama;
                                else if (t->view == "fisheye") r.cameraKind = CameraKind::Fisheye;
                                else if (t->view != "map")
                                    throw InputError(fmt::format("--view: expected perspective, orthographic, "
                                                                 "panorama, fisheye or map, found '{}'",
                                                                 t->view));
                                if (!t->sampler.empty())
                                    r.sampler = parseNamedOption(t->sampler, "--sampler", parseSamplePattern,
                                                                 samplePatternList());
                                if (!t->filter.empty())
                                    r.filter = parseNamedOption(t->filter, "--filter", parseFilterKind, filterKindList());
                                r.adaptive = t->adaptive->count() > 0;
                                // The map view is grey by default, perspective views take the elevation ramp.
                                const std::string colour =
                                    !t->colour.empty() ? t->colour : t->view == "map" ? "grey" : "ramp";
                                const std::optional<glm::vec3> hex = parseHexColour(colour);
                                if (colour != "grey" && colour != "ramp" && !(hex && t->view != "map"))
                                    throw InputError(fmt::format(
                                        "--colour: expected grey or ramp{}, found '{}'",
                                        t->view == "map" ? "" : " or a colour as #rrggbb", colour));
                                if (colour == "grey") {
                                    r.colouring = TerrainLook::Colouring::Plain;
                                } else if (hex) {
                                    r.colouring = TerrainLook::Colouring::Plain;
                                    r.plainColour = *hex;
                                }
                                if (!r.drape.empty()) {
                                    if (t->view == "map")
                                        throw InputError("--drape: only perspective views take a drape");
                                    if (!t->colour.empty())
                                        throw InputError("--drape and --colour both set the terrain's colour: give one");
                                    r.colouring = TerrainLook::Colouring::Drape;
                                }
                                const auto background = parseBackdrop(t->background);
                                if (!background)
                                    throw InputError(fmt::format(
                                        "--background: expected neutral, sky or ground, found '{}'", t->background));
                                r.backdrop = *background;
                                r.solidBase = !t->noBase;
                                r.mapView = t->view == "map";
                                if (!r.mapView) {  // the map view has no sky model and no camera to set
                                    const auto sky = parseSkyKind(t->sky);
                                    if (!sky)
                                        throw InputError(fmt::format(
                                            "--sky: expected physical, gradient, flat or none, found '{}'", t->sky));
                                    r.sky = *sky;
                                    r.camera = parseCameraOption(t->camera, r.cameraKind == CameraKind::Fisheye);
                                }
                                if (t->normals != "smooth" && t->normals != "facet")
                                    throw InputError(
                                        fmt::format("--normals: expected smooth or facet, found '{}'", t->normals));
                                r.smoothNormals = t->normals == "smooth";
                                r.castShadows = !t->noShadows;
                                r.colourRamp = colour == "ramp";
                                const ConsoleListener console(t->quiet);
                                renderDem(r, console.listener());
                            });
                        }});
}

}  // namespace terracast::cli
