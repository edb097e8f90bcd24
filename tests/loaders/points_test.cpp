// Point files for viewshed observers: CSV text and GDAL vector files, with one-line errors for bad input.
#include "loaders/points.h"
#include "tracer/core/errors.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace terracast;
namespace fs = std::filesystem;

namespace {

struct Folder {
    fs::path path = fs::temp_directory_path() / ("terracast-points-" + std::to_string(::getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() { fs::remove_all(path); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path / name) << text;
        return (path / name).string();
    }
};

std::string errorOf(const std::string& file) {
    try {
        readSitePoints(file, GeoReference{});
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("Points: CSV lines with a header, comments, heights and any separator", "[loaders][points]") {
    const Folder f;
    const auto csv = f.write("a.csv", "\xEF\xBB\xBF# sites\nx;y;h\n10.5,20,\n\n30\t40\t2.5\n 50 60 \n");
    const auto pts = readSitePoints(csv, GeoReference{});
    REQUIRE(pts.size() == 3);
    CHECK(pts[0].x == 10.5);
    CHECK(pts[0].y == 20.0);
    CHECK_FALSE(pts[0].heightM);
    CHECK(pts[1].heightM == 2.5);
    CHECK(pts[2].x == 50.0);
    CHECK(pts[1].where == csv + ":5");
}

TEST_CASE("Points: bad files are one line naming the file and the line or feature", "[loaders][points]") {
    const Folder f;
    CHECK(errorOf((f.path / "none.csv").string()).find("no such file") != std::string::npos);
    CHECK(errorOf(f.write("empty.csv", "x,y\n")).find("holds no point") != std::string::npos);
    const std::string bad = errorOf(f.write("bad.csv", "1,2\n3,x\n"));
    CHECK(bad.find("bad.csv:2: expected X,Y or X,Y,HEIGHT") != std::string::npos);
    CHECK(errorOf(f.write("four.csv", "1,2,3,4\n")).find("four.csv:1") != std::string::npos);
    CHECK(errorOf(f.write("nan.csv", "1,nan\n")).find("finite") != std::string::npos);
    CHECK(errorOf(f.write("huge.csv", "1e400,2\n")).find("huge.csv:1: expected finite numbers") != std::string::npos);
    // An empty field is an error, not a shift of the next one into its place.
    CHECK(errorOf(f.write("gap.csv", "1,,2\n")).find("gap.csv:1") != std::string::npos);
    // A first line with a number in it is data, and a typo there is an error rather than a skipped header.
    CHECK(errorOf(f.write("typo.csv", "10,2O\n30,40\n")).find("typo.csv:1") != std::string::npos);
    const std::string line = errorOf(f.write(
        "line.geojson", R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{},)"
                        R"("geometry":{"type":"LineString","coordinates":[[0,0],[1,1]]}}]})"));
    CHECK(line.find("line.geojson: feature 1: expected a point, found a Line String") != std::string::npos);
    CHECK(errorOf(f.write("junk.gpkg", "not a geopackage")).find("not a vector file GDAL can read") != std::string::npos);
    // A GeoJSON's points and their height field.
    const auto pts = readSitePoints(
        f.write("ok.geojson", R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{"height":4},)"
                              R"("geometry":{"type":"MultiPoint","coordinates":[[1,2],[3,4]]}}]})"),
        GeoReference{});
    REQUIRE(pts.size() == 2);
    CHECK(pts[1].x == 3.0);
    CHECK(pts[1].heightM == 4.0);
}
