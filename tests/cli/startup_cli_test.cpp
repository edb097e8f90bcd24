// Start-up: the executable does not load OpenImageIO; the image codec module is opened only when an EXR or a PNG
// libspng does not decode is read, or an EXR written (PNGs are written and most are read by libspng, linked in),
// and a missing module is one clear line.
#include "support/png_rasters.h"
#include "support/run_command.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

std::string commandOutput(const std::string& command) {
    std::string text;
    if (FILE* pipe = ::popen(command.c_str(), "r")) {
        char buffer[4096];
        size_t n = 0;
        while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) text.append(buffer, n);
        ::pclose(pipe);
    }
    return text;
}

// Sets an environment variable for the commands run while it lives.
struct ScopedEnv {
    std::string name;
    ScopedEnv(std::string n, const std::string& value) : name(std::move(n)) { ::setenv(name.c_str(), value.c_str(), 1); }
    ~ScopedEnv() { ::unsetenv(name.c_str()); }
};

}  // namespace

TEST_CASE("CLI: the executable does not link OpenImageIO and opens the image codec only for pictures", "[cli]") {
    // Sanitized builds link the codec in (loaders/CMakeLists.txt says why): there is no module to look for.
    if (terracast::testing::kSanitizedBuild) return;
    const std::string libraries = commandOutput(std::string("ldd '") + TERRACAST_CLI_PATH + "'");
    REQUIRE(libraries.find("libgdal") != std::string::npos);  // ldd answered
    CHECK(libraries.find("libOpenImageIO") == std::string::npos);
    CHECK(libraries.find("libmpi") == std::string::npos);  // MPI is opened only under mpirun (tracer/core/ranks.h)

    const fs::path dir = fs::temp_directory_path() / ("terracast-startup-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string dem =
        std::string(TERRACAST_SOURCE_DIR) + "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif";
    const std::string png = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png";
    const std::string png4 = (dir / "grey4.png").string();
    writePng(png4, 9, 7, 1, GDT_Byte, std::vector<double>(63, 5.0), {"NBITS=4"});
    const ScopedEnv missing("TERRACAST_IMAGE_CODEC", (dir / "no-such-codec.so").string());
    // GeoTIFF in, GeoTIFF or PNG out: the module is never looked for.
    const auto maps = runTerracast("horizon '" + dem + "' --azimuth 90 -o '" + (dir / "h.tif").string() + "'");
    INFO(maps.err);
    CHECK(maps.exitCode == 0);
    const auto picture = runTerracast("render '" + dem + "' --size 32x18 -o '" + (dir / "p.png").string() + "'");
    INFO(picture.err);
    CHECK(picture.exitCode == 0);
    CHECK(fs::file_size(dir / "p.png") > 0);
    // A 16-bit PNG height map is decoded without the module (libspng, linked in).
    const auto heights = runTerracast("horizon '" + png + "' --azimuth 90 -o '" + (dir / "ph.tif").string() + "'");
    INFO(heights.err);
    CHECK(heights.exitCode == 0);
    CHECK(fs::exists(dir / "ph.tif"));
    // An EXR out, or a 4-bit PNG height map in (left to the module): one line naming the module, no output file.
    for (const std::string& args : {"render '" + dem + "' --size 32x18 -o '" + (dir / "v.exr").string() + "'",
                                    "horizon '" + png4 + "' --azimuth 90 -o '" + (dir / "w.tif").string() + "'"}) {
        const auto r = runTerracast(args);
        INFO(args << "\n" << r.err);
        CHECK(r.exitCode != 0);
        CHECK(r.err.find("cannot load the image codec module " + (dir / "no-such-codec.so").string()) !=
              std::string::npos);
        size_t errors = 0;
        for (size_t at = r.err.find("terracast: error"); at != std::string::npos; at = r.err.find("terracast: error", at + 1))
            ++errors;
        CHECK(errors == 1);
        CHECK(r.err.find("TERRACAST_IMAGE_CODEC to its path\n") != std::string::npos);  // the line ends there
    }
    CHECK(!fs::exists(dir / "w.tif"));
    CHECK(!fs::exists(dir / "v.exr"));
    fs::remove_all(dir);
}
