// Loading elevation rasters. GDAL reads georeferenced rasters (GeoTIFF, SRTM .hgt, ...) here, whole or as
// tiles (tiled_dem.cpp), placed on the metric lattice by georeference.cpp; PNG height maps are read by
// png_height_map.cpp; both end in the same HeightGrid with rows flipped so that y points north, checked by
// dem_checks.cpp.
#include "loaders/loader_support.h"
#include "heightfield/large_buffer.h"

#include "tracer/core/angles.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "loaders/dem_loader.h"
#include "loaders/block_edges.h"
#include "loaders/dem_checks.h"
#include "loaders/georeference.h"
#include "loaders/png_height_map.h"
#include "loaders/tiled_dem.h"
#include "loaders/input_files.h"

#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/ranks.h"

#include <cpl_error.h>
#include <cpl_vsi.h>
#include <fmt/format.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <memory>
#include <thread>
#include <unistd.h>
#include <utility>

namespace terracast {
namespace {

using namespace loader_support;
using namespace dem_checks;

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
// The largest window (in samples) whose read buffer a thread keeps for the next read: a tile and its edges.
constexpr size_t kReusedSamples = size_t{1} << 17;

// The smallest tile cache a tiled grid is opened with when it is chosen for its size: 64 tiles of 257 x 257
// int16 vertices with their pyramids, enough for the rays of a few threads crossing tile corners.
constexpr double kMinTileCacheBytes = 16.0 * 1024 * 1024;

// ---- GDAL ----

// GDAL's last error on this thread as " (message)", or "" when it gave none.
std::string gdalReason() {
    const std::string line = firstLine(CPLGetLastErrorMsg());
    return line.empty() ? std::string() : " (" + line + ")";
}

// GDAL's own threads (a GeoTIFF's blocks decoded in parallel under GDAL_NUM_THREADS) report through the process's
// error handler rather than the reading thread's (QuietGdalErrors): quiet while one of these lives. A read that
// fails is then read again on one thread, whose reason is the first failing block's, as without the threads
// (loadWithGdal). Only while no other thread reads through GDAL.
class QuietGdalThreads {
public:
    QuietGdalThreads() : saved_(CPLSetErrorHandler(CPLQuietErrorHandler)) {}
    ~QuietGdalThreads() { CPLSetErrorHandler(saved_); }
    QuietGdalThreads(const QuietGdalThreads&) = delete;
    QuietGdalThreads& operator=(const QuietGdalThreads&) = delete;

private:
    CPLErrorHandler saved_;
};

// Refuses a band whose storage blocks are absurd for its raster. GDAL allocates one whole block (all bands of it
// when they are pixel-interleaved) before decoding it, so a damaged header declaring, say, 32768 x 32768 tiles on
// a 20 x 20 raster would otherwise cost gigabytes before any read fails. Real files use strips no larger than the
// raster and tiles of at most a few thousand samples a side.
void checkBlockSize(const std::string& path, GDALDataset& dataset, GDALRasterBand& band, double maxBytes) {
    constexpr double kAlwaysAllowedBytes = 64.0 * 1024 * 1024;
    int blockX = 0;
    int blockY = 0;
    band.GetBlockSize(&blockX, &blockY);
    const char* interleave = dataset.GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
    const bool pixelInterleaved = interleave != nullptr && std::string_view(interleave) == "PIXEL";
    const double sampleBytes = std::max(1, GDALGetDataTypeSizeBytes(band.GetRasterDataType())) *
                               (pixelInterleaved ? std::max(1, dataset.GetRasterCount()) : 1.0);
    const double blockBytes = static_cast<double>(std::max(blockX, 1)) * std::max(blockY, 1) * sampleBytes;
    const double rasterBytes =
        static_cast<double>(dataset.GetRasterXSize()) * static_cast<double>(dataset.GetRasterYSize()) * sampleBytes;
    // A block is held against the room the limit leaves beside what the process holds already.
    const double limit = memoryLimitBytes(maxBytes) - currentResidentBytes();
    const double plausibleBytes = std::max(kAlwaysAllowedBytes, rasterBytes);
    const double allowedBytes = std::min(limit, plausibleBytes);
    if (blockBytes <= allowedBytes) return;
    auto size = [](double bytes) {
        return bytes >= kGiB ? fmt::format("{:.2f} GiB", bytes / kGiB) : fmt::format("{:.1f} MiB", bytes / (kGiB / 1024));
    };
    throw InputError(fmt::format("{}: band {} of the {} x {} raster is stored in blocks of {} x {} samples ({} each), "
                                 "expected blocks of at most {} {}",
                                 path, band.GetBand(), dataset.GetRasterXSize(), dataset.GetRasterYSize(), blockX, blockY,
                                 size(blockBytes), size(allowedBytes),
                                 limit < plausibleBytes ? "(the memory limit, --max-memory)" : "(damaged header?)"));
}

}  // namespace

// An open GDAL raster whose band 1 is decoded into heights as loadDem decodes it. A GDAL dataset takes one
// reader at a time, so threads that read at once each get their own opening of the raster (at most one per
// hardware thread), and a thread keeps to the one it used last, whose decoded blocks GDAL still caches.
struct DemWindowReader::Impl {
    // One opening of the raster, read by one thread at a time.
    struct Handle {
        GDALDatasetUniquePtr dataset;
        GDALRasterBand* band = nullptr;
        std::mutex mutex;
    };

    std::string path;
    std::string source;  // what GDAL opened: `path`, or the file standing for it
    std::string driver;
    int64_t width = 0;
    int64_t height = 0;
    Lattice lattice;
    GeoReference geo;
    std::vector<std::string> warnings;
    GDALDatasetUniquePtr dataset;
    GDALRasterBand* band = nullptr;
    double metresPerRaw = 1.0;
    double metresOffset = 0.0;
    bool hasNodata = false;
    double nodata = 0.0;
    bool float32 = false;
    bool storedInBlocks = false;  // blocks narrower than the rows, or a VRT
    int64_t blockRows = 1;        // rows of band 1's storage blocks
    // The first row and column of band 1's blocks, kept as they are read (block_edges.h); none for a band
    // stored in whole rows.
    std::unique_ptr<BlockEdges> blockEdges;
    bool wholeMetres = false;  // Int16 band in metres, without scale or offset
    bool nodataInt16 = false;  // the nodata value is one an Int16 sample can hold
    mutable std::mutex readMutex;  // for `dataset` and `band`
    mutable std::mutex handlesMutex;  // for `handles`
    mutable std::vector<std::unique_ptr<Handle>> handles;  // more openings, made as threads read at once
    mutable std::atomic<bool> noMoreHandles{false};

    // Opens `openPath` (or `path`) and checks everything but the heights, in the order loadDem reports them.
    // With `wholeRaster` the raster must also fit the memory limit.
    Impl(const std::string& path_, const DemLoadOptions& options, bool wholeRaster, const std::string& openPath) : path(path_) {
        registerGdalDrivers();
        QuietGdalErrors quiet;
        source = openPath.empty() ? path : openPath;
        {
            // A raster read whole decodes the blocks of each band of rows on the array-pass threads (the command's
            // --threads): GDAL's GeoTIFF driver decodes the blocks one request spans in parallel when told so at
            // its opening (GDAL_NUM_THREADS; other drivers ignore it). The 8193^2 DEFLATE GeoTIFF's load: 0.46 to
            // 0.63 s on one thread, 0.38 to 0.47 s on two (docs/bench.md).
            const std::string threads = std::to_string(wholeRaster ? arrayPassThreads() : 1);
            CPLConfigOptionSetter decodeThreads("GDAL_NUM_THREADS", threads.c_str(), false);
            dataset.reset(GDALDataset::Open(source.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        }
        if (!dataset) {
            const std::string reason = gdalReason();
            const bool unrecognised = reason.find("not recognized as") != std::string::npos;
            throw InputError(path + ": not a raster GDAL can read" + (unrecognised ? "" : reason));
        }
        driver = dataset->GetDriver() ? dataset->GetDriver()->GetDescription() : "";
        width = dataset->GetRasterXSize();
        height = dataset->GetRasterYSize();
        checkRasterSize(path, width, height, wholeRaster ? options.maxBytes : -1.0);
        const int bands = dataset->GetRasterCount();
        if (bands < 1) throw InputError(path + ": raster has no band");
        if (bands > 1) warnings.push_back(fmt::format("{}: {} bands, using band 1 as elevation", path, bands));

        lattice = georeference(path, *dataset, options, geo, warnings);

        band = dataset->GetRasterBand(1);
        if (GDALDataTypeIsComplex(band->GetRasterDataType()))
            throw InputError(fmt::format("{}: band 1 holds complex numbers ({}), expected real heights", path,
                                         GDALGetDataTypeName(band->GetRasterDataType())));
        checkBlockSize(path, *dataset, *band, options.maxBytes);
        const VerticalUnit unit = verticalUnit(path, band->GetUnitType() ? band->GetUnitType() : "");
        if (!unit.warning.empty()) warnings.push_back(unit.warning);
        int hasScale = 0;
        int hasOffset = 0;
        const double scale = band->GetScale(&hasScale);
        const double offset = band->GetOffset(&hasOffset);
        metresPerRaw = (hasScale ? scale : 1.0) * unit.metresPerUnit;
        metresOffset = (hasOffset ? offset : 0.0) * unit.metresPerUnit;
        int declared = 0;
        nodata = band->GetNoDataValue(&declared);
        hasNodata = declared != 0;
        float32 = band->GetRasterDataType() == GDT_Float32;
        wholeMetres = band->GetRasterDataType() == GDT_Int16 && metresPerRaw == 1.0 && metresOffset == 0.0;
        int blockX = 0, blockY = 0;
        band->GetBlockSize(&blockX, &blockY);
        storedInBlocks = driver == "VRT" || blockX < width;
        blockRows = std::max(1, blockY);
        if (blockX > 1 && blockY > 1) blockEdges = std::make_unique<BlockEdges>(width, height, blockX, blockY);
        nodataInt16 = hasNodata && nodata == std::trunc(nodata) && nodata >= -32768.0 && nodata <= 32767.0;
    }

    // Nodata is compared on stored values; float32 bands often declare it at double precision.
    bool isNodata(double raw) const {
        if (!hasNodata) return false;
        if (std::isnan(nodata)) return std::isnan(raw);
        return raw == nodata || (float32 && static_cast<float>(raw) == static_cast<float>(nodata));
    }

    // A buffer of `samples` values for one window: this thread's own for tile-sized windows (tiled grids read
    // thousands of them, and a fresh buffer each time costs page faults), else `own`.
    template <class T>
    static std::vector<T>& windowBuffer(size_t samples, std::vector<T>& own) {
        thread_local std::vector<T> reused;
        std::vector<T>& raw = samples <= kReusedSamples ? reused : own;
        if (raw.size() < samples) raw.resize(samples);
        return raw;
    }

    void checkWindow(int64_t i0, int64_t j0, int64_t w, int64_t h) const {
        if (i0 < 0 || j0 < 0 || w < 1 || h < 1 || i0 + w > width || j0 + h > height)
            throw std::invalid_argument(fmt::format("{}: window {}+{} x {}+{} outside the {} x {} raster", path, i0, w,
                                                    j0, h, width, height));
    }

    // Reads grid window i0, j0, w x h (checked) as `type` into `raw`, row-major from the raster's first row of
    // the window; returns that window's first column and row in the raster.
    std::pair<int64_t, int64_t> readRaw(int64_t i0, int64_t j0, int64_t w, int64_t h, GDALDataType type,
                                        void* raw) const {
        // The raster window holding the grid's: rows (and columns) are mirrored when the raster runs north to
        // south (or east to west).
        const int64_t column0 = lattice.flipColumns ? width - i0 - w : i0;
        const int64_t row0 = lattice.flipRows ? height - j0 - h : j0;
        std::unique_lock<std::mutex> lock;
        GDALRasterBand* reading = lockBand(lock);
        QuietGdalErrors quiet;
        // A tile's window: a block and the first row and column of the blocks beyond (block_edges.h).
        if (blockEdges && blockEdges->serves(column0, row0, w, h)) {
            blockEdges->read(int(type), GDALGetDataTypeSizeBytes(type), column0, row0, w, h,
                             static_cast<unsigned char*>(raw),
                             [&](int64_t c0, int64_t r0, int64_t cw, int64_t ch, unsigned char* out, int64_t stride) {
                                 rasterIO(*reading, c0, r0, cw, ch, type, out, stride);
                             });
            return {column0, row0};
        }
        rasterIO(*reading, column0, row0, w, h, type, raw, w);
        return {column0, row0};
    }

    // RasterIO of a raster window into `raw`, rows `stride` values apart.
    void rasterIO(GDALRasterBand& reading, int64_t column0, int64_t row0, int64_t w, int64_t h, GDALDataType type,
                  void* raw, int64_t stride) const {
        const int bytes = GDALGetDataTypeSizeBytes(type);
        CPLErrorReset();
        if (reading.RasterIO(GF_Read, static_cast<int>(column0), static_cast<int>(row0), static_cast<int>(w),
                             static_cast<int>(h), raw, static_cast<int>(w), static_cast<int>(h), type, bytes,
                             static_cast<GSpacing>(stride) * bytes, nullptr) != CE_None)
            throw InputError(fmt::format("{}: cannot read rows {}..{} of band 1{}", path, row0, row0 + h - 1,
                                         gdalReason()));
    }

    // A band no other thread is reading, locked into `lock`: the first opening when it is free, else the opening
    // this thread used last, another free one, or a new one; when none can be had, the first after a wait.
    GDALRasterBand* lockBand(std::unique_lock<std::mutex>& lock) const {
        thread_local const Impl* lastReader = nullptr;
        thread_local size_t lastHandle = 0;  // 0 for the first opening, k + 1 for handles[k]
        const auto take = [&](std::mutex& m) {
            lock = std::unique_lock<std::mutex>(m, std::try_to_lock);
            return lock.owns_lock();
        };
        const size_t preferred = lastReader == this ? lastHandle : 0;
        lastReader = this;
        {
            std::lock_guard list(handlesMutex);
            if (preferred > 0 && preferred <= handles.size() && take(handles[preferred - 1]->mutex)) {
                lastHandle = preferred;
                return handles[preferred - 1]->band;
            }
            if (take(readMutex)) {
                lastHandle = 0;
                return band;
            }
            for (size_t k = 0; k < handles.size(); ++k)
                if (take(handles[k]->mutex)) {
                    lastHandle = k + 1;
                    return handles[k]->band;
                }
        }
        if (!noMoreHandles.load(std::memory_order_relaxed)) {
            // Opened outside the list's lock (it takes milliseconds), then added to the list locked.
            auto handle = std::make_unique<Handle>();
            handle->dataset.reset(GDALDataset::Open(source.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
            if (handle->dataset && handle->dataset->GetRasterCount() >= 1) {
                handle->band = handle->dataset->GetRasterBand(1);
                std::lock_guard list(handlesMutex);
                if (handles.size() + 1 < std::max<size_t>(std::thread::hardware_concurrency(), 2)) {
                    Handle& added = *handles.emplace_back(std::move(handle));
                    lock = std::unique_lock<std::mutex>(added.mutex);
                    lastHandle = handles.size();
                    return added.band;
                }
            }
            noMoreHandles = true;
        }
        lock = std::unique_lock<std::mutex>(readMutex);
        lastHandle = 0;
        return band;
    }

    // Drops the blocks GDAL's cache holds of every opening (of all its bands: an interleaved raster caches the
    // others' blocks beside band 1's): a whole raster read band by band need not keep the decoded raster a
    // second time beside the grid. (The sources behind a VRT keep theirs, up to GDAL's cache limit.)
    void dropCachedBlocks() const {
        {
            const std::lock_guard<std::mutex> lock(readMutex);
            dataset->FlushCache(false);
        }
        const std::lock_guard<std::mutex> list(handlesMutex);
        for (const auto& h : handles) {
            const std::lock_guard<std::mutex> lock(h->mutex);
            h->dataset->FlushCache(false);
        }
    }

    void readWholeMetres(int64_t i0, int64_t j0, int64_t w, int64_t h, int16_t* metres, uint8_t* valid) const {
        if (!wholeMetres) throw std::logic_error(path + ": band 1 does not hold 16-bit integers in metres");
        checkWindow(i0, j0, w, h);
        // Straight into the caller's array, in the raster's order, then mirrored in place into the grid's.
        readRaw(i0, j0, w, h, GDT_Int16, metres);
        if (lattice.flipRows)
            for (int64_t r = 0; r < h / 2; ++r)
                std::swap_ranges(metres + r * w, metres + (r + 1) * w, metres + (h - 1 - r) * w);
        if (lattice.flipColumns)
            for (int64_t r = 0; r < h; ++r) std::reverse(metres + r * w, metres + (r + 1) * w);
        const auto n = static_cast<size_t>(w * h);
        if (!nodataInt16) {
            std::fill(valid, valid + n, uint8_t{1});
            return;
        }
        const auto nodataValue = static_cast<int16_t>(nodata);
        for (size_t k = 0; k < n; ++k) {
            const bool good = metres[k] != nodataValue;
            valid[k] = good ? 1 : 0;
            if (!good) metres[k] = 0;
        }
    }

    void read(int64_t i0, int64_t j0, int64_t w, int64_t h, float* heightsM, uint8_t* valid) const {
        checkWindow(i0, j0, w, h);
        // As float64, so that every integer and float32 type converts exactly.
        std::vector<double> own;
        std::vector<double>& raw = windowBuffer(static_cast<size_t>(w * h), own);
        const auto [column0, row0] = readRaw(i0, j0, w, h, GDT_Float64, raw.data());
        for (int64_t r = 0; r < h; ++r) {
            const int64_t row = row0 + r;
            const int64_t j = (lattice.flipRows ? height - 1 - row : row) - j0;
            for (int64_t c = 0; c < w; ++c) {
                const int64_t column = column0 + c;
                const int64_t i = (lattice.flipColumns ? width - 1 - column : column) - i0;
                const auto index = static_cast<size_t>(j * w + i);
                const double value = raw[static_cast<size_t>(r * w + c)];
                if (isNodata(value)) {
                    valid[index] = 0;
                    heightsM[index] = 0.0f;
                    continue;
                }
                if (valid != nullptr) valid[index] = 1;
                const double heightM = value * metresPerRaw + metresOffset;
                const auto heightF = static_cast<float>(heightM);
                if (!std::isfinite(heightF) || std::abs(heightM) > kMaxAbsHeightM)
                    throwBadHeight(path, column, row, heightM);
                heightsM[index] = heightF;
            }
        }
    }
};

DemWindowReader::DemWindowReader(const std::string& path, const DemLoadOptions& options)
    : impl_(std::make_unique<Impl>(path, options, false, std::string())) {}
DemWindowReader::~DemWindowReader() = default;
const std::string& DemWindowReader::path() const { return impl_->path; }
const std::string& DemWindowReader::driver() const { return impl_->driver; }
int64_t DemWindowReader::width() const { return impl_->width; }
int64_t DemWindowReader::height() const { return impl_->height; }
double DemWindowReader::cellSizeXM() const { return impl_->lattice.cellSizeXM; }
double DemWindowReader::cellSizeYM() const { return impl_->lattice.cellSizeYM; }
double DemWindowReader::metresPerUnit() const { return impl_->metresPerRaw; }
bool DemWindowReader::hasNodata() const { return impl_->hasNodata; }
const GeoReference& DemWindowReader::geo() const { return impl_->geo; }
const std::vector<std::string>& DemWindowReader::warnings() const { return impl_->warnings; }
std::vector<std::string> DemWindowReader::files() const {
    std::vector<std::string> out;
    char** list = impl_->dataset->GetFileList();
    for (char** f = list; f && *f; ++f) out.emplace_back(*f);
    CSLDestroy(list);
    return out;
}
std::string DemWindowReader::decodingKey() const {
    return fmt::format("{} {} {:.17g} {:.17g} {} {:.17g}", impl_->driver,
                       GDALGetDataTypeName(impl_->band->GetRasterDataType()), impl_->metresPerRaw,
                       impl_->metresOffset, impl_->hasNodata, impl_->nodata);
}
void DemWindowReader::read(int64_t i0, int64_t j0, int64_t w, int64_t h, float* heightsM, uint8_t* valid) const {
    impl_->read(i0, j0, w, h, heightsM, valid);
}
bool DemWindowReader::storedInBlocks() const { return impl_->storedInBlocks; }
bool DemWindowReader::wholeMetres() const { return impl_->wholeMetres; }
int DemWindowReader::openings() const {
    std::lock_guard list(impl_->handlesMutex);
    return 1 + static_cast<int>(impl_->handles.size());
}
void DemWindowReader::readWholeMetres(int64_t i0, int64_t j0, int64_t w, int64_t h, int16_t* metres,
                                      uint8_t* valid) const {
    impl_->readWholeMetres(i0, j0, w, h, metres, valid);
}

namespace {

// The raster rows [first, end) that rank `part` of `parts` reads in a load shared by the ranks: equal bands,
// their bounds rounded to 256 rows (a whole number of the storage blocks of common tiled GeoTIFFs, so that no
// block is decoded by two ranks).
std::pair<int64_t, int64_t> sharedRows(int64_t height, int part, int parts) {
    const auto bound = [&](int q) {
        if (q >= parts) return height;
        return std::min(height, (height * q / parts + 255) / 256 * 256);
    };
    return {bound(part), bound(part + 1)};
}

// Loads band 1 of any raster GDAL can open, a band of rows at a time. Messages name `path`; GDAL opens
// `openPath` when one is given. In a load shared by the ranks, each rank reads its part of the rows and the
// ranks exchange them, so that every rank ends with the whole grid.
LoadedDem loadWithGdal(const std::string& path, const DemLoadOptions& options, const std::string& openPath = {}) {
    const bool shared = options.sharedByRanks && ranks::size() > 1;
    std::optional<DemWindowReader::Impl> opened;
    std::optional<RasterTooLarge> tooLarge;
    try {
        opened.emplace(path, options, true, openPath);
    } catch (const RasterTooLarge& e) {
        if (!shared) throw;
        tooLarge = e;
    }
    if (shared) {
        // What one rank's memory cannot hold, every rank holds as tiles: the ranks must take the same path.
        int64_t shortOfMemory = tooLarge ? 1 : 0;
        ranks::sum(&shortOfMemory, 1);
        if (tooLarge) throw *tooLarge;
        if (shortOfMemory > 0) {
            const double limit = memoryLimitBytes(options.maxBytes);
            throw RasterTooLarge(path + ": another rank cannot hold the raster whole", currentResidentBytes(), limit);
        }
    }
    const DemWindowReader::Impl& reader = *opened;
    LoadedDem dem;
    dem.path = path;
    dem.driver = reader.driver;
    dem.sourceWidth = reader.width;
    dem.sourceHeight = reader.height;
    dem.geo = reader.geo;
    dem.warnings = reader.warnings;
    const int64_t width = reader.width, height = reader.height;
    const auto vertexCount = static_cast<size_t>(width * height);
    // 16-bit integers in metres go straight into the grid's int16 codes, without a float copy of the raster.
    const bool codes = reader.wholeMetres;
    std::vector<float> heightsM;
    std::vector<int16_t> metres;
    if (codes) metres = largeVector<int16_t>(vertexCount);
    else heightsM = largeVector<float>(vertexCount);
    std::vector<uint8_t> valid, bandValid;
    if (reader.hasNodata) valid = largeVector<uint8_t>(vertexCount, 1);
    // Raster row r is grid row height - 1 - r when the raster's rows run north to south (flipRows), else r.
    const auto gridRows = [&](int64_t first, int64_t end) {
        return reader.lattice.flipRows ? std::pair{height - end, height - first} : std::pair{first, end};
    };
    const int parts = shared ? ranks::size() : 1;
    const auto [firstRow, endRow] = sharedRows(height, shared ? ranks::rank() : 0, parts);
    // From the first raster row on (the grid's last), so that a bad height is reported at the first raster row
    // that holds one (in a shared load: the first of the rank that meets one first; that rank ends them all).
    // Bands of about 2^21 samples, in whole storage blocks where a block is shorter than that, whose decoded blocks
    // are dropped from GDAL's cache once read: a block is decoded once (unless taller than a band: a raster
    // stored as a few strips), and the cache does not hold the raster beside the grid.
    const QuietGdalThreads quietDecoders;  // the whole raster's blocks are decoded on GDAL's threads
    const int64_t budgetRows = std::max<int64_t>(1, (int64_t{1} << 21) / width);
    const int64_t rowsPerBand =
        reader.blockRows <= budgetRows ? budgetRows / reader.blockRows * reader.blockRows : budgetRows;
    for (int64_t r = firstRow; r < endRow; r += rowsPerBand) {
        // (Not a structured binding: the lambda below captures them, which clang 14 refuses.)
        const std::pair<int64_t, int64_t> band = gridRows(r, std::min(endRow, r + rowsPerBand));
        const int64_t j0 = band.first, j1 = band.second;
        const auto offset = static_cast<size_t>(j0 * width);
        const auto readBand = [&](const DemWindowReader::Impl& from) {
            if (codes) {
                // Flags come with the codes; without nodata they go to a scratch band.
                uint8_t* flags = valid.empty() ? nullptr : valid.data() + offset;
                if (flags == nullptr) {
                    bandValid.resize(static_cast<size_t>((j1 - j0) * width));
                    flags = bandValid.data();
                }
                from.readWholeMetres(0, j0, width, j1 - j0, metres.data() + offset, flags);
            } else {
                from.read(0, j0, width, j1 - j0, heightsM.data() + offset, valid.empty() ? nullptr : valid.data() + offset);
            }
        };
        try {
            readBand(reader);
        } catch (const InputError&) {
            if (arrayPassThreads() <= 1) throw;
            // Read again on this thread alone (an opening that decodes on one thread), so that the error names the
            // first block that fails, as it does without GDAL's threads, not whichever a thread met first.
            const DemWindowReader::Impl alone(path, options, false, openPath);
            readBand(alone);
            throw;  // read this time: the first failure stands
        }
        reader.dropCachedBlocks();
    }
    std::vector<uint8_t>().swap(bandValid);
    for (int q = 0; shared && q < parts; ++q) {
        const auto [first, end] = sharedRows(height, q, parts);
        const auto [j0, j1] = gridRows(first, end);
        const auto offset = static_cast<size_t>(j0 * width), count = static_cast<size_t>((j1 - j0) * width);
        if (codes) ranks::broadcast(metres.data() + offset, count * sizeof(int16_t), q);
        else ranks::broadcast(heightsM.data() + offset, count * sizeof(float), q);
        if (!valid.empty()) ranks::broadcast(valid.data() + offset, count, q);
    }
    // The raster closed before the grid is built: GDAL's buffers are not held beside the pyramid.
    const double cellSizeXM = reader.lattice.cellSizeXM, cellSizeYM = reader.lattice.cellSizeYM;
    const double metresPerRaw = reader.metresPerRaw;
    opened.reset();
    if (codes)
        dem.grid = makeGrid(path, width, height, cellSizeXM, cellSizeYM, std::move(metres), 0, metresPerRaw,
                            std::move(valid));
    else
        dem.grid = makeGrid(path, width, height, cellSizeXM, cellSizeYM, std::move(heightsM), std::move(valid),
                            metresPerRaw);
    return dem;
}

// loadDem before the exaggeration of a DEM held whole.
LoadedDem loadAsStored(const std::string& path, const DemLoadOptions& options) {
    checkInputFile(path, "a DEM");
    const ExitOnCancel interruptible;  // GDAL may block (a network path); nothing is written yet
    // The one place where a format is chosen: PNG height maps through png_height_map.cpp, everything else through
    // GDAL.
    if (lowerExtension(path) == ".png") {
        if (options.tileCacheBytes > 0.0)
            throw InputError(path + ": PNG height maps are read whole, not as tiles (convert it to a tiled GeoTIFF "
                                    "to hold it as tiles: gdal_translate -co TILED=YES)");
        return loadPngHeightMap(path, options);
    }
    if (options.tileCacheBytes > 0.0) return openTiledDem(path, size_t(options.tileCacheBytes), options);
    if (options.tilesUnderRanks && ranks::size() > 1) {
        // --max-memory bounds each process, as everywhere; the default limit is the machine's, shared by its
        // ranks. A quarter of what is left goes to the cache, as for a raster too large to hold whole.
        const double limit = options.maxBytes > 0.0 ? options.maxBytes
                                                    : defaultMemoryLimitBytes() / double(ranks::sizeOnThisMachine());
        const double cacheBytes = (limit - currentResidentBytes()) / 4.0;
        // Opened once for both the decision and the tiles. A raster GDAL cannot open, or one stored in strips,
        // takes the whole load (which says what is wrong with the former).
        std::unique_ptr<DemWindowReader> reader;
        if (cacheBytes >= kMinTileCacheBytes) {
            try {
                reader = std::make_unique<DemWindowReader>(path, options);
            } catch (const InputError&) {
            }
        }
        // Every rank takes the same path (the whole load is collective): tiles only when every rank can.
        int64_t able = reader && reader->storedInBlocks() ? 1 : 0;
        ranks::sum(&able, 1);
        if (able == ranks::size()) {
            // The DEM fits: a cache of a quarter of the whole grid's bytes (int16 codes and their pyramid, about
            // 3 bytes a vertex) holds what a rank's part reaches more than once. A larger one only costs fresh
            // memory for every tile, which the rank touches once: 0.3 s of a rank's 1 s render of the 8193^2
            // grid on the machine of docs/scale.md.
            const double quarterOfGrid = 0.75 * double(reader->width()) * double(reader->height());
            return openTiledDem(std::move(reader), size_t(std::min(cacheBytes, std::max(quarterOfGrid,
                                                                                       double(kMinTileCacheBytes)))),
                                options.exaggeration, options.tileStore);
        }
    }
    // A raster too large to hold whole is held as tiles, with a quarter of the memory left for their cache.
    try {
        return loadWithGdal(path, options);
    } catch (const RasterTooLarge& e) {
        const double cacheBytes = (e.limitBytes - e.heldBytes) / 4.0;
        if (cacheBytes < kMinTileCacheBytes)
            throw InputError(fmt::format("{}; held as tiles, it would get a cache of {}, less than the {} it needs",
                                         e.what(), humanBytes(std::max(0.0, cacheBytes)),
                                         humanBytes(kMinTileCacheBytes)));
        return openTiledDem(path, size_t(cacheBytes), options);
    }
}

// Refuses a factor DemLoadOptions::exaggeration does not allow.
void checkExaggeration(const std::string& path, double k) {
    if (!(k > 0.0) || !std::isfinite(k))
        throw InputError(fmt::format("{}: vertical exaggeration: expected a positive number, found {}", path, k));
}

// A DEM held whole under DemLoadOptions::exaggeration (one held as tiles is scaled as it is read).
LoadedDem exaggerated(LoadedDem dem, double k) {
    if (k == 1.0 || dem.grid.tiled()) return dem;
    const HeightGrid& g = dem.grid;
    const double top = std::max(std::abs(double(g.minHeightM())), std::abs(double(g.maxHeightM())));
    if (!(double(float(k)) * top <= kMaxExaggeratedHeightM))
        throw InputError(fmt::format("{}: a vertical exaggeration of {} makes heights of up to {:.0f} m unusable "
                                     "(expected a factor that keeps them below {:.0e} m)",
                                     dem.path, k, top, kMaxExaggeratedHeightM));
    dem.grid.scaleHeights(float(k));
    return dem;
}

}  // namespace

LoadedDem exaggeratedDem(LoadedDem dem, double k) {
    checkExaggeration(dem.path, k);
    if (k != 1.0 && dem.grid.tiled())
        throw InputError(fmt::format("{}: a DEM held as tiles is exaggerated as its tiles are read; load it with "
                                     "DemLoadOptions::exaggeration", dem.path));
    return exaggerated(std::move(dem), k);
}

LoadedDem loadDem(const std::string& path, const DemLoadOptions& options) {
    checkExaggeration(path, options.exaggeration);
    return exaggerated(loadAsStored(path, options), options.exaggeration);
}

ArrayPlacement placeArray(const std::string& name, const double gt[6], const std::string& crs, int64_t width,
                          int64_t height) {
    registerGdalDrivers();
    ArrayPlacement out;
    OGRSpatialReference srs;
    if (!crs.empty()) {
        CPLErrorReset();
        if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE)
            throw InputError(fmt::format("{}: crs: expected WKT, an EPSG code or a PROJ string, found '{}'{}", name,
                                         firstLine(crs), gdalReason()));
        srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    }
    const Lattice lattice = placeRaster(name, gt, crs.empty() ? nullptr : &srs, width, height, out.geo, out.warnings);
    out.cellSizeXM = lattice.cellSizeXM;
    out.cellSizeYM = lattice.cellSizeYM;
    out.flipRows = lattice.flipRows;
    out.flipColumns = lattice.flipColumns;
    return out;
}

LoadedDem loadDemFromBytes(std::string_view bytes, const std::string& name, const DemLoadOptions& options) {
    if (bytes.empty()) throw InputError(name + ": file is empty");
    registerGdalDrivers();
    // A unique in-memory file per call, keeping the name's extension (some drivers look at it).
    static std::atomic<uint64_t> counter{0};
    const std::string memoryPath =
        fmt::format("/vsimem/terracast-{}-{}{}", getpid(), counter++, std::filesystem::path(name).extension().string());
    // GDAL reads the caller's buffer in place (no copy, not owned); the file is unlinked on every way out.
    VSILFILE* file = VSIFileFromMemBuffer(memoryPath.c_str(), reinterpret_cast<GByte*>(const_cast<char*>(bytes.data())),
                                          static_cast<vsi_l_offset>(bytes.size()), FALSE);
    if (file == nullptr) throw std::runtime_error(name + ": cannot make an in-memory file");
    VSIFCloseL(file);
    struct Unlink {
        const std::string& path;
        ~Unlink() { VSIUnlink(path.c_str()); }
    } unlink{memoryPath};
    checkExaggeration(name, options.exaggeration);
    return exaggerated(loadWithGdal(name, options, memoryPath), options.exaggeration);
}

}  // namespace terracast
