#include "tracer/terrain/map_pipeline.h"

#include "loaders/crs.h"
#include "loaders/output_paths.h"
#include "loaders/raster_writer.h"
#include "tracer/core/angles.h"
#include "tracer/core/errors.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "tracer/terrain/maps.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace terracast {

namespace {

// Writes a per-vertex map raster as a GeoTIFF on the DEM's own grid (NaN becomes `noData`).
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

// The line that ends a raster command: what was written, its size, seconds and peak memory.
void tellRasterSummary(const RunListener& listener, const std::string& what, const std::string& path,
                       const MapRaster& r, std::chrono::steady_clock::time_point start) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    listener.tell(fmt::format("{} {} ({} x {} vertices) in {:.2f} s, peak memory {}", what, path, r.width, r.height,
                              seconds, humanBytes(peakResidentBytes())));
}

}  // namespace

void writeShadowMap(const ShadowMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    checkViewValues(1.0, o.sunElevationDeg);
    if (!(o.sunSizeDeg >= 0.0 && o.sunSizeDeg < 30.0))
        throw InputError(fmt::format("--sun-size: expected degrees in [0, 30), found {}", o.sunSizeDeg));
    const CellMethod method = requireDirectMethod(o.method, "shadow");
    const LoadedDem dem = loadDemSource(o.dem, listener);
    const auto start = std::chrono::steady_clock::now();
    const MapRaster mask = shadowMask(dem.grid, radians(o.sunAzimuthDeg), radians(o.sunElevationDeg), method,
                                      radians(0.5 * o.sunSizeDeg), 16, o.threads);
    writeVertexRaster(o.output, dem, mask, RasterType::Float32, -9999.0);
    tellRasterSummary(listener, "shadow mask", o.output, mask, start);
}

void writeHorizonMap(const HorizonMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    const CellMethod method = requireDirectMethod(o.method, "horizon");
    const LoadedDem dem = loadDemSource(o.dem, listener);
    const auto start = std::chrono::steady_clock::now();
    const MapRaster horizon = horizonMap(dem.grid, radians(o.azimuthDeg), method, o.threads);
    writeVertexRaster(o.output, dem, horizon, RasterType::Float32, -9999.0);
    tellRasterSummary(listener, "horizon angles", o.output, horizon, start);
}

void writeViewshedMap(const ViewshedMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    if (!std::isfinite(o.observerHeightM) || !std::isfinite(o.targetHeightM) || !std::isfinite(o.curvatureCoeff))
        throw InputError("--observer-height, --target-height and --curvature-coeff must be finite numbers");
    ViewshedSettings s;
    s.method = requireDirectMethod(o.method, "viewshed");
    const LoadedDem dem = loadDemSource(o.dem, listener);
    double x = o.observerX, y = o.observerY;
    if (o.lonLat) lonLatToSource(dem.geo, o.observerX, o.observerY, x, y);
    sourceToLocal(dem, x, y, s.observerXM, s.observerYM);
    if (s.observerXM < 0.0 || s.observerYM < 0.0 || s.observerXM > dem.grid.extentXM() ||
        s.observerYM > dem.grid.extentYM())
        throw InputError(fmt::format("--observer: {}, {} lies outside the DEM (x {:.3f} .. {:.3f}, y {:.3f} .. {:.3f} "
                                     "in its CRS)",
                                     o.observerX, o.observerY, dem.geo.originX,
                                     dem.geo.originX + dem.grid.cellsX() * sourcePixelSizeX(dem.geo), dem.geo.originY,
                                     dem.geo.originY + dem.grid.cellsY() * sourcePixelSizeY(dem.geo)));
    s.observerHeightM = o.observerHeightM;
    s.targetHeightM = o.targetHeightM;
    s.curvatureCoeff = o.curvatureCoeff;
    s.threads = o.threads;
    const auto start = std::chrono::steady_clock::now();
    const MapRaster vis = viewshed(dem.grid, s);
    writeVertexRaster(o.output, dem, vis, RasterType::Byte, 255.0);
    tellRasterSummary(listener, "viewshed", o.output, vis, start);
}

}  // namespace terracast
