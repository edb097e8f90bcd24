// Writing and reading pictures through OpenImageIO. PNG holds 8-bit sRGB (transfer function of
// IEC 61966-2-1); EXR holds linear half floats.
#include "loaders/loader_support.h"
#include "loaders/image_io.h"

#include "loaders/errors.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace terracast {
namespace {

using namespace loader_support;

namespace fs = std::filesystem;

// Decodes an sRGB value in [0, 1] to linear.
float linearFromSrgb(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

float srgbFromLinear(float linear) {
    if (!(linear > 0.0f)) return 0.0f;
    if (linear >= 1.0f) return 1.0f;
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

void writeTextFile(const std::string& path, const std::string& text) {
    const fs::path folder = writableFolder(path);
    const fs::path target(path);
    TemporaryFile temporary(folder / fmt::format(".{}.tmp{}", target.filename().string(), getpid()));
    {
        std::ofstream out(temporary.path(), std::ios::binary);
        out << text;
        out.flush();
        if (!out) throw std::runtime_error(fmt::format("{}: cannot write in '{}'", path, folder.string()));
    }
    std::error_code ec;
    fs::rename(temporary.path(), target, ec);
    if (ec) throw std::runtime_error(fmt::format("{}: cannot write ({})", path, ec.message()));
    temporary.release();
}

void writeImage(const std::string& path, const RgbImage& image) {
    const std::string ext = lowerExtension(path);
    if (ext != ".png" && ext != ".exr")
        throw InputError(fmt::format("{}: unsupported output format '{}' (expected .png or .exr)", path, ext));
    const bool png = ext == ".png";
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3)
        throw std::invalid_argument(fmt::format("writeImage: {} x {} image holds {} values", image.width,
                                                image.height, image.rgb.size()));

    const fs::path target(path);
    const fs::path folder = writableFolder(path);
    std::error_code ec;

    // The real extension stays last so that OpenImageIO picks the format from the temporary name.
    // Declared before the writer, so the writer closes its file before the file is removed.
    TemporaryFile temporary(folder / fmt::format(".{}.tmp{}{}", target.filename().string(), getpid(), ext));
    // A write that fails on the way (a full disk) is a runtime failure (exit 1).
    auto fail = [&](const std::string& reason) {
        return std::runtime_error(fmt::format("{}: cannot write in '{}' ({})", path, folder.string(), firstLine(reason)));
    };

    auto output = OIIO::ImageOutput::create(temporary.path().string());
    if (!output) throw fail(OIIO::geterror());
    OIIO::ImageSpec spec(image.width, image.height, 3, png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::HALF);
    spec.attribute("oiio:ColorSpace", png ? "sRGB" : "Linear");
    if (!output->open(temporary.path().string(), spec)) throw fail(output->geterror());

    bool written = false;
    if (png) {
        std::vector<uint8_t> encoded(image.rgb.size());
        for (size_t k = 0; k < encoded.size(); ++k)
            encoded[k] = static_cast<uint8_t>(std::lround(srgbFromLinear(image.rgb[k]) * 255.0f));
        written = output->write_image(OIIO::TypeDesc::UINT8, encoded.data());
    } else {
        written = output->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
    }
    if (!written || !output->close()) throw fail(output->geterror());
    output.reset();

    fs::rename(temporary.path(), target, ec);
    if (ec) throw fail(ec.message());
    temporary.release();
}

RgbImage readImage(const std::string& path) {
    std::error_code ec;
    const auto status = fs::status(path, ec);
    if (status.type() == fs::file_type::not_found) throw InputError(path + ": no such file");
    if (fs::is_directory(status)) throw InputError(path + ": is a directory");

    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // colour as stored, not multiplied by alpha
    auto input = OIIO::ImageInput::open(path, &config);
    if (!input) throw InputError(path + ": cannot read image (" + firstLine(OIIO::geterror()) + ")");
    const OIIO::ImageSpec& spec = input->spec();
    const int channels = std::min(spec.nchannels, 3);
    if (spec.width <= 0 || spec.height <= 0 || channels < 1)
        throw InputError(fmt::format("{}: image is {} x {} with {} channels", path, spec.width, spec.height,
                                     spec.nchannels));

    const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
    std::vector<float> stored(pixels * static_cast<size_t>(channels));
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, stored.data()))
        throw InputError(path + ": cannot read pixels (" + firstLine(input->geterror()) + ")");

    // Integer files (PNG) hold display-referred sRGB; float files (EXR) hold linear values.
    const bool srgb = !spec.format.is_floating_point();
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
