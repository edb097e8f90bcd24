// Writing rasters on a DEM's own grid as GeoTIFF (through GDAL), so they overlay the DEM exactly.
#pragma once

#include "loaders/dem_loader.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace terracast {

// A single- or multi-band raster in the grid's orientation: row 0 is the SOUTHMOST row (as in HeightGrid),
// values band-interleaved by pixel (band b of pixel (i, j) at ((j * width + i) * bands + b)).
struct GridRaster {
    int64_t width = 0;
    int64_t height = 0;
    int bands = 1;
    std::vector<float> values;
    double noDataValue = 0.0;       // written as the bands' nodata value when hasNoData
    bool hasNoData = false;
    std::vector<std::string> bandDescriptions;  // one per band, or none
    std::vector<std::string> bandUnits;         // one per band ("degree", "1"), one for all bands, or none
    std::vector<std::pair<std::string, std::string>> metadata;  // the dataset's metadata items
    bool pixelIsPoint = false;      // declare AREA_OR_POINT=Point (the geotransform is written the same)
    bool lastBandIsAlpha = false;   // the last band is an alpha band (Byte RGBA: a transparent nodata mask)
};

// Sample type of the written file.
enum class RasterType { Byte, Float32 };

// Writes `raster` to `path` as a GeoTIFF (DEFLATE-compressed) with the CRS of `geo` and a geotransform in
// which sample (i, j) of the raster sits at source-CRS position (originX + i * pixelX, originY + j * pixelY)
// for the pixel centres, rows written north-up. `pixelSizeX` / `pixelSizeY` are the raster's spacing in
// source-CRS units (positive); the DEM's own spacing reproduces its grid exactly. For a DEM without a
// georeference the file gets no CRS and a plain pixel geotransform. Byte rasters clamp and round values to
// 0..255. Writes to a temporary file in the same folder and renames it; throws InputError for a missing or
// unwritable folder or a bad extension (expects .tif or .tiff), std::runtime_error for a failed write.
void writeGeoTiff(const std::string& path, const GridRaster& raster, RasterType type, const GeoReference& geo,
                  double originX, double originY, double pixelSizeX, double pixelSizeY);

// The source-CRS spacing of the DEM's samples, |geoTransform[1]| and |geoTransform[5]| (1, 1 without one).
double sourcePixelSizeX(const GeoReference& geo);
double sourcePixelSizeY(const GeoReference& geo);

}  // namespace terracast
