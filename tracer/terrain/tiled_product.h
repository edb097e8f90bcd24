#pragma once
// A per-vertex map product computed and written an output tile at a time on the DEM's own grid
// (docs/architecture.md, "Tiled outputs"), shared by the map commands of map_pipeline.cpp.

#include "loaders/raster_writer.h"
#include "loaders/dem_loader.h"
#include "tracer/core/listener.h"
#include "tracer/terrain/maps.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace terracast {

// What a product's GeoTIFF says about itself besides its values.
struct RasterLabels {
    std::vector<std::string> bands;    // one description per band
    std::vector<std::string> units;    // one unit per band, or one for all
    std::vector<std::pair<std::string, std::string>> metadata;
};

// A per-vertex product to write: its sample type, nodata value, labels, and how a window of it is computed
// (`progress` hears the window's share done and its rays so far).
struct VertexProduct {
    int bands = 1;
    RasterType type = RasterType::Float32;
    double noData = -9999.0;
    RasterLabels labels;
    std::function<MapRaster(const VertexWindow&, const MapProgress&)> compute;
    // The last band is an alpha band (0 over holes) rather than a nodata value: Byte RGBA pictures.
    bool lastBandIsAlpha = false;
};

// What writing a product counted: vertices with a value and rays in the tiles computed by this run, and the
// output's tiles, of which `resumed` were kept from an interrupted run.
struct ProductCount {
    int64_t valid = 0;
    int64_t rays = 0;
    int64_t outputTiles = 0;
    int64_t resumed = 0;
    int64_t width = 0, height = 0;
    int bands = 1;
    std::string tiles;  // the DEM's tile traffic (tileTraffic) in this process, for a DEM held as tiles
    double tilesSeconds = 0.0;  // computing the output tiles and writing each as it is finished
    double cogSeconds = 0.0;    // making the COG from them (0 on a rank that does not write it)
};

// The wall-clock seconds of one map product's run: from the start of the command's work to the DEM and its grid
// held (`load`), then to the product planned (`setup`: for a viewshed its curved copy and sight bounds); the
// output tiles' and the COG's seconds come from the ProductCount.
struct MapPhaseClock {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), loaded = start, planned = start;
    void demLoaded() { loaded = std::chrono::steady_clock::now(); }
    void productPlanned() { planned = std::chrono::steady_clock::now(); }
};

// The line `--verbose` adds to a map product's summary: each phase's seconds and the total.
std::string mapPhasesLine(const MapPhaseClock& clock, const ProductCount& count);

// Writes a per-vertex product on the DEM's own grid as a COG, computed and written an output tile at a time:
// NaN becomes `noData`; with `resume` the tiles an interrupted run of the same job finished are kept. The next
// tile is computed while the last one is written. In a launch of several ranks every rank computes the tiles it
// draws from a shared count, and the leader makes the COG, compressing its blocks on `threads` (0: every core).
ProductCount writeVertexProduct(const std::string& path, bool resume, const LoadedDem& dem, VertexProduct product,
                                int threads, const RunListener& listener);

// A per-vertex product computed whole into memory, holding the samples its GeoTIFF holds: `out` has room for
// width x height x bands samples of product.type (uint8_t or float), rows north first, bands interleaved by
// vertex; Byte samples as rasterByte stores them with NaN as product.noData, Float32 samples with NaN kept where
// the file holds product.noData. Computed a band of rows at a time; `progress` hears the share done and the rays
// so far, and cancellation (tracer/core/cancel.h) is honoured between bands. Returns the rays traced.
int64_t computeVertexProduct(const HeightGrid& grid, const VertexProduct& product, void* out,
                             const MapProgress& progress = {});

// The memory guard for a per-vertex product of `bands` bands written as `type`, with `more` bytes besides
// (a curved grid, a second raster); `what` names the job in the refusal.
void checkRasterJob(const LoadedDem& dem, double maxMemoryBytes, int bands, RasterType type, double more,
                    const std::string& what);

// The line that ends a raster command: what was written, its size, seconds, rays and peak memory.
void tellRasterSummary(const RunListener& listener, const std::string& what, const std::string& path,
                       const ProductCount& c, int64_t rays, const std::string& rayKind,
                       std::chrono::steady_clock::time_point start);

}  // namespace terracast
