// Image writing and reading: round trips through PNG and EXR, the sRGB encoding of stored bytes, and failures
// that must leave no file behind.
#include "support/temp_dir.h"
#include "tracer/core/errors.h"
#include "loaders/image_io.h"

#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

using namespace terracast;
namespace fs = std::filesystem;
using terracast::testing::TempDir;

namespace {


// A 16 x 8 gradient covering [0, 1] in red and green, with blue at constant levels.
RgbImage gradient() {
    RgbImage image;
    image.width = 16;
    image.height = 8;
    image.rgb.resize(16 * 8 * 3);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            image.at(x, y, 0) = static_cast<float>(x) / 15.0f;
            image.at(x, y, 1) = static_cast<float>(y) / 7.0f;
            image.at(x, y, 2) = (x + y) % 2 == 0 ? 0.002f : 0.5f;
        }
    return image;
}

// The sRGB encoding (IEC 61966-2-1) of a linear value in [0, 1], as an 8-bit level before rounding.
double srgbLevel(double linear) {
    const double encoded = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
    return encoded * 255.0;
}

// The stored 8-bit channels of a PNG, read with OpenImageIO directly.
std::vector<unsigned char> storedBytes(const std::string& path, int& channels) {
    auto input = OIIO::ImageInput::open(path);
    REQUIRE(input);
    const OIIO::ImageSpec& spec = input->spec();
    REQUIRE(spec.format == OIIO::TypeDesc::UINT8);
    channels = spec.nchannels;
    std::vector<unsigned char> bytes(static_cast<size_t>(spec.width * spec.height * spec.nchannels));
    REQUIRE(input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, bytes.data()));
    return bytes;
}

std::string writeError(const std::string& path, const RgbImage& image) {
    try {
        writeImage(path, image);
    } catch (const InputError& e) {
        return e.what();
    }
    FAIL("writing " << path << " did not throw InputError");
    return {};
}

}  // namespace

TEST_CASE("PNG round trip keeps linear values within one 8-bit sRGB level", "[loaders]") {
    TempDir dir;
    const RgbImage original = gradient();
    const std::string path = dir.file("gradient.png");
    writeImage(path, original);
    const RgbImage read = readImage(path);
    REQUIRE(read.width == original.width);
    REQUIRE(read.height == original.height);
    for (size_t k = 0; k < original.rgb.size(); ++k)
        CHECK(srgbLevel(read.rgb[k]) == Approx(srgbLevel(original.rgb[k])).margin(1.0));
    CHECK(dir.entryCount() == 1);  // no temporary file left behind
}

TEST_CASE("PNG stores rounded sRGB levels and clamps out-of-range values", "[loaders]") {
    TempDir dir;
    RgbImage image;
    image.width = 2;
    image.height = 1;
    image.rgb = {0.5f, 0.0f, 1.0f, 4.0f, -1.0f, 0.002f};
    const std::string path = dir.file("levels.png");
    writeImage(path, image);
    int channels = 0;
    const std::vector<unsigned char> bytes = storedBytes(path, channels);
    REQUIRE(channels == 3);
    // Linear 0.5 encodes to sRGB 0.7354, level 187.5 -> 188; linear 0.002 stays in the linear toe: 0.0258 -> 7.
    CHECK(std::vector<int>(bytes.begin(), bytes.end()) == std::vector<int>{188, 0, 255, 255, 0, 7});
    // The file says what its levels are: it holds an sRGB chunk (PNG 1.2, section 4.2.2.3), before the image data.
    std::ifstream file(path, std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const size_t srgb = png.find("sRGB"), data = png.find("IDAT");
    CHECK(srgb != std::string::npos);
    CHECK(srgb < data);
}

TEST_CASE("PNG of a large picture: every value's sRGB level, each row filtered by Sub", "[loaders]") {
    // 1024 x 512 x 3 values: more than the 2^20 above which the levels are made on several threads.
    TempDir dir;
    RgbImage image;
    image.width = 1024;
    image.height = 512;
    image.rgb.resize(size_t(image.width) * size_t(image.height) * 3);
    uint32_t state = 12345;
    for (float& v : image.rgb) {
        state = state * 1664525u + 1013904223u;
        v = float(state >> 8) / float(1u << 24) * 1.2f - 0.1f;  // some below 0 and above 1
    }
    const std::string path = dir.file("large.png");
    writeImage(path, image);
    int channels = 0;
    const std::vector<unsigned char> bytes = storedBytes(path, channels);
    REQUIRE(channels == 3);
    REQUIRE(bytes.size() == image.rgb.size());
    size_t wrong = 0;
    for (size_t k = 0; k < bytes.size(); ++k) wrong += bytes[k] != srgbByte(image.rgb[k]);
    CHECK(wrong == 0);
    // The image data, inflated: one filter-type byte before each row's 3 x 1024 bytes, 1 (Sub) on every row.
    std::ifstream file(path, std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    std::string stream;
    for (size_t at = 8; at + 8 <= png.size();) {
        const uint32_t length = uint32_t((unsigned char)png[at]) << 24 | uint32_t((unsigned char)png[at + 1]) << 16 |
                                uint32_t((unsigned char)png[at + 2]) << 8 | uint32_t((unsigned char)png[at + 3]);
        if (png.compare(at + 4, 4, "IDAT") == 0) stream += png.substr(at + 8, length);
        at += 12 + size_t(length);
    }
    const size_t rowBytes = 1 + 3 * size_t(image.width);
    std::vector<unsigned char> raw(rowBytes * size_t(image.height));
    uLongf rawLength = uLongf(raw.size());
    REQUIRE(uncompress(raw.data(), &rawLength, reinterpret_cast<const Bytef*>(stream.data()), uLong(stream.size())) ==
            Z_OK);
    REQUIRE(rawLength == raw.size());
    size_t notSub = 0;
    for (int y = 0; y < image.height; ++y) notSub += raw[size_t(y) * rowBytes] != 1;
    CHECK(notSub == 0);
}

TEST_CASE("EXR round trip keeps linear values, including values above 1, to half precision", "[loaders]") {
    TempDir dir;
    RgbImage original = gradient();
    original.at(3, 2, 0) = 4.0f;
    original.at(5, 5, 1) = 123.25f;
    const std::string path = dir.file("gradient.exr");
    writeImage(path, original);
    const RgbImage read = readImage(path);
    REQUIRE(read.width == original.width);
    REQUIRE(read.height == original.height);
    for (size_t k = 0; k < original.rgb.size(); ++k)
        CHECK(read.rgb[k] == Approx(original.rgb[k]).epsilon(1e-3).margin(1e-4));
    CHECK(dir.entryCount() == 1);
}

TEST_CASE("Grayscale PNG reads as three equal linear channels", "[loaders]") {
    TempDir dir;
    const std::string path = dir.file("gray.png");
    {
        auto output = OIIO::ImageOutput::create(path);
        REQUIRE(output);
        const OIIO::ImageSpec spec(2, 1, 1, OIIO::TypeDesc::UINT8);
        REQUIRE(output->open(path, spec));
        const unsigned char levels[2] = {188, 255};
        REQUIRE(output->write_image(OIIO::TypeDesc::UINT8, levels));
        REQUIRE(output->close());
    }
    const RgbImage read = readImage(path);
    REQUIRE(read.width == 2);
    for (int c = 0; c < 3; ++c) {
        CHECK(read.at(0, 0, c) == Approx(0.50289).margin(1e-4));  // ((188/255 + 0.055) / 1.055)^2.4
        CHECK(read.at(1, 0, c) == Approx(1.0).margin(1e-6));
    }
}

TEST_CASE("Writing over an existing image replaces it", "[loaders]") {
    TempDir dir;
    const std::string path = dir.file("view.png");
    RgbImage image = gradient();
    writeImage(path, image);
    std::fill(image.rgb.begin(), image.rgb.end(), 1.0f);
    writeImage(path, image);
    const RgbImage read = readImage(path);
    CHECK(read.at(0, 0, 0) == Approx(1.0).margin(1e-6));
    CHECK(dir.entryCount() == 1);
}

TEST_CASE("Writing into a missing folder throws and leaves no file", "[loaders]") {
    TempDir dir;
    const std::string path = dir.file("no-such-folder/view.png");
    const std::string message = writeError(path, gradient());
    CHECK_THAT(message, Catch::Contains(path) && Catch::Contains("does not exist"));
    CHECK_FALSE(fs::exists(path));
    CHECK(dir.entryCount() == 0);
}

TEST_CASE("Writing an unsupported format throws naming the extension", "[loaders]") {
    TempDir dir;
    const std::string path = dir.file("view.bmp");
    const std::string message = writeError(path, gradient());
    CHECK_THAT(message, Catch::Contains(path) && Catch::Contains("'.bmp'") && Catch::Contains(".png or .exr"));
    CHECK(dir.entryCount() == 0);
}

TEST_CASE("Reading a missing or broken image throws InputError naming it", "[loaders]") {
    TempDir dir;
    const std::string missing = dir.file("missing.png");
    CHECK_THROWS_MATCHES(readImage(missing), InputError, Catch::Message(missing + ": no such file"));
    const std::string broken = dir.file("broken.exr");
    {
        std::FILE* f = std::fopen(broken.c_str(), "wb");
        REQUIRE(f != nullptr);
        std::fputs("not an image", f);
        std::fclose(f);
    }
    CHECK_THROWS_WITH(readImage(broken), Catch::Contains(broken));
}
