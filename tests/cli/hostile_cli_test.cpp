// The hostile-input suite: every case runs the real executable in a folder of its own, and must end (no hang:
// killed after a timeout), with the expected exit code, exactly one line on stderr naming what is wrong, and the
// folder as it was (nothing written, nothing removed, no input changed). The README's Reliability table lists
// every case with its exit code and message: scripts/reliability_table.sh rewrites it, and the suite fails when
// a case's row there differs from what the executable printed.
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/stat.h>

#include <atomic>
#include <cstdlib>
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

struct Case {
    std::string name;               // what the case tries, for the table
    std::vector<std::string> args;  // run in the case folder
    int exitCode = 2;
    std::string message;            // part of the one stderr line
    double interruptAfterS = -1.0;  // SIGINT this long after the start
};

// The files a case folder starts with: a real DEM and the hostile inputs beside it.
void makeFixtures(const fs::path& dir) {
    fs::copy_file(kStHelens, dir / "dem.tif");
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
    for (const Case& c : cases) {
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
    std::vector<Case> cases;
    for (const auto& [command, options] : demCommands())
        for (const auto& [what, input] : inputs) {
            Case c{command + ": " + what, {command, input.first}, 2, input.second};
            c.args.insert(c.args.end(), options.begin(), options.end());
            cases.push_back(c);
        }
    runCases("dem-inputs", cases);
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
    CHECK(r.seconds < 5.0);
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
