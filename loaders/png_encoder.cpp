// PNG encoding with libspng (see png_encoder.h). The encoder writes into its own buffer, which is copied into the
// returned string and freed; the context is freed on every way out.
#include "loaders/png_encoder.h"

#include <fmt/format.h>
#include <spng.h>

#include <cstdlib>
#include <memory>
#include <stdexcept>

namespace terracast::png {
namespace {

struct ContextDeleter {
    void operator()(spng_ctx* ctx) const { spng_ctx_free(ctx); }
};

void check(int status, const std::string& name, const char* step) {
    if (status != 0)
        throw std::runtime_error(fmt::format("{}: cannot encode the PNG ({}: {})", name, step, spng_strerror(status)));
}

}  // namespace

std::string encode(const std::string& name, int width, int height, Layout layout, const void* samples) {
    // PNG's own bound on either side is 2^31 - 1; a row must also fit the encoder's size_t arithmetic.
    if (width <= 0 || height <= 0)
        throw std::invalid_argument(fmt::format("{}: cannot encode a {} x {} PNG", name, width, height));
    const bool rgb = layout == Layout::SrgbRgb8;
    const size_t bytes = size_t(width) * size_t(height) * (rgb ? 3u : 2u);

    std::unique_ptr<spng_ctx, ContextDeleter> ctx(spng_ctx_new(SPNG_CTX_ENCODER));
    if (!ctx) throw std::runtime_error(fmt::format("{}: cannot encode the PNG (out of memory)", name));
    check(spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1), name, "buffer");
    spng_ihdr header{};
    header.width = uint32_t(width);
    header.height = uint32_t(height);
    header.bit_depth = rgb ? 8 : 16;
    header.color_type = rgb ? SPNG_COLOR_TYPE_TRUECOLOR : SPNG_COLOR_TYPE_GRAYSCALE;
    check(spng_set_ihdr(ctx.get(), &header), name, "header");
    // Rendering intent 0 (perceptual): the pixels are display-referred sRGB (IEC 61966-2-1).
    if (rgb) check(spng_set_srgb(ctx.get(), 0), name, "sRGB chunk");
    if (rgb) {
        // Pictures: every row filtered by Sub and deflated at zlib's level 3, rather than the library's default
        // (each row's best of the five filters, level 6). On rendered terrain, a map view and a scene, measured
        // in docs/bench.md ("Writing the picture"): 4.1 to 4.5 times faster, files 2 to 10 % larger.
        check(spng_set_option(ctx.get(), SPNG_FILTER_CHOICE, SPNG_FILTER_CHOICE_SUB), name, "filter");
        check(spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, 3), name, "compression level");
    }
    // SPNG_FMT_PNG takes samples in the PNG's own layout, 16-bit ones in host byte order.
    check(spng_encode_image(ctx.get(), samples, bytes, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE), name, "image");
    size_t length = 0;
    int status = 0;
    std::unique_ptr<void, decltype(&std::free)> buffer(spng_get_png_buffer(ctx.get(), &length, &status), &std::free);
    check(status, name, "output");
    if (!buffer) throw std::runtime_error(fmt::format("{}: cannot encode the PNG (no output)", name));
    return std::string(static_cast<const char*>(buffer.get()), length);
}

}  // namespace terracast::png
