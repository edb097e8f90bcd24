#include "loaders/tiled_dem.h"

#include "loaders/dem_checks.h"
#include "loaders/summary_sidecar.h"
#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/ranks.h"

#include <fmt/format.h>
#include <gdal.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

namespace terracast {
namespace {

// Heights as the grid holds them under a vertical exaggeration `k` (a float product, as
// HeightGrid::scaleHeights makes it); throws InputError for a valid height the factor makes unusable.
void exaggerate(const std::string& path, float k, float* heightsM, const uint8_t* valid, size_t n) {
    for (size_t q = 0; q < n; ++q) {
        const float z = heightsM[q] * k;
        if ((valid == nullptr || valid[q] != 0) && !(std::abs(z) <= dem_checks::kMaxExaggeratedHeightM))
            throw InputError(fmt::format("{}: a vertical exaggeration of {} makes a height of {:.0f} m unusable "
                                         "(expected a factor that keeps heights below {:.0e} m)",
                                         path, k, std::abs(heightsM[q]), dem_checks::kMaxExaggeratedHeightM));
        heightsM[q] = z;
    }
}

// Window [i0, i0 + w) x [j0, j0 + h)'s heights under `t`.
void transform(const DemWindowReader& reader, const HeightTransform& t, int64_t i0, int64_t j0, int64_t w, int64_t h,
               float* heightsM) {
    const double cellSizeXM = reader.cellSizeXM(), cellSizeYM = reader.cellSizeYM();
    for (int64_t r = 0; r < h; ++r)
        for (int64_t c = 0; c < w; ++c) {
            float& z = heightsM[r * w + c];
            z = t.apply(z, i0 + c, j0 + r, cellSizeXM, cellSizeYM);
        }
}

// The summary from one pass over the raster, a band of rows at a time (about 16 MiB of heights and flags at
// most), of the heights under a vertical exaggeration `k`. With k other than 1 the summary must choose the
// storage the whole grid chooses after HeightGrid::scaleHeights: its int16 candidates are whole metres and the
// factor times the unscaled grid's scale (its code scale when it was stored in int16, else the source's unit).
// With the source in metres that is the factor either way; otherwise the unscaled grid's choice is made in the
// same pass, beside both candidates for the scaled one. Under a transform `t` as well, the summary is that of
// HeightGrid::transformed's copy, whose only int16 candidate is whole metres.
GridSummary streamSummary(const DemWindowReader& reader, const std::string& path, double k, const HeightTransform& t) {
    const int64_t width = reader.width(), height = reader.height();
    const double unit = reader.metresPerUnit();
    const auto kf = static_cast<float>(k);
    const double kd = double(kf);  // the factor scaleHeights multiplies its scale hint by
    GridSummaryBuilder scaledByUnit(width, height, !t.identity() ? 0.0 : k == 1.0 ? unit : kd * unit);
    std::optional<GridSummaryBuilder> unscaled, scaledByMetre;
    if (t.identity() && k != 1.0 && unit != 1.0) {
        unscaled.emplace(width, height, unit);
        scaledByMetre.emplace(width, height, kd);
    }
    const int64_t rowsPerBand = std::clamp<int64_t>((int64_t{16} << 20) / (5 * width), 1, kTileCells);
    std::vector<float> heights(static_cast<size_t>(rowsPerBand * width));
    std::vector<uint8_t> valid(heights.size());
    for (int64_t j0 = 0; j0 < height; j0 += rowsPerBand) {
        const int64_t rows = std::min(rowsPerBand, height - j0);
        const auto n = static_cast<size_t>(rows * width);
        reader.read(0, j0, width, rows, heights.data(), valid.data());
        try {
            if (unscaled) unscaled->addRows(j0, rows, heights.data(), valid.data());
            if (k != 1.0) exaggerate(path, kf, heights.data(), valid.data(), n);
            if (!t.identity()) transform(reader, t, 0, j0, width, rows, heights.data());
            scaledByUnit.addRows(j0, rows, heights.data(), valid.data());
            if (scaledByMetre) scaledByMetre->addRows(j0, rows, heights.data(), valid.data());
        } catch (const GridError& e) {
            throw InputError(path + ": " + e.what());
        }
    }
    if (!unscaled) return scaledByUnit.finish();
    const GridSummary before = unscaled->finish();
    const bool byMetre = before.storage == HeightStorage::Int16 && before.codeScale == 1.0;
    return byMetre ? scaledByMetre->finish() : scaledByUnit.finish();
}

}  // namespace

TiledDem::TiledDem(const std::string& path, size_t cacheBytes, const DemLoadOptions& options)
    : TiledDem(std::make_unique<DemWindowReader>(path, options), cacheBytes, options.exaggeration, options.tileStore) {}

TiledDem::TiledDem(std::unique_ptr<DemWindowReader> reader, size_t cacheBytes, double exaggeration, bool tileStore)
    : TiledDem(std::shared_ptr<const DemWindowReader>(std::move(reader)), cacheBytes, exaggeration, HeightTransform{}) {
    if (!tileStore) return;
    // The store holds what the reader returns, before any exaggeration: one store serves every factor.
    std::string why;
    const std::string path = TileStore::pathFor(reader_->path());
    store_ = TileStore::open(path, summaryKey(*reader_) + " tile store;", layout_,
                             reader_->wholeMetres() ? TileStore::Values::WholeMetres : TileStore::Values::FloatMetres,
                             why);
    if (!store_) storeOrigin_ = "none (" + why + ")";
    else storeOrigin_ = (store_->fresh() ? "made " : "found ") + path;
}

TiledDem::TiledDem(std::shared_ptr<const DemWindowReader> reader, size_t cacheBytes, double exaggeration,
                   const HeightTransform& transform)
    : reader_(std::move(reader)), exaggeration_(exaggeration), transform_(transform) {
    if (!(exaggeration > 0.0) || !std::isfinite(exaggeration))
        throw std::invalid_argument(fmt::format("vertical exaggeration must be positive and finite, got {}", exaggeration));
    const std::string& path = reader_->path();
    if (GDALGetCacheMax64() > kSourceBlockCacheBytes) GDALSetCacheMax64(kSourceBlockCacheBytes);
    const int64_t width = reader_->width(), height = reader_->height();
    layout_ = TileLayout{width, height};
    // The summary from the sidecar when it describes the DEM as it is now, else from one pass over the raster,
    // saved for the next open (under mpirun by the leader). Transformed heights belong to one job: no sidecar.
    const std::string sidecar = summarySidecarPath(path, exaggeration);
    const std::string key = keyFor(*reader_);
    openKey_ = key;
    if (!transform_.identity()) {
        summary_ = streamSummary(*reader_, path, exaggeration, transform_);
        summaryOrigin_ = "one pass over the raster, its heights transformed for this job (not saved)";
    } else if (auto stored = readSummarySidecar(sidecar, key, width, height)) {
        summary_ = std::move(*stored);
        summaryOrigin_ = "read from " + sidecar;
    } else {
        summary_ = streamSummary(*reader_, path, exaggeration, transform_);
        if (!ranks::leader()) {
            summaryOrigin_ = "one pass over the raster, saved by rank 0 to " + sidecar;
        } else if (keyFor(*reader_) != key) {
            // The files changed during the pass: what was read may be neither version.
            summaryOrigin_ = "one pass over the raster (not saved: the DEM changed while it was read)";
        } else {
            const DeferExitOnCancel finishWriting;  // loadDem exits at once on Ctrl-C; not halfway through this
            const std::string failed = writeSummarySidecar(sidecar, key, summary_);
            summaryOrigin_ = failed.empty() ? "one pass over the raster, saved to " + sidecar
                                            : "one pass over the raster (not saved: " + failed + ")";
        }
    }
    if (summary_.nodataVertices == width * height) throw InputError(path + ": every vertex is nodata");
    if (summary_.validCells == 0)
        throw InputError(fmt::format("{}: no cell has four valid corners ({} of {} vertices are nodata)", path,
                                     summary_.nodataVertices, width * height));
    cache_ = std::make_unique<TileCache<HeightTile>>(
        cacheBytes, [this](int64_t key) { return readTile(key); }, [](const HeightTile& t) { return t.bytes(); });
}

std::optional<CoarseHeights> TiledDem::keptCoarseHeights(int levels, int64_t width, int64_t height) const {
    if (!transform_.identity() || openKey_.empty() || keyFor(*reader_) != openKey_) return std::nullopt;
    return readCoarseSidecar(coarseSidecarPath(reader_->path(), exaggeration_, levels), openKey_, width, height);
}

void TiledDem::keepCoarseHeights(int levels, const CoarseHeights& heights) const {
    // Heights read from a DEM that changed since it was opened may be of neither version: not kept.
    if (!transform_.identity() || !ranks::leader() || openKey_.empty() || keyFor(*reader_) != openKey_) return;
    const DeferExitOnCancel finishWriting;
    // A cache: a folder that cannot be written to costs the next run one more read of every tile.
    (void)writeCoarseSidecar(coarseSidecarPath(reader_->path(), exaggeration_, levels), openKey_, heights);
}

std::string TiledDem::keyFor(const DemWindowReader& reader) const {
    std::string key = summaryKey(reader);
    if (!key.empty() && exaggeration_ != 1.0) key += fmt::format(" exaggeration {:.17g};", exaggeration_);
    return key;
}

std::shared_ptr<const TileSource> TiledDem::transformed(const HeightTransform& t, GridSummary& summary) const {
    if (!transform_.identity()) return nullptr;  // one transform at a time, as for whole grids' copies
    auto copy = std::make_shared<TiledDem>(reader_, cacheBudgetBytes(), exaggeration_, t);
    copy->copies_ = copies_;
    copy->store_ = store_;
    copy->storeOrigin_ = storeOrigin_;
    summary = copy->summary();
    std::lock_guard lock(copies_->mutex);
    std::erase_if(copies_->alive, [](const std::weak_ptr<const TiledDem>& c) { return c.expired(); });
    copies_->alive.push_back(copy);
    return copy;
}

namespace {

void add(TileCacheStats& sum, const TileCacheStats& s) {
    sum.hits += s.hits;
    sum.loads += s.loads;
    sum.evictions += s.evictions;
    sum.bytes += s.bytes;
    sum.peakBytes += s.peakBytes;  // an upper bound on the peak of the sum
    sum.tiles += s.tiles;
    sum.loadSeconds += s.loadSeconds;
    sum.waitSeconds += s.waitSeconds;
}

}  // namespace

TiledDem::~TiledDem() {
    if (!transform_.identity() && cache_) {
        std::lock_guard lock(copies_->mutex);
        TileCacheStats mine = cache_->stats();
        mine.bytes = 0;
        mine.tiles = 0;
        add(copies_->gone, mine);
    }
}

TileCacheStats TiledDem::cacheStats() const {
    TileCacheStats sum = cache_->stats();
    if (!transform_.identity()) return sum;
    std::lock_guard lock(copies_->mutex);
    add(sum, copies_->gone);
    for (const auto& weak : copies_->alive)
        if (const auto copy = weak.lock()) add(sum, copy->cache_->stats());
    return sum;
}

std::shared_ptr<const HeightTile> TiledDem::tile(int64_t ti, int64_t tj) const {
    return cache_->getRecent(layout_.key(ti, tj));
}

std::shared_ptr<const HeightTile> TiledDem::readTile(int64_t key) const {
    const int64_t ti = key % layout_.tilesX(), tj = key / layout_.tilesX();
    const int64_t x0 = layout_.firstVertexX(ti), y0 = layout_.firstVertexY(tj);
    const int64_t w = layout_.verticesX(ti), h = layout_.verticesY(tj);
    // This thread's buffers, kept from its last tile (a fresh pair each time costs page faults).
    thread_local std::vector<float> heights;
    thread_local std::vector<int16_t> metres;
    thread_local std::vector<uint8_t> valid;
    valid.resize(static_cast<size_t>(w * h));
    // The tile's heights as the reader returns them, from the store when it holds them (and into it when not).
    const auto readMetres = [&] {
        metres.resize(valid.size());
        if (store_ && store_->read(key, w, h, metres.data(), valid.data())) return;
        reader_->readWholeMetres(x0, y0, w, h, metres.data(), valid.data());
        if (store_) store_->write(key, w, h, metres.data(), valid.data());
    };
    try {
        // 16-bit heights in metres for a grid of one metre per code go straight to codes; the rest as floats.
        if (exaggeration_ == 1.0 && transform_.identity() && reader_->wholeMetres() &&
            HeightTile::takesWholeMetres(summary_)) {
            readMetres();
            return std::make_shared<const HeightTile>(summary_, x0, y0, w, h, metres.data(), valid.data());
        }
        heights.resize(valid.size());
        if (store_ && store_->values() == TileStore::Values::WholeMetres) {
            // Whole metres as floats: what read() gives for such a band.
            readMetres();
            for (size_t k = 0; k < heights.size(); ++k) heights[k] = float(metres[k]);
        } else if (!(store_ && store_->read(key, w, h, heights.data(), valid.data()))) {
            reader_->read(x0, y0, w, h, heights.data(), valid.data());
            if (store_) store_->write(key, w, h, heights.data(), valid.data());
        }
        if (exaggeration_ != 1.0) exaggerate(reader_->path(), float(exaggeration_), heights.data(), valid.data(), valid.size());
        if (!transform_.identity()) transform(*reader_, transform_, x0, y0, w, h, heights.data());
        return std::make_shared<const HeightTile>(summary_, x0, y0, w, h, heights.data(), valid.data());
    } catch (const GridError& e) {
        throw InputError(reader_->path() + ": changed while open (" + e.what() + ")");
    }
}

LoadedDem openTiledDem(const std::string& path, size_t cacheBytes, const DemLoadOptions& options) {
    return openTiledDem(std::make_unique<DemWindowReader>(path, options), cacheBytes, options.exaggeration,
                        options.tileStore);
}

LoadedDem openTiledDem(std::unique_ptr<DemWindowReader> opened, size_t cacheBytes, double exaggeration, bool tileStore) {
    const std::string path = opened->path();
    auto tiles = std::make_shared<const TiledDem>(std::move(opened), cacheBytes, exaggeration, tileStore);
    const DemWindowReader& reader = tiles->reader();
    LoadedDem dem;
    dem.path = path;
    dem.driver = reader.driver();
    dem.sourceWidth = reader.width();
    dem.sourceHeight = reader.height();
    dem.geo = reader.geo();
    dem.warnings = reader.warnings();
    try {
        dem.grid = HeightGrid(tiles->summary(), reader.cellSizeXM(), reader.cellSizeYM(), tiles);
    } catch (const GridError& e) {
        throw InputError(path + ": " + e.what());
    }
    return dem;
}

}  // namespace terracast
