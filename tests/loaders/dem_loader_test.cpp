// Loader tests on the real sample files. Expected figures come from `gdalinfo -stats` and from the tiles'
// published extents; pixels are cross-checked by reading them independently with GDAL and OpenImageIO.
#include "support/grid_compare.h"
#include "support/png_rasters.h"
#include "support/temp_dir.h"
#include "loaders/dem_loader.h"
#include "tracer/core/resources.h"
#include "tracer/core/errors.h"

#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

using namespace terracast;
namespace fs = std::filesystem;
using terracast::testing::TempDir;
using terracast::testing::writePng;

namespace {

std::string sample(const std::string& name) { return std::string(TERRACAST_SOURCE_DIR "/data-samples/") + name; }

const std::string kStHelens = sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
const std::string kStormLake = sample("landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
const std::string kWhiteMountains = sample("N44W072.srtm3-white-mountains-nh.hgt");
const std::string kNice = sample("srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif");
const std::string kPugetSound = sample("puget-sound-usgs-1025x1025-16bit-heightmap.png");


void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

std::string readBytes(const std::string& path, size_t count) {
    std::ifstream in(path, std::ios::binary);
    std::string bytes(count, '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(count));
    bytes.resize(static_cast<size_t>(in.gcount()));
    return bytes;
}

// One pixel of band 1 at raster (column, row), read with GDAL directly.
double gdalPixel(const std::string& path, int column, int row) {
    GDALAllRegister();
    GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(dataset);
    double value = 0.0;
    REQUIRE(dataset->GetRasterBand(1)->RasterIO(GF_Read, column, row, 1, 1, &value, 1, 1, GDT_Float64, 0, 0,
                                                nullptr) == CE_None);
    return value;
}

// A GeoTIFF description for tests: bands of row-major values, row 0 at the top of the raster.
struct TiffSpec {
    int width = 3;
    int height = 3;
    GDALDataType type = GDT_Float32;
    std::vector<std::vector<double>> bands;
    double geoTransform[6] = {500000.0, 10.0, 0.0, 4000000.0, 0.0, -10.0};
    int epsg = 32633;  // WGS 84 / UTM zone 33N; 0 for none
    bool setGeoTransform = true;
    bool hasNodata = false;
    double nodata = 0.0;
    std::string unit = "m";
    double scale = 1.0;
    double offset = 0.0;
    std::vector<std::string> creationOptions;  // e.g. TILED=YES, BLOCKYSIZE=64
};

void writeTiff(const std::string& path, const TiffSpec& spec) {
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    REQUIRE(driver != nullptr);
    const int bandCount = std::max<int>(1, static_cast<int>(spec.bands.size()));
    CPLStringList options;
    for (const auto& o : spec.creationOptions) options.AddString(o.c_str());
    GDALDatasetUniquePtr dataset(
        driver->Create(path.c_str(), spec.width, spec.height, bandCount, spec.type, options.List()));
    REQUIRE(dataset);
    if (spec.setGeoTransform) {
        double gt[6];
        std::copy(spec.geoTransform, spec.geoTransform + 6, gt);
        dataset->SetGeoTransform(gt);
    }
    if (spec.epsg != 0) {
        OGRSpatialReference srs;
        srs.importFromEPSG(spec.epsg);
        dataset->SetSpatialRef(&srs);
    }
    for (int b = 0; b < static_cast<int>(spec.bands.size()); ++b) {
        GDALRasterBand* band = dataset->GetRasterBand(b + 1);
        std::vector<double> values = spec.bands[static_cast<size_t>(b)];
        REQUIRE(values.size() == static_cast<size_t>(spec.width * spec.height));
        REQUIRE(band->RasterIO(GF_Write, 0, 0, spec.width, spec.height, values.data(), spec.width, spec.height,
                               GDT_Float64, 0, 0, nullptr) == CE_None);
        if (spec.hasNodata) band->SetNoDataValue(spec.nodata);
        band->SetUnitType(spec.unit.c_str());
        if (spec.scale != 1.0) band->SetScale(spec.scale);
        if (spec.offset != 0.0) band->SetOffset(spec.offset);
    }
}

// Rewrites the TileWidth and TileLength tags (322, 323) of a little-endian tiled TIFF's first IFD, as a damaged
// header would declare them. Returns false when the file holds no such tags.
bool patchTileSize(const std::string& path, uint32_t tileSize) {
    std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
    std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    auto u16 = [&](size_t at) { return static_cast<uint32_t>(uint8_t(bytes[at]) | uint8_t(bytes[at + 1]) << 8); };
    auto u32 = [&](size_t at) { return u16(at) | u16(at + 2) << 16; };
    if (bytes.size() < 8 || bytes.compare(0, 2, "II") != 0) return false;
    const size_t ifd = u32(4);
    int patched = 0;
    for (uint32_t k = 0, n = u16(ifd); k < n; ++k) {
        const size_t entry = ifd + 2 + 12 * size_t{k};
        const uint32_t tag = u16(entry);
        const uint32_t type = u16(entry + 2);  // 3 = SHORT, 4 = LONG
        if (tag != 322 && tag != 323) continue;
        const int width = type == 3 ? 2 : 4;
        for (int b = 0; b < width; ++b) bytes[entry + 8 + size_t(b)] = static_cast<char>(tileSize >> (8 * b));
        ++patched;
    }
    file.seekp(0);
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return patched == 2;
}

double validPercent(const HeightGrid& grid) {
    const double n = static_cast<double>(grid.width() * grid.height());
    return 100.0 * (n - static_cast<double>(grid.nodataVertexCount())) / n;
}

bool anyWarningContains(const LoadedDem& dem, const std::string& text) {
    return std::any_of(dem.warnings.begin(), dem.warnings.end(),
                       [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

// The message of the InputError that loading `path` throws; fails the test when nothing is thrown.
std::string loadError(const std::string& path, const DemLoadOptions& options = {}) {
    try {
        loadDem(path, options);
    } catch (const InputError& e) {
        return e.what();
    }
    FAIL("loading " << path << " did not throw InputError");
    return {};
}

bool oneLine(const std::string& message) { return message.find('\n') == std::string::npos; }

}  // namespace

TEST_CASE("Mt St Helens UTM GeoTIFF loads with its size, heights, nodata and origin", "[loaders]") {
    const LoadedDem dem = loadDem(kStHelens);
    const HeightGrid& grid = dem.grid;
    CHECK(dem.driver == "GTiff");
    CHECK(grid.width() == 327);
    CHECK(grid.height() == 468);
    CHECK(grid.cellSizeXM() == Approx(30.0).margin(1e-9));
    CHECK(grid.cellSizeYM() == Approx(30.0).margin(1e-9));
    CHECK(grid.minHeightM() == 682.0f);
    CHECK(grid.maxHeightM() == 2543.0f);
    CHECK(validPercent(grid) == Approx(97.29).margin(0.01));
    CHECK(dem.geo.georeferenced);
    CHECK_FALSE(dem.geo.geographic);
    CHECK_THAT(dem.geo.crsName, Catch::Contains("UTM zone 10N"));
    CHECK_FALSE(dem.geo.crsWkt.empty());
    // Vertex (0, 0) is the centre of the south-west pixel.
    CHECK(dem.geo.originX == Approx(557805.0 + 15.0).margin(1e-6));
    CHECK(dem.geo.originY == Approx(5122005.0 - 468.0 * 30.0 + 15.0).margin(1e-6));
    CHECK(dem.warnings.empty());
}

TEST_CASE("Storm Lake LANDFIRE GeoTIFF honours a positive nodata value and warns about its missing unit",
          "[loaders]") {
    const LoadedDem dem = loadDem(kStormLake);
    const HeightGrid& grid = dem.grid;
    CHECK(grid.width() == 143);
    CHECK(grid.height() == 107);
    CHECK(grid.cellSizeXM() == Approx(30.0).margin(1e-9));
    CHECK(grid.cellSizeYM() == Approx(30.0).margin(1e-9));
    CHECK(grid.minHeightM() == 2438.0f);
    CHECK(grid.maxHeightM() == 3046.0f);
    CHECK(validPercent(grid) == Approx(94.27).margin(0.01));
    CHECK(anyWarningContains(dem, "no vertical unit, assuming metres"));
}

TEST_CASE("SRTM .hgt tile is geographic, with WGS84 cell sizes at its centre latitude", "[loaders]") {
    const LoadedDem dem = loadDem(kWhiteMountains);
    const HeightGrid& grid = dem.grid;
    CHECK(dem.driver == "SRTMHGT");
    CHECK(grid.width() == 1201);
    CHECK(grid.height() == 1201);
    CHECK(grid.minHeightM() == 115.0f);
    CHECK(grid.maxHeightM() == 1908.0f);
    CHECK(grid.nodataVertexCount() == 0);
    CHECK(dem.geo.geographic);
    CHECK(dem.geo.centreLatDeg == Approx(44.5).margin(1e-9));
    CHECK(grid.cellSizeYM() == Approx(92.6).margin(0.1));
    CHECK(grid.cellSizeXM() == Approx(66.3).margin(0.1));
    // SRTM samples fall on whole degrees: the south-west sample of N44W072 is at 72 W, 44 N.
    CHECK(dem.geo.originX == Approx(-72.0).margin(1e-9));
    CHECK(dem.geo.originY == Approx(44.0).margin(1e-9));
}

TEST_CASE("Geographic GeoTIFF near Nice loads its below-sea-level heights and nodata share", "[loaders]") {
    const LoadedDem dem = loadDem(kNice);
    const HeightGrid& grid = dem.grid;
    CHECK(grid.width() == 1201);
    CHECK(grid.height() == 1201);
    CHECK(grid.minHeightM() == -11.0f);
    CHECK(grid.maxHeightM() == 2064.0f);
    CHECK(validPercent(grid) == Approx(99.89).margin(0.01));
    CHECK(dem.geo.geographic);
    CHECK(dem.geo.originX == Approx(7.0).margin(1e-9));
    CHECK(dem.geo.originY == Approx(43.0).margin(1e-9));
}

TEST_CASE("metresPerDegree matches WGS84 geodesic lengths of a degree", "[loaders]") {
    // Geodesic lengths of a 1e-4 degree arc divided by 1e-4, from GeographicLib (Karney 2013) on WGS84.
    CHECK(metresPerDegree(0.0).lat == Approx(110574.276).margin(0.01));
    CHECK(metresPerDegree(0.0).lon == Approx(111319.491).margin(0.01));
    CHECK(metresPerDegree(45.0).lat == Approx(111131.777).margin(0.01));
    CHECK(metresPerDegree(45.0).lon == Approx(78846.835).margin(0.01));
    CHECK(metresPerDegree(44.5).lat == Approx(111122.008).margin(0.01));
    CHECK(metresPerDegree(44.5).lon == Approx(79529.562).margin(0.01));
    CHECK(metresPerDegree(90.0).lon == Approx(0.0).margin(1e-6));
}

TEST_CASE("PNG height map scales raw 16-bit values and uses the given cell size", "[loaders]") {
    DemLoadOptions options;
    options.imageCellSizeM = 160.0;
    options.imageHeightScale = 0.1;
    const LoadedDem dem = loadDem(kPugetSound, options);
    const HeightGrid& grid = dem.grid;
    CHECK(dem.driver == "PNG (libspng)");
    CHECK_FALSE(dem.geo.georeferenced);
    CHECK(grid.width() == 1025);
    CHECK(grid.height() == 1025);
    CHECK(grid.cellSizeXM() == 160.0);
    CHECK(grid.cellSizeYM() == 160.0);
    CHECK(grid.minHeightM() == Approx(0.0).margin(1e-6));
    CHECK(grid.maxHeightM() == Approx(4379.8).margin(1e-3));
    CHECK(dem.warnings.empty());
}

TEST_CASE("GDAL rasters are flipped so that grid row 0 is the southmost raster row", "[loaders]") {
    const LoadedDem dem = loadDem(kStHelens);
    const int64_t h = dem.grid.height();
    for (const auto& [column, row] : {std::pair{100, 50}, std::pair{200, 400}, std::pair{160, 234}}) {
        const double raw = gdalPixel(kStHelens, column, row);
        REQUIRE(raw > 0.0);  // a valid height, so the comparison means something
        CHECK(dem.grid.at(column, h - 1 - row) == static_cast<float>(raw));
    }
    const LoadedDem srtm = loadDem(kWhiteMountains);
    CHECK(srtm.grid.at(0, 1200) == static_cast<float>(gdalPixel(kWhiteMountains, 0, 0)));
    CHECK(srtm.grid.at(1200, 0) == static_cast<float>(gdalPixel(kWhiteMountains, 1200, 1200)));
}

TEST_CASE("PNG height maps are flipped so that grid row 0 is the bottom image row", "[loaders]") {
    DemLoadOptions options;
    options.imageHeightScale = 0.1;
    const LoadedDem dem = loadDem(kPugetSound, options);

    // Every sample, decoded independently by OpenImageIO: the height is the sample times the scale, in double,
    // rounded to float, bit for bit.
    auto input = OIIO::ImageInput::open(kPugetSound);
    REQUIRE(input);
    const OIIO::ImageSpec& spec = input->spec();
    std::vector<uint16_t> raw(static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height));
    REQUIRE(input->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT16, raw.data()));
    const int64_t h = dem.grid.height();
    REQUIRE(dem.grid.width() == spec.width);
    REQUIRE(h == spec.height);
    int64_t differ = 0, positive = 0;
    for (int64_t y = 0; y < h; ++y)
        for (int64_t x = 0; x < spec.width; ++x) {
            const uint16_t stored = raw[static_cast<size_t>(y * spec.width + x)];
            positive += stored > 0;
            differ += dem.grid.at(x, h - 1 - y) != static_cast<float>(double(stored) * 0.1);
        }
    CHECK(positive > h * h / 2);
    CHECK(differ == 0);
}

TEST_CASE("PNG height maps: 8- and 16-bit grey, RGB and grey with alpha decode as OpenImageIO reads channel 0",
          "[loaders]") {
    TempDir dir;
    const int w = 67, h = 41;
    struct Case {
        const char* name;
        int bands;
        GDALDataType type;
        int top;
        std::vector<std::string> options;
        const char* driver;
        int expand;  // what the reader multiplies samples by
    };
    const Case cases[] = {
        {"grey8", 1, GDT_Byte, 254, {}, "PNG (libspng)", 1},
        {"grey16", 1, GDT_UInt16, 65534, {}, "PNG (libspng)", 1},
        {"grey-alpha8", 2, GDT_Byte, 254, {}, "PNG (libspng)", 1},
        {"rgb16", 3, GDT_UInt16, 65533, {}, "PNG (libspng)", 1},
        {"rgba8", 4, GDT_Byte, 251, {}, "PNG (libspng)", 1},
        // 4-bit grey is left to OpenImageIO, which stretches it to 8 bits (15 becomes 255).
        {"grey4", 1, GDT_Byte, 15, {"NBITS=4"}, "PNG (OpenImageIO)", 17},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        std::vector<double> samples(size_t(w * h));
        for (size_t k = 0; k < samples.size(); ++k) samples[k] = double((k * 7919 + k / w * 13) % size_t(c.top + 1));
        const std::string path = dir.file(std::string(c.name) + ".png");
        writePng(path, w, h, c.bands, c.type, samples, c.options);
        DemLoadOptions options;
        options.imageHeightScale = 0.25;
        const LoadedDem dem = loadDem(path, options);
        CHECK(dem.driver == c.driver);
        CHECK(anyWarningContains(dem, "using channel 0") == (c.bands > 1));
        // Channel 0 as stored: not multiplied by alpha, which OpenImageIO does unless asked not to.
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);
        auto input = OIIO::ImageInput::open(path, &config);
        REQUIRE(input);
        std::vector<uint8_t> raw8(size_t(w * h));
        std::vector<uint16_t> raw16(size_t(w * h));
        if (c.type == GDT_Byte) REQUIRE(input->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT8, raw8.data()));
        else REQUIRE(input->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT16, raw16.data()));
        int64_t differ = 0;
        for (int64_t y = 0; y < h; ++y)
            for (int64_t x = 0; x < w; ++x) {
                const size_t k = size_t(y * w + x);
                const double stored = c.type == GDT_Byte ? double(raw8[k]) : double(raw16[k]);
                differ += dem.grid.at(x, h - 1 - y) != static_cast<float>(stored * 0.25);
            }
        CHECK(differ == 0);
        // The samples written, as a check on the reference itself.
        CHECK(dem.grid.at(5, h - 1) == static_cast<float>(samples[5] * c.expand * 0.25));
    }
}

TEST_CASE("Synthetic GeoTIFF: pixel centres, row order, scale, offset and feet", "[loaders]") {
    TempDir dir;
    TiffSpec spec;
    spec.width = 4;
    spec.height = 3;
    spec.bands = {{0, 1, 2, 3, 100, 101, 102, 103, 200, 201, 202, 203}};  // 100 * row + column
    spec.geoTransform[0] = 1000.0;
    spec.geoTransform[1] = 10.0;
    spec.geoTransform[3] = 2000.0;
    spec.geoTransform[5] = -20.0;

    SECTION("north-up rows are flipped and the origin is the south-west pixel centre") {
        const std::string path = dir.file("north-up.tif");
        writeTiff(path, spec);
        const LoadedDem dem = loadDem(path);
        CHECK(dem.grid.cellSizeXM() == 10.0);
        CHECK(dem.grid.cellSizeYM() == 20.0);
        CHECK(dem.geo.originX == 1005.0);
        CHECK(dem.geo.originY == 1950.0);  // 2000 - 3 * 20 + 10
        CHECK(dem.grid.at(0, 0) == 200.0f);
        CHECK(dem.grid.at(3, 0) == 203.0f);
        CHECK(dem.grid.at(1, 2) == 1.0f);
        CHECK(dem.warnings.empty());
    }
    SECTION("south-up rows keep their order") {
        spec.geoTransform[5] = 20.0;
        const std::string path = dir.file("south-up.tif");
        writeTiff(path, spec);
        const LoadedDem dem = loadDem(path);
        CHECK(dem.geo.originY == 2010.0);
        CHECK(dem.grid.at(0, 0) == 0.0f);
        CHECK(dem.grid.at(2, 1) == 102.0f);
    }
    SECTION("scale, offset and a unit in feet give metres") {
        spec.scale = 0.5;
        spec.offset = 10.0;
        spec.unit = "ft";
        const std::string path = dir.file("feet.tif");
        writeTiff(path, spec);
        const LoadedDem dem = loadDem(path);
        CHECK(dem.grid.at(1, 2) == Approx((1 * 0.5 + 10.0) * 0.3048).epsilon(1e-6));
        CHECK(dem.grid.at(3, 0) == Approx((203 * 0.5 + 10.0) * 0.3048).epsilon(1e-6));
        CHECK(anyWarningContains(dem, "feet"));
    }
    SECTION("US survey feet") {
        spec.unit = "US survey foot";
        const std::string path = dir.file("us-feet.tif");
        writeTiff(path, spec);
        const LoadedDem dem = loadDem(path);
        CHECK(dem.grid.at(3, 0) == Approx(203.0 * 1200.0 / 3937.0).epsilon(1e-6));
    }
    SECTION("a raster without CRS is taken to be in metres, with a warning") {
        spec.epsg = 0;
        const std::string path = dir.file("no-crs.tif");
        writeTiff(path, spec);
        const LoadedDem dem = loadDem(path);
        CHECK(dem.grid.cellSizeXM() == 10.0);
        CHECK(anyWarningContains(dem, "no CRS, assuming metres"));
    }
    SECTION("a rotated geotransform is refused") {
        spec.geoTransform[2] = 0.5;
        const std::string path = dir.file("rotated.tif");
        writeTiff(path, spec);
        const std::string message = loadError(path);
        CHECK_THAT(message, Catch::Contains(path) && Catch::Contains("rotated"));
    }
}

TEST_CASE("A geographic raster spanning many degrees warns about the tangent-plane approximation", "[loaders]") {
    TempDir dir;
    TiffSpec spec;
    spec.bands = {{1, 2, 3, 4, 5, 6, 7, 8, 9}};
    spec.epsg = 4326;
    const double gt[6] = {0.0, 4.0, 0.0, 3.0, 0.0, -2.0};  // 12 x 6 degrees around latitude 0
    std::copy(gt, gt + 6, spec.geoTransform);
    const std::string path = dir.file("large.tif");
    writeTiff(path, spec);
    const LoadedDem dem = loadDem(path);
    CHECK(dem.geo.centreLatDeg == Approx(0.0));
    CHECK(anyWarningContains(dem, "tangent-plane"));
    CHECK(dem.grid.cellSizeXM() == Approx(4.0 * metresPerDegree(0.0).lon));
}

TEST_CASE("A geographic raster too tall for one local frame is refused with the way to reproject it",
          "[loaders]") {
    TempDir dir;
    TiffSpec spec;
    spec.bands = {{1, 2, 3, 4, 5, 6, 7, 8, 9}};
    spec.epsg = 4326;
    // 12 x 12 degrees around 44 N, 9 E: at 50 N a cell is cos(50) / cos(44) = 0.894 of the frame's width.
    const double gt[6] = {3.0, 4.0, 0.0, 50.0, 0.0, -4.0};
    std::copy(gt, gt + 6, spec.geoTransform);
    const std::string path = dir.file("mosaic.tif");
    writeTiff(path, spec);
    const std::string message = loadError(path);
    CHECK_THAT(message, Catch::Contains(path) && Catch::Contains("too tall for one local metre frame") &&
                            Catch::Contains("10.6 % off") && Catch::Contains("gdalwarp -t_srs EPSG:32632"));
    // A one-degree tile at 79 N is still held (4.6 % at its edges).
    const double tile[6] = {10.0, 1.0 / 3.0, 0.0, 79.5, 0.0, -1.0 / 3.0};
    std::copy(tile, tile + 6, spec.geoTransform);
    writeTiff(dir.file("svalbard.tif"), spec);
    CHECK(loadDem(dir.file("svalbard.tif")).grid.width() == 3);
}

TEST_CASE("A multi-band GeoTIFF uses band 1 and says so", "[loaders]") {
    TempDir dir;
    TiffSpec spec;
    spec.bands = {{1, 2, 3, 4, 5, 6, 7, 8, 9}, std::vector<double>(9, 50.0), std::vector<double>(9, -5.0)};
    const std::string path = dir.file("three-bands.tif");
    writeTiff(path, spec);
    const LoadedDem dem = loadDem(path);
    CHECK(dem.grid.minHeightM() == 1.0f);
    CHECK(dem.grid.maxHeightM() == 9.0f);
    CHECK(dem.grid.at(0, 2) == 1.0f);
    CHECK(anyWarningContains(dem, "3 bands, using band 1"));
}

TEST_CASE("Unreadable inputs throw one-line InputErrors naming the file", "[loaders]") {
    TempDir dir;
    std::string path;
    SECTION("missing file") {
        path = dir.file("missing.tif");
        CHECK_THAT(loadError(path), Catch::Contains("no such file"));
    }
    SECTION("directory") {
        path = dir.file("folder.tif");
        fs::create_directory(path);
        CHECK_THAT(loadError(path), Catch::Contains("directory"));
    }
    SECTION("empty file") {
        path = dir.file("empty.tif");
        writeBytes(path, "");
        CHECK_THAT(loadError(path), Catch::Contains("empty"));
    }
    SECTION("text file") {
        path = dir.file("notes.txt");
        writeBytes(path, "this is not a raster\nat all\n");
        CHECK_THAT(loadError(path), Catch::Contains("not a raster"));
    }
    SECTION("truncated GeoTIFF") {
        path = dir.file("truncated.tif");
        writeBytes(path, readBytes(kStHelens, 1000));
    }
    SECTION("truncated PNG") {
        path = dir.file("truncated.png");
        writeBytes(path, readBytes(kPugetSound, 1000));
        CHECK_THAT(loadError(path), Catch::Contains("truncated PNG"));
    }
    SECTION("PNG missing only its last bytes") {
        path = dir.file("no-iend.png");
        writeBytes(path, readBytes(kPugetSound, static_cast<size_t>(fs::file_size(kPugetSound)) - 6));
        CHECK_THAT(loadError(path), Catch::Contains("truncated PNG"));
    }
    SECTION("text file named .png") {
        path = dir.file("fake.png");
        writeBytes(path, "not a png");
    }
    SECTION("1 x 1 GeoTIFF") {
        path = dir.file("one-pixel.tif");
        TiffSpec spec;
        spec.width = 1;
        spec.height = 1;
        spec.bands = {{42.0}};
        writeTiff(path, spec);
        CHECK_THAT(loadError(path), Catch::Contains("1 x 1") && Catch::Contains("2 x 2"));
    }
    SECTION("NaN height without nodata") {
        path = dir.file("nan.tif");
        TiffSpec spec;
        spec.bands = {{1, 2, 3, 4, 5, std::numeric_limits<double>::quiet_NaN(), 7, 8, 9}};
        writeTiff(path, spec);
        CHECK_THAT(loadError(path), Catch::Contains("NaN") && Catch::Contains("column 2, row 1"));
    }
    SECTION("every vertex nodata") {
        path = dir.file("all-nodata.tif");
        TiffSpec spec;
        spec.bands = {std::vector<double>(9, -9999.0)};
        spec.hasNodata = true;
        spec.nodata = -9999.0;
        writeTiff(path, spec);
        CHECK_THAT(loadError(path), Catch::Contains("every vertex is nodata"));
    }
    SECTION("GeoTIFF header declaring absurd tiles") {
        // A 20 x 20 raster claiming 32768 x 32768 int16 tiles: GDAL would allocate 2 GiB for the first tile.
        path = dir.file("huge-tiles.tif");
        GDALAllRegister();
        GDALDatasetUniquePtr dataset(GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
            path.c_str(), 20, 20, 1, GDT_Int16,
            std::vector<const char*>{"TILED=YES", "BLOCKXSIZE=16", "BLOCKYSIZE=16", nullptr}.data()));
        REQUIRE(dataset);
        std::vector<int16_t> values(400, 7);
        REQUIRE(dataset->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 20, 20, values.data(), 20, 20, GDT_Int16, 0, 0,
                                                    nullptr) == CE_None);
        dataset.reset();
        // The raster with its real 16 x 16 tiles loads.
        CHECK(loadDem(path).grid.at(3, 3) == 7.0f);
        REQUIRE(patchTileSize(path, 32768));
        CHECK_THAT(loadError(path), Catch::Contains("blocks of 32768 x 32768 samples (2.00 GiB each)") &&
                                        Catch::Contains("20 x 20 raster") && Catch::Contains("at most 64.0 MiB") &&
                                        Catch::Contains("damaged header"));
        // When the limit leaves less than 64 MiB beside what the process holds, that room is what the block is
        // held against, and the limit is named.
        DemLoadOptions tight;
        tight.maxBytes = currentResidentBytes() + 16.0 * 1024 * 1024;
        CHECK_THAT(loadError(path, tight), Catch::Contains("MiB (the memory limit, --max-memory)") &&
                                               !Catch::Contains("at most 64.0 MiB"));
    }
    SECTION("raster too large to hold") {
        // A VRT declares any size without storing pixels.
        path = dir.file("huge.vrt");
        writeBytes(path, "<VRTDataset rasterXSize=\"800000\" rasterYSize=\"800000\">\n"
                         "  <VRTRasterBand dataType=\"Float32\" band=\"1\"/>\n"
                         "</VRTDataset>\n");
        // 6.4e11 vertices: more than even tiles hold, refused from the header alone.
        CHECK_THAT(loadError(path), Catch::Contains("800000 x 800000 raster holds 6.4e+11 samples") &&
                                        Catch::Contains("even as tiles"));
        // A small DEM under an explicit limit below its need, which leaves too little for a tile cache, is
        // refused too, naming the limit and both needs.
        DemLoadOptions tight;
        tight.maxBytes = 1024.0 * 1024.0;
        const std::string small = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
        CHECK_THROWS_WITH(loadDem(small, tight), Catch::Contains("327 x 468 raster needs about 1.7 MiB") &&
                                                     Catch::Contains("more than the 1.0 MiB limit (--max-memory)") &&
                                                     Catch::Contains("less than the 16.0 MiB it needs"));
        // Asked for tiles, it is held as tiles, whatever its size and the limit.
        tight.maxBytes = currentResidentBytes() + 1.0 * 1024 * 1024 * 1024;
        DemLoadOptions tiles = tight;
        tiles.tileCacheBytes = 1 << 20;
        CHECK(loadDem(small, tiles).grid.tiled());
        // The limit counts what the process holds already (this test runner's own memory) plus the grid.
        tight.maxBytes = currentResidentBytes() + 64.0 * 1024.0 * 1024.0;
        CHECK_NOTHROW(loadDem(small, tight));
    }
    const std::string message = loadError(path);
    CHECK_THAT(message, Catch::Contains(path));
    CHECK(oneLine(message));
}

TEST_CASE("NaN nodata marks vertices invalid instead of failing", "[loaders]") {
    TempDir dir;
    TiffSpec spec;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    spec.width = 4;
    spec.bands = {{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, nan}};
    spec.hasNodata = true;
    spec.nodata = nan;
    const std::string path = dir.file("nan-nodata.tif");
    writeTiff(path, spec);
    const LoadedDem dem = loadDem(path);
    CHECK(dem.grid.nodataVertexCount() == 1);
    CHECK_FALSE(dem.grid.vertexValid(3, 0));  // raster row 2 is the south row
    CHECK(dem.grid.validCellCount() == 5);
    CHECK(dem.grid.maxHeightM() == 11.0f);
}

namespace {

// A zlib stream that inflates to 1 + 258 * matches zero bytes in a few bits per 258: one fixed-Huffman deflate
// block (RFC 1951) of a literal 0 and `matches` copies of length 258 at distance 1, then the Adler-32 of the
// zeros (RFC 1950).
std::string zeroBomb(int64_t matches) {
    std::string out = "\x78\x01";
    uint32_t bits = 0;
    int count = 0;
    auto put = [&](uint32_t value, int n) {  // least significant bit first
        for (int k = 0; k < n; ++k) {
            bits |= ((value >> k) & 1u) << count;
            if (++count == 8) {
                out += char(bits);
                bits = 0;
                count = 0;
            }
        }
    };
    auto code = [&](uint32_t value, int n) {  // Huffman codes go most significant bit first
        for (int k = n - 1; k >= 0; --k) put((value >> k) & 1u, 1);
    };
    put(1, 1);                  // the last block
    put(1, 2);                  // fixed Huffman codes
    code(0x30, 8);              // literal 0
    for (int64_t m = 0; m < matches; ++m) {
        code(0xC5, 8);          // length 258 (symbol 285)
        code(0, 5);             // distance 1 (code 0)
    }
    code(0, 7);                 // end of block (symbol 256)
    if (count > 0) out += char(bits);
    const uint64_t n = 1 + 258 * uint64_t(matches);
    const uint32_t a = 1, b = uint32_t(n % 65521);  // Adler-32 of n zero bytes
    const uint32_t adler = b << 16 | a;
    for (int s = 24; s >= 0; s -= 8) out += char((adler >> s) & 0xff);
    return out;
}

uint32_t crc32Of(const std::string& bytes) {
    uint32_t crc = 0xffffffffu;
    for (unsigned char c : bytes) {
        crc ^= c;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

}  // namespace

TEST_CASE("A PNG height map whose text chunk inflates to 256 MiB loads without inflating it", "[loaders]") {
    // A zTXt chunk of under 2 MB that inflates to 256 MiB, right after the header: libspng stops at its bounds on
    // ancillary chunks, and the map is read through OpenImageIO, whose libpng skips the chunk.
    std::ifstream in(kPugetSound, std::ios::binary);
    std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string body = "zTXt" + std::string("Comment") + '\0' + '\0' + zeroBomb((int64_t(256) << 20) / 258);
    std::string chunk;
    const auto length = uint32_t(body.size() - 4);
    for (int s = 24; s >= 0; s -= 8) chunk += char((length >> s) & 0xff);
    chunk += body;
    const uint32_t crc = crc32Of(body);
    for (int s = 24; s >= 0; s -= 8) chunk += char((crc >> s) & 0xff);
    png.insert(33, chunk);  // after the signature (8 bytes) and IHDR (25)
    REQUIRE(chunk.size() < (size_t(2) << 20));
    TempDir dir;
    const std::string path = dir.file("bomb.png");
    writeBytes(path, png);
    const double before = peakResidentBytes();
    DemLoadOptions options;
    const LoadedDem dem = loadDem(path, options);
    CHECK(dem.grid.width() == 1025);
    CHECK(dem.driver == "PNG (OpenImageIO)");
    CHECK(peakResidentBytes() - before < 64.0 * 1024 * 1024);
}

// The loader's direct path for 16-bit integer rasters in metres (codes read straight into the grid's int16
// storage, band by band of whole storage blocks, without a float copy) against GDAL's own reading of every
// sample, and against the float path's grid for the same heights (a Float32 copy of the raster): the same
// heights, validity, storage and pyramid, bit for bit.
TEST_CASE("16-bit DEMs load straight into codes: every vertex as GDAL reads it, and the float path's grid",
          "[loaders]") {
    TempDir dir("int16-codes");
    // A tiled raster read in two bands (the loader's bands hold about 2^21 samples in whole blocks: 960 rows of
    // 2100, then 140), its height no multiple of its 64-row blocks, with nodata holes, negative heights and a row
    // of nodata; and the int16 samples.
    const std::string tiled = (dir.path() / "tiled.tif").string();
    {
        TiffSpec spec;
        spec.width = 2100;
        spec.height = 1100;
        spec.type = GDT_Int16;
        spec.hasNodata = true;
        spec.nodata = -9999;
        spec.creationOptions = {"TILED=YES", "BLOCKXSIZE=64", "BLOCKYSIZE=64", "COMPRESS=DEFLATE"};
        std::vector<double> values(size_t(spec.width) * spec.height);
        uint32_t state = 7;
        for (size_t k = 0; k < values.size(); ++k) {
            state = state * 1664525u + 1013904223u;
            const int64_t row = int64_t(k) / spec.width;
            values[k] = (state >> 28) == 0 || row == 777 ? -9999.0 : double(int(state >> 17) % 3000 - 400);
        }
        spec.bands = {values};
        writeTiff(tiled, spec);
    }
    for (const std::string& path : {tiled, kStHelens, kStormLake, kWhiteMountains, kNice}) {
        INFO(path);
        REQUIRE(DemWindowReader(path).wholeMetres());  // the direct path is the one taken
        const HeightGrid grid = loadDem(path).grid;
        // Every sample as GDAL reads it: grid row j is raster row height - 1 - j (these rasters run north to south).
        GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        REQUIRE(dataset);
        GDALRasterBand* band = dataset->GetRasterBand(1);
        const int W = dataset->GetRasterXSize(), H = dataset->GetRasterYSize();
        std::vector<int32_t> raw(size_t(W) * H);
        REQUIRE(band->RasterIO(GF_Read, 0, 0, W, H, raw.data(), W, H, GDT_Int32, 0, 0, nullptr) == CE_None);
        int hasNodata = 0;
        const double nodata = band->GetNoDataValue(&hasNodata);
        REQUIRE(grid.width() == W);
        REQUIRE(grid.height() == H);
        int64_t wrong = 0, holes = 0;
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const int32_t value = raw[size_t(H - 1 - j) * W + i];
                const bool valid = !(hasNodata && double(value) == nodata);
                holes += valid ? 0 : 1;
                wrong += grid.vertexValid(i, j) != valid || (valid && grid.at(i, j) != float(value));
            }
        CHECK(wrong == 0);
        CHECK(grid.nodataVertexCount() == holes);
        if (path == tiled) CHECK(holes > W);
        // The float path's grid from a Float32 copy of the same samples.
        const std::string copy = (dir.path() / "float.tif").string();
        {
            GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
            GDALDatasetUniquePtr out(gtiff->Create(copy.c_str(), W, H, 1, GDT_Float32, nullptr));
            double gt[6];
            REQUIRE(dataset->GetGeoTransform(gt) == CE_None);
            out->SetGeoTransform(gt);
            out->SetSpatialRef(dataset->GetSpatialRef());
            std::vector<float> values(raw.begin(), raw.end());
            REQUIRE(out->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, W, H, values.data(), W, H, GDT_Float32, 0, 0,
                                                    nullptr) == CE_None);
            if (hasNodata) out->GetRasterBand(1)->SetNoDataValue(nodata);
            if (band->GetUnitType() && *band->GetUnitType()) out->GetRasterBand(1)->SetUnitType(band->GetUnitType());
        }
        REQUIRE_FALSE(DemWindowReader(copy).wholeMetres());
        const HeightGrid reference = loadDem(copy).grid;
        CHECK(grid.storage() == reference.storage());
        CHECK(grid.codeOffset() == reference.codeOffset());
        CHECK(grid.codeScale() == reference.codeScale());
        CHECK(grid.minHeightM() == reference.minHeightM());
        CHECK(grid.maxHeightM() == reference.maxHeightM());
        CHECK(grid.validCellCount() == reference.validCellCount());
        CHECK(grid.memoryBytes() == reference.memoryBytes());
        int64_t differ = 0;
        for (int64_t j = 0; j < H; ++j)
            for (int64_t i = 0; i < W; ++i)
                differ += std::bit_cast<uint32_t>(grid.at(i, j)) != std::bit_cast<uint32_t>(reference.at(i, j));
        REQUIRE(grid.pyramidLevels() == reference.pyramidLevels());
        differ += terracast::testing::pyramidDifferences(grid, reference);
        CHECK(differ == 0);
        fs::remove(copy);
    }
}
