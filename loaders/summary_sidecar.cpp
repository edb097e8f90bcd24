// The sidecar's layout: a text line naming the format, a text line holding the key, then the summary's fields
// and its two per-tile arrays in the machine's own binary layout (the key names the machine's byte order and
// sizes, so a sidecar made elsewhere is made again rather than misread).
#include "loaders/summary_sidecar.h"

#include "heightfield/height_tile.h"
#include "loaders/image_io.h"

#include <fmt/format.h>

#include <bit>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace terracast {
namespace {

namespace fs = std::filesystem;

constexpr char kFormatLine[] = "terracast grid summary 1\n";

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

std::string summarySidecarPath(const std::string& demPath) { return demPath + ".terracast-summary"; }

std::string summaryKey(const DemWindowReader& reader) {
    std::string key = fmt::format("{} {}x{} {} {}-endian;", reader.decodingKey(), reader.width(), reader.height(),
                                  sizeof(Fields), std::endian::native == std::endian::little ? "little" : "big");
    const auto files = reader.files();
    if (files.empty()) return "";
    for (const std::string& file : files) {
        std::error_code ec;
        const fs::path path = fs::absolute(file, ec);
        if (ec || !fs::is_regular_file(path, ec)) return "";
        const auto size = fs::file_size(path, ec);
        const auto modified = fs::last_write_time(path, ec);
        if (ec) return "";
        // The key is one line: a file name with a line break gets no sidecar.
        if (path.string().find('\n') != std::string::npos) return "";
        key += fmt::format(" {} {} {};", path.string(), size,
                           std::chrono::duration_cast<std::chrono::nanoseconds>(modified.time_since_epoch()).count());
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
    if (key.empty()) return "the raster is not made of local files";
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

}  // namespace terracast
