// The accuracy report on real DEMs: the goals of each method against the long-double reference.
#include "loaders/dem_loader.h"
#include "support/brute_force.h"
#include "support/run_command.h"
#include "support/temp_dir.h"
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

// The reference is the bilinear solve in long double, the same formula the bilinear methods evaluate in float
// and double: a mistake in that formula would pass every comparison of the report. So every `stride`-th ray
// of the report is also searched by brute force (dense sampling of the bilinear height along the ray, then
// bisection; tests/support/brute_force.h), which shares nothing with the reference but the grid, and the two
// must agree on hit or miss and on t.
void checkReferenceByBruteForce(const HeightGrid& g, const AccuracyReport& r, size_t stride) {
    REQUIRE(r.referenceRays.size() == size_t(r.rays));
    const double tolM = grazingToleranceM(g);
    const double cell = std::min(g.cellSizeXM(), g.cellSizeYM());
    int checked = 0, hits = 0, grazing = 0;
    for (size_t k = 0; k < r.referenceRays.size(); k += stride) {
        const ReferenceRay& rr = r.referenceRays[k];
        const auto range = testing::footprintRange(g, rr.ray, rr.interval);
        std::optional<long double> bfT;
        long double minG = INFINITY;
        if (range) {
            const double cellsCrossed = (range->second - range->first) * (std::abs(rr.ray.dir.x) / g.cellSizeXM() +
                                                                          std::abs(rr.ray.dir.y) / g.cellSizeYM());
            const int samples = int(std::min(400000.0, 64.0 * (cellsCrossed + 1.0) + 100.0));
            const auto bf = testing::bruteForceHit(g, rr.ray, range->first, range->second, samples);
            bfT = bf.t;
            minG = bf.minAbsGNoCross;
        }
        // A ray that passes within the tolerance of the surface without crossing it, or that the reference
        // itself flags, may be decided either way by any finite arithmetic.
        if (rr.ambiguous || minG < tolM) {
            ++grazing;
            continue;
        }
        ++checked;
        INFO("ray " << k << " origin " << rr.ray.origin.x << "," << rr.ray.origin.y << "," << rr.ray.origin.z
                    << " dir " << rr.ray.dir.x << "," << rr.ray.dir.y << "," << rr.ray.dir.z);
        REQUIRE(rr.t.has_value() == bfT.has_value());
        if (!rr.t) continue;
        ++hits;
        REQUIRE(std::abs(*rr.t - double(*bfT)) <= 1e-6 * std::max(*rr.t, cell));
    }
    INFO(checked << " rays checked, " << hits << " hits, " << grazing << " grazing");
    CHECK(checked * 10 >= 9 * int(r.referenceRays.size() / stride));
    CHECK(hits * 4 >= checked);
}

void checkGoals(const std::string& file) {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + file);
    AccuracyOptions o;
    o.rays = 30000;
    o.seed = 7;
    o.keepReferenceRays = true;
    const AccuracyReport r = measureAccuracy(dem.grid, o);
    checkReferenceByBruteForce(dem.grid, r, 100);
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
    o.keepReferenceRays = true;
    const AccuracyReport a = measureAccuracy(dem.grid, o), b = measureAccuracy(dem.grid, o);
    checkReferenceByBruteForce(dem.grid, a, 10);
    CHECK(a.referenceHits == b.referenceHits);
    CHECK(a.methods[0].tErrorM.max == b.methods[0].tErrorM.max);
    o.seed = 2;
    const AccuracyReport c = measureAccuracy(dem.grid, o);
    CHECK(c.methods[0].tErrorM.max != a.methods[0].tErrorM.max);
}

TEST_CASE("CLI: accuracy prints a table and writes the JSON report", "[cli][accuracy]") {
    const std::string demPath =
        std::string(TERRACAST_SOURCE_DIR) + "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif";
    testing::TempDir dir("accuracy");
    const std::string json = dir.file("report.json");
    const auto r = testing::runTerracast("accuracy '" + demPath + "' --rays 3000 --seed 5 --json '" + json + "'");
    REQUIRE(r.exitCode == 0);
    for (const char* name : {"bilinear ", "bilinear-double", "triangles", "nearest"})
        CHECK(r.out.find(name) != std::string::npos);
    const std::string text = testing::slurp(json);
    for (const char* key : {"\"dem\"", "\"rays\": 3000", "\"seed\": 5", "\"reference\": \"reference\"",
                            "\"ambiguous_rays\"", "\"methods\"", "\"hit_agreement\"", "\"t_error_m\"",
                            "\"t_error_rel\"", "\"p99\"", "\"rays_per_s\"", "\"name\": \"triangles\""})
        CHECK(text.find(key) != std::string::npos);
    // The report's reference is the one checked by brute force: the same seed in this process gives the same
    // reference hits, and those agree with the brute-force search.
    AccuracyOptions o;
    o.rays = 3000;
    o.seed = 5;
    o.keepReferenceRays = true;
    o.methods = {CellMethod::Bilinear};
    const LoadedDem dem = loadDem(demPath);
    const AccuracyReport same = measureAccuracy(dem.grid, o);
    CHECK(text.find("\"reference_hits\": " + std::to_string(same.referenceHits) + ",") != std::string::npos);
    checkReferenceByBruteForce(dem.grid, same, 10);
    // A JSON path in a missing folder is refused before any work, with exit code 2.
    const auto bad = testing::runTerracast("accuracy '" + demPath + "' --json /no/such/dir/r.json");
    CHECK(bad.exitCode == 2);
    CHECK(testing::lineCount(bad.err) == 1);
}
