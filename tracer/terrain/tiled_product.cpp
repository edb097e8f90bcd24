#include "tracer/terrain/tiled_product.h"

#include "tracer/core/cancel.h"
#include "tracer/core/ranks.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "tracer/terrain/dem_pipeline.h"
#include "tracer/terrain/memory_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <future>
#include <optional>

namespace terracast {

namespace {

// The DEM as a resumed job must find it again: its path, file size and time, and the grid made of it.
std::string demIdentity(const LoadedDem& dem) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(dem.path, ec);
    const auto time = std::filesystem::last_write_time(dem.path, ec);
    return fmt::format("{} {} bytes, modified {}; grid {} x {}, cells {:.17g} x {:.17g} m", dem.path,
                       ec ? 0 : size, ec ? 0 : int64_t(time.time_since_epoch().count()), dem.grid.width(),
                       dem.grid.height(), dem.grid.cellSizeXM(), dem.grid.cellSizeYM());
}

}  // namespace

int64_t computeVertexProduct(const HeightGrid& grid, const VertexProduct& product, void* out,
                             const MapProgress& progress) {
    const int64_t width = grid.width(), height = grid.height();
    const size_t rowValues = size_t(width) * size_t(product.bands);
    // Bands of rows of about 2^20 values: enough work for every thread, little memory beside the output.
    const int64_t rowsPerBand =
        std::clamp<int64_t>((int64_t(1) << 20) / std::max<int64_t>(width * product.bands, 1), 1, height);
    int64_t rays = 0;
    for (int64_t j0 = 0; j0 < height; j0 += rowsPerBand) {
        throwIfCancelled();
        const int64_t j1 = std::min(height, j0 + rowsPerBand);
        int64_t bandRays = 0;
        const MapProgress inBand = [&](double f, int64_t r) {
            bandRays = r;
            if (progress) progress((double(j0) + f * double(j1 - j0)) / double(height), rays + r);
        };
        const MapRaster r = product.compute(VertexWindow{0, j0, width, j1}, inBand);
        rays += bandRays;
        for (int64_t j = j0; j < j1; ++j) {
            const float* source = r.values.data() + size_t(j - j0) * rowValues;
            const size_t row = size_t(height - 1 - j);  // north first
            if (product.type == RasterType::Byte) {
                uint8_t* target = static_cast<uint8_t*>(out) + row * rowValues;
                for (size_t k = 0; k < rowValues; ++k)
                    target[k] = rasterByte(std::isnan(source[k]) ? float(product.noData) : source[k]);
            } else {
                std::copy(source, source + rowValues, static_cast<float*>(out) + row * rowValues);
            }
        }
    }
    throwIfCancelled();
    if (progress) progress(1.0, rays);
    return rays;
}

// Writes a per-vertex product on the DEM's own grid as a COG, computed and written an output tile at a time
// (docs/architecture.md, "Tiled outputs"): NaN becomes `noData`; with `resume` the tiles an interrupted run of
// the same job finished are kept. The next tile is computed while the last one is written.
ProductCount writeVertexProduct(const std::string& path, bool resume, const LoadedDem& dem, VertexProduct product,
                                int threads, const RunListener& listener) {
    RasterLayout layout;
    layout.width = dem.grid.width();
    layout.height = dem.grid.height();
    layout.bands = product.bands;
    layout.hasNoData = !product.lastBandIsAlpha;
    layout.noDataValue = product.noData;
    layout.lastBandIsAlpha = product.lastBandIsAlpha;
    layout.bandDescriptions = std::move(product.labels.bands);
    layout.bandUnits = std::move(product.labels.units);
    layout.metadata = std::move(product.labels.metadata);
    layout.metadata.emplace_back("TERRACAST_SOURCE", dem.path);
    layout.pixelIsPoint = dem.geo.pixelIsPoint;
    const RasterPlacement placement{dem.geo, dem.geo.originX, dem.geo.originY, sourcePixelSizeX(dem.geo),
                                    sourcePixelSizeY(dem.geo)};
    // In a launch of several ranks (tracer/core/ranks.h) the leader prepares the partial folder and makes the COG;
    // every rank writes the tiles it draws from the shared count into that folder.
    using Role = TiledGeoTiffWriter::Role;
    const Role role = ranks::size() == 1 ? Role::Sole : ranks::leader() ? Role::Leader : Role::Follower;
    std::optional<TiledGeoTiffWriter> made;
    if (role != Role::Follower) made.emplace(path, layout, product.type, placement, demIdentity(dem), resume, role);
    ranks::barrier();
    if (role == Role::Follower) made.emplace(path, layout, product.type, placement, demIdentity(dem), resume, role);
    TiledGeoTiffWriter& writer = *made;
    if (role != Role::Sole) {
        std::vector<uint8_t> mask = writer.finishedMask();
        ranks::broadcast(mask.data(), mask.size());
        writer.setFinished(mask);
    }
    ProductCount count;
    count.width = layout.width;
    count.height = layout.height;
    count.bands = layout.bands;
    count.outputTiles = writer.tilesX() * writer.tilesY();
    count.resumed = writer.resumedTiles();
    if (resume)
        listener.tell(fmt::format("--resume: {} of {} output tiles kept from '{}'{}", count.resumed, count.outputTiles,
                                  writer.partialFolder(),
                                  writer.discardedTiles() > 0 ? fmt::format(" ({} unreadable ones computed again)",
                                                                            writer.discardedTiles())
                                                              : ""));
    else if (writer.discardedTiles() > 0)
        listener.tell(fmt::format("removed {} output tiles an unfinished run left in '{}' (--resume continues such a "
                                  "run)", writer.discardedTiles(), writer.partialFolder()));
    if (ranks::size() > 1)
        listener.tell(fmt::format("{} ranks share {} output tiles", ranks::size(), count.outputTiles - count.resumed));
    // The tiles left to compute, in file order, handed out one at a time over the ranks; progress counts their
    // vertices.
    std::vector<std::pair<int64_t, int64_t>> todo;
    std::vector<double> before{0.0};
    for (int64_t ty = 0; ty < writer.tilesY(); ++ty)
        for (int64_t tx = 0; tx < writer.tilesX(); ++tx)
            if (!writer.finished(tx, ty)) {
                todo.emplace_back(tx, ty);
                const TiledGeoTiffWriter::Window w = writer.window(tx, ty);
                before.push_back(before.back() + double(w.width() * w.height()));
            }
    const double total = before.back();
    const auto showProgress = progressWithTiles(listener, dem.grid);
    // The tiles left, dealt over the ranks from one shared count (collective: every rank makes it here).
    ranks::SpanTasks tasks({int64_t(todo.size())});
    // An interruption or a failure keeps the finished tiles: say where, for --resume.
    struct KeptTiles {
        const TiledGeoTiffWriter& writer;
        const RunListener& listener;
        ~KeptTiles() {
            if (!std::uncaught_exceptions() || writer.partialFolder().empty()) return;
            const std::vector<uint8_t> done = writer.finishedMask();
            const auto kept = std::count(done.begin(), done.end(), uint8_t(1));
            if (kept > 0)
                listener.tell(fmt::format("kept {} of {} finished output tiles in '{}' (--resume continues from them)",
                                          kept, done.size(), writer.partialFolder()));
        }
    } keptTiles{writer, listener};
    std::future<void> pending;
    const auto tilesStart = std::chrono::steady_clock::now();
    for (int64_t k = tasks.next(); k < int64_t(todo.size()); k = tasks.next()) {
        const auto [tx, ty] = todo[size_t(k)];
        const TiledGeoTiffWriter::Window w = writer.window(tx, ty);
        const double vertices = double(w.width() * w.height());
        int64_t tileRays = 0;
        MapProgress progress = [&](double f, int64_t rays) {
            tileRays = rays;
            if (showProgress)
                showProgress(total > 0.0 ? (before[size_t(k)] + f * vertices) / total : 1.0, count.rays + rays);
        };
        MapRaster r = product.compute(VertexWindow{w.i0, w.j0, w.i1, w.j1}, progress);
        count.valid += int64_t(std::count_if(r.values.begin(), r.values.end(), [](float v) { return !std::isnan(v); }));
        count.rays += tileRays;
        if (pending.valid()) pending.get();
        throwIfCancelled();
        pending = std::async(std::launch::async, [&writer, tx = tx, ty = ty, values = std::move(r.values)] {
            writer.write(tx, ty, values.data());
        });
    }
    if (pending.valid()) pending.get();
    count.tilesSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tilesStart).count();
    int64_t sums[2] = {count.valid, count.rays};
    ranks::sum(sums, 2);
    count.valid = sums[0];
    count.rays = sums[1];
    ranks::barrier();  // every rank's tiles are in the folder
    count.tiles = tileTraffic(dem.grid);
    if (role == Role::Follower) return count;
    listener.at("writing");
    const auto cogStart = std::chrono::steady_clock::now();
    writer.commit([&](double f) {
        if (listener.progress) listener.progress(f, count.rays);
        return true;
    }, threads);
    count.cogSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - cogStart).count();
    return count;
}

std::string mapPhasesLine(const MapPhaseClock& clock, const ProductCount& count) {
    const auto seconds = [](std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
        return std::chrono::duration<double>(b - a).count();
    };
    return fmt::format("phases: reading the DEM and making the grid {:.4f} s, set-up {:.4f} s, output tiles (computed, "
                       "each written as it is finished) {:.4f} s, COG {:.4f} s; total {:.4f} s",
                       seconds(clock.start, clock.loaded), seconds(clock.loaded, clock.planned), count.tilesSeconds,
                       count.cogSeconds, seconds(clock.start, std::chrono::steady_clock::now()));
}

// The memory guard for a per-vertex product of `bands` bands written as `type`, tile by tile: two tiles in
// float (one computed while the last is written) with the written one's samples and its compression, then
// the making of the COG: GDAL's bounded block cache, and buffers of the copy and the overviews (measured on
// 1025^2 and 4100^2 outputs of 1 to 16 bands: under 32 MiB and 10 MiB per band more); and `more` (a curved
// grid, a second raster). What the process holds already (the grid, libraries) is measured by checkMemory.
void checkRasterJob(const LoadedDem& dem, double maxMemoryBytes, int bands, RasterType type, double more,
                    const std::string& what) {
    const double tile = double(TiledGeoTiffWriter::kTile) * double(TiledGeoTiffWriter::kTile);
    const double stored = type == RasterType::Byte ? 1.0 : 4.0;
    const double tiles = 2.0 * tile * double(bands) * (4.0 + stored) + 16.0 * 1048576.0;
    const double copy = double(TiledGeoTiffWriter::kCopyCacheBytes) + (32.0 + 10.0 * double(bands)) * 1048576.0;
    checkMemory(dem.path, maxMemoryBytes, dem.grid, std::max(tiles, copy) + more, what);
}

// The line that ends a raster command: what was written, its size, seconds, rays and peak memory.
void tellRasterSummary(const RunListener& listener, const std::string& what, const std::string& path,
                       const ProductCount& c, int64_t rays, const std::string& rayKind,
                       std::chrono::steady_clock::time_point start) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    listener.tell(fmt::format("{} {} ({} x {} vertices{}, {} output tile{}{}) in {:.2f} s, {} {} ({:.2f} M/s), peak "
                              "memory {}{}",
                              what, path, c.width, c.height, c.bands > 1 ? fmt::format(", {} bands", c.bands) : "",
                              c.outputTiles, c.outputTiles == 1 ? "" : "s",
                              c.resumed > 0 ? fmt::format(" of which {} resumed", c.resumed) : "",
                              seconds, rays, rayKind, seconds > 0.0 ? double(rays) / seconds * 1e-6 : 0.0,
                              humanBytes(peakResidentBytes()), c.tiles.empty() ? "" : "; DEM " + c.tiles));
}

}  // namespace terracast
