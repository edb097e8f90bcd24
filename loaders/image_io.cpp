// Writing and reading pictures. PNG holds 8-bit sRGB (transfer function of IEC 61966-2-1) and is written by the
// loaders' own PNG encoder (libspng); EXR holds linear half floats and, like every read, goes through the image
// codec module (OpenImageIO).
#include "loaders/loader_support.h"
#include "loaders/image_codec.h"
#include "loaders/image_io.h"
#include "loaders/png_encoder.h"

#include "heightfield/large_buffer.h"
#include "tracer/core/errors.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <utility>

namespace terracast {
namespace {

using namespace loader_support;

namespace fs = std::filesystem;

// True when `path` exists and is (or links to) something other than a regular file or folder: a device such as
// /dev/null or /dev/full, or a pipe.
bool isDeviceOrPipe(const std::string& path) {
    std::error_code ec;
    const auto status = fs::status(path, ec);
    return !ec && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
}

// Writes all of `bytes` to `fd`; returns 0, or the errno of the first failed write.
int writeAll(int fd, std::string_view bytes) {
    while (!bytes.empty()) {
        const ssize_t n = ::write(fd, bytes.data(), bytes.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return n < 0 ? errno : EIO;
        bytes.remove_prefix(static_cast<size_t>(n));
    }
    return 0;
}

// Creates the temporary file beside `path` in `folder` and returns its descriptor and name. A folder where no
// file can be made is the user's to fix (InputError); anything else is a runtime failure.
std::pair<int, fs::path> createTemporary(const std::string& path, const fs::path& folder) {
    const fs::path temporary = temporaryPathFor(folder, lowerExtension(path));
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd >= 0) return {fd, temporary};
    const int error = errno;
    if (error == EACCES || error == EPERM || error == EROFS || error == ENOENT || error == ENOTDIR)
        throw InputError(fmt::format("{}: folder '{}' is not writable ({})", path, folder.string(), std::strerror(error)));
    throw std::runtime_error(fmt::format("{}: cannot create a file in '{}' ({})", path, folder.string(),
                                         std::strerror(error)));
}

// Opens a device or pipe for writing in place. A pipe without a reader would block the open forever: it is
// refused instead.
int openInPlace(const std::string& path) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        const int error = errno;
        if (error == ENXIO) throw InputError(fmt::format("{}: a pipe with no reader; nothing would take the output", path));
        throw std::runtime_error(fmt::format("{}: cannot open for writing ({})", path, std::strerror(error)));
    }
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    return fd;
}

}  // namespace

float linearFromSrgb(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

uint8_t srgbByte(float linear) { return static_cast<uint8_t>(std::lround(srgbFromLinear(linear) * 255.0f)); }

std::optional<glm::vec3> parseHexColour(const std::string& text) {
    if (text.size() != 7 || text[0] != '#') return std::nullopt;
    glm::vec3 linear{0.0f};
    for (int c = 0; c < 3; ++c) {
        unsigned value = 0;
        for (int k = 0; k < 2; ++k) {
            const char ch = text[size_t(1 + 2 * c + k)];
            const int digit = ch >= '0' && ch <= '9' ? ch - '0'
                            : ch >= 'a' && ch <= 'f' ? ch - 'a' + 10
                            : ch >= 'A' && ch <= 'F' ? ch - 'A' + 10
                                                     : -1;
            if (digit < 0) return std::nullopt;
            value = value * 16 + unsigned(digit);
        }
        linear[c] = linearFromSrgb(float(value) / 255.0f);
    }
    return linear;
}

float srgbFromLinear(float linear) {
    if (!(linear > 0.0f)) return 0.0f;
    if (linear >= 1.0f) return 1.0f;
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

void checkCanWrite(const std::string& path) {
    // A device or pipe is written in place at the end; opening a pipe now would end its reader's stream.
    if (isDeviceOrPipe(path)) return;
    const fs::path folder = writableFolder(path);
    // Permission bits do not tell the whole story (read-only mounts, /proc, root): create a file to be sure.
    const auto [fd, probe] = createTemporary(path, folder);
    ::close(fd);
    std::error_code ignored;
    fs::remove(probe, ignored);
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
    writeFileAtomically(path, std::initializer_list<std::string_view>{bytes});
}

void writeFileAtomically(const std::string& path, std::initializer_list<std::string_view> pieces) {
    const auto writePieces = [&pieces](int fd) {
        for (const std::string_view piece : pieces)
            if (const int error = writeAll(fd, piece)) return error;
        return 0;
    };
    if (isDeviceOrPipe(path)) {
        // A device or a pipe is written in place: renaming over it would replace it, and it keeps no partial file.
        const int fd = openInPlace(path);
        const int error = writePieces(fd);
        const bool closed = ::close(fd) == 0;
        if (error != 0 || !closed)
            throw std::runtime_error(fmt::format("{}: cannot write ({})", path, std::strerror(error ? error : errno)));
        return;
    }
    const fs::path folder = writableFolder(path);
    auto [fd, temporaryPath] = createTemporary(path, folder);
    TemporaryFile temporary(temporaryPath);
    // Failures from here on (a full disk, an I/O error) are runtime failures: exit 1.
    const int error = writePieces(fd);
    const bool closed = ::close(fd) == 0;
    if (error != 0 || !closed)
        throw std::runtime_error(fmt::format("{}: cannot write in '{}' ({})", path, folder.string(),
                                             std::strerror(error ? error : errno)));
    if (const int failed = commitTemporary(temporary.path(), fs::path(path)))
        throw std::runtime_error(fmt::format("{}: cannot write ({})", path, std::strerror(failed)));
    temporary.release();
}

void writeTextFile(const std::string& path, const std::string& text) { writeFileAtomically(path, text); }

void prepareImageWriter(const std::string& path) {
    if (lowerExtension(path) == ".exr") image_codec::api();
}

namespace {

// The bytes of an image in the format `path`'s extension names, encoded in memory from `pixels` (of type `given`,
// `channels` per pixel, stored as `stored`). Throws naming `path` when the encoder fails.
std::string encodeInMemory(const std::string& path, int width, int height, int channels, image_codec::PixelType stored,
                           const std::string& colorSpace, image_codec::PixelType given, const void* pixels) {
    std::string bytes, error;
    if (!image_codec::api().encode(path, width, height, channels, stored, colorSpace, given, pixels, bytes, error))
        throw std::runtime_error(fmt::format("{}: cannot encode the image ({})", path, firstLine(error)));
    return bytes;
}

}  // namespace

void writeImage(const std::string& path, const RgbImage& image) {
    const std::string ext = lowerExtension(path);
    if (ext != ".png" && ext != ".exr")
        throw InputError(fmt::format("{}: unsupported output format '{}' (expected .png or .exr)", path, ext));
    const bool png = ext == ".png";
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3)
        throw std::invalid_argument(fmt::format("writeImage: {} x {} image holds {} values", image.width,
                                                image.height, image.rgb.size()));

    // The image is encoded in memory, then written through writeFileAtomically, which sees every system call's
    // error (a full disk included) and never leaves a partial file.
    using image_codec::PixelType;
    std::string bytes;
    if (png) {
        std::vector<uint8_t> levels(image.rgb.size());
        // The transfer function's power takes about 7 ns a value: a 1920 x 1080 picture's 6.2 million values
        // are converted on the array-pass threads (heightfield/large_buffer.h), in contiguous slices.
        const int64_t n = int64_t(levels.size());
        runInSlices(n, n < (int64_t(1) << 20) ? 1 : arrayPassThreads(), [&](int64_t k0, int64_t k1) {
            for (int64_t k = k0; k < k1; ++k) levels[size_t(k)] = srgbByte(image.rgb[size_t(k)]);
        });
        bytes = png::encode(path, image.width, image.height, png::Layout::SrgbRgb8, levels.data());
    } else {
        bytes = encodeInMemory(path, image.width, image.height, 3, PixelType::Half, "Linear", PixelType::Float,
                               image.rgb.data());
    }
    writeFileAtomically(path, bytes);
}

std::string encodeGreyPng16(const std::string& name, int width, int height, const std::vector<uint16_t>& samples) {
    if (width <= 0 || height <= 0 || samples.size() != size_t(width) * size_t(height))
        throw std::invalid_argument(fmt::format("encodeGreyPng16: {} x {} image holds {} samples", width, height,
                                                samples.size()));
    return png::encode(name, width, height, png::Layout::Grey16, samples.data());
}

RgbImage readImage(const std::string& path) {
    std::error_code ec;
    const auto status = fs::status(path, ec);
    if (status.type() == fs::file_type::not_found) throw InputError(path + ": no such file");
    if (fs::is_directory(status)) throw InputError(path + ": is a directory");

    image_codec::ImageHeader spec;
    std::string error;
    const image_codec::OpenImage input(image_codec::api().open(path, spec, error));
    if (!input.get()) throw InputError(path + ": cannot read image (" + firstLine(error) + ")");
    const int channels = std::min(spec.channels, 3);
    if (spec.width <= 0 || spec.height <= 0 || channels < 1)
        throw InputError(fmt::format("{}: image is {} x {} with {} channels", path, spec.width, spec.height,
                                     spec.channels));

    const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
    std::vector<float> stored(pixels * static_cast<size_t>(channels));
    if (!image_codec::api().read(input.get(), channels, image_codec::PixelType::Float, stored.data(), error))
        throw InputError(path + ": cannot read pixels (" + firstLine(error) + ")");

    // Integer files (PNG) hold display-referred sRGB; float files (EXR) hold linear values.
    const bool srgb = !spec.floating;
    RgbImage image;
    image.width = spec.width;
    image.height = spec.height;
    image.rgb.resize(pixels * 3);
    for (size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < 3; ++c) {
            const float value = stored[p * static_cast<size_t>(channels) + static_cast<size_t>(channels >= 3 ? c : 0)];
            image.rgb[p * 3 + static_cast<size_t>(c)] = srgb ? linearFromSrgb(value) : value;
        }
    }
    return image;
}

}  // namespace terracast
