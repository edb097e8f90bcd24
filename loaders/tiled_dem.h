// A DEM held as tiles read on demand (docs/architecture.md, "Tiled grids"): opening streams the raster once, a
// band of rows at a time, for the grid's summary (or reads it from the sidecar an earlier open saved); each tile is then one windowed read through GDAL, kept in a
// least-recently-used cache bounded in bytes. Nothing in proportion to the raster is ever held.
#pragma once

#include "heightfield/grid_summary.h"
#include "heightfield/height_tile.h"
#include "heightfield/tile_cache.h"
#include "loaders/dem_loader.h"
#include "loaders/tile_store.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace terracast {

class TiledDem : public TileSource {
public:
    // GDAL keeps the source blocks it decodes in a cache of its own, by default 5 % of the machine's memory:
    // enough to hold a DEM read once through it, whatever the tile cache's bound. Opening a DEM as tiles lowers
    // that cache (for the whole process) to this.
    static constexpr int64_t kSourceBlockCacheBytes = int64_t{16} << 20;

    // Opens `path` and streams it once; throws InputError as loadDem does (but never for the raster's size).
    // Heights are those under options.exaggeration, in the summary and in every tile.
    TiledDem(const std::string& path, size_t cacheBytes, const DemLoadOptions& options = {});
    // The same over a raster already open; with `tileStore`, tiles are kept decoded in a store beside the DEM
    // (TileStore) and read from there when it holds them.
    TiledDem(std::unique_ptr<DemWindowReader> reader, size_t cacheBytes, double exaggeration = 1.0,
             bool tileStore = false);
    // Over a raster another TiledDem reads too, its heights under `transform` after the exaggeration (the
    // summary streamed for them, never kept in a sidecar).
    TiledDem(std::shared_ptr<const DemWindowReader> reader, size_t cacheBytes, double exaggeration,
             const HeightTransform& transform);
    ~TiledDem() override;

    const DemWindowReader& reader() const { return *reader_; }
    const GridSummary& summary() const { return summary_; }
    // Where the summary came from: "read from SIDECAR", or "one pass over the raster, saved to SIDECAR" (or why
    // it was not saved).
    const std::string& summaryOrigin() const { return summaryOrigin_; }
    const TileLayout& layout() const { return layout_; }
    // The store of decoded tiles in use (nullptr without one), and what became of it: "" when none was asked
    // for, else its path and whether it was found or made, or why there is none.
    const TileStore* store() const { return store_.get(); }
    const std::string& storeOrigin() const { return storeOrigin_; }

    // Tile (ti, tj), from the cache or read now.
    std::shared_ptr<const HeightTile> tile(int64_t ti, int64_t tj) const override;

    // Single values through the cache (each call may read a tile): for checks and slow paths, not for rays.
    float at(int64_t i, int64_t j) const { return vertexTile(i, j)->at(i, j); }
    bool vertexValid(int64_t i, int64_t j) const { return vertexTile(i, j)->vertexValid(i, j); }
    bool cellValid(int64_t i, int64_t j) const {
        return tile(layout_.tileOfCellX(i), layout_.tileOfCellY(j))->cellValid(i, j);
    }

    // This DEM's cache and those of the transformed copies made from it (alive or gone), summed: a job's tile
    // traffic.
    TileCacheStats cacheStats() const override;
    size_t cacheBudgetBytes() const override { return cache_->budgetBytes(); }
    // A TiledDem over the same raster under `t` (nullptr for one already transformed).
    std::shared_ptr<const TileSource> transformed(const HeightTransform& t, GridSummary& summary) const override;
    // A level of detail's coarser grids, kept in a sidecar beside the DEM (summary_sidecar.h) under the summary's
    // key as it was when the DEM was opened (one made from a DEM that changed since is not kept); none for
    // transformed heights. Only the leader of an MPI launch writes one.
    std::optional<CoarseHeights> keptCoarseHeights(int levels, int64_t width, int64_t height) const override;
    void keepCoarseHeights(int levels, const CoarseHeights& heights) const override;

private:
    std::shared_ptr<const HeightTile> vertexTile(int64_t i, int64_t j) const {
        return tile(layout_.tileOfCellX(std::min(i, layout_.width - 2)), layout_.tileOfCellY(std::min(j, layout_.height - 2)));
    }
    std::shared_ptr<const HeightTile> readTile(int64_t key) const;
    // The sidecar key: the raster's, and the exaggeration's.
    std::string keyFor(const DemWindowReader& reader) const;

    // The copies made by transformed(), for cacheStats: those alive, and what the gone ones did.
    struct Copies {
        std::mutex mutex;
        std::vector<std::weak_ptr<const TiledDem>> alive;
        TileCacheStats gone;
    };

    std::shared_ptr<const DemWindowReader> reader_;
    double exaggeration_ = 1.0;
    HeightTransform transform_;
    std::shared_ptr<Copies> copies_ = std::make_shared<Copies>();  // shared by a DEM and its copies
    GridSummary summary_;
    std::string summaryOrigin_;
    std::string openKey_;  // the sidecars' key when the DEM was opened (keyFor)
    TileLayout layout_;
    std::unique_ptr<TileCache<HeightTile>> cache_;
    std::shared_ptr<const TileStore> store_;  // shared with the transformed copies
    std::string storeOrigin_;
};

// Opens a DEM as a tiled grid (HeightGrid::tiled) over a TiledDem whose cache holds at most `cacheBytes` of
// tiles: everything loadDem returns, with the heights left in the file. Throws InputError as loadDem does.
LoadedDem openTiledDem(const std::string& path, size_t cacheBytes, const DemLoadOptions& options = {});
// The same over a raster already open, its heights under a vertical exaggeration.
LoadedDem openTiledDem(std::unique_ptr<DemWindowReader> reader, size_t cacheBytes, double exaggeration = 1.0,
                       bool tileStore = false);

}  // namespace terracast
