// Writing rasters on a DEM's own grid as GeoTIFF (through GDAL), so they overlay the DEM exactly.
#pragma once

#include "loaders/dem_loader.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace terracast {

// What a raster file holds besides its values: its size, bands, nodata value and labels.
struct RasterLayout {
    int64_t width = 0;
    int64_t height = 0;
    int bands = 1;
    double noDataValue = 0.0;       // written as the bands' nodata value when hasNoData
    bool hasNoData = false;
    std::vector<std::string> bandDescriptions;  // one per band, or none
    std::vector<std::string> bandUnits;         // one per band ("degree", "1"), one for all bands, or none
    std::vector<std::pair<std::string, std::string>> metadata;  // the dataset's metadata items
    bool pixelIsPoint = false;      // declare AREA_OR_POINT=Point (the geotransform is written the same)
    bool lastBandIsAlpha = false;   // the last band is an alpha band (Byte RGBA: a transparent nodata mask)
};

// A single- or multi-band raster in the grid's orientation: row 0 is the SOUTHMOST row (as in HeightGrid),
// values band-interleaved by pixel (band b of pixel (i, j) at ((j * width + i) * bands + b)).
struct GridRaster : RasterLayout {
    std::vector<float> values;
};

// Sample type of the written file.
enum class RasterType { Byte, Float32 };

// A Byte sample as the writers store a value: rounded to the nearest integer and clamped to 0..255 (NaN
// becomes 0).
uint8_t rasterByte(float value);

// Where a raster lies: the CRS of `geo`, and sample (i, j) (row 0 south) centred on source-CRS position
// (originX + i * pixelSizeX, originY + j * pixelSizeY). `pixelSizeX` / `pixelSizeY` are the raster's spacing in
// source-CRS units (positive); the DEM's own spacing reproduces its grid exactly. For a DEM without a
// georeference the file gets no CRS and a plain pixel geotransform.
struct RasterPlacement {
    GeoReference geo;
    double originX = 0.0;
    double originY = 0.0;
    double pixelSizeX = 1.0;
    double pixelSizeY = 1.0;
};

// A raster written tile by tile as a Cloud Optimized GeoTIFF (docs/architecture.md, "Tiled outputs"): each
// finished tile goes to a file of its own in a folder beside the output (`NAME.partial`), and commit() turns
// the tiles into the COG (DEFLATE, 512 x 512 blocks, overviews) in a temporary file renamed over `path`. The
// whole raster is never held. The tiles outlive a failure or an interruption; a writer made with `resume`
// keeps those of an earlier writer of the same raster (the same layout, placement, type and `job`) and the
// caller computes only the others. Byte rasters clamp and round values to 0..255; NaN becomes the nodata
// value. Throws InputError for a missing or unwritable folder, a bad extension (expects .tif or .tiff) or a
// partial folder of another raster under --resume, std::runtime_error for a failed write.
class TiledGeoTiffWriter {
public:
    static constexpr int64_t kTile = 512;  // vertices along a tile's side (the COG's block size)
    static constexpr int64_t kCopyCacheBytes = int64_t{32} << 20;  // GDAL's block cache while the COG is made

    // The raster columns [i0, i1) and rows [j0, j1) (row 0 south) of a tile.
    struct Window {
        int64_t i0 = 0, j0 = 0, i1 = 0, j1 = 0;
        int64_t width() const { return i1 - i0; }
        int64_t height() const { return j1 - j0; }
    };

    // Who writes: the only writer; the leader of several processes writing one raster's tiles (it prepares the
    // partial folder, finds the tiles to keep and makes the COG); or one of the others (it only writes tiles,
    // into the folder the leader prepared, and learns the kept tiles from the leader: setFinished).
    enum class Role { Sole, Leader, Follower };

    TiledGeoTiffWriter(const std::string& path, const RasterLayout& layout, RasterType type,
                       const RasterPlacement& placement, const std::string& job, bool resume, Role role = Role::Sole);
    ~TiledGeoTiffWriter();
    TiledGeoTiffWriter(const TiledGeoTiffWriter&) = delete;
    TiledGeoTiffWriter& operator=(const TiledGeoTiffWriter&) = delete;

    // Tiles in file order: tile (tx, ty) counts from the north-west corner, ty = 0 the northmost row of tiles.
    int64_t tilesX() const;
    int64_t tilesY() const;
    Window window(int64_t tx, int64_t ty) const;
    // True for a tile kept from an earlier writer (resume) or already written.
    bool finished(int64_t tx, int64_t ty) const;
    // Per tile in file order, 1 when finished; a follower takes the leader's.
    std::vector<uint8_t> finishedMask() const;
    void setFinished(const std::vector<uint8_t>& mask);
    // Tiles kept from an earlier writer; tiles of another job found and removed (a fresh start).
    int64_t resumedTiles() const;
    int64_t discardedTiles() const;
    // The folder holding the finished tiles ("" for a device target, whose tiles live in memory).
    std::string partialFolder() const;

    // Writes tile (tx, ty) from `values`: window(tx, ty)'s samples, row 0 south, bands interleaved. Distinct
    // tiles may be written from several threads at once.
    void write(int64_t tx, int64_t ty, const float* values);

    // Makes the COG from the finished tiles (all of them) and removes the partial folder. `progress` hears the
    // share done; when it returns false the copy stops and Cancelled is thrown (the tiles stay). `threads`
    // compress the COG's blocks (0: one per core); the file's bytes do not depend on how many.
    void commit(const std::function<bool(double)>& progress = {}, int threads = 1);

private:
    struct State;
    // Makes the partial folder, or takes over the one an earlier run left: its tiles are kept (with `resume`,
    // those of the same job that GDAL can read) or removed, and job.txt is written for `jobText`.
    void preparePartialFolder(const std::string& jobText, bool resume);
    std::unique_ptr<State> s_;
};

// Writes `raster` to `path` through a TiledGeoTiffWriter (no resume). Throws as the writer does, and
// std::invalid_argument for a raster whose values do not match its size.
void writeGeoTiff(const std::string& path, const GridRaster& raster, RasterType type, const RasterPlacement& placement);

// The source-CRS spacing of the DEM's samples, |geoTransform[1]| and |geoTransform[5]| (1, 1 without one).
double sourcePixelSizeX(const GeoReference& geo);
double sourcePixelSizeY(const GeoReference& geo);

}  // namespace terracast
