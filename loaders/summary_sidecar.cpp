// The sidecar's layout: a text line naming the format, a text line holding the key, then the summary's fields
// and its two per-tile arrays in the machine's own binary layout (the key names the machine's byte order and
// sizes, so a sidecar made elsewhere is made again rather than misread).
#include "loaders/summary_sidecar.h"

#include "heightfield/height_tile.h"
#include "loaders/image_io.h"

#include <fmt/format.h>

#include <sys/stat.h>

#include <bit>
#include <cctype>
#include <cmath>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace terracast {
namespace {

namespace fs = std::filesystem;

// The format's and the summary's version: raise it whenever the layout below or what a summary holds changes
// (GridSummaryBuilder, PyramidCoding::forHeights, the int16 storage choice), so that older sidecars are made again.
constexpr char kFormatLine[] = "terracast grid summary 2\n";

// The summary's fixed fields, in the order they are stored.
struct Fields {
    int64_t width, height;
    float minHeightM, maxHeightM;
    int64_t nodataVertices, validCells;
    int32_t storage;
    int32_t codeOffset;
    double codeScale;
    int32_t pyramidOffset;
    double pyramidScale, pyramidCodesPerMetre;
    int64_t tiles;
};

template <class T>
void append(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

template <class T>
bool take(std::string_view& in, T& value) {
    if (in.size() < sizeof value) return false;
    std::memcpy(&value, in.data(), sizeof value);
    in.remove_prefix(sizeof value);
    return true;
}

}  // namespace

std::string summarySidecarPath(const std::string& demPath, double exaggeration) {
    if (exaggeration == 1.0) return demPath + ".terracast-summary";
    return fmt::format("{}.x{}.terracast-summary", demPath, exaggeration);
}

std::string summaryKey(const DemWindowReader& reader) {
    std::string key = fmt::format("{} {}x{} {} {}-endian;", reader.decodingKey(), reader.width(), reader.height(),
                                  sizeof(Fields), std::endian::native == std::endian::little ? "little" : "big");
    const auto files = reader.files();
    if (files.empty()) return "";
    for (size_t k = 0; k < files.size(); ++k) {
        std::error_code ec;
        const fs::path path = fs::absolute(files[k], ec);
        // The key is one line: a file name with a line break gets no sidecar.
        if (ec || path.string().find('\n') != std::string::npos) return "";
        // GDAL lists a VRT's sources but not the sources of a source that is itself a VRT: a change there could
        // not be seen, so such a mosaic gets no sidecar.
        std::string extension = path.extension().string();
        for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (k > 0 && extension == ".vrt") return "";
        // Size, modification time, and the inode's change time, which every write, rename or copy over the file
        // moves and no tool sets back (`touch -r` and `cp -p` restore the modification time only), with the
        // device and inode: a file replaced by another is another inode.
        struct stat st {};
        if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return "";
        key += fmt::format(" {} {} {}.{:09d} {}.{:09d} {}:{};", path.string(), int64_t(st.st_size),
                           int64_t(st.st_mtim.tv_sec), long(st.st_mtim.tv_nsec), int64_t(st.st_ctim.tv_sec),
                           long(st.st_ctim.tv_nsec), uint64_t(st.st_dev), uint64_t(st.st_ino));
    }
    return key;
}

std::optional<GridSummary> readSummarySidecar(const std::string& sidecarPath, const std::string& key, int64_t width,
                                              int64_t height) {
    if (key.empty()) return std::nullopt;
    std::ifstream file(sidecarPath, std::ios::binary);
    if (!file) return std::nullopt;
    const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    std::string_view in(text);
    const std::string head = std::string(kFormatLine) + key + "\n";
    if (in.substr(0, head.size()) != head) return std::nullopt;
    in.remove_prefix(head.size());
    Fields f{};
    if (!take(in, f)) return std::nullopt;
    const TileLayout layout{width, height};
    if (f.width != width || f.height != height || f.tiles != layout.tileCount() ||
        in.size() != 2 * size_t(f.tiles) * sizeof(int16_t) ||
        (f.storage != int32_t(HeightStorage::Int16) && f.storage != int32_t(HeightStorage::Float32)))
        return std::nullopt;
    GridSummary s;
    s.width = f.width;
    s.height = f.height;
    s.minHeightM = f.minHeightM;
    s.maxHeightM = f.maxHeightM;
    s.nodataVertices = f.nodataVertices;
    s.validCells = f.validCells;
    s.storage = HeightStorage(f.storage);
    s.codeOffset = f.codeOffset;
    s.codeScale = f.codeScale;
    s.pyramid.offset = f.pyramidOffset;
    s.pyramid.scale = f.pyramidScale;
    s.pyramid.codesPerMetre = f.pyramidCodesPerMetre;
    s.tileMaxCodes.resize(size_t(f.tiles));
    s.tileMinCodes.resize(size_t(f.tiles));
    std::memcpy(s.tileMaxCodes.data(), in.data(), size_t(f.tiles) * sizeof(int16_t));
    std::memcpy(s.tileMinCodes.data(), in.data() + size_t(f.tiles) * sizeof(int16_t), size_t(f.tiles) * sizeof(int16_t));
    return s;
}

std::string writeSummarySidecar(const std::string& sidecarPath, const std::string& key, const GridSummary& s) {
    if (key.empty()) return "its files cannot all be checked for changes (a network or in-memory source, or a VRT of VRTs)";
    std::string out = std::string(kFormatLine) + key + "\n";
    Fields f;
    std::memset(&f, 0, sizeof f);  // the padding too: every byte written is defined
    f.width = s.width;
    f.height = s.height;
    f.minHeightM = s.minHeightM;
    f.maxHeightM = s.maxHeightM;
    f.nodataVertices = s.nodataVertices;
    f.validCells = s.validCells;
    f.storage = int32_t(s.storage);
    f.codeOffset = s.codeOffset;
    f.codeScale = s.codeScale;
    f.pyramidOffset = s.pyramid.offset;
    f.pyramidScale = s.pyramid.scale;
    f.pyramidCodesPerMetre = s.pyramid.codesPerMetre;
    f.tiles = int64_t(s.tileMaxCodes.size());
    append(out, f);
    out.append(reinterpret_cast<const char*>(s.tileMaxCodes.data()), s.tileMaxCodes.size() * sizeof(int16_t));
    out.append(reinterpret_cast<const char*>(s.tileMinCodes.data()), s.tileMinCodes.size() * sizeof(int16_t));
    try {
        writeFileAtomically(sidecarPath, out);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

namespace {
constexpr char kCoarseFormatLine[] = "terracast coarse grid 1\n";
}  // namespace

std::string coarseSidecarPath(const std::string& demPath, double exaggeration, int levels) {
    if (exaggeration == 1.0) return fmt::format("{}.terracast-lod{}", demPath, levels);
    return fmt::format("{}.x{}.terracast-lod{}", demPath, exaggeration, levels);
}

std::optional<CoarseHeights> readCoarseSidecar(const std::string& sidecarPath, const std::string& key, int64_t width,
                                               int64_t height) {
    if (key.empty() || width < 2 || height < 2) return std::nullopt;
    std::ifstream file(sidecarPath, std::ios::binary);
    if (!file) return std::nullopt;
    // The header and the size first: nothing is allocated for a file that is not the one expected.
    const std::string head = std::string(kCoarseFormatLine) + key + "\n";
    const size_t n = size_t(width) * size_t(height);
    std::error_code ec;
    const auto size = fs::file_size(sidecarPath, ec);
    if (ec || size != head.size() + 2 * sizeof(int64_t) + n * (sizeof(float) + 1)) return std::nullopt;
    std::string got(head.size(), '\0');
    int64_t w = 0, h = 0;
    if (!file.read(got.data(), std::streamsize(got.size())) || got != head ||
        !file.read(reinterpret_cast<char*>(&w), sizeof w) || !file.read(reinterpret_cast<char*>(&h), sizeof h) ||
        w != width || h != height)
        return std::nullopt;
    CoarseHeights c;
    c.width = w;
    c.height = h;
    c.heightsM.resize(n);
    c.valid.resize(n);
    if (!file.read(reinterpret_cast<char*>(c.heightsM.data()), std::streamsize(n * sizeof(float))) ||
        !file.read(reinterpret_cast<char*>(c.valid.data()), std::streamsize(n)))
        return std::nullopt;
    // What a grid would refuse (a valid height that is not finite, a flag other than 0 or 1) is a damaged file.
    for (size_t k = 0; k < n; ++k)
        if (c.valid[k] > 1 || (c.valid[k] && !std::isfinite(c.heightsM[k]))) return std::nullopt;
    return c;
}

std::string writeCoarseSidecar(const std::string& sidecarPath, const std::string& key, const CoarseHeights& c) {
    if (key.empty()) return "its files cannot all be checked for changes";
    try {
        const std::string head = std::string(kCoarseFormatLine) + key + "\n";
        const int64_t size[2] = {c.width, c.height};
        writeFileAtomically(sidecarPath,
                            {head, std::string_view(reinterpret_cast<const char*>(size), sizeof size),
                             std::string_view(reinterpret_cast<const char*>(c.heightsM.data()),
                                              c.heightsM.size() * sizeof(float)),
                             std::string_view(reinterpret_cast<const char*>(c.valid.data()), c.valid.size())});
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

}  // namespace terracast
