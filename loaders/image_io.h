// Writing and reading pictures (PNG written by libspng; EXR and every read through the image codec module,
// OpenImageIO), and writing small text outputs, always atomically.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <initializer_list>
#include <string_view>
#include <vector>

namespace terracast {

// A linear-light RGB picture, row 0 at the top.
struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width * height * 3 linear values

    float& at(int x, int y, int c) { return rgb[(static_cast<size_t>(y) * width + x) * 3 + c]; }
    float at(int x, int y, int c) const { return rgb[(static_cast<size_t>(y) * width + x) * 3 + c]; }
};

// Writes `image` to `path`; the extension picks the format: .png (8-bit sRGB) or .exr (linear half/float).
// Writes to a temporary file in the same folder and renames it, so a failure never leaves a partial file.
// Throws InputError for an unsupported extension or an unwritable folder.
void writeImage(const std::string& path, const RgbImage& image);

// The bytes of a 16-bit greyscale PNG of width x height samples (row-major, top row first), encoded in memory;
// `name` names the image in errors.
std::string encodeGreyPng16(const std::string& name, int width, int height, const std::vector<uint16_t>& samples);

// Writes `text` to `path` through a temporary file in the same folder and a rename. Throws InputError for a
// missing or unwritable folder, std::runtime_error when the write itself fails.
void writeTextFile(const std::string& path, const std::string& text);

// Checks, before any work, that `path` can be written: its folder exists and a file can be created in it, or it
// names a device or pipe (written in place). Throws InputError naming the path otherwise.
void checkCanWrite(const std::string& path);

// Loads now whatever writing a picture to `path` will need (the image codec module for EXR; nothing for PNG), so
// that the memory it takes is counted by a memory check made before the picture is written. Throws
// std::runtime_error when the module cannot load.
void prepareImageWriter(const std::string& path);

// Writes `bytes` to `path` through a temporary file in the same folder and a rename; a device or pipe (such
// as /dev/null) is written in place. Throws InputError for a missing or unwritable folder, std::runtime_error
// when writing fails (a full disk), and never leaves a partial file.
void writeFileAtomically(const std::string& path, std::string_view bytes);
// The same for bytes in pieces, written one after the other (no copy of them joined).
void writeFileAtomically(const std::string& path, std::initializer_list<std::string_view> pieces);

// The sRGB encoding (IEC 61966-2-1) of a linear value, in [0, 1]; inputs outside [0, 1] and NaN are clamped.
float srgbFromLinear(float linear);
// The 8-bit sRGB level of a linear value, as PNG pictures store it.
uint8_t srgbByte(float linear);
// The sRGB transfer function inverted (IEC 61966-2-1): an encoded value in [0, 1] to linear.
float linearFromSrgb(float encoded);
// "#rrggbb" (sRGB, as web colours are written) as linear RGB; none for anything else.
std::optional<glm::vec3> parseHexColour(const std::string& text);

// Reads an image as linear RGB (PNG is decoded from sRGB). Throws InputError on failure.
RgbImage readImage(const std::string& path);

}  // namespace terracast
