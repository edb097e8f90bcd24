// The image codec module (loaders/image_codec.h): the only code that includes OpenImageIO, built as a shared
// module that the loaders open on first use.
#include "loaders/image_codec.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>

namespace {

using terracast::image_codec::Api;
using terracast::image_codec::ImageHeader;
using terracast::image_codec::PixelType;

OIIO::TypeDesc typeOf(PixelType t) {
    switch (t) {
    case PixelType::UInt8: return OIIO::TypeDesc::UINT8;
    case PixelType::UInt16: return OIIO::TypeDesc::UINT16;
    case PixelType::Half: return OIIO::TypeDesc::HALF;
    case PixelType::Float: return OIIO::TypeDesc::FLOAT;
    default: return OIIO::TypeDesc::UNKNOWN;
    }
}

PixelType pixelTypeOf(OIIO::TypeDesc t) {
    if (t == OIIO::TypeDesc::UINT8) return PixelType::UInt8;
    if (t == OIIO::TypeDesc::UINT16) return PixelType::UInt16;
    if (t == OIIO::TypeDesc::HALF) return PixelType::Half;
    if (t == OIIO::TypeDesc::FLOAT) return PixelType::Float;
    return PixelType::Other;
}

void* openImage(const std::string& path, ImageHeader& header, std::string& error) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // colour as stored, not multiplied by alpha
    auto input = OIIO::ImageInput::open(path, &config);
    if (!input) {
        error = OIIO::geterror();
        return nullptr;
    }
    const OIIO::ImageSpec& spec = input->spec();
    header.width = spec.width;
    header.height = spec.height;
    header.channels = spec.nchannels;
    header.format = pixelTypeOf(spec.format);
    header.floating = spec.format.is_floating_point();
    header.formatName = spec.format.c_str();
    return input.release();
}

bool readImage(void* image, int channels, PixelType as, void* out, std::string& error) {
    auto* input = static_cast<OIIO::ImageInput*>(image);
    if (input->read_image(0, 0, 0, channels, typeOf(as), out)) return true;
    error = input->geterror();
    return false;
}

void closeImage(void* image) {
    // ImageInput's destructor closes the file; it is deleted through the library's own unique_ptr deleter.
    OIIO::ImageInput::unique_ptr(static_cast<OIIO::ImageInput*>(image));
}

bool encodeImage(const std::string& path, int width, int height, int channels, PixelType stored,
                 const std::string& colorSpace, PixelType given, const void* pixels, std::string& bytes,
                 std::string& error) {
    OIIO::ImageSpec spec(width, height, channels, typeOf(stored));
    if (!colorSpace.empty()) spec.attribute("oiio:ColorSpace", colorSpace);
    OIIO::Filesystem::IOVecOutput encoded;
    auto output = OIIO::ImageOutput::create(path);
    if (!output) {
        error = OIIO::geterror();
        return false;
    }
    if (!output->set_ioproxy(&encoded) || !output->open(path, spec) || !output->write_image(typeOf(given), pixels) ||
        !output->close()) {
        error = output->geterror();
        return false;
    }
    output.reset();
    const std::vector<unsigned char>& buffer = encoded.buffer();
    bytes.assign(reinterpret_cast<const char*>(buffer.data()), buffer.size());
    return true;
}

const Api kApi{openImage, readImage, closeImage, encodeImage};

}  // namespace

extern "C" __attribute__((visibility("default"))) const Api* terracastImageCodec() { return &kApi; }
