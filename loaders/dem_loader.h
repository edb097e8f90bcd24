// Reading elevation rasters into a HeightGrid: GDAL for GeoTIFF, SRTM .hgt and any single-band raster;
// libspng (or OpenImageIO for palettes, 1- to 4-bit grey and interlacing) for PNG height maps.
#pragma once

#include "heightfield/height_grid.h"

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace terracast {

// Where the local frame sits on the Earth. The local origin is vertex (0, 0): the south-west sample.
struct GeoReference {
    bool georeferenced = false;     // false for plain height maps (PNG)
    bool geographic = false;        // true when the source CRS is in degrees
    std::string crsName;            // short CRS name ("WGS 84", "NAD27 / UTM zone 10N"), empty if none
    std::string crsWkt;             // full WKT, empty if none
    double geoTransform[6] = {0, 1, 0, 0, 0, -1};  // GDAL geotransform of the source raster (CRS units)
    double originX = 0.0;           // source-CRS x of vertex (0, 0) (double: UTM-sized values)
    double originY = 0.0;           // source-CRS y of vertex (0, 0)
    double centreLatDeg = 0.0;      // latitude used for the metric conversion of a geographic CRS
    bool pixelIsPoint = false;      // the source declares its samples as points (AREA_OR_POINT=Point)
};

// Options for loading a DEM.
struct DemLoadOptions {
    double imageCellSizeM = 1.0;    // height maps without georeference: metres between samples
    double imageHeightScale = 1.0;  // height maps: metres per stored unit (8-bit 0..255, 16-bit 0..65535)
    double maxBytes = 0.0;          // the memory a job may use; 0 = 80% of physical memory
    // How the grid is held (docs/architecture.md, "Tiled grids"). 0: whole, when it fits in maxBytes with what
    // the process holds already, and otherwise as tiles read on demand with a cache of a quarter of the memory
    // left; above 0: as tiles, with a cache of this many bytes. PNG height maps are always held whole.
    double tileCacheBytes = 0.0;
    // Under mpirun, a load that every rank makes together (collective): a DEM held whole is read a band of rows
    // per rank and the bands are exchanged, and the ranks agree on holding it whole or as tiles. Off, each rank
    // loads on its own.
    bool sharedByRanks = false;
    // Under mpirun (more than one rank), hold a GDAL raster stored in blocks (tiled GeoTIFF, COG, VRT) as tiles
    // even when it fits, so that each rank reads only the tiles its part of the work reaches
    // (docs/architecture.md, "Ranks"); for jobs that never need the whole grid. The cache takes a quarter of
    // what the memory limit leaves (maxBytes per process; the default limit shared by the machine's ranks).
    // No effect on one rank.
    bool tilesUnderRanks = false;
    // Vertical exaggeration: every height multiplied by this factor (in float, as HeightGrid::scaleHeights
    // does), after the whole load or, for a DEM held as tiles, as each tile is read (its summary, and the
    // sidecar that keeps it, are those of the scaled heights). Positive and finite; a factor that makes a
    // height larger than kMaxExaggeratedHeightM is refused.
    double exaggeration = 1.0;
    // For a DEM held as tiles: keep each tile decoded in a store beside the DEM (loaders/tile_store.h; 2 bytes a
    // vertex for 16-bit heights in metres, else 4) and read it from there in later runs instead of decoding the
    // raster's blocks again.
    bool tileStore = false;
};

// A loaded DEM: plain data, no GDAL or OpenImageIO types.
struct LoadedDem {
    std::string path;               // as given
    std::string driver;             // "GTiff", "SRTMHGT", "PNG (OpenImageIO)", ...
    int64_t sourceWidth = 0;        // raster columns
    int64_t sourceHeight = 0;       // raster rows
    HeightGrid grid;                // heights in metres, rows flipped so that y points north
    GeoReference geo;
    std::vector<std::string> warnings;  // assumptions made while loading, one line each
};

// Loads a DEM, whole or as a tiled grid (see DemLoadOptions::tileCacheBytes). Throws InputError (one line
// naming the file and the problem) when the file is missing, not a raster, empty, holds non-finite heights, or
// has no valid cell.
LoadedDem loadDem(const std::string& path, const DemLoadOptions& options = {});

// How an array of heights lies, as loadDem finds it for a raster file of that size with this geotransform and
// CRS: the georeference, the metres between vertices, and which way the array's rows and columns run.
struct ArrayPlacement {
    GeoReference geo;
    double cellSizeXM = 1.0;
    double cellSizeYM = 1.0;
    bool flipRows = true;      // array row 0 is the north edge (a negative geotransform term 5)
    bool flipColumns = false;  // array column 0 is the east edge
    std::vector<std::string> warnings;
};

// `gt`: a GDAL geotransform; `crs`: anything GDAL's SetFromUserInput reads (WKT, "EPSG:32610", a PROJ string),
// or empty for none (metres assumed). Throws InputError naming `name`, as loadDem does for such a file.
ArrayPlacement placeArray(const std::string& name, const double gt[6], const std::string& crs, int64_t width,
                          int64_t height);

// A DEM held whole with its heights multiplied by `k`, as DemLoadOptions::exaggeration loads it; throws
// InputError for a factor it refuses or a DEM held as tiles.
LoadedDem exaggeratedDem(LoadedDem dem, double k);

// Loads a DEM held in memory (a whole file's bytes) through GDAL, as if read from a file called `name`, which
// the messages cite. Throws as loadDem does.
LoadedDem loadDemFromBytes(std::string_view bytes, const std::string& name, const DemLoadOptions& options = {});

// A DEM opened through GDAL and read a window of vertices at a time, each decoded exactly as loadDem decodes
// the whole raster (unit, scale and offset, nodata, row order): the source of tiled grids, which never hold the
// raster (docs/architecture.md, "Tiled grids"). loadDem reads GDAL rasters through it too. Reads may come from
// several threads: threads that read at once get their own opening of the raster, up to one per hardware thread.
class DemWindowReader {
public:
    // Opens the raster and checks everything but its heights, refusing what loadDem refuses (but not for its
    // size: nothing in proportion to the raster is held). Throws InputError.
    explicit DemWindowReader(const std::string& path, const DemLoadOptions& options = {});
    ~DemWindowReader();
    DemWindowReader(const DemWindowReader&) = delete;
    DemWindowReader& operator=(const DemWindowReader&) = delete;

    const std::string& path() const;
    const std::string& driver() const;
    int64_t width() const;          // vertices along x (the raster's columns)
    int64_t height() const;         // vertices along y (the raster's rows)
    double cellSizeXM() const;
    double cellSizeYM() const;
    double metresPerUnit() const;   // metres per stored unit (band scale and vertical unit)
    bool hasNodata() const;         // the band declares a nodata value
    const GeoReference& geo() const;
    const std::vector<std::string>& warnings() const;
    // The files GDAL reads for this raster (the file itself, a VRT's sources, sidecars such as .aux.xml); empty
    // when GDAL does not say (an in-memory or network source).
    std::vector<std::string> files() const;
    // The decoding of stored values as text (band type, scale, offset, unit, nodata), for cache keys.
    std::string decodingKey() const;

    // Vertices [i0, i0 + w) x [j0, j0 + h) of the grid (j northward), row-major from row j0: heights in metres
    // into `heightsM`, and into `valid` 1 per valid vertex and 0 per nodata one (whose height is then 0).
    // `valid` may be null when the band declares no nodata. Throws InputError naming the raster rows when GDAL
    // cannot read them or a height is non-finite or absurd; std::invalid_argument for a window off the grid.
    void read(int64_t i0, int64_t j0, int64_t w, int64_t h, float* heightsM, uint8_t* valid) const;
    // Whether a window is cheap to read on its own: GDAL stores band 1 in blocks narrower than its rows (tiled
    // GeoTIFF, COG) or the raster is a VRT of other files. Strips of whole rows (striped GeoTIFF, .hgt, ASCII
    // grids) are decoded in full for every window that touches them.
    bool storedInBlocks() const;
    // Whether band 1 stores 16-bit integers in metres (no scale, no offset), which readWholeMetres reads.
    bool wholeMetres() const;
    // As read, for such a band: the heights as stored (0 at nodata vertices), without conversion to float;
    // `valid` must not be null. Throws InputError as read does, std::logic_error for another band.
    void readWholeMetres(int64_t i0, int64_t j0, int64_t w, int64_t h, int16_t* metres, uint8_t* valid) const;
    // How many times GDAL has opened the raster for this reader: 1, and one more for each thread that found the
    // others' openings busy.
    int openings() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// Metres per degree of latitude and longitude on the WGS84 ellipsoid at a latitude (degrees).
struct MetresPerDegree {
    double lat;  // north-south
    double lon;  // east-west
};
MetresPerDegree metresPerDegree(double latDeg);

}  // namespace terracast
