// The hostile-input suite: every case runs the real executable in a folder of its own, and must end (no hang:
// killed after a timeout), with the expected exit code, exactly one line on stderr naming what is wrong, and the
// folder as it was (nothing written, nothing removed, no input changed). The README's Reliability table lists
// every case with its exit code and message: scripts/reliability_table.sh rewrites it, and the suite fails when
// a case's row there differs from what the executable printed.
#include "support/run_command.h"
#include "support/sanitizers.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/stat.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>
#include <random>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
const std::string kStHelens = kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
const std::string kPuget = kSamples + "puget-sound-usgs-1025x1025-16bit-heightmap.png";

struct Case {
    std::string name;               // what the case tries, for the table
    std::vector<std::string> args;  // run in the case folder
    int exitCode = 2;
    std::string message;            // part of the one stderr line
    double interruptAfterS = -1.0;  // SIGINT this long after the start
};

// A 64 x 64 Float32 GeoTIFF on a UTM grid of 30 m cells (or the given geotransform): a ramp of heights with
// `edit` applied, and `nodata` declared when given.
void writeSmallTiff(const fs::path& path, const std::function<void(std::vector<float>&)>& edit,
                    std::array<double, 6> geoTransform = {500000.0, 30.0, 0.0, 5000000.0, 0.0, -30.0},
                    std::optional<double> nodata = std::nullopt, int width = 64, int height = 64) {
    GDALAllRegister();
    GDALDriver* tiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDatasetUniquePtr ds(tiff->Create(path.c_str(), width, height, 1, GDT_Float32, nullptr));
    REQUIRE(ds);
    ds->SetGeoTransform(geoTransform.data());
    OGRSpatialReference utm;
    utm.importFromEPSG(32610);
    ds->SetSpatialRef(&utm);
    std::vector<float> z(size_t(width) * size_t(height));
    for (size_t k = 0; k < z.size(); ++k) z[k] = 100.0f + float(k % 97);
    edit(z);
    if (nodata) ds->GetRasterBand(1)->SetNoDataValue(*nodata);
    REQUIRE(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, width, height, z.data(), width, height, GDT_Float32, 0, 0,
                                           nullptr) == CE_None);
}

// Files that break a reader: cut short, corrupted, or holding heights and georeferences no DEM has.
void makeBrokenDems(const fs::path& dir) {
    const std::string tif = slurp(kStHelens), png = slurp(kPuget);
    std::ofstream(dir / "truncated.tif", std::ios::binary) << tif.substr(0, tif.size() / 2);
    std::ofstream(dir / "header-only.tif", std::ios::binary) << tif.substr(0, 16);
    std::ofstream(dir / "text.tif") << "elevation,metres\n1,2\n";
    std::string noise(4096, '\0');
    std::mt19937 rng(5);
    for (char& c : noise) c = char(rng() & 0xff);
    std::ofstream(dir / "noise.tif", std::ios::binary) << noise;
    std::ofstream(dir / "truncated.png", std::ios::binary) << png.substr(0, png.size() / 2);
    // The first IDAT chunk's type, bytes 37..40, made invalid.
    std::string chunk = png;
    chunk[40] = char(chunk[40] ^ 0xff);
    std::ofstream(dir / "bad-chunk.png", std::ios::binary) << chunk;
    const auto keep = [](std::vector<float>&) {};
    writeSmallTiff(dir / "one-row.tif", keep, {500000.0, 30.0, 0.0, 5000000.0, 0.0, -30.0}, std::nullopt, 64, 1);
    writeSmallTiff(dir / "all-nodata.tif", [](std::vector<float>& z) { std::fill(z.begin(), z.end(), -9999.0f); },
                   {500000.0, 30.0, 0.0, 5000000.0, 0.0, -30.0}, -9999.0);
    writeSmallTiff(dir / "nan-height.tif", [](std::vector<float>& z) { z[5 * 64 + 5] = NAN; });
    writeSmallTiff(dir / "inf-height.tif", [](std::vector<float>& z) { z[10 * 64 + 10] = INFINITY; });
    writeSmallTiff(dir / "spike.tif", [](std::vector<float>& z) { z[3 * 64 + 3] = 1e30f; });
    writeSmallTiff(dir / "rotated.tif", keep, {500000.0, 30.0, 5.0, 5000000.0, 5.0, -30.0});
    writeSmallTiff(dir / "nan-origin.tif", keep, {NAN, 30.0, 0.0, 5000000.0, 0.0, -30.0});
    writeSmallTiff(dir / "nanometre-cells.tif", keep, {500000.0, 1e-9, 0.0, 5000000.0, 0.0, -1e-9});
}

// Scene files with one thing wrong each, beside a small PNG height map they may name.
void makeBrokenScenes(const fs::path& dir) {
    fs::copy_file(std::string(TERRACAST_SOURCE_DIR) + "/tests/golden/st-helens-160x90.png", dir / "drape.png");
    const std::string ball = "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";
    const std::vector<std::pair<std::string, std::string>> scenes = {
        {"nan-radius", "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = nan\n"},
        {"inf-center", "[[object]]\ntype = \"sphere\"\ncenter = [inf, 0, 0]\nradius = 1\n"},
        {"far-center", "[[object]]\ntype = \"sphere\"\ncenter = [1e300, 0, 0]\nradius = 1\n"},
        {"huge-radius", "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1e300\n"},
        {"nan-eye", ball + "[camera]\neye = [nan, 0, 5]\n"},
        {"eye-at-target", ball + "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 5]\n"},
        {"zero-fov", ball + "[camera]\nfov = 0\n"},
        {"wide-film", ball + "[render]\nwidth = 100000\n"},
        {"no-samples", ball + "[render]\nsamples = 0\n"},
        {"deep-bounces", ball + "[render]\nmax_depth = 1000000\n"},
        {"noise", "\x89\x50\xff\xfe\x01\x02garbage\n"},
        {"latin1", "[render]\nwidth = 10 # caf\xe9\n"},
        {"two-render-tables", ball + "[render]\nwidth = 10\n[render]\nheight = 10\n"},
        {"missing-material", ball + "material = \"chrome\"\n"},
        {"negative-colour", "[[material]]\nname = \"m\"\ncolor = [-1, 0, 0]\n"},
        {"empty-polygon", "[[object]]\ntype = \"polygon\"\nvertices = []\n"},
        {"flat-triangle", "[[object]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]\n"},
        {"inside-out-box", "[[object]]\ntype = \"box\"\nmin = [1, 1, 1]\nmax = [0, 0, 0]\n"},
        {"missing-dem", "[[object]]\ntype = \"heightfield\"\nfile = \"nothing.tif\"\n"},
        {"text-dem", "[[object]]\ntype = \"heightfield\"\nfile = \"text.tif\"\n"},
        {"self-dem", "[[object]]\ntype = \"heightfield\"\nfile = \"self-dem.toml\"\n"},
        {"writes-itself", ball + "[render]\noutput = \"writes-itself.toml\"\n"},
        {"writes-its-dem", "[[object]]\ntype = \"heightfield\"\nfile = \"drape.png\"\n[render]\noutput = \"drape.png\"\n"},
        {"writes-its-drape", ball + "[[material]]\nname = \"photo\"\ndrape = \"drape.png\"\n[render]\noutput = \"./drape.png\"\n"},
        {"newline-output", ball + "[render]\noutput = \"a\\nb.png\"\n"},
        {"huge-integer", ball + "[render]\nwidth = 99999999999999999999\n"},
        {"nan-sun", ball + "[[light]]\ntype = \"sun\"\nelevation = nan\n"},
        {"inf-exposure", ball + "[render]\nexposure = inf\n"},
        {"negative-aperture", ball + "[camera]\ntype = \"thin-lens\"\naperture = -1\n"},
        {"misspelt-key", ball + "[render]\nwidht = 10\n"},
        {"unknown-object", "[[object]]\ntype = \"torus\"\n"},
    };
    for (const auto& [name, text] : scenes) std::ofstream(dir / (name + ".toml"), std::ios::binary) << text;
}

// The files a case folder starts with: a real DEM and the hostile inputs beside it.
void makeFixtures(const fs::path& dir) {
    fs::copy_file(kStHelens, dir / "dem.tif");
    makeBrokenDems(dir);
    makeBrokenScenes(dir);
    ::mkfifo((dir / "fifo.tif").c_str(), 0644);
    ::mkfifo((dir / "fifo.toml").c_str(), 0644);
    fs::create_symlink("/dev/zero", dir / "zero.tif");
    fs::create_symlink("/dev/zero", dir / "zero.toml");
    fs::create_symlink("loop-b.tif", dir / "loop-a.tif");
    fs::create_symlink("loop-a.tif", dir / "loop-b.tif");
    fs::create_directory(dir / "folder.tif");
    fs::create_directory(dir / "folder.png");
    fs::create_directory(dir / "sub");
    // Outputs that are not plain new files, and other names of the DEM.
    fs::create_symlink("/dev/null", dir / "null.tif");
    fs::create_symlink("/dev/full", dir / "full.tif");
    fs::create_symlink("/dev/full", dir / "full.png");
    ::mkfifo((dir / "out-fifo.png").c_str(), 0644);
    fs::create_symlink("dem.tif", dir / "alias.tif");
    fs::create_hard_link(dir / "dem.tif", dir / "hard.tif");
    fs::create_hard_link(dir / "dem.tif", dir / "bilinear.png");
    // Scene files that name paths out of their folder, absolute, virtual or on a network.
    {
        const auto heightField = [](const std::string& file) {
            return "[[object]]\ntype = \"heightfield\"\nfile = \"" + file + "\"\n";
        };
        const std::string ball = "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";
        fs::create_symlink("/etc/hostname", dir / "out-link.tif");
        std::ofstream(dir / "escape-dotdot.toml") << heightField("../dem.tif");
        std::ofstream(dir / "escape-absolute.toml") << heightField("/etc/hostname");
        std::ofstream(dir / "escape-link.toml") << heightField("out-link.tif");
        std::ofstream(dir / "network.toml") << heightField("/vsicurl/http://127.0.0.1:9/dem.tif");
        std::ofstream(dir / "https.toml") << heightField("https://example.com/dem.tif");
        std::ofstream(dir / "archive.toml") << heightField("/vsizip/dems.zip/dem.tif");
        std::ofstream(dir / "drape-absolute.toml") << "[[material]]\nname = \"m\"\ndrape = \"/etc/hostname\"\n";
        std::ofstream(dir / "output-absolute.toml") << ball << "[render]\noutput = \"/tmp/terracast-replaced.png\"\n";
        std::ofstream(dir / "output-dotdot.toml") << ball << "[render]\noutput = \"../replaced.png\"\n";
        std::ofstream(dir / "inside.toml") << heightField("dem.tif");
        std::ofstream(dir / "trusted.toml") << heightField(kStHelens);
        fs::create_symlink("/dev/null", dir / "null.png");
    }
    // A scene that would run for hours.
    std::ofstream(dir / "long.toml") << "[render]\nwidth = 4096\nheight = 4096\nsamples = 65536\n"
                                        "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";
    std::ofstream(dir / "empty.tif").flush();
    // A 68-byte PNG whose header claims 30000 x 30000 16-bit samples, with 11 bytes of compressed data.
    {
        static const unsigned char kClaim[] = {
            0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
            0x00, 0x75, 0x30, 0x00, 0x00, 0x75, 0x30, 0x10, 0x00, 0x00, 0x00, 0x00, 0x13, 0xdc, 0x7b, 0x25, 0x00,
            0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x60, 0x80, 0x01, 0x00, 0x00, 0x0a, 0x00,
            0x01, 0x7f, 0x80, 0x74, 0x5e, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
        std::ofstream(dir / "claim.png", std::ios::binary).write(reinterpret_cast<const char*>(kClaim), sizeof kClaim);
    }
    // A Unix socket where the DEM should be.
    {
        const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        const std::string socketPath = (dir / "socket.tif").string();
        REQUIRE(socketPath.size() < sizeof address.sun_path);
        std::copy(socketPath.begin(), socketPath.end(), address.sun_path);
        REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
        ::close(fd);
    }
    // Deep nesting that would exhaust the TOML parser's stack.
    {
        std::string key;
        for (int k = 0; k < 50000; ++k) key += "a.";
        std::ofstream(dir / "deep-key.toml") << key << "a = 1\n";
        std::ofstream(dir / "deep-array.toml") << "a = " << std::string(100000, '[') << std::string(100000, ']') << "\n";
        std::string inl = "x = ";
        for (int k = 0; k < 20000; ++k) inl += "{ a = ";
        inl.append("1").append(20000, '}').append("\n");
        std::ofstream(dir / "deep-inline.toml") << inl;
    }
    // A scene file larger than any scene needs (sparse: no disk is used).
    {
        std::ofstream(dir / "huge.toml").flush();
        fs::resize_file(dir / "huge.toml", (int64_t(64) << 20) + 1);
    }
    // A complex-valued raster on the DEM's grid.
    GDALAllRegister();
    GDALDatasetUniquePtr src(GDALDataset::Open((dir / "dem.tif").c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    GDALDriver* tiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDatasetUniquePtr complex(tiff->Create((dir / "complex.tif").c_str(), 8, 8, 1, GDT_CFloat32, nullptr));
    std::vector<float> zeros(2 * 64, 100.0f);
    REQUIRE(complex->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 8, 8, zeros.data(), 8, 8, GDT_CFloat32, 0, 0, nullptr) ==
            CE_None);
}

// Each file's name, size and modification time: what a case must leave as it found.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> entries;
    for (const auto& e : fs::directory_iterator(dir)) {
        struct stat st {};
        ::lstat(e.path().c_str(), &st);
        entries[e.path().filename().string()] =
            std::to_string(st.st_mode) + " " + std::to_string(st.st_size) + " " + std::to_string(st.st_mtim.tv_sec) +
            "." + std::to_string(st.st_mtim.tv_nsec);
    }
    return entries;
}

std::string shellWord(const std::string& arg) {
    bool plain = !arg.empty();
    for (char c : arg) plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || std::string("-_.,/=:+").find(c) != std::string::npos);
    if (plain) return arg;
    std::string quoted = "'";
    for (char c : arg) quoted += c == '\n' ? std::string("'$'\\n''") : c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

// The README row of a case.
std::string tableRow(const Case& c, const ArgsResult& r) {
    std::string command = "terracast";
    for (const auto& a : c.args) command.append(" ").append(shellWord(a));
    // A run that succeeds prints its summary, with times that vary.
    std::string line = r.exitCode == 0 ? std::string("(its summary)") : r.err.substr(0, r.err.find('\n'));
    std::string escaped;
    for (char ch : line) escaped += ch == '|' ? std::string("\\|") : ch == '`' ? std::string("'") : std::string(1, ch);
    return "| " + c.name + " | `" + command + "` | " + std::to_string(r.exitCode) + " | " + escaped + " |";
}

// The rows of the README's Reliability table, to compare with.
const std::string& readme() {
    static const std::string text = slurp(std::string(TERRACAST_SOURCE_DIR) + "/README.md");
    return text;
}

void runCases(const std::string& group, const std::vector<Case>& cases) {
    TempDir dir("hostile-" + group);
    makeFixtures(dir.path());
    const auto before = snapshot(dir.path());
    std::string rows;
    // Under the sanitizers a case costs several times more; the large groups, which repeat each input across the
    // commands, run every third case there (every input and every command still appear).
    const size_t stride = kSanitizedBuild && cases.size() > 60 && !std::getenv("TERRACAST_RELIABILITY_TABLE") ? 3 : 1;
    for (size_t k = 0; k < cases.size(); k += stride) {
        const Case& c = cases[k];
        RunSettings settings;
        settings.workDir = dir.path();
        settings.timeoutS = 30.0;
        settings.interruptAfterS = c.interruptAfterS;
        const ArgsResult r = runTerracastArgs(c.args, settings);
        INFO(group << ": " << c.name << "\nstderr: " << r.err);
        CHECK_FALSE(r.hung);
        CHECK(r.termSignal == 0);
        CHECK(r.exitCode == c.exitCode);
        CHECK(lineCount(r.err) == 1);
        CHECK(r.err.find(c.message) != std::string::npos);
        CHECK(snapshot(dir.path()) == before);
        const std::string row = tableRow(c, r);
        rows += row + "\n";
        if (!std::getenv("TERRACAST_RELIABILITY_TABLE")) {
            INFO("README.md lacks this row (scripts/reliability_table.sh rewrites the table):\n" << row);
            CHECK(readme().find(row + "\n") != std::string::npos);
        }
    }
    if (const char* table = std::getenv("TERRACAST_RELIABILITY_TABLE")) {
        static std::mutex mutex;
        std::lock_guard lock(mutex);
        std::ofstream(fs::path(table) / (group + ".md")) << rows;
    }
}

// The commands that read a DEM, with the options each needs to get as far as reading it.
std::vector<std::pair<std::string, std::vector<std::string>>> demCommands() {
    return {{"info", {}},
            {"render", {"-o", "out.png", "--size", "32x24"}},
            {"shadow", {"-o", "out.tif"}},
            {"horizon", {"--azimuth", "90", "-o", "out.tif"}},
            {"svf", {"-o", "out.tif"}},
            {"insolation", {"--date", "2026-06-21", "-o", "out.tif"}},
            {"viewshed", {"--observer", "560000,5110000", "-o", "out.tif"}},
            {"accuracy", {"--rays", "100"}},
            {"compare", {"--size", "32x24"}}};
}

// Each input (what it is, then its file and the message expected) through every command that reads a DEM.
std::vector<Case> acrossDemCommands(
    const std::vector<std::pair<std::string, std::pair<std::string, std::string>>>& inputs) {
    std::vector<Case> cases;
    for (const auto& [command, options] : demCommands())
        for (const auto& [what, input] : inputs) {
            Case c{command + ": " + what, {command, input.first}, 2, input.second};
            c.args.insert(c.args.end(), options.begin(), options.end());
            cases.push_back(c);
        }
    return cases;
}

}  // namespace

TEST_CASE("Hostile inputs: DEMs that are not regular readable rasters", "[cli][hostile]") {
    const std::vector<std::pair<std::string, std::pair<std::string, std::string>>> inputs = {
        {"missing DEM", {"missing.tif", "missing.tif: no such file"}},
        {"DEM is a folder", {"folder.tif", "folder.tif: is a directory"}},
        {"DEM is a FIFO", {"fifo.tif", "fifo.tif: expected a DEM as a regular file, found a pipe (FIFO)"}},
        {"DEM links to /dev/zero", {"zero.tif", "zero.tif: expected a DEM as a regular file, found a character device"}},
        {"DEM is a link loop", {"loop-a.tif", "loop-a.tif: expected a DEM, found a loop of symbolic links"}},
        {"DEM is empty", {"empty.tif", "empty.tif: file is empty"}},
        {"DEM is a Unix socket", {"socket.tif", "socket.tif: expected a DEM as a regular file, found a socket"}},
        {"PNG header claims 30000^2 samples in 68 bytes",
         {"claim.png", "claim.png: header claims 30000 x 30000 samples (1.7 GiB of pixel data), more than its 11 "
                       "compressed bytes can hold"}},
        {"DEM is complex-valued", {"complex.tif", "band 1 holds complex numbers (CFloat32), expected real heights"}},
        {"DEM name holds a newline", {"new\nline.tif", "new\\nline.tif: no such file"}},
    };
    runCases("dem-inputs", acrossDemCommands(inputs));
}

TEST_CASE("Hostile inputs: DEMs cut short, corrupted, or holding impossible heights and georeferences",
          "[cli][hostile][heavy]") {
    const std::vector<std::pair<std::string, std::pair<std::string, std::string>>> inputs = {
        {"GeoTIFF cut in half", {"truncated.tif", "truncated.tif: cannot read rows 0..467 of band 1"}},
        {"GeoTIFF header alone", {"header-only.tif", "header-only.tif: not a raster GDAL can read"}},
        {"text named .tif", {"text.tif", "text.tif: not a raster GDAL can read"}},
        {"random bytes named .tif", {"noise.tif", "noise.tif: not a raster GDAL can read"}},
        {"PNG cut in half", {"truncated.png", "truncated.png: truncated PNG (IDAT chunk at byte"}},
        {"PNG with a corrupt chunk type", {"bad-chunk.png", "bad-chunk.png: corrupt PNG (chunk type IDA"}},
        {"one row of samples", {"one-row.tif", "one-row.tif: 64 x 1 raster has no cell to trace (need at least 2 x 2)"}},
        {"every sample nodata", {"all-nodata.tif", "all-nodata.tif: every vertex is nodata"}},
        {"an undeclared NaN height", {"nan-height.tif", "nan-height.tif: height at column 5, row 5 is NaN (not declared as nodata)"}},
        {"an infinite height", {"inf-height.tif", "inf-height.tif: height at column 10, row 10 is infinite"}},
        {"a height of 1e30 m", {"spike.tif", "spike.tif: height at column 3, row 3 is 1e+30 m, expected within 1e+06 m"}},
        {"a rotated geotransform", {"rotated.tif", "rotated.tif: rotated geotransform (terms 5 and 5) is not supported"}},
        {"a NaN origin", {"nan-origin.tif", "nan-origin.tif: geotransform term 0 is nan, expected a finite coordinate"}},
        {"nanometre cells", {"nanometre-cells.tif", "nanometre-cells.tif: cell size 1e-09 x 1e-09 m, expected 1e-06 m to 1e+06 m"}},
    };
    runCases("dem-content", acrossDemCommands(inputs));
}

TEST_CASE("Hostile scene files: impossible values, broken text, and outputs over inputs", "[cli][hostile][heavy]") {
    const std::vector<std::tuple<std::string, std::string, std::string>> scenes = {
        {"a NaN radius", "nan-radius", "nan-radius.toml:4:10: radius: expected a finite number in (0, 1e+09], found nan"},
        {"an infinite centre", "inf-center", "inf-center.toml:3:11: center[0]: expected a finite number in [-1e+09, 1e+09], found inf"},
        {"a centre 1e300 m away", "far-center", "far-center.toml:3:11: center[0]: expected a number in [-1e+09, 1e+09], found 1e+300"},
        {"a radius of 1e300 m", "huge-radius", "huge-radius.toml:4:10: radius: expected a number in (0, 1e+09], found 1e+300"},
        {"a NaN eye", "nan-eye", "nan-eye.toml:6:8: eye[0]: expected a finite number in [-1e+09, 1e+09], found nan"},
        {"the eye on its target", "eye-at-target", "eye-at-target.toml:7:11: look_at: expected a point other than eye"},
        {"a zero field of view", "zero-fov", "zero-fov.toml:6:7: fov: expected a number in (0, 180), found 0"},
        {"a film 100000 pixels wide", "wide-film", "wide-film.toml:6:9: width: expected an integer in 1..16384, found 100000"},
        {"zero samples", "no-samples", "no-samples.toml:6:11: samples: expected an integer in 1..65536, found 0"},
        {"a million bounces", "deep-bounces", "deep-bounces.toml:6:13: max_depth: expected an integer in 0..64, found 1000000"},
        {"binary bytes", "noise", "noise.toml:1:1: invalid TOML: Encountered invalid utf-8 sequence"},
        {"Latin-1 text", "latin1", "latin1.toml:2:16: invalid TOML: Encountered invalid utf-8 sequence"},
        {"two [render] tables", "two-render-tables", "two-render-tables.toml:7:1: invalid TOML: Error while parsing table header: cannot redefine existing table 'render'"},
        {"an undefined material", "missing-material", "missing-material.toml:5:12: material: no [[material]] is named \"chrome\""},
        {"a negative colour", "negative-colour", "negative-colour.toml:3:10: color[0]: expected a number >= 0, found -1"},
        {"a polygon without vertices", "empty-polygon", "empty-polygon.toml:3:12: vertices: expected at least 3 points, found 0"},
        {"a triangle on a line", "flat-triangle", "flat-triangle.toml:3:12: vertices: expected a triangle with an area"},
        {"a box inside out", "inside-out-box", "inside-out-box.toml:4:7: max: expected a corner above min on every axis"},
        {"a missing DEM", "missing-dem", "missing-dem.toml:3:1: file: "},
        {"a DEM that is text", "text-dem", "text-dem.toml:3:1: file: text.tif: not a raster GDAL can read"},
        {"itself as its DEM", "self-dem", "self-dem.toml:3:1: file: self-dem.toml: not a raster GDAL can read"},
        {"writing over itself", "writes-itself", "writes-itself.toml: output path is the scene file; refusing to overwrite it"},
        {"writing over its DEM", "writes-its-dem", "drape.png: output path is a height field's DEM; refusing to overwrite it"},
        {"writing over its drape", "writes-its-drape", "drape.png: output path is a material's drape; refusing to overwrite it"},
        {"an output name with a newline", "newline-output", "newline-output.toml:6:10: output: expected a file path, found a string with a control character (code 10)"},
        {"an integer beyond 64 bits", "huge-integer", "huge-integer.toml:6:29: invalid TOML: Error while parsing decimal integer"},
        {"a NaN sun elevation", "nan-sun", "nan-sun.toml:7:13: elevation: expected a finite number in [-90, 90], found nan"},
        {"an infinite exposure", "inf-exposure", "inf-exposure.toml:6:12: exposure: expected a finite number > 0, found inf"},
        {"a negative aperture", "negative-aperture", "negative-aperture.toml:7:12: aperture: expected a number in [0, 1e+09], found -1"},
        {"a misspelt key", "misspelt-key", "misspelt-key.toml:6:1: unknown key 'widht' in [render] (did you mean 'width'?)"},
        {"an unknown object type", "unknown-object", "unknown-object.toml:2:8: type: expected one of"},
    };
    std::vector<Case> cases;
    for (const auto& [what, file, message] : scenes) {
        // Scenes that name their own output are run without -o, so that the file's output is the one checked.
        const bool ownOutput = file.starts_with("writes-") || file == "newline-output";
        Case c{"scene with " + what, {"scene", file + ".toml"}, 2, message};
        if (!ownOutput) c.args.insert(c.args.end(), {"-o", "out.png"});
        cases.push_back(c);
    }
    runCases("scene-content", cases);
}

TEST_CASE("Hostile inputs: malformed and out-of-range option values", "[cli][hostile]") {
    const std::vector<std::string> render = {"render", "dem.tif", "-o", "out.png"};
    const std::vector<std::string> shadow = {"shadow", "dem.tif", "-o", "out.tif"};
    const std::vector<std::string> insolation = {"insolation", "dem.tif", "-o", "out.tif"};
    const std::vector<std::string> viewshed = {"viewshed", "dem.tif", "-o", "out.tif"};
    const auto with = [](std::vector<std::string> prefix, std::initializer_list<std::string> more) {
        prefix.insert(prefix.end(), more);
        return prefix;
    };
    const std::vector<std::tuple<std::string, std::vector<std::string>, std::string>> options = {
        {"no command", {}, "no command given (expected one of info, scene, render"},
        {"an unknown command", {"rendre"}, "unknown command 'rendre'"},
        {"a misspelt option", with(render, {"--sizee", "32x24"}), "render: unexpected argument '--sizee'; did you mean --size?"},
        {"an extra DEM", {"info", "dem.tif", "dem2.tif"}, "info: unexpected argument 'dem2.tif'"},
        {"info without a DEM", {"info"}, "DEM is required"},
        {"render without -o", {"render", "dem.tif"}, "--output is required"},
        {"--size 0x0", with(render, {"--size", "0x0"}), "--size: expected WxH with whole numbers from 1 to 65536, found '0x0'"},
        {"--size 100000x100000", with(render, {"--size", "100000x100000"}), "--size: expected WxH with whole numbers from 1 to 65536"},
        {"--size -5x3", with(render, {"--size", "-5x3"}), "--size: expected WxH"},
        {"--size 32x", with(render, {"--size", "32x"}), "--size: expected WxH"},
        {"--sun with one number", with(render, {"--sun", "315"}), "--sun: expected AZ,EL in degrees, found '315'"},
        {"--sun elevation 95", with(render, {"--sun", "315,95"}), "--sun: elevation must lie in [-90, 90] degrees, found 95"},
        {"--sun with words", with(render, {"--sun", "west,high"}), "--sun: expected AZ,EL in degrees, found 'west,high'"},
        {"--sun with three numbers", with(render, {"--sun", "315,35,2"}), "--sun: expected AZ,EL in degrees"},
        {"an unknown --method", with(render, {"--method", "bilinar"}), "--method: expected one of bilinear, bilinear-double"},
        {"an unknown --view", with(render, {"--view", "sideways"}), "--view: expected perspective, orthographic, panorama, fisheye or map, found 'sideways'"},
        {"an unknown --sampler", with(render, {"--spp", "4", "--sampler", "sobol"}), "--sampler: expected one of regular, random, stratified, poisson, best-candidate, found 'sobol'"},
        {"an unknown --filter", with(render, {"--spp", "4", "--filter", "lanczos"}), "--filter: expected one of box, tent, gaussian, found 'lanczos'"},
        {"--adaptive 0", with(render, {"--spp", "64", "--adaptive", "0"}), "--adaptive: expected an error > 0, found 0"},
        {"a field of view for the panorama", with(render, {"--view", "panorama", "--camera", "eye=0,0,5000 look=100,100,5000 fov=60"}), "--camera: fov does not apply to --view panorama (found fov=60)"},
        {"a fisheye's field of view over 360", with(render, {"--view", "fisheye", "--camera", "eye=0,0,5000 look=100,100,0 fov=400"}), "--camera: fov expects degrees in (0, 360], found '400'"},
        {"an unknown --sky", with(render, {"--sky", "cloudy"}), "--sky: expected physical, gradient, flat or none, found 'cloudy'"},
        {"an unknown --colour", with(render, {"--view", "map", "--colour", "rainbow"}), "--colour: expected grey or ramp, found 'rainbow'"},
        {"an unknown --normals", with(render, {"--normals", "smoth"}), "--normals: expected smooth or facet, found 'smoth'"},
        {"--max-memory 10Q", with(render, {"--max-memory", "10Q"}), "--max-memory: expected a size such as 512M or 8G, found '10Q'"},
        {"--max-memory -1G", with(render, {"--max-memory", "-1G"}), "--max-memory: expected a size such as 512M or 8G, found '-1G'"},
        {"--max-memory 0", with(render, {"--max-memory", "0"}), "--max-memory: expected a size such as 512M or 8G, found '0'"},
        {"--sun-time in month 13", with(render, {"--sun-time", "2026-13-45T00:00Z"}), "--sun-time: expected an ISO 8601 time such as 2026-06-21T19:30Z, found '2026-13-45T00:00Z' (month 13 is not in 01..12)"},
        {"--sun-time with words", with(render, {"--sun-time", "noon"}), "--sun-time: expected an ISO 8601 time"},
        {"a JPEG output", {"render", "dem.tif", "-o", "out.jpg"}, "out.jpg: unsupported output format '.jpg' (expected .png or .exr)"},
        {"an output without extension", {"render", "dem.tif", "-o", "out"}, "out: unsupported output format '' (expected .png or .exr)"},
        {"--camera eye with two numbers", with(render, {"--camera", "eye=1,2"}), "--camera: eye expects x,y,z in metres (each within 1e9), found '1,2'"},
        {"--camera fov 0", with(render, {"--camera", "eye=0,0,5000 look=100,100,0 fov=0"}), "--camera: fov expects degrees in (0, 180), found '0'"},
        {"--camera fov 200", with(render, {"--camera", "eye=0,0,5000 look=100,100,0 fov=200"}), "--camera: fov expects degrees in (0, 180), found '200'"},
        {"--camera eye on look", with(render, {"--camera", "eye=0,0,5000 look=0,0,5000"}), "--camera: eye and look are the same point"},
        {"--camera with an unknown key", with(render, {"--camera", "zoom=3"}), "--camera: unknown key 'zoom' (expected eye, look, up or fov)"},
        {"--sky-samples -1", with(render, {"--sky-samples", "-1"}), "--sky-samples: expected a whole number from 0 to 4096, found '-1'"},
        {"--sky-samples 100000", with(render, {"--sky-samples", "100000"}), "--sky-samples: expected a whole number from 0 to 4096, found '100000'"},
        {"--hillshade-blend 2", with(render, {"--view", "map", "--hillshade-blend", "2"}), "--hillshade-blend: expected 0..1, found 2"},
        {"--scale 0", with(render, {"--view", "map", "--scale", "0"}), "--scale: expected (0, 16], found 0"},
        {"--seed -1", with(render, {"--seed", "-1"}), "--seed: expected a whole number from 0 to 9007199254740992, found '-1'"},
        {"--threads 1.5", with(render, {"--threads", "1.5"}), "--threads: expected a whole number from 0 to 2147483647, found '1.5'"},
        {"--sun-time step 0m", with(shadow, {"--sun-time", "2026-06-21T00:00Z/2026-06-21T23:00Z/0m"}), "(STEP: a whole number > 0 with a unit s, m, h or d)"},
        {"--sun-time ending before it starts", with(shadow, {"--sun-time", "2026-06-21T23:00Z/2026-06-21T00:00Z/1h"}), "(END is before START)"},
        {"--sun-time with 2 million times", with(shadow, {"--sun-time", "2026-01-01T00:00Z/2030-01-01T00:00Z/1m"}), "(more than 3600 times)"},
        {"--sun-time with two parts", with(shadow, {"--sun-time", "2026-06-21T00:00Z/2026-06-21T05:00Z"}), "(three parts separated by /)"},
        {"--sun-time without a zone", with(shadow, {"--sun-time", "2026-06-21T10:00"}), "--sun-time: expected an ISO 8601 time such as 2026-06-21T15:00Z or START/END/STEP"},
        {"--sun-size 90", with(shadow, {"--sun-size", "90"}), "--sun-size: expected degrees in [0, 30), found 90"},
        {"a PNG shadow mask", {"shadow", "dem.tif", "-o", "out.png"}, "out.png: unsupported output format '.png' (expected .tif or .tiff)"},
        {"horizon without an azimuth", {"horizon", "dem.tif", "-o", "out.tif"}, "horizon: give --azimuth DEGREES or --azimuths START:END:STEP"},
        {"--azimuths with step 0", {"horizon", "dem.tif", "-o", "out.tif", "--azimuths", "0:360:0"}, "--azimuths: expected START:END:STEP in degrees with END > START and STEP > 0"},
        {"--azimuths 3.6 million", {"horizon", "dem.tif", "-o", "out.tif", "--azimuths", "0:360:0.0001"}, "--azimuths: '0:360:0.0001' gives more than 3600 azimuths"},
        {"--directions 0", {"svf", "dem.tif", "-o", "out.tif", "--directions", "0"}, "svf --directions: expected 1 to 3600, found 0"},
        {"--directions 100000", {"svf", "dem.tif", "-o", "out.tif", "--directions", "100000"}, "svf --directions: expected 1 to 3600, found 100000"},
        {"--date February 30", with(insolation, {"--date", "2026-02-30"}), "found '2026-02-30' (the date is no such day)"},
        {"--date range backwards", with(insolation, {"--date", "2026-06-21/2026-06-01"}), "(END is before START)"},
        {"--step 0m", with(insolation, {"--date", "2026-06-21", "--step", "0m"}), "--step: expected a whole number > 0 with a unit s, m, h or d (such as 30m), found '0m'"},
        {"--step 5s", with(insolation, {"--date", "2026-06-21", "--step", "5s"}), "insolation --step: expected 10 s to 1 d, found 5 s"},
        {"--day-step 0", with(insolation, {"--date", "2026-06-21", "--day-step", "0"}), "insolation --day-step: expected 1 to 366 days, found 0"},
        {"--linke 100", with(insolation, {"--date", "2026-06-21", "--linke", "100"}), "insolation --linke: expected a Linke turbidity in [0.5, 10], found 100"},
        {"--albedo 2", with(insolation, {"--date", "2026-06-21", "--albedo", "2"}), "insolation --albedo: expected a ground reflectance in [0, 1], found 2"},
        {"an observer outside the DEM", with(viewshed, {"--observer", "0,0"}), "--observer: 0, 0 lies outside the DEM"},
        {"an observer with four numbers", with(viewshed, {"--observer", "1,2,3,4"}), "--observer: expected X,Y, found '1,2,3,4'"},
        {"an observer at longitude 200", with(viewshed, {"--observer", "200,45", "--lonlat"}), "--lonlat: expected a longitude in [-180, 180] and a latitude in [-90, 90] (degrees), found 200, 45"},
        {"a missing observers file", with(viewshed, {"--observers", "missing.csv"}), "missing.csv: no such file"},
        {"an unknown --values", with(viewshed, {"--observer", "560000,5110000", "--values", "colour"}), "--values: expected visible, angle or height, found 'colour'"},
        {"viewshed without an observer", viewshed, "viewshed: give --observer X,Y or --observers FILE"},
        {"--rays 0", {"accuracy", "dem.tif", "--rays", "0"}, "--rays: expected 3 .. 100000000, found 0"},
        {"an unknown compare --methods", {"compare", "dem.tif", "--methods", "exact"}, "--methods: expected names from bilinear"},
    };
    std::vector<Case> cases;
    for (const auto& [what, args, message] : options) cases.push_back({what, args, 2, message});
    runCases("option-values", cases);
}

TEST_CASE("Hostile inputs: scene files that are not regular or nest too deep", "[cli][hostile]") {
    runCases("scene-inputs",
             {{"scene: missing file", {"scene", "missing.toml"}, 2, "missing.toml: no such file"},
              {"scene: a FIFO", {"scene", "fifo.toml"}, 2, "expected a scene file as a regular file, found a pipe (FIFO)"},
              {"scene: links to /dev/zero", {"scene", "zero.toml"}, 2, "found a character device"},
              {"scene: a link loop", {"scene", "loop-a.tif"}, 2, "found a loop of symbolic links"},
              {"scene: a folder", {"scene", "folder.tif"}, 2, "folder.tif: is a directory"},
              {"scene: dotted key 50,000 levels deep", {"scene", "deep-key.toml"}, 2,
               "deep-key.toml:1:128: keys, tables and arrays nest more than 64 levels deep here"},
              {"scene: arrays 100,000 levels deep", {"scene", "deep-array.toml"}, 2,
               "deep-array.toml:1:68: keys, tables and arrays nest more than 64 levels deep here"},
              {"scene: inline tables 20,000 levels deep", {"scene", "deep-inline.toml"}, 2,
               "nest more than 64 levels deep here"},
              {"scene: a 64 MiB file", {"scene", "huge.toml"}, 2, "huge.toml: 67108865 bytes, more than the 67108864 (64.0 MiB) allowed for a scene file"}});
}

TEST_CASE("Hostile scene files: paths out of their folder, absolute, virtual or on a network", "[cli][hostile]") {
    const std::string rule = "a scene file may name only files in its own folder unless --allow-paths is given";
    runCases("scene-paths",
             {{"scene naming ../dem.tif", {"scene", "escape-dotdot.toml"}, 2,
               "escape-dotdot.toml:3:8: file: \"../dem.tif\" leads out of the scene file's folder (to /tmp/dem.tif); " + rule},
              {"scene naming /etc/hostname", {"scene", "escape-absolute.toml"}, 2,
               "escape-absolute.toml:3:8: file: \"/etc/hostname\" is an absolute path; " + rule},
              {"scene naming a link out of its folder", {"scene", "escape-link.toml"}, 2,
               "escape-link.toml:3:8: file: \"out-link.tif\" leads out of the scene file's folder (to /etc/hostname); " + rule},
              {"scene naming a /vsicurl/ path", {"scene", "network.toml"}, 2, "is a GDAL virtual or network path; " + rule},
              {"scene naming an https:// URL", {"scene", "https.toml"}, 2, "is a GDAL virtual or network path; " + rule},
              {"scene naming a /vsizip/ archive", {"scene", "archive.toml"}, 2, "is a GDAL virtual or network path; " + rule},
              {"scene draping /etc/hostname", {"scene", "drape-absolute.toml"}, 2, "drape: \"/etc/hostname\" is an absolute path"},
              {"scene writing to an absolute path", {"scene", "output-absolute.toml"}, 2,
               "output: \"/tmp/terracast-replaced.png\" is an absolute path"},
              {"scene writing to ../replaced.png", {"scene", "output-dotdot.toml"}, 2, "output: \"../replaced.png\" leads out"},
              {"scene naming its folder's DEM", {"scene", "inside.toml", "-o", "null.png", "--size", "16x9"}, 0, "rendered null.png"},
              {"scene naming a DEM elsewhere, with --allow-paths", {"scene", "trusted.toml", "--allow-paths", "-o", "null.png", "--size", "16x9"},
               0, "rendered null.png"}});
}

TEST_CASE("Hostile inputs: non-finite and absurd numbers in options", "[cli][hostile]") {
    const std::vector<std::pair<std::vector<std::string>, std::string>> options = {
        {{"render", "dem.tif", "-o", "out.png"}, "--exaggeration"},
        {{"render", "dem.tif", "-o", "out.png"}, "--haze"},
        {{"render", "dem.tif", "-o", "out.png"}, "--hillshade-blend"},
        {{"render", "dem.tif", "-o", "out.png", "--view", "map"}, "--scale"},
        {{"render", "dem.tif", "-o", "out.png"}, "--lod"},
        {{"shadow", "dem.tif", "-o", "out.tif"}, "--sun-size"},
        {{"shadow", "dem.tif", "-o", "out.tif"}, "--max-distance"},
        {{"horizon", "dem.tif", "-o", "out.tif"}, "--azimuth"},
        {{"horizon", "dem.tif", "-o", "out.tif", "--azimuth", "90"}, "--curvature-coeff"},
        {{"viewshed", "dem.tif", "-o", "out.tif", "--observer", "560000,5110000"}, "--observer-height"},
        {{"viewshed", "dem.tif", "-o", "out.tif", "--observer", "560000,5110000"}, "--target-height"},
        {{"viewshed", "dem.tif", "-o", "out.tif", "--observer", "560000,5110000"}, "--curvature-coeff"},
        {{"insolation", "dem.tif", "-o", "out.tif", "--date", "2026-06-21"}, "--linke"},
        {{"insolation", "dem.tif", "-o", "out.tif", "--date", "2026-06-21"}, "--albedo"},
        {{"compare", "dem.tif"}, "--exaggeration"},
        {{"compare", "dem.tif"}, "--lod"},
        {{"info", "dem.tif"}, "--cell-size"},
        {{"info", "dem.tif"}, "--height-scale"},
    };
    std::vector<Case> cases;
    for (const auto& [prefix, option] : options)
        for (const std::string value : {"nan", "inf", "-inf", "1e999"}) {
            // Options with a range say so; the others ask for a finite number.
            Case c{prefix[0] + " " + option + " " + value, prefix, 2, option + ": expected "};
            c.args.push_back(option);
            c.args.push_back(value);
            cases.push_back(c);
        }
    cases.push_back({"render --threads -1", {"render", "dem.tif", "-o", "out.png", "--threads", "-1"}, 2,
                     "--threads: expected a whole number from 0 to 2147483647, found '-1'"});
    cases.push_back({"viewshed --curvature-coeff -1e300",
                     {"viewshed", "dem.tif", "-o", "out.tif", "--observer", "560000,5110000", "--curvature-coeff", "-1e300"},
                     2, "--curvature-coeff: expected a coefficient from -10 to 10, found '-1e300'"});
    cases.push_back({"render --camera eye=-1e300,0,0",
                     {"render", "dem.tif", "-o", "out.png", "--camera", "eye=-1e300,0,0 look=0,0,0"}, 2,
                     "--camera: eye expects x,y,z in metres (each within 1e9), found '-1e300,0,0'"});
    runCases("options", cases);
}

TEST_CASE("Hostile outputs: inputs never overwritten, devices and pipes written in place or refused", "[cli][hostile]") {
    runCases("outputs",
             {{"shadow -o the DEM itself", {"shadow", "dem.tif", "-o", "dem.tif"}, 2, "dem.tif: output path is the input DEM"},
              {"shadow -o a link to the DEM", {"shadow", "dem.tif", "-o", "alias.tif"}, 2, "alias.tif: output path is the input DEM"},
              {"shadow -o a hard link to the DEM", {"shadow", "dem.tif", "-o", "hard.tif"}, 2, "hard.tif: output path is the input DEM"},
              {"shadow -o the DEM through ..", {"shadow", "dem.tif", "-o", "sub/../dem.tif"}, 2, "output path is the input DEM"},
              {"compare --out-dir holding the DEM as bilinear.png", {"compare", "dem.tif", "--out-dir", ".", "--size", "32x24"}, 2,
               "bilinear.png: --out-dir file is the input DEM"},
              {"render -o a folder", {"render", "dem.tif", "-o", "folder.png", "--size", "32x24"}, 2, "folder.png: "},
              {"shadow -o a link to /dev/full", {"shadow", "dem.tif", "-o", "full.tif"}, 1, "full.tif: cannot write (No space left on device)"},
              {"render -o a link to /dev/full", {"render", "dem.tif", "-o", "full.png", "--size", "32x24"}, 1,
               "full.png: cannot write (No space left on device)"},
              {"shadow -o a link to /dev/null", {"shadow", "dem.tif", "-o", "null.tif"}, 0, "shadow mask null.tif"},
              {"render -o a FIFO nobody reads", {"render", "dem.tif", "-o", "out-fifo.png", "--size", "32x24"}, 2,
               "out-fifo.png: a pipe with no reader"}});
}

TEST_CASE("Hostile inputs: Ctrl-C stops every long command between units of work", "[cli][hostile]") {
    runCases("interrupts",
             {{"scene of 4096^2 pixels at 65536 spp, SIGINT after 1.5 s", {"scene", "long.toml", "-o", "long.png"}, 130,
               "terracast: interrupted; no output written", 1.5},
              {"accuracy of 3 M rays, SIGINT after 1 s", {"accuracy", "dem.tif", "--rays", "3000000", "--json", "acc.json"}, 130,
               "terracast: interrupted; no output written", 1.0},
              {"compare at 2048x2048 into a new folder, SIGINT after 1.5 s",
               {"compare", "dem.tif", "--out-dir", "new-folder", "--size", "2048x2048"}, 130,
               "terracast: interrupted; no output written", 1.5}});
}

TEST_CASE("Hostile inputs: Ctrl-C while GDAL waits on a server that never answers", "[cli][hostile]") {
    // A server that accepts the connection and then says nothing.
    const int listener = ::socket(AF_INET, SOCK_STREAM, 0);
    REQUIRE(listener >= 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
    socklen_t length = sizeof address;
    REQUIRE(::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length) == 0);
    REQUIRE(::listen(listener, 8) == 0);
    const std::string url = "/vsicurl/http://127.0.0.1:" + std::to_string(ntohs(address.sin_port)) + "/dem.tif";
    Case c{"info on a silent server, interrupted after 1 s", {"info", url}, 130, "terracast: interrupted; no output written",
           1.0};
    TempDir dir("hostile-network");
    RunSettings settings;
    settings.workDir = dir.path();
    settings.timeoutS = 20.0;
    settings.interruptAfterS = c.interruptAfterS;
    const ArgsResult r = runTerracastArgs(c.args, settings);
    ::close(listener);
    INFO(r.err);
    CHECK_FALSE(r.hung);
    CHECK(r.exitCode == 130);
    CHECK(r.err == c.message + "\n");
    CHECK(r.stopSeconds < 4.0);
    CHECK(dir.entryCount() == 0);
}

TEST_CASE("Hostile outputs: a 248-byte output name is written, and temporary files of dead runs are cleared",
          "[cli][hostile]") {
    TempDir dir("hostile-names");
    fs::copy_file(kStHelens, dir.path() / "dem.tif");
    // A temporary file left by a run killed between writing and renaming (its process is gone: a pid above
    // Linux's largest), and one of a run still going (this test's own process).
    const std::string stale = ".terracast-4194305-0.tmp.png";
    const std::string live = ".terracast-" + std::to_string(::getpid()) + "-0.tmp.png";
    std::ofstream(dir.path() / stale) << "partial";
    std::ofstream(dir.path() / live) << "in progress";
    const std::string name = std::string(244, 'x') + ".png";
    RunSettings settings;
    settings.workDir = dir.path();
    const ArgsResult r = runTerracastArgs({"render", "dem.tif", "--size", "32x24", "-o", name}, settings);
    INFO(r.err);
    CHECK(r.exitCode == 0);
    CHECK(fs::file_size(dir.path() / name) > 100);
    CHECK_FALSE(fs::exists(dir.path() / stale));
    CHECK(fs::exists(dir.path() / live));
    CHECK(dir.entryCount() == 3);  // the DEM, the picture and the live run's file
}
