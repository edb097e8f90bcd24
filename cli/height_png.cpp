#include "cli/height_png.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace terracast {

namespace {

void putBigEndian32(std::string& out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out += char((v >> shift) & 0xffu);
}

// One PNG chunk: length, type, data and the CRC of type and data.
void putChunk(std::string& out, const char type[4], const std::string& data) {
    putBigEndian32(out, uint32_t(data.size()));
    const size_t start = out.size();
    out.append(type, 4);
    out += data;
    uLong crc = crc32(0L, Z_NULL, 0);
    // zlib's crc32 takes a 32-bit length; large IDAT chunks are fed in pieces.
    for (size_t k = start; k < out.size();) {
        const size_t n = std::min<size_t>(out.size() - k, size_t(1) << 30);
        crc = crc32(crc, reinterpret_cast<const Bytef*>(out.data() + k), uInt(n));
        k += n;
    }
    putBigEndian32(out, uint32_t(crc));
}

}  // namespace

std::string encodeHeightPng16(const HeightGrid& grid) {
    const int64_t W = grid.width(), H = grid.height();
    if (W <= 0 || H <= 0 || W > 0x7fffffff || H > 0x7fffffff) throw std::runtime_error("height PNG: bad grid size");
    // Scanlines: a filter byte, then big-endian samples. "Sub" subtracts, byte by byte and without carries, the
    // byte two to the left (the same byte of the previous sample).
    const size_t rowBytes = 1 + 2 * size_t(W);
    std::vector<unsigned char> raw(rowBytes * size_t(H));
    for (int64_t y = 0; y < H; ++y) {
        unsigned char* row = raw.data() + size_t(y) * rowBytes;
        row[0] = 1;
        const int64_t j = H - 1 - y;  // the image's top row is the grid's northmost
        unsigned hiLeft = 0, loLeft = 0;
        for (int64_t i = 0; i < W; ++i) {
            const float h = grid.vertexValid(i, j) ? grid.at(i, j) : 0.0f;
            const unsigned v = std::isfinite(h) ? unsigned(std::clamp(std::lround(h), 0L, 65535L)) : 0u;
            const unsigned hi = v >> 8, lo = v & 0xffu;
            row[1 + 2 * i] = (unsigned char)((hi - hiLeft) & 0xffu);
            row[2 + 2 * i] = (unsigned char)((lo - loLeft) & 0xffu);
            hiLeft = hi;
            loLeft = lo;
        }
    }

    // One zlib stream, fed and drained in pieces zlib's 32-bit counts can hold.
    z_stream z{};
    if (deflateInit(&z, Z_DEFAULT_COMPRESSION) != Z_OK) throw std::runtime_error("height PNG: deflateInit failed");
    std::string idat(size_t(deflateBound(&z, uLong(raw.size()))), '\0');
    constexpr size_t kPiece = size_t(1) << 30;
    size_t inDone = 0, outDone = 0;
    int rc = Z_OK;
    while (rc != Z_STREAM_END) {
        const size_t inPiece = std::min(raw.size() - inDone, kPiece);
        const size_t outPiece = std::min(idat.size() - outDone, kPiece);
        z.next_in = raw.data() + inDone;
        z.avail_in = uInt(inPiece);
        z.next_out = reinterpret_cast<Bytef*>(idat.data() + outDone);
        z.avail_out = uInt(outPiece);
        rc = deflate(&z, inDone + inPiece == raw.size() ? Z_FINISH : Z_NO_FLUSH);
        inDone += inPiece - z.avail_in;
        outDone += outPiece - z.avail_out;
        if ((rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) || (rc == Z_BUF_ERROR && outDone == idat.size())) {
            deflateEnd(&z);
            throw std::runtime_error("height PNG: deflate failed");
        }
    }
    idat.resize(outDone);
    deflateEnd(&z);

    std::string png("\x89PNG\r\n\x1a\n", 8);
    std::string ihdr;
    putBigEndian32(ihdr, uint32_t(W));
    putBigEndian32(ihdr, uint32_t(H));
    ihdr += char(16);  // bit depth
    ihdr += char(0);   // greyscale
    ihdr += char(0);   // deflate
    ihdr += char(0);   // adaptive filtering (per-row filter bytes)
    ihdr += char(0);   // no interlace
    putChunk(png, "IHDR", ihdr);
    putChunk(png, "IDAT", idat);
    putChunk(png, "IEND", "");
    return png;
}

}  // namespace terracast
