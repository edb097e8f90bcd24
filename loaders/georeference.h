// Where a GDAL raster lies: its geotransform and CRS read into a GeoReference, and the metric lattice its samples
// form (cell sizes in metres, which way rows and columns run), with the band's vertical unit. Used by the DEM
// loader (dem_loader.cpp) for whole loads, tiled reads and in-memory rasters alike.
#pragma once

#include "loaders/dem_loader.h"

#include <cstdint>
#include <string>
#include <vector>

class GDALDataset;
class OGRSpatialReference;

namespace terracast {

// Metres per stored unit of a band, and the warning that states any assumption or conversion.
struct VerticalUnit {
    double metresPerUnit = 1.0;
    std::string warning;  // empty when the unit is metres
};

// Interprets a band's unit type ("m", "ft", "US survey foot", ...); an empty or unknown unit means metres.
VerticalUnit verticalUnit(const std::string& path, const std::string& unitType);

// How raster pixels map onto the metric lattice.
struct Lattice {
    double cellSizeXM = 1.0;
    double cellSizeYM = 1.0;
    bool flipRows = true;      // raster row 0 is the north edge
    bool flipColumns = false;  // raster column 0 is the east edge
};

// True for the identity transform GDAL reports for rasters without georeferencing.
bool isDefaultGeoTransform(const double gt[6]);

// A width x height raster's geotransform and CRS (null or empty: none) into `geo`, and its metric lattice.
// Throws InputError naming `path` for a geotransform or CRS it cannot place (rotated, non-finite, polar, or a
// geographic raster too tall for one local metre frame).
Lattice placeRaster(const std::string& path, const double gt[6], const OGRSpatialReference* srs, int64_t width,
                    int64_t height, GeoReference& geo, std::vector<std::string>& warnings);

// Reads the dataset's geotransform and CRS into `geo` and returns the metric lattice (a raster without a
// geotransform is a picture of options.imageCellSizeM cells).
Lattice georeference(const std::string& path, GDALDataset& dataset, const DemLoadOptions& options,
                     GeoReference& geo, std::vector<std::string>& warnings);

}  // namespace terracast
