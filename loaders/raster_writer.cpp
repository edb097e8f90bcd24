// Writing rasters on a DEM's grid as Cloud Optimized GeoTIFFs through GDAL, a tile at a time: each finished
// tile is a small GeoTIFF of its own in the output's partial folder, and the COG is made from a VRT mosaic of
// them (docs/architecture.md, "Tiled outputs"). Rows are written north-up (file row 0 is the northmost raster
// row) with a pixel-is-area geotransform whose pixel centres fall on the grid's vertices, so the file overlays
// the source DEM exactly.
#include "loaders/image_io.h"
#include "loaders/loader_support.h"
#include "loaders/raster_writer.h"

#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/text.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <fmt/format.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <type_traits>

namespace terracast {
namespace {

using namespace loader_support;

namespace fs = std::filesystem;

// GDAL's block cache while the COG is made (TiledGeoTiffWriter::kCopyCacheBytes).
constexpr int64_t kCopyCacheBytes = TiledGeoTiffWriter::kCopyCacheBytes;

// The partial folder's name beside `target`: NAME.partial, or a hash of the name when that would pass the file
// system's 255-byte limit.
std::string partialName(const fs::path& target) {
    const std::string name = target.filename().string();
    if (name.size() <= 240) return name + ".partial";
    uint64_t hash = 1469598103934665603ull;  // FNV-1a
    for (unsigned char c : name) hash = (hash ^ c) * 1099511628211ull;
    return fmt::format(".terracast-{:016x}.partial", hash);
}

bool vsiExists(const std::string& path) {
    VSIStatBufL stat;
    return VSIStatL(path.c_str(), &stat) == 0;
}

// The whole of a small file, or nothing when it cannot be read.
std::optional<std::string> vsiRead(const std::string& path) {
    GByte* data = nullptr;
    vsi_l_offset size = 0;
    if (!VSIIngestFile(nullptr, path.c_str(), &data, &size, 1 << 20)) return std::nullopt;
    std::string text(reinterpret_cast<const char*>(data), size_t(size));
    VSIFree(data);
    return text;
}

bool vsiWrite(const std::string& path, const std::string& text) {
    VSILFILE* f = VSIFOpenL(path.c_str(), "wb");
    if (f == nullptr) return false;
    const bool ok = VSIFWriteL(text.data(), 1, text.size(), f) == text.size();
    return VSIFCloseL(f) == 0 && ok;
}

const char* typeName(RasterType type) { return type == RasterType::Byte ? "Byte" : "Float32"; }

// Everything that decides the file's bytes, one item per line: a partial folder is resumed only by the same.
std::string describeJob(const RasterLayout& l, RasterType type, const RasterPlacement& p, const std::string& job) {
    std::string text = fmt::format("terracast tiled raster 1\nsize {} {} {}\ntype {}\ntile {}\nnodata {} {:.17g}\n",
                                   l.width, l.height, l.bands, typeName(type), TiledGeoTiffWriter::kTile, l.hasNoData,
                                   l.noDataValue);
    for (const auto& d : l.bandDescriptions) text += fmt::format("description {}\n", d);
    for (const auto& u : l.bandUnits) text += fmt::format("unit {}\n", u);
    for (const auto& [k, v] : l.metadata) text += fmt::format("metadata {}={}\n", k, v);
    text += fmt::format("point {}\nalpha {}\nplacement {:.17g} {:.17g} {:.17g} {:.17g}\n", l.pixelIsPoint,
                        l.lastBandIsAlpha, p.originX, p.originY, p.pixelSizeX, p.pixelSizeY);
    text += fmt::format("crs {}\n", p.geo.georeferenced ? p.geo.crsWkt : std::string("none"));
    for (char& c : text)
        if (c == '\r') c = ' ';
    return text + "job " + job + "\n";
}

// Where an earlier job's description differs from this one's: "'earlier line' where this run has 'line'".
std::string firstDifference(const std::string& earlier, const std::string& now) {
    std::istringstream x(earlier), y(now);
    std::string a, b;
    while (true) {
        const bool ga = bool(std::getline(x, a)), gb = bool(std::getline(y, b));
        if (!ga && !gb) return "";
        if (!ga) a.clear();
        if (!gb) b.clear();
        if (!ga || !gb || a != b)
            return fmt::format("'{}' where this run has '{}'", a.substr(0, 160), b.substr(0, 160));
    }
}

int CPL_STDCALL copyProgress(double done, const char*, void* data) {
    if (cancelFlag().load(std::memory_order_relaxed)) return FALSE;
    const auto* f = static_cast<const std::function<bool(double)>*>(data);
    return (*f && !(*f)(done)) ? FALSE : TRUE;
}

}  // namespace

uint8_t rasterByte(float value) {
    if (!(value > 0.0f)) return 0;
    if (value >= 255.0f) return 255;
    return static_cast<uint8_t>(std::lround(value));
}

struct TiledGeoTiffWriter::State {
    std::string path;
    RasterLayout layout;
    RasterType type = RasterType::Byte;
    GDALDataType gdalType = GDT_Byte;
    RasterPlacement placement;
    bool inPlace = false;        // a device or pipe: written from memory, in place
    fs::path folder;             // the output's folder (not for a device)
    std::string partial;         // the tiles' folder
    int64_t tilesX = 0, tilesY = 0;
    std::vector<uint8_t> done;   // per tile, file order
    std::atomic<int64_t> written{0};
    int64_t resumed = 0, discarded = 0;
    bool committed = false;
    Role role = Role::Sole;

    std::string tileName(int64_t tx, int64_t ty) const { return fmt::format("tile-{}-{}.tif", tx, ty); }
    std::string tilePath(int64_t tx, int64_t ty) const { return partial + "/" + tileName(tx, ty); }
    std::runtime_error fail(const std::string& what) const {
        const std::string reason = firstLine(CPLGetLastErrorMsg());
        return std::runtime_error(fmt::format("{}: {}{}", path, what, reason.empty() ? "" : " (" + reason + ")"));
    }
    // True when the tile file exists and holds a tile of this raster.
    bool validTile(int64_t tx, int64_t ty, const Window& w) const {
        GDALDataset* ds = GDALDataset::Open(tilePath(tx, ty).c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
        if (ds == nullptr) return false;
        const bool ok = ds->GetRasterXSize() == w.width() && ds->GetRasterYSize() == w.height() &&
                        ds->GetRasterCount() == layout.bands && ds->GetRasterBand(1)->GetRasterDataType() == gdalType;
        GDALClose(ds);
        return ok;
    }
};

TiledGeoTiffWriter::TiledGeoTiffWriter(const std::string& path, const RasterLayout& layout, RasterType type,
                                       const RasterPlacement& placement, const std::string& job, bool resume,
                                       Role role)
    : s_(std::make_unique<State>()) {
    if (layout.width < 1 || layout.height < 1 || layout.bands < 1 || layout.width > INT32_MAX ||
        layout.height > INT32_MAX || layout.bands > 65535)
        throw std::invalid_argument(fmt::format("TiledGeoTiffWriter: a {} x {} raster with {} bands", layout.width,
                                                layout.height, layout.bands));
    if (!(placement.pixelSizeX > 0.0) || !(placement.pixelSizeY > 0.0) || !std::isfinite(placement.pixelSizeX) ||
        !std::isfinite(placement.pixelSizeY) || !std::isfinite(placement.originX) || !std::isfinite(placement.originY))
        throw std::invalid_argument(fmt::format("TiledGeoTiffWriter: origin ({}, {}) and pixel size {} x {} must be "
                                                "finite, the pixel size positive",
                                                placement.originX, placement.originY, placement.pixelSizeX,
                                                placement.pixelSizeY));
    const std::string ext = lowerExtension(path);
    if (ext != ".tif" && ext != ".tiff")
        throw InputError(fmt::format("{}: unsupported output format '{}' (expected .tif)", path, ext));
    State& s = *s_;
    s.role = role;
    s.path = path;
    s.layout = layout;
    s.type = type;
    s.gdalType = type == RasterType::Byte ? GDT_Byte : GDT_Float32;
    s.placement = placement;
    s.tilesX = (layout.width + kTile - 1) / kTile;
    s.tilesY = (layout.height + kTile - 1) / kTile;
    s.done.assign(size_t(s.tilesX * s.tilesY), 0);

    const fs::path target(path);
    // A device or pipe (a link to /dev/null) is written in place, from a GeoTIFF made in memory: renaming over it
    // would replace it with a regular file.
    std::error_code ec;
    const auto status = fs::status(target, ec);
    s.inPlace = !ec && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
    registerGdalDrivers();
    QuietGdalErrors quiet;
    static std::atomic<int> memoryFolders{0};
    if (s.inPlace) {
        s.partial = fmt::format("/vsimem/terracast-partial-{}-{}", ::getpid(), memoryFolders++);
    } else {
        s.folder = writableFolder(path);
        s.partial = (s.folder / partialName(target)).string();
    }
    if (role == Role::Follower) {
        if (s.inPlace) throw InputError(fmt::format("{}: several processes cannot write to a device", path));
        if (!vsiExists(s.partial))
            throw s.fail(fmt::format("the partial output folder '{}' is not there (is the output folder shared "
                                     "by every rank?)", s.partial));
        return;
    }
    preparePartialFolder(describeJob(layout, type, placement, job), resume);
}

void TiledGeoTiffWriter::preparePartialFolder(const std::string& jobText, bool resume) {
    State& s = *s_;
    const std::string& path = s.path;
    const std::string jobPath = s.partial + "/job.txt";
    if (vsiExists(s.partial)) {
        const std::optional<std::string> earlier = vsiRead(jobPath);
        if (!earlier)
            throw InputError(fmt::format("{}: '{}' exists and is not a terracast partial output (it has no job.txt); "
                                         "move it away", path, s.partial));
        if (resume && *earlier != jobText)
            throw InputError(fmt::format("{}: --resume: the tiles in '{}' belong to another job (it has {}); run "
                                         "without --resume to start afresh",
                                         path, s.partial, firstDifference(*earlier, jobText)));
        for (int64_t ty = 0; ty < s.tilesY; ++ty)
            for (int64_t tx = 0; tx < s.tilesX; ++tx) {
                if (!vsiExists(s.tilePath(tx, ty))) continue;
                if (resume && s.validTile(tx, ty, window(tx, ty))) {
                    s.done[size_t(ty * s.tilesX + tx)] = 1;
                    ++s.resumed;
                } else {
                    ++s.discarded;
                    VSIUnlink(s.tilePath(tx, ty).c_str());
                }
            }
        if (!resume) {
            VSIRmdirRecursive(s.partial.c_str());
            if (vsiExists(s.partial)) throw s.fail(fmt::format("cannot remove the earlier partial output '{}'", s.partial));
        }
    }
    if (!vsiExists(s.partial) && VSIMkdir(s.partial.c_str(), 0755) != 0)
        throw s.fail(fmt::format("cannot make the partial output folder '{}' ({})", s.partial, std::strerror(errno)));
    if (!vsiWrite(jobPath + ".tmp", jobText) || VSIRename((jobPath + ".tmp").c_str(), jobPath.c_str()) != 0)
        throw s.fail(fmt::format("cannot write '{}'", jobPath));
}

TiledGeoTiffWriter::~TiledGeoTiffWriter() {
    State& s = *s_;
    if (s.committed) return;
    // Tiles in memory cannot be resumed; a folder without a finished tile is only litter (a sole writer knows
    // that no other process wrote one).
    if (s.inPlace || (s.role == Role::Sole && s.resumed == 0 && s.written.load() == 0))
        VSIRmdirRecursive(s.partial.c_str());
}

int64_t TiledGeoTiffWriter::tilesX() const { return s_->tilesX; }
int64_t TiledGeoTiffWriter::tilesY() const { return s_->tilesY; }
int64_t TiledGeoTiffWriter::resumedTiles() const { return s_->resumed; }
int64_t TiledGeoTiffWriter::discardedTiles() const { return s_->discarded; }
std::string TiledGeoTiffWriter::partialFolder() const { return s_->inPlace ? std::string() : s_->partial; }

TiledGeoTiffWriter::Window TiledGeoTiffWriter::window(int64_t tx, int64_t ty) const {
    const int64_t h = s_->layout.height;
    Window w;
    w.i0 = tx * kTile;
    w.i1 = std::min(s_->layout.width, w.i0 + kTile);
    // File rows [ty T, (ty + 1) T) are raster rows h - 1 - fileRow.
    w.j1 = h - ty * kTile;
    w.j0 = std::max<int64_t>(0, w.j1 - kTile);
    return w;
}

std::vector<uint8_t> TiledGeoTiffWriter::finishedMask() const { return s_->done; }

void TiledGeoTiffWriter::setFinished(const std::vector<uint8_t>& mask) {
    if (mask.size() != s_->done.size()) throw std::invalid_argument("TiledGeoTiffWriter::setFinished: wrong size");
    s_->done = mask;
    s_->resumed = int64_t(std::count(mask.begin(), mask.end(), uint8_t(1)));
}

bool TiledGeoTiffWriter::finished(int64_t tx, int64_t ty) const { return s_->done[size_t(ty * s_->tilesX + tx)] != 0; }

namespace {

// Converts a tile's values (row 0 south) into file order (row 0 north) as `Sample`s, NaN as `noData`.
template <typename Sample>
std::vector<Sample> fileOrder(const float* values, int64_t width, int64_t height, int bands, float noData) {
    const size_t rowValues = size_t(width) * size_t(bands);
    std::vector<Sample> out(rowValues * size_t(height));
    for (int64_t r = 0; r < height; ++r) {
        const float* source = values + size_t(height - 1 - r) * rowValues;
        Sample* target = out.data() + size_t(r) * rowValues;
        for (size_t k = 0; k < rowValues; ++k) {
            const float v = std::isnan(source[k]) ? noData : source[k];
            if constexpr (std::is_same_v<Sample, uint8_t>)
                target[k] = rasterByte(v);
            else
                target[k] = v;
        }
    }
    return out;
}

}  // namespace

void TiledGeoTiffWriter::write(int64_t tx, int64_t ty, const float* values) {
    State& s = *s_;
    if (tx < 0 || ty < 0 || tx >= s.tilesX || ty >= s.tilesY)
        throw std::invalid_argument(fmt::format("TiledGeoTiffWriter::write: no tile {}, {}", tx, ty));
    const Window w = window(tx, ty);
    QuietGdalErrors quiet;
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    if (driver == nullptr) throw s.fail("GDAL has no GTiff driver");
    // Fast compression: these files live only until the COG is made.
    CPLStringList options;
    options.SetNameValue("COMPRESS", "ZSTD");
    options.SetNameValue("ZSTD_LEVEL", "1");
    options.SetNameValue("TILED", "YES");
    options.SetNameValue("BLOCKXSIZE", std::to_string(kTile).c_str());
    options.SetNameValue("BLOCKYSIZE", std::to_string(kTile).c_str());
    // Band by band: the COG is made a band at a time, and reading one band of a pixel-interleaved tile would
    // decode (and cache) all of them.
    if (s.layout.bands > 1) options.SetNameValue("INTERLEAVE", "BAND");
    const std::string file = s.tilePath(tx, ty), temporary = file + ".tmp";
    GDALDataset* ds = driver->Create(temporary.c_str(), int(w.width()), int(w.height()), s.layout.bands, s.gdalType,
                                     options.List());
    if (ds == nullptr) throw s.fail(fmt::format("cannot create tile {}, {} in '{}'", tx, ty, s.partial));
    const float noData = float(s.layout.hasNoData ? s.layout.noDataValue : 0.0);
    const int bands = s.layout.bands;
    CPLErr err = CE_None;
    if (s.type == RasterType::Byte) {
        const auto data = fileOrder<uint8_t>(values, w.width(), w.height(), bands, noData);
        err = ds->RasterIO(GF_Write, 0, 0, int(w.width()), int(w.height()), const_cast<uint8_t*>(data.data()),
                           int(w.width()), int(w.height()), GDT_Byte, bands, nullptr, bands, GSpacing(bands) * w.width(),
                           1, nullptr);
    } else {
        const auto data = fileOrder<float>(values, w.width(), w.height(), bands, noData);
        const GSpacing pixel = GSpacing(sizeof(float)) * bands;
        err = ds->RasterIO(GF_Write, 0, 0, int(w.width()), int(w.height()), const_cast<float*>(data.data()),
                           int(w.width()), int(w.height()), GDT_Float32, bands, nullptr, pixel, pixel * w.width(),
                           sizeof(float), nullptr);
    }
    if (err != CE_None) {
        const std::runtime_error error = s.fail(fmt::format("cannot write tile {}, {} in '{}'", tx, ty, s.partial));
        GDALClose(ds);
        VSIUnlink(temporary.c_str());
        throw error;
    }
    CPLErrorReset();
    GDALClose(ds);
    if (CPLGetLastErrorType() >= CE_Failure || VSIRename(temporary.c_str(), file.c_str()) != 0) {
        const std::runtime_error error = s.fail(fmt::format("cannot write tile {}, {} in '{}'", tx, ty, s.partial));
        VSIUnlink(temporary.c_str());
        throw error;
    }
    s.done[size_t(ty * s.tilesX + tx)] = 1;
    ++s.written;
}

void TiledGeoTiffWriter::commit(const std::function<bool(double)>& progress, int threads) {
    State& s = *s_;
    if (s.role == Role::Follower) throw std::logic_error("TiledGeoTiffWriter::commit: the leader makes the COG");
    if (s.role == Role::Leader)
        for (int64_t ty = 0; ty < s.tilesY; ++ty)
            for (int64_t tx = 0; tx < s.tilesX; ++tx) {
                uint8_t& done = s.done[size_t(ty * s.tilesX + tx)];
                if (!done && !vsiExists(s.tilePath(tx, ty)))
                    throw s.fail(fmt::format("no process wrote tile {}, {} into '{}'", tx, ty, s.partial));
                done = 1;
            }
    if (std::find(s.done.begin(), s.done.end(), 0) != s.done.end())
        throw std::logic_error("TiledGeoTiffWriter::commit: tiles are missing");
    const RasterLayout& l = s.layout;
    QuietGdalErrors quiet;
    // The mosaic: one simple source per tile and band; the declared source properties let GDAL open the tiles
    // only when it reads them, through its pool of open datasets. The sources repeat for every band (the VRT
    // format has no per-dataset source list): about 400 bytes per tile and band, 7 MB per band of a 65537^2 product
    // (16,384 tiles), which GDAL parses once.
    std::string xml = fmt::format("<VRTDataset rasterXSize=\"{}\" rasterYSize=\"{}\">\n", l.width, l.height);
    for (int b = 1; b <= l.bands; ++b) {
        xml += fmt::format("<VRTRasterBand dataType=\"{}\" band=\"{}\">\n", typeName(s.type), b);
        for (int64_t ty = 0; ty < s.tilesY; ++ty)
            for (int64_t tx = 0; tx < s.tilesX; ++tx) {
                const Window w = window(tx, ty);
                xml += fmt::format(
                    "<SimpleSource><SourceFilename relativeToVRT=\"1\">{}</SourceFilename><SourceBand>{}</SourceBand>"
                    "<SourceProperties RasterXSize=\"{}\" RasterYSize=\"{}\" DataType=\"{}\" BlockXSize=\"{}\" "
                    "BlockYSize=\"{}\"/><SrcRect xOff=\"0\" yOff=\"0\" xSize=\"{}\" ySize=\"{}\"/>"
                    "<DstRect xOff=\"{}\" yOff=\"{}\" xSize=\"{}\" ySize=\"{}\"/></SimpleSource>\n",
                    s.tileName(tx, ty), b, w.width(), w.height(), typeName(s.type), kTile, kTile, w.width(),
                    w.height(), tx * kTile, ty * kTile, w.width(), w.height());
            }
        xml += "</VRTRasterBand>\n";
    }
    xml += "</VRTDataset>\n";
    const std::string vrtPath = s.partial + "/mosaic.vrt";
    if (!vsiWrite(vrtPath, xml)) throw s.fail(fmt::format("cannot write '{}'", vrtPath));
    // Each open tile holds its decoder's buffers: a small pool of open tiles (GDAL keeps 100 by default) keeps
    // the copy's memory independent of the number of tiles; the copy reads them in order, a row of tiles at a time.
    struct PoolLimit {
        std::string saved;
        PoolLimit() {
            if (const char* v = CPLGetThreadLocalConfigOption("GDAL_MAX_DATASET_POOL_SIZE", nullptr)) saved = v;
            CPLSetThreadLocalConfigOption("GDAL_MAX_DATASET_POOL_SIZE", "8");
        }
        ~PoolLimit() {
            CPLSetThreadLocalConfigOption("GDAL_MAX_DATASET_POOL_SIZE", saved.empty() ? nullptr : saved.c_str());
        }
    } poolLimit;
    GDALDataset* vrt = GDALDataset::Open(vrtPath.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE);
    if (vrt == nullptr) throw s.fail(fmt::format("cannot open the mosaic of tiles '{}'", vrtPath));
    struct Closer {
        GDALDataset* ds;
        ~Closer() { GDALClose(ds); }
    } closeVrt{vrt};
    // Before the geotransform: with AREA_OR_POINT=Point GDAL stores the tie point half a pixel in, and reads the
    // same geotransform back.
    if (l.pixelIsPoint) vrt->SetMetadataItem(GDALMD_AREA_OR_POINT, GDALMD_AOP_POINT);
    for (const auto& [key, value] : l.metadata) vrt->SetMetadataItem(key.c_str(), value.c_str());
    for (int b = 1; b <= l.bands; ++b) {
        GDALRasterBand* band = vrt->GetRasterBand(b);
        if (size_t(b) <= l.bandDescriptions.size()) band->SetDescription(l.bandDescriptions[size_t(b - 1)].c_str());
        const size_t unit = l.bandUnits.size() == 1 ? 0 : size_t(b - 1);
        if (unit < l.bandUnits.size()) band->SetUnitType(l.bandUnits[unit].c_str());
        if (l.hasNoData && band->SetNoDataValue(l.noDataValue) != CE_None)
            throw s.fail(fmt::format("cannot set nodata value {} on band {}", l.noDataValue, b));
        if (l.lastBandIsAlpha)
            band->SetColorInterpretation(b == l.bands ? GCI_AlphaBand
                                         : l.bands == 4 && s.type == RasterType::Byte
                                             ? GDALColorInterp(GCI_RedBand + (b - 1))
                                             : GCI_GrayIndex);
    }
    // Pixel-is-area geotransform: the centre of raster sample (i, j) lands on (originX + i * pixelSizeX,
    // originY + j * pixelSizeY); file row 0 is raster row height - 1.
    const RasterPlacement& p = s.placement;
    double gt[6] = {p.originX - 0.5 * p.pixelSizeX, p.pixelSizeX, 0.0,
                    p.originY + (double(l.height) - 0.5) * p.pixelSizeY, 0.0, -p.pixelSizeY};
    if (vrt->SetGeoTransform(gt) != CE_None) throw s.fail("cannot set the geotransform");
    if (p.geo.georeferenced && !p.geo.crsWkt.empty()) {
        OGRSpatialReference srs;
        srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        if (srs.importFromWkt(p.geo.crsWkt.c_str()) != OGRERR_NONE) throw s.fail("cannot interpret the CRS");
        if (vrt->SetSpatialRef(&srs) != CE_None) throw s.fail("cannot set the CRS");
    }

    GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
    if (cog == nullptr) throw s.fail("GDAL has no COG driver");
    const std::string ext = lowerExtension(s.path);
    static std::atomic<int> memoryFiles{0};
    const std::string temporaryPath =
        s.inPlace ? fmt::format("/vsimem/terracast-out-{}-{}.tif", ::getpid(), memoryFiles++)
                  : temporaryPathFor(s.folder, ext).string();
    TemporaryFile temporary(s.inPlace ? fs::path() : fs::path(temporaryPath));
    struct MemoryFile {
        std::string path;
        ~MemoryFile() {
            if (!path.empty()) VSIUnlink(path.c_str());
        }
    } memoryFile{s.inPlace ? temporaryPath : std::string()};
    CPLStringList options;
    options.SetNameValue("COMPRESS", "DEFLATE");
    options.SetNameValue("BLOCKSIZE", std::to_string(kTile).c_str());
    options.SetNameValue("BIGTIFF", "IF_SAFER");
    // Blocks compressed on several threads (GDAL's NUM_THREADS), each block's stream as one thread makes it.
    if (threads != 1) options.SetNameValue("NUM_THREADS", threads <= 0 ? "ALL_CPUS" : std::to_string(threads).c_str());
    // Overviews average measured values and colours; Byte classes and counts keep their values.
    options.SetNameValue("RESAMPLING", s.type == RasterType::Float32 || l.lastBandIsAlpha ? "AVERAGE" : "NEAREST");
    // GDAL's block cache holds what the copy reads and writes; its default (5 % of the machine's memory) would let
    // a large raster's blocks pile up there. A bounded cache keeps the copy's memory independent of the raster.
    struct CacheLimit {
        int64_t saved = GDALGetCacheMax64();
        CacheLimit() { GDALSetCacheMax64(std::min<int64_t>(saved, kCopyCacheBytes)); }
        ~CacheLimit() { GDALSetCacheMax64(saved); }
    } cacheLimit;
    // The COG driver builds the overviews in a temporary file first, compressed by default with ZSTD at a level
    // whose set-up alone (about 0.07 s of clearing its tables) outweighs a small raster's whole copy; LZW makes
    // that file as fast and the final file is the same.
    CPLConfigOptionSetter temporaryCompression("COG_TMP_COMPRESSION", "LZW", true);
    CPLErrorReset();
    GDALDataset* out = cog->CreateCopy(temporaryPath.c_str(), vrt, FALSE, options.List(), copyProgress,
                                       const_cast<std::function<bool(double)>*>(&progress));
    if (out == nullptr) {
        if (cancelFlag().load()) throw Cancelled();
        throw s.fail("cannot write the GeoTIFF");
    }
    CPLErrorReset();
    GDALClose(out);
    if (CPLGetLastErrorType() >= CE_Failure) throw s.fail("cannot write the GeoTIFF");
    if (s.inPlace) {
        vsi_l_offset size = 0;
        const GByte* data = VSIGetMemFileBuffer(temporaryPath.c_str(), &size, FALSE);
        if (data == nullptr) throw s.fail("cannot write the GeoTIFF");
        writeFileAtomically(s.path, std::string_view(reinterpret_cast<const char*>(data), size_t(size)));
    } else {
        if (const int failed = commitTemporary(temporary.path(), fs::path(s.path)))
            throw std::runtime_error(fmt::format("{}: cannot write ({})", s.path, std::strerror(failed)));
        temporary.release();
    }
    s.committed = true;
    GDALClose(closeVrt.ds);
    closeVrt.ds = nullptr;
    VSIRmdirRecursive(s.partial.c_str());
}

void writeGeoTiff(const std::string& path, const GridRaster& raster, RasterType type, const RasterPlacement& placement) {
    if (raster.width < 1 || raster.height < 1 || raster.bands < 1 ||
        raster.values.size() != static_cast<size_t>(raster.width) * static_cast<size_t>(raster.height) *
                                    static_cast<size_t>(raster.bands))
        throw std::invalid_argument(fmt::format("writeGeoTiff: {} x {} raster with {} bands holds {} values",
                                                raster.width, raster.height, raster.bands, raster.values.size()));
    TiledGeoTiffWriter writer(path, raster, type, placement, "whole raster", false);
    std::vector<float> tile;
    const size_t bands = size_t(raster.bands);
    for (int64_t ty = 0; ty < writer.tilesY(); ++ty)
        for (int64_t tx = 0; tx < writer.tilesX(); ++tx) {
            const TiledGeoTiffWriter::Window w = writer.window(tx, ty);
            tile.resize(size_t(w.width() * w.height()) * bands);
            for (int64_t j = w.j0; j < w.j1; ++j)
                std::copy_n(&raster.values[(size_t(j * raster.width + w.i0)) * bands], size_t(w.width()) * bands,
                            &tile[size_t((j - w.j0) * w.width()) * bands]);
            writer.write(tx, ty, tile.data());
        }
    writer.commit();
}

double sourcePixelSizeX(const GeoReference& geo) { return geo.georeferenced ? std::abs(geo.geoTransform[1]) : 1.0; }

double sourcePixelSizeY(const GeoReference& geo) { return geo.georeferenced ? std::abs(geo.geoTransform[5]) : 1.0; }

}  // namespace terracast
