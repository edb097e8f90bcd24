// The image codec: PNG and EXR encoding and decoding through OpenImageIO, in a module of its own
// (libterracast_image_codec.so) that the loaders open on first use. OpenImageIO's dependencies (codecs for dozens
// of formats) take about 0.17 s to load and relocate; commands that read and write only GeoTIFF never pay it.
// Plain types only cross this boundary.
#pragma once

#include <cstdint>
#include <string>

namespace terracast::image_codec {

enum class PixelType { UInt8, UInt16, Half, Float, Other };

// What an opened image holds.
struct ImageHeader {
    int width = 0;
    int height = 0;
    int channels = 0;
    PixelType format = PixelType::Other;  // the stored sample type
    bool floating = false;                // the stored samples are floating point
    std::string formatName;               // OpenImageIO's name of the stored type, for messages
};

// The module's functions. Failures return false (or null) and set `error` to the codec's first line of reason.
struct Api {
    // Opens an image for reading, colour as stored (alpha not multiplied in); null on failure.
    void* (*open)(const std::string& path, ImageHeader& header, std::string& error);
    // Reads the first `channels` channels of every pixel, converted to `as` (UInt8, UInt16 or Float), row 0 at the
    // top, into `out` (width * height * channels values).
    bool (*read)(void* image, int channels, PixelType as, void* out, std::string& error);
    void (*close)(void* image);
    // Encodes width x height pixels of `channels` channels, given as `given` and stored as `stored`, in the format
    // that `path`'s extension names; `colorSpace` (may be empty) is recorded in the file.
    bool (*encode)(const std::string& path, int width, int height, int channels, PixelType stored,
                   const std::string& colorSpace, PixelType given, const void* pixels, std::string& bytes,
                   std::string& error);
};

// The module, opened once (thread-safe). Throws std::runtime_error naming the module's path when it cannot be
// loaded. The path is TERRACAST_IMAGE_CODEC from the environment, else the build's own, else the file beside the
// executable.
const Api& api();

// Reads the whole of an open image and closes it on every way out.
class OpenImage {
public:
    OpenImage(void* handle) : handle_(handle) {}
    ~OpenImage() {
        if (handle_) api().close(handle_);
    }
    OpenImage(const OpenImage&) = delete;
    OpenImage& operator=(const OpenImage&) = delete;
    void* get() const { return handle_; }

private:
    void* handle_;
};

}  // namespace terracast::image_codec
