// PNG height maps: channel 0 of an 8- or 16-bit image, scaled by the options, rows flipped so that y points north.
// libspng decodes the common layouts row by row straight into the grid's int16 codes; the image codec module
// (OpenImageIO) reads the rest (palettes, 1- to 4-bit grey, interlacing) into floats first.
#include "loaders/png_height_map.h"

#include "heightfield/large_buffer.h"
#include "loaders/dem_checks.h"
#include "loaders/image_codec.h"
#include "loaders/loader_support.h"
#include "tracer/core/errors.h"
#include "tracer/core/text.h"

#include <fmt/format.h>
#include <spng.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <fstream>
#include <string>
#include <vector>

namespace terracast {
namespace {

using namespace loader_support;
using namespace dem_checks;

// Walks the PNG chunk layout (signature, then length, type, data and CRC per chunk, up to IEND) without
// decoding anything, so that a truncated file gets a one-line InputError: OpenImageIO leaves libpng's default
// error handler in place, which prints to stderr. A file named .png without the PNG signature is refused here.
void checkPngIsComplete(const std::string& path) {
    constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    unsigned char bytes[8] = {};
    if (ec || !in.read(reinterpret_cast<char*>(bytes), 8)) return;
    if (!std::equal(bytes, bytes + 8, kSignature))
        throw InputError(path + ": not a PNG file (its first 8 bytes are not the PNG signature)");
    int64_t width = 0, height = 0;
    int bitDepth = 8, channels = 1;
    uint64_t compressedBytes = 0;
    for (uint64_t position = 8;;) {
        if (position + 8 > size || !in.seekg(static_cast<std::streamoff>(position)) ||
            !in.read(reinterpret_cast<char*>(bytes), 8))
            throw InputError(fmt::format("{}: truncated PNG ({} bytes, ends before its IEND chunk)", path, size));
        const uint64_t length = uint64_t{bytes[0]} << 24 | uint64_t{bytes[1]} << 16 | uint64_t{bytes[2]} << 8 |
                                uint64_t{bytes[3]};
        // The chunk type as printable text: a damaged file's type bytes may be anything, newlines included.
        std::string type;
        for (int k = 4; k < 8; ++k)
            type += std::isprint(bytes[k]) ? std::string(1, static_cast<char>(bytes[k])) : fmt::format("\\x{:02x}", bytes[k]);
        const uint64_t end = position + 12 + length;  // length and type, data, CRC
        if (end > size)
            throw InputError(fmt::format("{}: truncated PNG ({} chunk at byte {} ends at byte {}, file has {})", path,
                                         type, position, end, size));
        if (position == 8 && type == "IHDR" && length >= 10) {
            // The header's size, read here so that a 0 x 0 image gets the same message as any other raster.
            unsigned char header[10] = {};
            if (in.read(reinterpret_cast<char*>(header), 10)) {
                const auto be32 = [](const unsigned char* b) {
                    return int64_t{b[0]} << 24 | int64_t{b[1]} << 16 | int64_t{b[2]} << 8 | int64_t{b[3]};
                };
                width = be32(header);
                height = be32(header + 4);
                bitDepth = header[8];
                const int colourType = header[9];
                channels = colourType == 2 ? 3 : colourType == 4 ? 2 : colourType == 6 ? 4 : 1;
                if (width == 0 || height == 0) throw InputError(fmt::format("{}: raster is {} x {}, with no sample to trace", path, width, height));
            }
        }
        // Each byte of a chunk type is a letter; an upper-case first letter marks a chunk a decoder must know,
        // and PNG defines four.
        const bool letters = std::all_of(bytes + 4, bytes + 8, [](unsigned char c) { return std::isalpha(c) != 0; });
        const bool critical = std::isupper(bytes[4]) != 0;
        if (!letters || (critical && type != "IHDR" && type != "PLTE" && type != "IDAT" && type != "IEND"))
            throw InputError(fmt::format("{}: corrupt PNG (chunk type {} at byte {} is {})", path, type, position,
                                         letters ? "a critical chunk PNG does not define" : "not four letters"));
        if (type == "IDAT") compressedBytes += length;
        if (type == "IEND") {
            // Deflate encodes at most 258 bytes in a match of about 2 bits (1032 : 1): a header that claims more
            // samples than the compressed data could hold is refused here, before the decoder allocates for it.
            // Each row adds its filter byte (and interlaced passes up to seven per row).
            const double rowBytes = std::ceil(double(width) * channels * bitDepth / 8.0) + 8.0;
            const double rawBytes = double(height) * rowBytes;
            if (rawBytes > 1100.0 * double(compressedBytes) + 65536.0)
                throw InputError(fmt::format("{}: header claims {} x {} samples ({} of pixel data), more than its {} "
                                             "compressed bytes can hold; the file is truncated or corrupt",
                                             path, width, height, humanBytes(rawBytes), compressedBytes));
            return;
        }
        position = end;
    }
}

// Channel 0 of an open image as raw stored integers, in image row order (row 0 at the top).
template <typename Sample>
std::vector<Sample> readChannel0(const std::string& path, void* input, const image_codec::ImageHeader& spec,
                                 image_codec::PixelType type) {
    std::vector<Sample> samples(static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height));
    std::string error;
    if (!image_codec::api().read(input, 1, type, samples.data(), error))
        throw InputError(path + ": cannot read pixels (" + firstLine(error) + ")");
    return samples;
}

// Decodes `path` with libspng when its layout is one decoded row by row into codes: 8- or 16-bit samples (grey,
// grey and alpha, RGB or RGBA), not interlaced. Nothing for other layouts, which the caller reads through the
// image codec module. Each row is decoded as stored (host-endian 16-bit samples, no gamma or transparency
// applied, as the codec module reads it) and its channel 0 becomes int16 codes: for 16-bit samples, the sample
// less 32768 with a code offset of 32768; for 8-bit samples, the sample itself. The codes stand for exactly
// the heights the float path gives (the sample times the height scale, in double, rounded to float).
std::optional<LoadedDem> loadWithSpng(const std::string& path, const DemLoadOptions& options) {
    struct Closer {
        void operator()(std::FILE* f) const { std::fclose(f); }
        void operator()(spng_ctx* c) const { spng_ctx_free(c); }
    };
    std::unique_ptr<std::FILE, Closer> file(std::fopen(path.c_str(), "rb"));
    if (!file) return std::nullopt;
    std::unique_ptr<spng_ctx, Closer> ctx(spng_ctx_new(0));
    if (!ctx || spng_set_png_file(ctx.get(), file.get()) != 0) return std::nullopt;
    // libspng inflates compressed text and colour-profile chunks before the first row, by default up to 2 GiB
    // each: a few kilobytes of file could claim gigabytes. A height map needs none of them; these bounds keep
    // what they may take near libpng's (8 MB per chunk); a PNG past them is read through the codec module.
    if (spng_set_chunk_limits(ctx.get(), size_t(8) << 20, size_t(32) << 20) != 0) return std::nullopt;
    // A header libspng refuses (its own limits, a bad CRC) goes to the codec module, whose messages the
    // loader's tests pin down.
    spng_ihdr ihdr{};
    if (spng_get_ihdr(ctx.get(), &ihdr) != 0) return std::nullopt;
    int channels = 0;
    switch (ihdr.color_type) {
    case SPNG_COLOR_TYPE_GRAYSCALE: channels = 1; break;
    case SPNG_COLOR_TYPE_GRAYSCALE_ALPHA: channels = 2; break;
    case SPNG_COLOR_TYPE_TRUECOLOR: channels = 3; break;
    case SPNG_COLOR_TYPE_TRUECOLOR_ALPHA: channels = 4; break;
    default: return std::nullopt;  // palette
    }
    if ((ihdr.bit_depth != 8 && ihdr.bit_depth != 16) || ihdr.interlace_method != SPNG_INTERLACE_NONE)
        return std::nullopt;

    LoadedDem dem;
    dem.path = path;
    dem.driver = "PNG (libspng)";
    const int64_t width = ihdr.width, height = ihdr.height;
    dem.sourceWidth = width;
    dem.sourceHeight = height;
    checkRasterSize(path, width, height, options.maxBytes);
    if (channels > 1)
        dem.warnings.push_back(fmt::format("{}: {} channels, using channel 0 as height", path, channels));

    const bool wide = ihdr.bit_depth == 16;
    const int32_t offset = wide ? 32768 : 0;
    const double scale = options.imageHeightScale;
    // The largest sample's height must be a plausible one (the float path checks every sample alike).
    const int32_t top = wide ? 65535 : 255;
    const bool checkHeights = double(top) * scale > kMaxAbsHeightM;

    int status = spng_decode_image(ctx.get(), nullptr, 0, SPNG_FMT_PNG, SPNG_DECODE_PROGRESSIVE);
    // An ancillary chunk past those bounds: libpng, behind the codec module, skips such chunks with a warning.
    if (status == SPNG_ECHUNK_LIMITS) return std::nullopt;
    if (status != 0) throw InputError(fmt::format("{}: cannot read PNG ({})", path, spng_strerror(status)));
    const size_t rowBytes = size_t(width) * size_t(channels) * (wide ? 2 : 1);
    std::vector<uint8_t> row(rowBytes);
    std::vector<int16_t> codes = largeVector<int16_t>(static_cast<size_t>(width * height));
    for (int64_t r = 0; r < height; ++r) {
        status = spng_decode_row(ctx.get(), row.data(), row.size());
        if (status != 0 && !(status == SPNG_EOI && r == height - 1))
            throw InputError(fmt::format("{}: cannot read PNG (row {} of {}: {})", path, r, height, spng_strerror(status)));
        // Image row 0 is the north edge; grid row 0 is the south edge.
        int16_t* out = codes.data() + (height - 1 - r) * width;
        if (wide) {
            const auto* in = reinterpret_cast<const uint16_t*>(row.data());
            for (int64_t i = 0; i < width; ++i) out[i] = static_cast<int16_t>(int32_t(in[i * channels]) - offset);
        } else {
            for (int64_t i = 0; i < width; ++i) out[i] = static_cast<int16_t>(row[size_t(i * channels)]);
        }
        if (checkHeights)
            for (int64_t i = 0; i < width; ++i) {
                const double heightM = double(int32_t(out[i]) + offset) * scale;
                if (heightM > kMaxAbsHeightM) throwBadHeight(path, i, r, heightM);
            }
    }
    dem.grid = makeGrid(path, width, height, options.imageCellSizeM, options.imageCellSizeM, std::move(codes), offset,
                        scale);
    return dem;
}

}  // namespace

LoadedDem loadPngHeightMap(const std::string& path, const DemLoadOptions& options) {
    if (!(options.imageCellSizeM > 0.0) || !std::isfinite(options.imageCellSizeM))
        throw InputError(fmt::format("{}: image cell size must be positive and finite, got {} m", path,
                                     options.imageCellSizeM));
    if (!(options.imageHeightScale > 0.0) || !std::isfinite(options.imageHeightScale))
        throw InputError(fmt::format("{}: image height scale must be positive and finite, got {} m per unit", path,
                                     options.imageHeightScale));

    checkPngIsComplete(path);
    if (auto dem = loadWithSpng(path, options)) return std::move(*dem);
    // The codec module is loaded first: a failure to load it is no message of libpng's.
    const image_codec::Api& codec = image_codec::api();
    // libpng's own error lines are kept off stderr; OpenImageIO passes their text on through its errors.
    CapturedStderr libpngMessages;
    image_codec::ImageHeader spec;  // channel 0 is read as stored, not multiplied by alpha
    std::string error;
    const image_codec::OpenImage input(codec.open(path, spec, error));
    if (!input.get()) throw InputError(path + ": cannot read PNG (" + firstLine(error) + ")");

    LoadedDem dem;
    dem.path = path;
    dem.driver = "PNG (OpenImageIO)";
    const int64_t width = spec.width;
    const int64_t height = spec.height;
    dem.sourceWidth = width;
    dem.sourceHeight = height;
    checkRasterSize(path, width, height, options.maxBytes);
    if (spec.channels > 1)
        dem.warnings.push_back(fmt::format("{}: {} channels, using channel 0 as height", path, spec.channels));

    const auto vertexCount = static_cast<size_t>(width * height);
    std::vector<float> heightsM = largeVector<float>(vertexCount);
    // Image row 0 is the north edge; grid row 0 is the south edge.
    auto store = [&](const auto& samples) {
        for (int64_t row = 0; row < height; ++row) {
            const int64_t j = height - 1 - row;
            for (int64_t i = 0; i < width; ++i) {
                const double heightM =
                    static_cast<double>(samples[static_cast<size_t>(row * width + i)]) * options.imageHeightScale;
                if (heightM > kMaxAbsHeightM) throwBadHeight(path, i, row, heightM);
                heightsM[static_cast<size_t>(j * width + i)] = static_cast<float>(heightM);
            }
        }
    };
    using image_codec::PixelType;
    if (spec.format == PixelType::UInt8)
        store(readChannel0<uint8_t>(path, input.get(), spec, PixelType::UInt8));
    else if (spec.format == PixelType::UInt16)
        store(readChannel0<uint16_t>(path, input.get(), spec, PixelType::UInt16));
    else
        throw InputError(fmt::format("{}: {} samples, expected 8- or 16-bit unsigned integers", path,
                                     spec.formatName));

    dem.grid = makeGrid(path, width, height, options.imageCellSizeM, options.imageCellSizeM, std::move(heightsM), {},
                        options.imageHeightScale);
    return dem;
}

}  // namespace terracast
