// The fuzz target bodies (see fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

#include "heightfield/cell_intersectors.h"
#include "loaders/dem_loader.h"
#include "tracer/core/errors.h"
#include "loaders/scene_file.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>

namespace terracast::fuzz {
namespace {

// Checks that an InputError reads as the contract says: one line, starting with the file it is about.
void checkMessage(const InputError& e, const std::string& name) {
    const std::string_view message = e.what();
    if (message.find('\n') != std::string_view::npos)
        throw FuzzFailure(fmt::format("message spans several lines: {}", message));
    if (!message.starts_with(name)) throw FuzzFailure(fmt::format("message does not start with '{}': {}", name, message));
}

// Reads fixed-size values off the front of the input; past its end every value is zero.
class Reader {
public:
    Reader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    uint32_t u32() {
        uint32_t v = 0;
        for (int k = 0; k < 4; ++k) v = v << 8 | byte();
        return v;
    }
    uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
    // A value in [0, 1].
    double unit() { return double(u32()) / double(std::numeric_limits<uint32_t>::max()); }
    // A signed value whose magnitude spans 2^-12 .. 2^20 times the fraction, as float.
    float scaled() {
        const int exponent = int(byte() % 33) - 12;
        const double fraction = double(int32_t(u32())) / 2147483648.0;
        return float(std::ldexp(fraction, exponent));
    }

private:
    const uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
};

}  // namespace

void sceneFile(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    // Relative file names resolve against the sample scenes' folder, so references to real DEMs also get parsed.
    const std::string baseDir = std::string(TERRACAST_SOURCE_DIR) + "/data-samples";
    try {
        parseSceneText(text, "fuzz.toml", baseDir);
    } catch (const InputError& e) {
        checkMessage(e, "fuzz.toml");
    }
}

void demLoader(const uint8_t* data, size_t size) {
    if (size == 0) return;
    const uint8_t route = data[0];
    const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
    DemLoadOptions options;
    options.maxBytes = 64.0 * 1024 * 1024;  // big enough for real tiles, small enough for a fuzzer's memory
    std::string name;
    try {
        LoadedDem dem;
        if (route % 2 == 0) {
            static const char* const kNames[] = {"fuzz.tif", "fuzz.asc", "fuzz.hgt", "fuzz.dem"};
            name = kNames[(route / 2) % 4];
            dem = loadDemFromBytes(bytes, name, options);
        } else {
            // PNG height maps are read from files (by libspng, or OpenImageIO for the layouts libspng leaves).
            name = (std::filesystem::temp_directory_path() / fmt::format("terracast-fuzz-{}.png", ::getpid())).string();
            std::ofstream(name, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
            struct Remove {
                const std::string& path;
                ~Remove() { std::remove(path.c_str()); }
            } remove{name};
            dem = loadDem(name, options);
        }
        const HeightGrid& g = dem.grid;
        if (g.width() < 2 || g.height() < 2 || g.validCellCount() == 0)
            throw FuzzFailure(fmt::format("loaded a {} x {} grid with {} valid cells", g.width(), g.height(),
                                          g.validCellCount()));
        for (int64_t j = 0; j < g.height(); ++j)
            for (int64_t i = 0; i < g.width(); ++i)
                if (g.vertexValid(i, j) && !std::isfinite(g.at(i, j)))
                    throw FuzzFailure(fmt::format("vertex {}, {} holds {}", i, j, g.at(i, j)));
        if (!(g.cellSizeXM() > 0.0) || !(g.cellSizeYM() > 0.0) || !std::isfinite(g.cellSizeXM() * g.cellSizeYM()))
            throw FuzzFailure(fmt::format("cell size {} x {} m", g.cellSizeXM(), g.cellSizeYM()));
    } catch (const InputError& e) {
        checkMessage(e, name);
    }
}

void cellIntersector(const uint8_t* data, size_t size) {
    using LD = long double;
    Reader in(data, size);
    // Corner heights relative to h00, as the traversal passes them.
    const CellCorners<float> h{0.0f, in.scaled(), in.scaled(), in.scaled()};
    // An entry point on the cell's boundary or inside it, and a direction in grid units per unit s.
    float u0 = float(in.unit()), v0 = float(in.unit());
    switch (in.byte() % 5) {
    case 0: u0 = 0.0f; break;
    case 1: v0 = 0.0f; break;
    case 2: u0 = 1.0f; break;
    case 3: v0 = 1.0f; break;
    default: break;
    }
    const float du = in.scaled(), dv = in.scaled(), dz = in.scaled();
    // The segment runs from the entry to where the ray leaves the unit square (or a set length when vertical).
    double length = std::numeric_limits<double>::infinity();
    if (du > 0) length = std::min(length, (1.0 - u0) / du);
    if (du < 0) length = std::min(length, -double(u0) / du);
    if (dv > 0) length = std::min(length, (1.0 - v0) / dv);
    if (dv < 0) length = std::min(length, -double(v0) / dv);
    if (!std::isfinite(length)) length = std::abs(double(in.scaled()));
    if (!(length > 0.0) || !std::isfinite(float(length))) return;
    const auto surface = [&](LD u, LD v) {  // the bilinear height, nested as the traversal computes it
        const LD bottom = LD(h.h00) + (LD(h.h10) - LD(h.h00)) * u, top = LD(h.h01) + (LD(h.h11) - LD(h.h01)) * u;
        return bottom + (top - bottom) * v;
    };
    const float z0 = float(surface(u0, v0) + LD(in.scaled()));
    const float len = float(length);
    const LD u1 = std::clamp<LD>(LD(u0) + LD(len) * du, 0, 1), v1 = std::clamp<LD>(LD(v0) + LD(len) * dv, 0, 1);
    const LD z1 = LD(z0) + LD(len) * dz;
    const CellSegment<LD> segLD{u0, v0, z0, du, dv, dz, len, surface(u0, v0) - z0, surface(u1, v1) - z1};
    // The float segment gets its end values rounded once from the exact ones, as the traversal's are.
    const CellSegment<float> seg{u0, v0, z0, du, dv, dz, len, float(segLD.gEntry), float(segLD.gExit)};
    const CellCorners<LD> hLD{h.h00, h.h10, h.h01, h.h11};

    const std::optional<float> s = intersectBilinearCell(h, seg);
    const std::optional<LD> reference = intersectBilinearCell(hLD, segLD);
    const auto describe = [&] {
        return fmt::format("corners {} {} {} {}, entry ({}, {}, {}), direction ({}, {}, {}), length {}: float {}, "
                           "long double {}",
                           h.h00, h.h10, h.h01, h.h11, u0, v0, z0, du, dv, dz, len, s ? double(*s) : -1.0,
                           reference ? double(*reference) : -1.0);
    };

    // A hit lies on the segment, and a sign change between the ends is never missed.
    if (s && !(*s >= 0.0f && *s <= len)) throw FuzzFailure("hit off the segment: " + describe());
    const bool signChange = seg.gEntry == 0.0f || seg.gExit == 0.0f || (seg.gEntry < 0.0f) != (seg.gExit < 0.0f);
    if (signChange && !s) throw FuzzFailure("crossing between the ends missed: " + describe());

    // G(s) in long double, and the size of the rounding errors the float solver may make in it.
    const LD A = hLD.d() * LD(du) * LD(dv);
    const LD B = hLD.b() * LD(du) + hLD.c() * LD(dv) + hLD.d() * (LD(u0) * LD(dv) + LD(v0) * LD(du)) - LD(dz);
    const auto G = [&](LD t) { return (A * t + B) * t + segLD.gEntry; };
    const LD maxH = std::max({std::abs(LD(h.h10)), std::abs(LD(h.h01)), std::abs(LD(h.h11))});
    const LD errG = 64 * LD(std::numeric_limits<float>::epsilon()) *
                    (4 * maxH + std::abs(LD(z0)) + LD(len) * std::abs(LD(dz)) + LD(1e-30));
    // A float hit is acceptable where the surface is within rounding of the ray, or at the crossing that the
    // rounded end values promise.
    const bool hitPlausible = s && (std::abs(G(LD(*s))) <= 4 * errG || std::abs(segLD.gEntry) <= 4 * errG ||
                                    std::abs(segLD.gExit) <= 4 * errG);

    // Where the exact G crosses zero cleanly (|G'| large against the rounding, and neither end of the segment
    // within rounding of the surface), the float solver must hit there. An end within rounding may sit on either
    // side of the crossing: the exit values come from the exit point clamped to the cell, which can differ from
    // G(length) by more than the crossing's distance from the end.
    if (reference) {
        const LD slope = std::abs(2 * A * *reference + B);
        const LD tolerance = 16 * errG / std::max(slope, LD(1e-300L));
        const bool clean = tolerance < LD(len) / 8 && std::abs(segLD.gEntry) > 4 * errG &&
                           std::abs(segLD.gExit) > 4 * errG;
        if (clean && !s) throw FuzzFailure("clean crossing missed: " + describe());
        if (clean && std::abs(LD(*s) - *reference) > tolerance + 4 * LD(std::numeric_limits<float>::epsilon()) * LD(len) &&
            !hitPlausible)
            throw FuzzFailure("hit far from the clean crossing: " + describe());
    } else if (s && !hitPlausible) {
        throw FuzzFailure("hit where the exact surface is clear of the ray: " + describe());
    }

    // An independent check of the long-double solver: a dense scan for sign changes well above the rounding.
    constexpr int kSamples = 64;
    LD previous = G(0);
    for (int k = 1; k <= kSamples; ++k) {
        const LD value = G(LD(len) * k / kSamples);
        if (std::abs(previous) > 4 * errG && std::abs(value) > 4 * errG && (previous < 0) != (value < 0)) {
            if (!reference) throw FuzzFailure("long-double solver missed a crossing: " + describe());
            break;
        }
        previous = value;
    }
}

}  // namespace terracast::fuzz
