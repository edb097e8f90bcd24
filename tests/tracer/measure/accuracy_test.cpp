// The accuracy report on real DEMs: the goals of each method against the long-double reference.
#include "loaders/dem_loader.h"
#include "support/run_command.h"
#include "tracer/measure/accuracy.h"

#include <catch2/catch.hpp>

#include <filesystem>

using namespace terracast;

namespace {

const MethodAccuracy& find(const AccuracyReport& r, CellMethod m) {
    for (const auto& a : r.methods)
        if (a.method == m) return a;
    FAIL("method missing from the report");
    return r.methods.front();
}

void checkGoals(const std::string& file) {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + file);
    AccuracyOptions o;
    o.rays = 30000;
    o.seed = 7;
    const AccuracyReport r = measureAccuracy(dem.grid, o);
    INFO(file << ": " << r.rays << " rays, " << r.ambiguousRays << " ambiguous, " << r.referenceHits << " reference hits");
    CHECK(r.rays == 30000);
    CHECK(r.cameraRays == 10000);
    CHECK(r.grazingRays == 10000);
    CHECK(r.shadowRays == 10000);
    CHECK(r.referenceHits > 5000);
    CHECK(r.ambiguousRays * 100 < r.rays);  // under 1 %

    const auto& f = find(r, CellMethod::Bilinear);
    INFO("bilinear: rel p99 " << f.tErrorRel.p99 << ", rel max " << f.tErrorRel.max);
    CHECK(f.unambiguousDisagreements == 0);
    CHECK(f.tErrorRel.p99 <= 1e-5);
    CHECK(f.tErrorRel.max <= 1e-4);

    const auto& d = find(r, CellMethod::BilinearDouble);
    INFO("bilinear-double: rel p99 " << d.tErrorRel.p99 << ", rel max " << d.tErrorRel.max);
    CHECK(d.disagreements == 0);
    CHECK(d.tErrorRel.p99 <= 1e-12);
    CHECK(d.tErrorRel.max <= 1e-9);

    // The approximate surfaces are further off than the exact float solve, and nearest furthest.
    const auto& t = find(r, CellMethod::Triangles);
    const auto& n = find(r, CellMethod::Nearest);
    CHECK(t.tErrorM.mean > 10.0 * f.tErrorM.mean);
    CHECK(n.tErrorM.mean > t.tErrorM.mean);
}

}  // namespace

TEST_CASE("Accuracy goals on St Helens (UTM, nodata)", "[tracer][accuracy]") {
    checkGoals("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
}

TEST_CASE("Accuracy goals on the Maritime Alps SRTM tile (geographic, sea level)", "[tracer][accuracy]") {
    checkGoals("srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif");
}

TEST_CASE("The same seed gives the same report", "[tracer][accuracy]") {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                  "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
    AccuracyOptions o;
    o.rays = 3000;
    const AccuracyReport a = measureAccuracy(dem.grid, o), b = measureAccuracy(dem.grid, o);
    CHECK(a.referenceHits == b.referenceHits);
    CHECK(a.methods[0].tErrorM.max == b.methods[0].tErrorM.max);
    o.seed = 2;
    const AccuracyReport c = measureAccuracy(dem.grid, o);
    CHECK(c.methods[0].tErrorM.max != a.methods[0].tErrorM.max);
}

TEST_CASE("CLI: accuracy prints a table and writes the JSON report", "[cli][accuracy]") {
    namespace fs = std::filesystem;
    const fs::path json = fs::temp_directory_path() / ("terracast-accuracy-" + std::to_string(::getpid()) + ".json");
    const auto r = terracast::testing::runTerracast(
        "accuracy '" + std::string(TERRACAST_SOURCE_DIR) +
        "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif' --rays 3000 --json '" + json.string() + "'");
    REQUIRE(r.exitCode == 0);
    for (const char* name : {"bilinear ", "bilinear-double", "triangles", "nearest"})
        CHECK(r.out.find(name) != std::string::npos);
    const std::string text = terracast::testing::slurp(json);
    for (const char* key : {"\"dem\"", "\"rays\": 3000", "\"reference\": \"reference\"", "\"ambiguous_rays\"",
                            "\"methods\"", "\"hit_agreement\"", "\"t_error_m\"", "\"t_error_rel\"", "\"p99\"",
                            "\"rays_per_s\"", "\"name\": \"triangles\""})
        CHECK(text.find(key) != std::string::npos);
    fs::remove(json);
    // A JSON path in a missing folder is refused before any work, with exit code 2.
    const auto bad = terracast::testing::runTerracast(
        "accuracy '" + std::string(TERRACAST_SOURCE_DIR) +
        "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif' --json /no/such/dir/r.json");
    CHECK(bad.exitCode == 2);
    CHECK(terracast::testing::lineCount(bad.err) == 1);
}
