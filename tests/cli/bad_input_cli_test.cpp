// Hostile inputs and outputs through the real executable: each is refused with exactly one line on stderr that
// names the file and the problem, exit code 2 for bad input and 1 for a runtime failure, and no output (nor a
// temporary file) left behind. The bad files are made here, with GDAL or by cutting the sample files.
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
const std::string kStHelens = kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
const std::string kPugetSound = kSamples + "puget-sound-usgs-1025x1025-16bit-heightmap.png";

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

// A single-band Float32 GeoTIFF of `width` x `height` values (row 0 at the top), in UTM zone 33N unless
// `epsg` says otherwise, with 10 m pixels from `west`, `north` (CRS units).
void writeTiff(const fs::path& path, int width, int height, const std::vector<double>& values, int epsg = 32633,
               double west = 500000.0, double north = 4000000.0, double pixel = 10.0,
               std::optional<double> nodata = std::nullopt) {
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    REQUIRE(driver != nullptr);
    GDALDatasetUniquePtr dataset(driver->Create(path.c_str(), width, height, 1, GDT_Float32, nullptr));
    REQUIRE(dataset);
    double gt[6] = {west, pixel, 0.0, north, 0.0, -pixel};
    dataset->SetGeoTransform(gt);
    OGRSpatialReference srs;
    srs.importFromEPSG(epsg);
    dataset->SetSpatialRef(&srs);
    GDALRasterBand* band = dataset->GetRasterBand(1);
    band->SetUnitType("m");
    if (nodata) band->SetNoDataValue(*nodata);
    std::vector<double> copy = values;
    REQUIRE(band->RasterIO(GF_Write, 0, 0, width, height, copy.data(), width, height, GDT_Float64, 0, 0, nullptr) ==
            CE_None);
}

std::vector<double> ramp(int count) {
    std::vector<double> v(static_cast<size_t>(count));
    for (int k = 0; k < count; ++k) v[static_cast<size_t>(k)] = 100.0 + k;
    return v;
}

std::set<std::string> entries(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

// Runs `terracast <command> DEM -o OUT ...` and checks the refusal: the exit code, stderr being exactly
// "terracast: error: <message>" on one line, and the folder holding what it held before (no output, no
// temporary file).
void expectRefused(const TempDir& dir, const std::string& args, int exitCode, const std::string& message) {
    const std::set<std::string> before = entries(dir.path());
    const CommandResult r = runTerracast(args);
    INFO("terracast " << args);
    CHECK(r.exitCode == exitCode);
    CHECK(r.err == "terracast: error: " + message + "\n");
    CHECK(lineCount(r.err) == 1);
    CHECK(entries(dir.path()) == before);
}

// `render DEM -o DIR/out.png` at a small size, as the shell reads it.
std::string render(const std::string& dem, const TempDir& dir) {
    return "render '" + dem + "' -o '" + dir.file("out.png") + "' --size 32x24 --threads 1";
}

}  // namespace

TEST_CASE("Bad input: a directory given as the DEM", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("folder.tif");
    fs::create_directory(dem);
    expectRefused(dir, render(dem, dir), 2, dem + ": is a directory");
}

TEST_CASE("Bad input: an empty file", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("empty.tif");
    writeBytes(dem, "");
    expectRefused(dir, render(dem, dir), 2, dem + ": file is empty");
}

TEST_CASE("Bad input: a truncated GeoTIFF", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("truncated.tif");
    writeBytes(dem, slurp(kStHelens).substr(0, 1000));  // the header survives, the tiles do not
    expectRefused(dir, render(dem, dir), 2,
                  dem + ": cannot read rows 0..467 of band 1 (" + dem +
                      ", band 1: IReadBlock failed at X offset 0, Y offset 0: TIFFReadEncodedTile() failed.)");
}

TEST_CASE("Bad input: a truncated PNG", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("truncated.png");
    writeBytes(dem, slurp(kPugetSound).substr(0, 1000));
    expectRefused(dir, render(dem, dir), 2,
                  dem + ": truncated PNG (IDAT chunk at byte 33 ends at byte 8237, file has 1000)");
}

TEST_CASE("Bad input: a PNG with a corrupted signature", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("signature.png");
    std::string bytes = slurp(kPugetSound);
    bytes[1] = 'X';  // "\x89XNG..."
    writeBytes(dem, bytes);
    expectRefused(dir, render(dem, dir), 2, dem + ": not a PNG file (its first 8 bytes are not the PNG signature)");
}

TEST_CASE("Bad input: a PNG whose data does not decompress is one line naming the file", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("idat.png");
    std::string bytes = slurp(kPugetSound);
    // Overwrite the first IDAT chunk's zlib header (at byte 41: signature 8, IHDR 25, IDAT length and type 8)
    // and fix nothing else: the chunk walk passes, decoding fails.
    bytes[41] = 0x00;
    bytes[42] = 0x00;
    writeBytes(dem, bytes);
    const CommandResult r = runTerracast(render(dem, dir));
    CHECK(r.exitCode == 2);
    CHECK(lineCount(r.err) == 1);
    CHECK(r.err.rfind("terracast: error: " + dem + ": cannot read PNG (IDAT stream error)", 0) == 0);
    CHECK_FALSE(fs::exists(dir.file("out.png")));
}

TEST_CASE("Bad input: a multi-band RGB image is read as band 1, with a warning that says so", "[cli][bad-input]") {
    // The documented rule (README, "Reliability"): the first band of a multi-band raster is the elevation.
    TempDir dir("bad-input");
    const std::string dem = dir.file("rgb.tif");
    GDALAllRegister();
    {
        GDALDatasetUniquePtr rgb(GetGDALDriverManager()->GetDriverByName("GTiff")->Create(dem.c_str(), 8, 6, 3, GDT_Byte,
                                                                                          nullptr));
        REQUIRE(rgb);
        for (int b = 1; b <= 3; ++b) {
            std::vector<uint8_t> values(48);
            for (size_t k = 0; k < values.size(); ++k) values[k] = static_cast<uint8_t>(b * 40 + k);
            REQUIRE(rgb->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, 8, 6, values.data(), 8, 6, GDT_Byte, 0, 0,
                                                    nullptr) == CE_None);
        }
    }
    const CommandResult r = runTerracast(render(dem, dir));
    CHECK(r.exitCode == 0);
    CHECK(r.err.find("terracast: warning: " + dem + ": 3 bands, using band 1 as elevation\n") != std::string::npos);
    CHECK(fs::exists(dir.file("out.png")));
}

TEST_CASE("Bad input: a 0 x 0 raster", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("zero.png");
    // The PNG signature and an IHDR chunk declaring 0 x 0 (16-bit grey), with its CRC, then IEND.
    const std::string png("\x89PNG\r\n\x1a\n"
                          "\x00\x00\x00\x0dIHDR\x00\x00\x00\x00\x00\x00\x00\x00\x10\x00\x00\x00\x00\x4e\x70\xff\x8d"
                          "\x00\x00\x00\x00IEND\xae\x42\x60\x82",
                          8 + 25 + 12);
    writeBytes(dem, png);
    expectRefused(dir, render(dem, dir), 2, dem + ": raster is 0 x 0, with no sample to trace");
}

TEST_CASE("Bad input: a 1 x 1 raster", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("one.tif");
    writeTiff(dem, 1, 1, {42.0});
    expectRefused(dir, render(dem, dir), 2, dem + ": 1 x 1 raster has no cell to trace (need at least 2 x 2)");
}

TEST_CASE("Bad input: a header claiming 10^6 x 10^6 samples is refused before any allocation", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("huge.vrt");
    // A VRT declares a size without storing a pixel.
    writeBytes(dem, "<VRTDataset rasterXSize=\"1000000\" rasterYSize=\"1000000\">\n"
                    "  <VRTRasterBand dataType=\"Float32\" band=\"1\"/>\n</VRTDataset>\n");
    const CommandResult r = runTerracast(render(dem, dir) + " --max-memory 8G");
    CHECK(r.exitCode == 2);
    CHECK(lineCount(r.err) == 1);
    // Beyond what even tiles hold: opening it would stream 10^12 samples.
    CHECK(r.err == "terracast: error: " + dem +
                       ": 1000000 x 1000000 raster holds 1e+12 samples, more than the 5.5e+11 (2^39) terracast traces, "
                       "even as tiles\n");
    CHECK(dir.entryCount() == 1);  // the VRT alone
}

TEST_CASE("Bad input: a DEM where every vertex is nodata", "[cli][bad-input]") {
    TempDir dir("bad-input");
    const std::string dem = dir.file("all-nodata.tif");
    writeTiff(dem, 4, 3, std::vector<double>(12, -9999.0), 32633, 500000.0, 4000000.0, 10.0, -9999.0);
    expectRefused(dir, render(dem, dir), 2, dem + ": every vertex is nodata");
}

TEST_CASE("Bad input: NaN and infinite heights", "[cli][bad-input]") {
    TempDir dir("bad-input");
    std::vector<double> values = ramp(12);
    values[6] = std::numeric_limits<double>::quiet_NaN();  // column 2, row 1 of a 4 x 3 raster
    const std::string nan = dir.file("nan.tif");
    writeTiff(nan, 4, 3, values);
    values[6] = 7.0;
    values[9] = std::numeric_limits<double>::infinity();  // column 1, row 2
    const std::string inf = dir.file("inf.tif");
    writeTiff(inf, 4, 3, values);
    values[9] = -std::numeric_limits<double>::infinity();
    const std::string minusInf = dir.file("minus-inf.tif");
    writeTiff(minusInf, 4, 3, values);
    expectRefused(dir, render(nan, dir), 2, nan + ": height at column 2, row 1 is NaN (not declared as nodata)");
    expectRefused(dir, render(inf, dir), 2, inf + ": height at column 1, row 2 is infinite (not declared as nodata)");
    expectRefused(dir, render(minusInf, dir), 2,
                  minusInf + ": height at column 1, row 2 is minus infinite (not declared as nodata)");
}

TEST_CASE("Bad input: absurd heights (1e30 m)", "[cli][bad-input]") {
    TempDir dir("bad-input");
    std::vector<double> values = ramp(12);
    values[11] = 1e30;  // column 3, row 2
    const std::string dem = dir.file("absurd.tif");
    writeTiff(dem, 4, 3, values);
    expectRefused(dir, render(dem, dir), 2,
                  dem + ": height at column 3, row 2 is 1e+30 m, expected within 1e+06 m of sea level (wrong unit or "
                        "scale, or an undeclared nodata value?)");
}

TEST_CASE("Bad input: a geographic DEM spanning the poles", "[cli][bad-input]") {
    TempDir dir("bad-input");
    // 36 x 19 pixels of 10 degrees from 180 W, 95 N: latitudes -95 .. 95.
    const std::string dem = dir.file("poles.tif");
    writeTiff(dem, 36, 19, ramp(36 * 19), 4326, -180.0, 95.0, 10.0);
    const std::string message = ": latitudes -95 .. 95 reach or cross a pole, which a local metric frame cannot hold; "
                                "expected a raster within -90..90 degrees (reproject polar data first, e.g. gdalwarp "
                                "-t_srs EPSG:3413 or EPSG:3031)";
    expectRefused(dir, render(dem, dir), 2, dem + message);
    // A global DEM whose edges sit exactly on the poles is refused too.
    const std::string global = dir.file("global.tif");
    writeTiff(global, 36, 18, ramp(36 * 18), 4326, -180.0, 90.0, 10.0);
    const CommandResult r = runTerracast(render(global, dir));
    CHECK(r.exitCode == 2);
    CHECK(r.err.find(global + ": latitudes -90 .. 90 reach or cross a pole") != std::string::npos);
}

TEST_CASE("Bad output: an unwritable output folder", "[cli][bad-input]") {
    TempDir dir("bad-output");
    if (::geteuid() == 0) {
        // Permission bits do not stop root; /proc takes no new file from anyone.
        const CommandResult r = runTerracast("render '" + kStHelens + "' -o /proc/terracast-out.png --size 32x24");
        CHECK(r.exitCode == 2);
        CHECK(r.err == "terracast: error: /proc/terracast-out.png: folder '/proc' is not writable (No such file or "
                       "directory)\n");
        return;
    }
    const fs::path locked = dir.path() / "locked";
    fs::create_directory(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    const std::string out = (locked / "out.png").string();
    const CommandResult r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --size 32x24");
    CHECK(r.exitCode == 2);
    CHECK(r.err == "terracast: error: " + out + ": folder '" + locked.string() + "' is not writable (Permission denied)\n");
    fs::permissions(locked, fs::perms::owner_all);
    CHECK(fs::is_empty(locked));
}

TEST_CASE("Bad output: the output path is the input DEM", "[cli][bad-input]") {
    TempDir dir("bad-output");
    const std::string png = dir.file("dem.png"), tif = dir.file("dem.tif");
    fs::copy_file(kPugetSound, png);
    fs::copy_file(kStHelens, tif);
    expectRefused(dir, "render '" + png + "' -o '" + png + "' --size 32x24", 2,
                  png + ": output path is the input DEM; refusing to overwrite it");
    // The same file under another spelling, and a map view whose format (.tif) the input shares.
    expectRefused(dir, "render '" + tif + "' -o '" + dir.path().string() + "/./dem.tif' --view map", 2,
                  dir.path().string() + "/./dem.tif: output path is the input DEM; refusing to overwrite it");
    CHECK(slurp(png) == slurp(kPugetSound));
    CHECK(slurp(tif) == slurp(kStHelens));
}

TEST_CASE("Bad output: a full disk fails the write with exit 1 and leaves nothing", "[cli][bad-input]") {
    TempDir dir("bad-output");
    // out.png is a link to /dev/full, where every write fails with ENOSPC. A device is written in place (a
    // rename would replace it), so the image's bytes meet the full device.
    const fs::path out = dir.path() / "out.png";
    fs::create_symlink("/dev/full", out);
    expectRefused(dir, "render '" + kStHelens + "' -o '" + out.string() + "' --size 32x24 --threads 1", 1,
                  out.string() + ": cannot write (No space left on device)");
    expectRefused(dir,
                  "scene '" + kSamples + "boxes-and-polygons.toml' -o '" + out.string() +
                      "' --size 32x24 --threads 1 -q",
                  1, out.string() + ": cannot write (No space left on device)");
    CHECK(fs::is_symlink(out));
    CHECK(fs::read_symlink(out) == "/dev/full");
}
