#include "tracer/terrain/dem_pipeline.h"

#include "heightfield/height_tile.h"

#include "loaders/image_io.h"
#include "loaders/output_paths.h"
#include "loaders/raster_writer.h"
#include "loaders/scene_assets.h"
#include "loaders/crs.h"
#include "tracer/core/angles.h"
#include "tracer/core/errors.h"
#include "loaders/tiled_dem.h"
#include "tracer/core/ranks.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "tracer/terrain/maps.h"
#include "tracer/terrain/memory_model.h"
#include "tracer/terrain/solid_base.h"
#include "tracer/terrain/surface.h"
#include "tracer/terrain/tiled_product.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace terracast {

LoadedDem loadDemSource(const DemSource& source, const RunListener& listener, bool takesTiles, double exaggeration) {
    DemLoadOptions lo;
    lo.exaggeration = exaggeration;
    lo.maxBytes = source.maxMemoryBytes;
    lo.imageCellSizeM = source.imageCellSizeM;
    lo.imageHeightScale = source.imageHeightScale;
    lo.tileCacheBytes = source.tileCacheBytes;
    lo.tileStore = source.tileStore;
    // Under mpirun every command that gets here runs on every rank (cli/main.cpp refuses the others).
    lo.sharedByRanks = ranks::size() > 1;
    lo.tilesUnderRanks = takesTiles;
    LoadedDem dem = loadDem(source.path, lo);
    for (const auto& w : dem.warnings) listener.warn(w);
    if (source.tileStore) {
        const auto* tiles = dem.grid.tiled() ? dynamic_cast<const TiledDem*>(dem.grid.tileSource()) : nullptr;
        if (tiles == nullptr)
            listener.warn(source.path + ": --tile-store has no effect: the DEM is held whole in memory");
        else if (tiles->store() == nullptr)
            listener.warn(source.path + ": no tile store: " + tiles->storeOrigin());
    }
    return dem;
}

std::string demInfoReport(const DemSource& source, const RunListener& listener) {
    const LoadedDem dem = loadDemSource(source, listener);
    const HeightGrid& g = dem.grid;
    const double total = double(g.width()) * double(g.height());
    std::string out;
    out += fmt::format("file:        {}\n", dem.path);
    out += fmt::format("driver:      {}\n", dem.driver);
    out += fmt::format("size:        {} x {} vertices ({} x {} cells)\n", g.width(), g.height(), g.cellsX(), g.cellsY());
    if (dem.geo.georeferenced) {
        out += fmt::format("crs:         {}{}\n", dem.geo.crsName.empty() ? "(unnamed)" : dem.geo.crsName,
                           dem.geo.geographic
                               ? fmt::format(" (geographic, converted at latitude {:.4f})", dem.geo.centreLatDeg)
                               : "");
        out += fmt::format("origin:      {:.3f}, {:.3f} (south-west sample, CRS units)\n", dem.geo.originX,
                           dem.geo.originY);
    } else {
        out += "crs:         none (plain height map)\n";
    }
    out += fmt::format("cell size:   {:.3f} x {:.3f} m\n", g.cellSizeXM(), g.cellSizeYM());
    out += fmt::format("extent:      {:.1f} x {:.1f} m\n", g.extentXM(), g.extentYM());
    out += fmt::format("heights:     {:.2f} .. {:.2f} m\n", g.minHeightM(), g.maxHeightM());
    out += fmt::format("nodata:      {:.2f}% of vertices ({} of {}), {} valid cells\n",
                       100.0 * double(g.nodataVertexCount()) / total, g.nodataVertexCount(), int64_t(total),
                       g.validCellCount());
    if (g.tiled()) {
        const TileLayout layout{g.width(), g.height()};
        out += fmt::format("held:        as {} x {} tiles of {} x {} cells read on demand, a cache of {} ({} "
                           "pyramid levels resident)\n",
                           layout.tilesX(), layout.tilesY(), kTileCells, kTileCells,
                           humanBytes(double(g.tileSource()->cacheBudgetBytes())),
                           g.pyramidLevels() - g.tileLevels());
        if (const auto* dem = dynamic_cast<const TiledDem*>(g.tileSource()))
        {
            out += fmt::format("summary:     {}\n", dem->summaryOrigin());
            if (const TileStore* store = dem->store())
                out += fmt::format("tile store:  {} ({} of {} on disk)\n", dem->storeOrigin(),
                                   humanBytes(double(store->diskBytes())), humanBytes(double(store->fullBytes())));
            else if (!dem->storeOrigin().empty())
                out += fmt::format("tile store:  {}\n", dem->storeOrigin());
        }
    } else {
        out += "held:        whole, in memory\n";
    }
    out += fmt::format("memory:      {} for the grid; about {} to render at 1280x720\n",
                       humanBytes(double(g.memoryBytes())),
                       humanBytes(double(g.memoryBytes()) + 1280.0 * 720.0 * kFilmBytesPerPixel));
    return out;
}

std::string tileTraffic(const HeightGrid& grid) {
    if (!grid.tiled()) return "";
    const TileCacheStats t = grid.tileSource()->cacheStats();
    const int64_t reads = t.hits + t.loads;
    std::string line = fmt::format("tiles: {} loaded, {:.1f} % of {} reads from the cache", t.loads,
                                   reads > 0 ? 100.0 * double(t.hits) / double(reads) : 100.0, reads);
    if (const auto* tiles = dynamic_cast<const TiledDem*>(grid.tileSource()); tiles && tiles->store())
        line += fmt::format(" ({} from the tile store, {} written to it)", tiles->store()->reads(),
                            tiles->store()->writes());
    return line;
}

std::string tileTimes(const HeightGrid& grid) {
    if (!grid.tiled()) return "";
    const TileCacheStats t = grid.tileSource()->cacheStats();
    return fmt::format("tile cache: loading {:.4f} thread-s ({:.1f} us a tile), waiting for another thread's load "
                       "{:.4f} thread-s", t.loadSeconds, t.loads > 0 ? 1e6 * t.loadSeconds / double(t.loads) : 0.0,
                       t.waitSeconds);
}

std::function<void(double, int64_t)> progressWithTiles(const RunListener& listener, const HeightGrid& grid) {
    if (!listener.progress) return {};
    if (!grid.tiled()) return listener.progress;
    return [&listener, &grid](double fraction, int64_t rays) {
        listener.show(tileTraffic(grid));
        listener.progress(fraction, rays);
    };
}

void checkViewValues(double exaggeration, double sunElevationDeg) {
    if (!(exaggeration > 0.0) || !std::isfinite(exaggeration))
        throw InputError(fmt::format("--exaggeration: expected a positive number, found {}", exaggeration));
    if (!(sunElevationDeg >= -90.0 && sunElevationDeg <= 90.0))
        throw InputError(fmt::format("--sun: elevation must lie in [-90, 90] degrees, found {}", sunElevationDeg));
}

TerrainRenderSettings makeView(const HeightGrid& grid, int width, int height, double sunAzimuthDeg,
                               double sunElevationDeg, const std::optional<PinholeCamera>& camera, int threads) {
    TerrainRenderSettings s;
    s.width = width;
    s.height = height;
    s.threads = threads;
    s.sun.azimuthDeg = sunAzimuthDeg;
    s.sun.elevationDeg = sunElevationDeg;
    s.camera = camera ? *camera : autoCamera(grid, double(width) / double(height));
    return s;
}

namespace {

// With a sun time, the sun's azimuth and (apparent) elevation at that instant over the DEM's centre.
void applySunTime(const DemRenderOptions& o, const LoadedDem& dem, double& azimuthDeg, double& elevationDeg,
                  const RunListener& listener) {
    if (!o.sunTime) return;
    listener.tell(placeSunOverGrid(*o.sunTime, dem.geo, dem.grid.width(), dem.grid.height(),
                                   o.dem.path + ": --sun-time", azimuthDeg, elevationDeg));
}

void checkSkySamples(int skySamples) {
    if (skySamples < -1 || skySamples > 4096)
        throw InputError(fmt::format("--sky-samples: expected 0..4096, found {}", skySamples));
}

// A map view GeoTIFF's four samples at a pixel: 8-bit sRGB of the linear colour, and alpha 255 where the
// terrain has a surface, 0 over holes.
void mapViewSample(const glm::vec3& linear, bool covered, float* out) {
    for (int b = 0; b < 3; ++b) out[b] = 255.0f * srgbFromLinear(linear[b]);
    out[3] = covered ? 255.0f : 0.0f;
}

}  // namespace

void checkMapViewOptions(const DemRenderOptions& o) {
    checkViewValues(o.exaggeration, o.sunElevationDeg);
    if (!(o.scale > 0.0 && o.scale <= 16.0)) throw InputError(fmt::format("--scale: expected (0, 16], found {}", o.scale));
    if (!(o.hillshadeBlend >= 0.0 && o.hillshadeBlend <= 1.0))
        throw InputError(fmt::format("--hillshade-blend: expected 0..1, found {}", o.hillshadeBlend));
    checkSkySamples(o.skySamples);
    requireDirectMethod(o.method, "--view map");
}

MapViewSettings mapViewSettings(const DemRenderOptions& o, const LoadedDem& dem, const RunListener& listener) {
    checkMapViewOptions(o);
    double sunAzimuthDeg = o.sunAzimuthDeg, sunElevationDeg = o.sunElevationDeg;
    applySunTime(o, dem, sunAzimuthDeg, sunElevationDeg, listener);
    TerrainRenderSettings view =
        makeView(dem.grid, 16, 16, sunAzimuthDeg, sunElevationDeg, std::nullopt, o.threads);
    MapViewSettings m;
    m.scale = o.scale;
    m.sun = view.sun;
    m.castShadows = o.castShadows;
    m.skySamples = o.skySamples < 0 ? 16 : o.skySamples;
    m.colourRamp = o.colourRamp;
    m.hillshadeBlend = o.hillshadeBlend;
    m.method = requireDirectMethod(o.method, "--view map");
    m.threads = o.threads;
    m.progress = listener.progress;
    return m;
}

VertexProduct mapViewProduct(const MapViewSettings& m, const LoadedDem& dem) {
    if (m.scale != 1.0 || m.method == CellMethod::Nearest)
        throw InputError("render --view map: a map view on the DEM's own grid takes --scale 1 and a method whose "
                         "surface passes through the vertices (not nearest)");
    // 8-bit sRGB in three bands and an alpha band (0 over holes), on the DEM's own grid, a tile at a time.
    VertexProduct product;
    product.bands = 4;
    product.type = RasterType::Byte;
    product.lastBandIsAlpha = true;
    product.labels.bands = {"red", "green", "blue", "alpha: 255 over the terrain, 0 over nodata"};
    product.compute = [make = mapViewMaker(dem.grid, m)](const VertexWindow& w, const MapProgress& p) {
        MapRaster r = make(w, p);
        for (size_t k = 0; k < r.values.size(); k += 4) {
            mapViewSample({r.values[k], r.values[k + 1], r.values[k + 2]}, r.values[k + 3] > 0.0f, &r.values[k]);
        }
        return r;
    };
    return product;
}

std::vector<uint8_t> mapViewPixels(const MapImage& image) {
    const Film& film = image.film;
    std::vector<uint8_t> out(size_t(film.width) * size_t(film.height) * 4);
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            float v[4];
            mapViewSample(film.get(x, y), image.covered[size_t(y) * size_t(film.width) + size_t(x)] != 0, v);
            for (int b = 0; b < 4; ++b) out[(size_t(y) * size_t(film.width) + size_t(x)) * 4 + size_t(b)] = rasterByte(v[b]);
        }
    return out;
}

namespace {

// `render --view map`: the top-down shaded relief, as a GeoTIFF on the DEM's georeference or a PNG.
void renderMap(const DemRenderOptions& o, const RunListener& listener) {
    if (o.lodPixels != 0.0) throw InputError("--lod: expected the perspective view, found --view map");
    // A GeoTIFF at scale 1 on a surface through the vertices is a per-vertex product on the DEM's own grid,
    // written a tile at a time (and over the ranks); a PNG or another scale is one picture held whole.
    const bool onGrid = lowerExtension(o.output) != ".png" && o.scale == 1.0 &&
                        requireDirectMethod(o.method, "--view map") != CellMethod::Nearest;
    if (ranks::size() > 1 && !onGrid)
        throw InputError("render --view map: runs as one process as a PNG, at a --scale other than 1 or with "
                         "--method nearest; under mpirun the ranks share a GeoTIFF at scale 1");
    if (o.resume && !onGrid)
        throw InputError("render --resume: only the map view as a GeoTIFF at --scale 1 (not --method nearest) is "
                         "written a tile at a time and can resume");
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff", ".png"});
    checkMapViewOptions(o);
    LoadedDem dem = loadDemSource(o.dem, listener, onGrid, o.exaggeration);
    const MapViewSettings m = mapViewSettings(o, dem, listener);
    if (onGrid) {
        checkRasterJob(dem, o.dem.maxMemoryBytes, 4, RasterType::Byte, 0.0, "the map view");
        listener.at("map view");
        const auto start = std::chrono::steady_clock::now();
        VertexProduct product = mapViewProduct(m, dem);
        const ProductCount count = writeVertexProduct(o.output, o.resume, dem, std::move(product), o.threads, listener);
        tellRasterSummary(listener, "map view", o.output, count, count.rays, "sun and sky rays", start);
        return;
    }
    {
        // The film and its coverage mask, then either the PNG's copy and encoding or the GeoTIFF's four float
        // bands; the output size follows renderMapView's (scale times the DEM's vertices).
        const double pixels = std::ceil(double(dem.grid.width()) * o.scale) * std::ceil(double(dem.grid.height()) * o.scale);
        const bool png = lowerExtension(o.output) == ".png";
        checkMemory(o.dem.path, o.dem.maxMemoryBytes, dem.grid,
                    pixels * (kFilmBytesPerPixel + 1.0 + (png ? kFilmBytesPerPixel + kEncodeBytesPerPixel : 17.0)),
                    fmt::format("the map view at scale {:g}", o.scale));
    }
    listener.at("map view");
    const auto start = std::chrono::steady_clock::now();
    const MapImage image = renderMapView(dem.grid, m);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Film& film = image.film;
    if (lowerExtension(o.output) == ".png") {
        writeImage(o.output, RgbImage{film.width, film.height, film.rgb});
    } else {
        // 8-bit sRGB in three bands and an alpha band (0 over holes), rows south first as the writer expects;
        // at scale 1 the pixels are the DEM's own, at other scales they cover the same footprint.
        GridRaster out;
        out.width = film.width;
        out.height = film.height;
        out.bands = 4;
        out.lastBandIsAlpha = true;
        out.pixelIsPoint = dem.geo.pixelIsPoint;
        out.bandDescriptions = {"red", "green", "blue", "alpha: 255 over the terrain, 0 over nodata"};
        out.values.resize(size_t(film.width) * size_t(film.height) * 4);
        for (int y = 0; y < film.height; ++y)
            for (int x = 0; x < film.width; ++x) {
                const int row = film.height - 1 - y;
                const glm::vec3 c = film.get(x, row);
                float* v = &out.values[(size_t(y) * size_t(film.width) + size_t(x)) * 4];
                mapViewSample(c, image.covered[size_t(row) * size_t(film.width) + size_t(x)] != 0, v);
            }
        const double pxX = double(dem.grid.width()) / film.width * sourcePixelSizeX(dem.geo);
        const double pxY = double(dem.grid.height()) / film.height * sourcePixelSizeY(dem.geo);
        writeGeoTiff(o.output, out, RasterType::Byte,
                     RasterPlacement{dem.geo, dem.geo.originX - 0.5 * sourcePixelSizeX(dem.geo) + 0.5 * pxX,
                                     dem.geo.originY - 0.5 * sourcePixelSizeY(dem.geo) + 0.5 * pxY, pxX, pxY});
    }
    const int64_t rays = image.shadowRays + image.skyRays;
    listener.tell(fmt::format("map {} ({}x{}, {}) in {:.2f} s; shadows {}, {} sky rays per pixel: {} sun + {} sky "
                              "rays, {:.2f} Mrays/s, peak memory {}",
                              o.output, film.width, film.height, cellMethodName(m.method), seconds,
                              m.castShadows ? "on" : "off", m.skySamples, image.shadowRays, image.skyRays,
                              seconds > 0.0 ? double(rays) / seconds * 1e-6 : 0.0, humanBytes(peakResidentBytes())));
}

}  // namespace

void checkPerspectiveOptions(const DemRenderOptions& o) {
    checkViewValues(o.exaggeration, o.sunElevationDeg);
    checkSkySamples(o.skySamples);
    if (!(o.haze >= 0.0 && o.haze <= 1000.0))
        throw InputError(fmt::format("--haze: expected a number in 0..1000, found {}", o.haze));
    if (o.resume) throw InputError("render --resume: only the map view as a GeoTIFF at --scale 1 can resume");
    if (o.samples < 1 || o.samples > 65536)
        throw InputError(fmt::format("--spp: expected 1..65536 samples per pixel, found {}", o.samples));
    if (o.adaptive && !(o.adaptiveError > 0.0))
        throw InputError(fmt::format("--adaptive: expected an error > 0, found {}", o.adaptiveError));
    if (o.width < 1 || o.height < 1 || o.width > 65536 || o.height > 65536)
        throw InputError(fmt::format("--size: expected 1..65536 pixels a side, found {}x{}", o.width, o.height));
    if (o.lodPixels != 0.0) {
        if (!(o.lodPixels > 0.0 && o.lodPixels <= 1e6))
            throw InputError(fmt::format("--lod: expected pixels per cell in (0, 1e6], found {}", o.lodPixels));
        if (o.cameraKind != CameraKind::Pinhole)
            throw InputError(fmt::format("--lod: expected the perspective view, found --view {}", cameraKindName(o.cameraKind)));
        if (!directCellMethod(o.method))
            throw InputError(fmt::format("--lod: expected a direct method (bilinear, bilinear-double, triangles, nearest), "
                                         "found --method {}", surfaceMethodName(o.method)));
    }
}

TerrainRenderSettings perspectiveSettings(const DemRenderOptions& o, const LoadedDem& dem, const RunListener& listener) {
    checkPerspectiveOptions(o);
    const HeightGrid& grid = dem.grid;
    double sunAzimuthDeg = o.sunAzimuthDeg, sunElevationDeg = o.sunElevationDeg;
    applySunTime(o, dem, sunAzimuthDeg, sunElevationDeg, listener);
    TerrainRenderSettings s = makeView(grid, o.width, o.height, sunAzimuthDeg, sunElevationDeg,
                                       o.camera, o.threads);
    s.sky.kind = o.sky;
    s.sky.haze = o.haze;
    s.sky.samples = o.skySamples < 0 ? 4 : o.skySamples;
    s.seed = o.seed;
    s.smoothNormals = o.smoothNormals;
    s.sampling = PixelSampling::make(o.samples, o.sampler, o.filter, o.adaptive, o.adaptiveError);
    s.look.colouring = o.colouring;
    s.look.plain = o.plainColour;
    s.look.solidBase = o.solidBase;
    // The automatic view frames the base too.
    if (o.solidBase && !o.camera) s.camera = autoCamera(grid, double(o.width) / double(o.height), 40.0, solidBaseFloorM(grid));
    s.look.backdrop = o.backdrop;

    if (o.cameraKind != CameraKind::Pinhole) {
        s.view = makeViewCamera(grid, o.cameraKind, o.camera, double(o.width) / double(o.height));
        s.camera.eyeM = s.view->eye();  // the viewer's place in the atmosphere
        // Aerial perspective needs one centre of projection: the orthographic camera's rays have none.
        if (o.cameraKind == CameraKind::Orthographic) s.sky.aerialPerspective = false;
    }
    s.progress = progressWithTiles(listener, grid);
    return s;
}

std::string renderPhasesLine(const RenderPhaseSeconds& p) {
    const double threadSeconds =
        p.cameraRayThreadSeconds + p.shadowRayThreadSeconds + p.skyRayThreadSeconds + p.shadingThreadSeconds;
    const auto share = [&](double part) { return threadSeconds > 0.0 ? 100.0 * part / threadSeconds : 0.0; };
    // The decoders read as they decode (libspng from the file, GDAL block by block): one phase.
    return fmt::format("phases: read and decode {:.4f} s, grid {:.4f} s, pyramid {:.4f} s, surface {:.4f} s, trace and "
                       "shade {:.4f} s (sky tables {:.4f} s; the work tiles' thread time: camera rays {:.4f} s {:.0f} %, "
                       "shadow rays {:.4f} s {:.0f} %, sky-visibility rays {:.4f} s {:.0f} %, shading {:.4f} s {:.0f} %), "
                       "write {:.4f} s; total {:.4f} s",
                       std::max(0.0, p.load - p.pyramid - p.grid), p.grid, p.pyramid, p.build, p.render, p.skySetup, p.cameraRayThreadSeconds,
                       share(p.cameraRayThreadSeconds), p.shadowRayThreadSeconds, share(p.shadowRayThreadSeconds),
                       p.skyRayThreadSeconds, share(p.skyRayThreadSeconds), p.shadingThreadSeconds,
                       share(p.shadingThreadSeconds),
                       p.write, p.total);
}

namespace {

// What --verbose tells of a level of detail.
std::string levelOfDetailLine(const TerrainSurface& surface) {
    if (surface.detailLevels() == 0) return "level of detail: none (the grid has no coarser level)";
    const int first = surface.firstDetailLevel();
    return fmt::format("level of detail: {} coarser grids in memory ({}), the first keeping every {} vertex, "
                       "traced from {:.0f} m from the eye on{}",
                       surface.detailLevels(), humanBytes(double(surface.detailBytes())),
                       first == 1 ? std::string("other") : fmt::format("{}th", int64_t(1) << first),
                       surface.detailDistancesM().front(),
                       first == 2   ? std::string("; the DEM's tiles nearer (coarser grid 1 would not fit in the tile cache)")
                       : first > 2 ? fmt::format("; the DEM's tiles nearer (coarser grids 1 to {} would not fit in the "
                                                 "tile cache)",
                                                 first - 1)
                                   : std::string());
}

// `render` without --view map.
RenderPhaseSeconds renderPerspective(const DemRenderOptions& o, const RunListener& listener) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    checkOutputPath(o.output, o.dem.path);
    checkPerspectiveOptions(o);
    if (!o.drape.empty()) checkNotInput(o.output, o.drape, "-o", "the drape");
    // Embree's meshes read every vertex, and so does a level of detail's pass making its coarser grids: ranks hold a
    // DEM that fits whole for them, as one process does; the direct methods read only the tiles the render sees.
    LoadedDem dem =
        loadDemSource(o.dem, listener, directCellMethod(o.method).has_value() && o.lodPixels == 0.0, o.exaggeration);
    HeightGrid& grid = dem.grid;
    TerrainRenderSettings s = perspectiveSettings(o, dem, listener);

    prepareImageWriter(o.output);
    // A drape holds three floats a vertex.
    const bool draped = o.colouring == TerrainLook::Colouring::Drape;
    const double drapeBytes = draped ? 12.0 * double(grid.width()) * double(grid.height()) : 0.0;
    checkMemory(o.dem.path, o.dem.maxMemoryBytes, grid,
                double(o.width) * o.height * (kFilmBytesPerPixel + kEncodeBytesPerPixel) + embreeBytesEstimate(o.method, grid) +
                    drapeBytes + (o.lodPixels > 0.0 ? levelOfDetailBytes(grid) : 0.0),
                fmt::format("rendering {}x{} with {}{}", o.width, o.height, surfaceMethodName(o.method),
                            draped ? " and a drape" : ""));
    if (draped) {
        listener.at("drape");
        s.look.drape = std::make_shared<const DrapeImage>(loadDrape(o.drape, dem.geo, grid.width(), grid.height()));
    }
    const auto loaded = Clock::now();
    TerrainSurface surface(grid, o.method, o.threads);
    if (o.lodPixels > 0.0) {
        // A pixel at the centre of the picture subtends 2 tan(fov / 2) / height radians.
        const double radiansPerPixel = 2.0 * std::tan(0.5 * radians(s.camera.fovYDeg)) / double(o.height);
        surface.setLevelOfDetail({s.camera.eyeM, radiansPerPixel, o.lodPixels});
        if (o.verbose) listener.tell(levelOfDetailLine(surface));
    }
    const auto built = Clock::now();
    RenderStats stats;
    s.timePhases = o.verbose;
    Film film = renderTerrain(grid, surface, s, &stats);
    const auto rendered = Clock::now();
    // In a launch of several ranks the leader holds the whole picture (renderTerrain) and writes it.
    if (ranks::leader()) writeImage(o.output, RgbImage{film.width, film.height, std::move(film.rgb)});
    const auto written = Clock::now();
    const auto seconds = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double>(b - a).count();
    };
    RenderPhaseSeconds phases;
    phases.load = seconds(start, loaded);
    phases.build = seconds(loaded, built);
    phases.render = seconds(built, rendered);
    phases.write = seconds(rendered, written);
    phases.total = seconds(start, written);
    phases.pyramid = grid.tiled() ? 0.0 : grid.pyramidBuildSeconds();
    phases.grid = grid.tiled() ? 0.0 : std::max(0.0, grid.buildSeconds() - grid.pyramidBuildSeconds());
    phases.skySetup = stats.setupSeconds;
    phases.cameraRayThreadSeconds = stats.cameraRaySeconds;
    phases.shadowRayThreadSeconds = stats.shadowRaySeconds;
    phases.skyRayThreadSeconds = stats.skyRaySeconds;
    phases.shadingThreadSeconds = stats.shadingSeconds;
    const int64_t rays = stats.primaryRays + stats.shadowRays + stats.skyVisibilityRays;
    const std::string tiles = tileTraffic(grid);
    std::string view;
    if (o.cameraKind != CameraKind::Pinhole) view = std::string(", ") + cameraKindName(o.cameraKind);
    if (o.adaptive)
        view += fmt::format(", {:.1f} samples per pixel on average (adaptive up to {})",
                            double(stats.primaryRays) / (double(o.width) * o.height), s.sampling.rule.maxSamples);
    else if (o.samples > 1)
        view += fmt::format(", {} samples per pixel", s.sampling.samples);
    listener.tell(fmt::format("rendered {} ({}x{}, {}, {} sky{}) in {:.2f} s: {} primary + {} shadow + {} "
                              "sky-visibility rays, {:.2f} Mrays/s, peak memory {}{}",
                              o.output, o.width, o.height, surfaceMethodName(o.method), skyKindName(o.sky), view,
                              stats.seconds, stats.primaryRays, stats.shadowRays, stats.skyVisibilityRays,
                              stats.seconds > 0 ? double(rays) / stats.seconds * 1e-6 : 0.0,
                              humanBytes(peakResidentBytes()), tiles.empty() ? "" : "; " + tiles));
    if (o.verbose) {
        listener.tell(renderPhasesLine(phases));
        if (grid.tiled()) listener.tell(tileTimes(grid));
    }
    return phases;
}

}  // namespace

RenderPhaseSeconds renderDem(const DemRenderOptions& options, const RunListener& listener) {
    if (options.mapView) {
        renderMap(options, listener);
        return {};
    }
    return renderPerspective(options, listener);
}

}  // namespace terracast
