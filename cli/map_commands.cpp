// `shadow`, `horizon` and `viewshed`: option parsing into typed values; the work is in map_pipeline.
#include "cli/cli_support.h"

#include "tracer/core/errors.h"
#include "tracer/terrain/map_pipeline.h"

#include <fmt/core.h>

namespace terracast::cli {

namespace {

void addResume(CLI::App& cmd, bool& resume) {
    cmd.add_flag("--resume", resume,
                 "Keep the output tiles an interrupted run of the same command left in OUTPUT.partial and compute "
                 "only the others");
}

void addVerbose(CLI::App& cmd, bool& verbose) {
    cmd.add_flag("-v,--verbose", verbose,
                 "Also tell each phase's seconds: reading the DEM and making the grid, the set-up (a viewshed's curved "
                 "copy and sight bounds), the output tiles, the COG");
}

void addThreadsAndMethod(CLI::App& cmd, int& threads, std::string& method) {
    cmd.add_option("--method", method, "Direct cell method (default bilinear)");
    cmd.add_option("--threads", threads, "Worker threads, 0 = all cores")->check(nonNegativeInteger());
}

void addSearchOptions(CLI::App& cmd, double& maxDistanceM, double& curvatureCoeff, const char* distanceHelp) {
    cmd.add_option("--max-distance", maxDistanceM, distanceHelp)->check(numberRange(0.0, 1e8, "metres"));
    cmd.add_option("--curvature-coeff", curvatureCoeff,
                   "Earth curvature less refraction, as viewshed's (0.85714 for standard refraction; default 0: "
                   "flat earth)")
        ->check(numberRange(-10.0, 10.0, "a coefficient"));
}

}  // namespace

void addMapCommands(CLI::App& app, Commands& commands) {
    {
        struct Texts {
            ShadowMapOptions options;
            std::string sun = "315,35", sunTime, method = "bilinear";
        };
        auto t = std::make_shared<Texts>();
        auto* cmd = app.add_subcommand("shadow", "Sun shadow mask per DEM vertex (1 blocked, 0 lit), as GeoTIFF");
        addDemOptions(*cmd, t->options.dem);
        cmd->add_option("-o,--output", t->options.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
        addResume(*cmd, t->options.resume);
        addVerbose(*cmd, t->options.verbose);
        cmd->add_option("--sun", t->sun, "Sun azimuth,elevation in degrees (default 315,35)");
        cmd->add_option("--sun-size", t->options.sunSizeDeg,
                        "Sun's angular diameter in degrees; > 0 gives the blocked fraction (default 0: a point)");
        cmd->add_option("--sun-time", t->sunTime,
                        "An ISO 8601 time (2026-06-21T15:00Z), or START/END/STEP (a step such as 30m or 1h): one "
                        "band per time, the sun where it stands then over the DEM's centre; replaces --sun");
        addSearchOptions(*cmd, t->options.maxDistanceM, t->options.curvatureCoeff,
                         "Metres beyond which terrain casts no shadow (default 0: the whole DEM)");
        addThreadsAndMethod(*cmd, t->options.threads, t->method);
        commands.push_back({cmd, [t] {
                                return guarded([&] {
                                    parseSunOption(t->sun, t->options.sunAzimuthDeg, t->options.sunElevationDeg);
                                    if (!t->sunTime.empty())
                                        t->options.sunTimes = parseSunTimeRange(t->sunTime, "--sun-time");
                                    t->options.method = parseMethodOption(t->method);
                                    writeShadowMap(t->options, ConsoleListener(false).listener());
                                });
                            }});
    }
    {
        struct Texts {
            HorizonMapOptions options;
            double azimuth = 0.0;
            std::string azimuths, method = "bilinear";
        };
        auto t = std::make_shared<Texts>();
        auto* cmd = app.add_subcommand(
            "horizon", "Horizon elevation angle in degrees per DEM vertex towards an azimuth (or one band per azimuth)");
        addDemOptions(*cmd, t->options.dem);
        cmd->add_option("-o,--output", t->options.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
        addResume(*cmd, t->options.resume);
        addVerbose(*cmd, t->options.verbose);
        auto* one = cmd->add_option("--azimuth", t->azimuth, "Azimuth in degrees clockwise from north");
        auto* many = cmd->add_option("--azimuths", t->azimuths,
                                     "START:END:STEP in degrees, END excluded: one band per azimuth, in one pass "
                                     "(e.g. 0:360:15)");
        one->excludes(many);
        many->excludes(one);
        addSearchOptions(*cmd, t->options.maxDistanceM, t->options.curvatureCoeff,
                         "Search radius in metres (default 0: the whole DEM)");
        addThreadsAndMethod(*cmd, t->options.threads, t->method);
        commands.push_back({cmd, [t, one] {
                                return guarded([&] {
                                    if (one->count() == 0 && t->azimuths.empty())
                                        throw InputError("horizon: give --azimuth DEGREES or --azimuths START:END:STEP");
                                    t->options.azimuthsDeg = one->count() > 0
                                                                 ? std::vector<double>{t->azimuth}
                                                                 : parseAzimuthRange(t->azimuths, "--azimuths");
                                    t->options.method = parseMethodOption(t->method);
                                    writeHorizonMap(t->options, ConsoleListener(false).listener());
                                });
                            }});
    }
    {
        struct Texts {
            SkyViewMapOptions options;
            std::string method = "bilinear";
        };
        auto t = std::make_shared<Texts>();
        auto* cmd = app.add_subcommand("svf", "Sky-view factor, positive and negative openness per DEM vertex "
                                              "(three bands), from exact horizons");
        addDemOptions(*cmd, t->options.dem);
        cmd->add_option("-o,--output", t->options.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
        addResume(*cmd, t->options.resume);
        addVerbose(*cmd, t->options.verbose);
        cmd->add_option("--directions", t->options.directions, "Azimuths, evenly spaced from north (default 16)");
        addSearchOptions(*cmd, t->options.maxDistanceM, t->options.curvatureCoeff,
                         "Search radius in metres (default 0: 10 cells)");
        addThreadsAndMethod(*cmd, t->options.threads, t->method);
        commands.push_back({cmd, [t] {
                                return guarded([&] {
                                    t->options.method = parseMethodOption(t->method);
                                    writeSkyViewMap(t->options, ConsoleListener(false).listener());
                                });
                            }});
    }
    {
        struct Texts {
            InsolationMapOptions options;
            std::string dates, step = "30m", method = "bilinear";
        };
        auto t = std::make_shared<Texts>();
        auto* cmd = app.add_subcommand("insolation", "Clear-sky beam, diffuse, reflected and global irradiation (Wh/m2) "
                                                     "and hours of direct sun per DEM vertex over a day or dates, with "
                                                     "cast shadows (five bands; r.sun's model)");
        addDemOptions(*cmd, t->options.dem);
        cmd->add_option("-o,--output", t->options.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
        addResume(*cmd, t->options.resume);
        addVerbose(*cmd, t->options.verbose);
        cmd->add_option("--date", t->dates,
                        "A day YYYY-MM-DD or dates START/END (END included), local solar days at the DEM's centre")
            ->required();
        cmd->add_option("--step", t->step, "Time step within a day, such as 30m or 1h (default 30m, as r.sun's)");
        cmd->add_option("--day-step", t->options.dayStep,
                        "Compute every n-th day, each standing for the n days from it (default 1)");
        cmd->add_option("--linke", t->options.linkeTurbidity, "Linke turbidity factor (default 3.0)");
        cmd->add_option("--albedo", t->options.albedo, "Ground reflectance for the reflected part (default 0.2)");
        addSearchOptions(*cmd, t->options.maxDistanceM, t->options.curvatureCoeff,
                         "Metres beyond which terrain casts no shadow (default 0: the whole DEM)");
        addThreadsAndMethod(*cmd, t->options.threads, t->method);
        commands.push_back({cmd, [t] {
                                return guarded([&] {
                                    t->options.dates = parseDateSpan(t->dates, "--date");
                                    t->options.stepSeconds = parseDurationSeconds(t->step, "--step");
                                    t->options.method = parseMethodOption(t->method);
                                    writeInsolationMap(t->options, ConsoleListener(false).listener());
                                });
                            }});
    }
    {
        struct Texts {
            ViewshedMapOptions options;
            std::string observer, method = "bilinear", values = "visible";
        };
        auto t = std::make_shared<Texts>();
        ViewshedMapOptions& v = t->options;
        auto* cmd =
            app.add_subcommand("viewshed", "Visibility from an observer per DEM vertex (1 visible, 0 hidden)");
        addDemOptions(*cmd, v.dem);
        cmd->add_option("-o,--output", v.output, "Output GeoTIFF (.tif) on the DEM's grid")->required();
        addResume(*cmd, v.resume);
        addVerbose(*cmd, v.verbose);
        auto* one = cmd->add_option("--observer", t->observer, "Observer X,Y in the DEM's CRS (lon,lat with --lonlat)");
        auto* many = cmd->add_option("--observers", v.observersFile,
                                     "Many observers: a CSV of X,Y[,HEIGHT] in the DEM's CRS or a vector file of points "
                                     "(any GDAL reads); writes how many see each vertex");
        one->excludes(many);
        many->excludes(one);
        cmd->add_option("--max-distance", v.maxDistanceM, "Targets farther than this (metres) are not seen (default 0: "
                                                           "no limit)");
        cmd->add_flag("--lonlat", v.lonLat, "The observer is WGS84 longitude,latitude");
        cmd->add_option("--observer-height", v.observerHeightM, "Metres above the terrain (default 1.7)")
            ->check(numberRange(-1e6, 1e6, "metres"));
        cmd->add_option("--target-height", v.targetHeightM, "Metres above the terrain (default 0)")
            ->check(numberRange(-1e6, 1e6, "metres"));
        cmd->add_option("--values", t->values,
                        "visible (1/0, Byte), angle (degrees from the eye to each visible target, Float32) or height "
                        "(metres above the ground a target needs to be seen, Float32); default visible");
        cmd->add_option("--curvature-coeff", v.curvatureCoeff,
                        "Earth curvature and refraction, as gdal_viewshed -cc (default 0.85714; 0 = flat earth)")
            ->check(numberRange(-10.0, 10.0, "a coefficient"));
        addThreadsAndMethod(*cmd, v.threads, t->method);
        commands.push_back({cmd, [t] {
                                return guarded([&] {
                                    if (t->observer.empty() && t->options.observersFile.empty())
                                        throw InputError("viewshed: give --observer X,Y or --observers FILE");
                                    if (!t->observer.empty() &&
                                        !parsePair(t->observer, t->options.observerX, t->options.observerY))
                                        throw InputError(
                                            fmt::format("--observer: expected X,Y, found '{}'", t->observer));
                                    t->options.method = parseMethodOption(t->method);
                                    t->options.values = parseViewshedValues(t->values, "--values");
                                    writeViewshedMap(t->options, ConsoleListener(false).listener());
                                });
                            }});
    }
}

}  // namespace terracast::cli
