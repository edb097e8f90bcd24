// PNG encoding through libspng, linked into the loaders: writing a picture or a height map as PNG needs none of
// the image codec module's libraries (OpenImageIO and the dozens of codecs it brings).
#pragma once

#include <cstdint>
#include <string>

namespace terracast::png {

// What the samples are: 8-bit RGB in sRGB (the file records the sRGB chunk) or 16-bit greyscale heights.
enum class Layout { SrgbRgb8, Grey16 };

// The bytes of a PNG of width x height pixels, rows top first; `samples` holds width * height * 3 bytes
// (SrgbRgb8) or width * height host-endian uint16 values (Grey16). `name` names the image in errors. Throws
// std::runtime_error when the encoder fails, std::invalid_argument for sizes PNG cannot hold.
std::string encode(const std::string& name, int width, int height, Layout layout, const void* samples);

}  // namespace terracast::png
