#include "tracer/measure/compare.h"

#include "tracer/core/angles.h"
#include "tracer/core/errors.h"
#include "tracer/measure/svg_chart.h"

#include "tracer/sky/sky.h"

#include "tracer/core/parallel.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

namespace terracast {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

MethodComparison traceSurface(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& s,
                              bool shade, int rowBegin, int rowEnd) {
    MethodComparison m;
    m.method = surface.method();
    m.buildSeconds = surface.buildSeconds();
    m.memoryBytes = surface.memoryBytes();
    const int w = s.width, h = s.height;
    const int y0 = std::clamp(rowBegin, 0, h), y1 = rowEnd < 0 ? h : std::clamp(rowEnd, y0, h);
    const size_t n = size_t(w) * size_t(y1 - y0);  // pixels traced; pixel (x, y) at (y - y0) * w + x
    auto index = [&](int x, int y) { return size_t(y - y0) * size_t(w) + size_t(x); };
    std::vector<std::optional<HeightFieldHit>> hits(n);
    std::vector<glm::dvec3> dirs(n);

    auto start = std::chrono::steady_clock::now();
    parallelForTiles(w, y1 - y0, s.tileSize, s.threads, [&](int x0, int ty0, int x1, int ty1) {
        traceCameraRays(surface, s.camera, w, h, x0, ty0 + y0, x1, ty1 + y0,
                        [&](int x, int y, const Ray& ray, const std::optional<HeightFieldHit>& hit) {
                            const size_t k = index(x, y);
                            dirs[k] = ray.dir;
                            hits[k] = hit;
                        });
    });
    m.primarySeconds = secondsSince(start);
    m.primaryRays = int64_t(n);
    m.primaryRaysPerSecond = m.primarySeconds > 0.0 ? double(n) / m.primarySeconds : 0.0;

    std::vector<signed char> lit(n, -1);  // -1: no shadow ray, 0: shadowed, 1: lit
    std::atomic<int64_t> shadowRays{0};
    start = std::chrono::steady_clock::now();
    parallelForTiles(w, y1 - y0, s.tileSize, s.threads, [&](int x0, int ty0, int x1, int ty1) {
        int64_t count = 0;
        for (int y = ty0 + y0; y < ty1 + y0; ++y)
            for (int x = x0; x < x1; ++x) {
                const size_t k = index(x, y);
                if (!hits[k]) continue;
                if (const auto r = sunShadowRay(*hits[k], dirs[k], s.sun)) {
                    ++count;
                    lit[k] = surface.occluded(*r, {0.0, kInfinity}) ? 0 : 1;
                }
            }
        shadowRays += count;
    });
    m.shadowSeconds = secondsSince(start);
    m.shadowRays = shadowRays;
    m.shadowRaysPerSecond = m.shadowSeconds > 0.0 ? double(m.shadowRays) / m.shadowSeconds : 0.0;

    m.hitT.assign(size_t(w) * size_t(h), kNaN);
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < w; ++x)
            if (const auto& hit = hits[index(x, y)]) m.hitT[size_t(y) * size_t(w) + size_t(x)] = hit->t;
    if (!shade) return m;
    m.image = Film(w, h);
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = index(x, y);
            if (!hits[k]) {
                m.image.set(x, y, gradientSky(dirs[k]));
                continue;
            }
            m.image.set(x, y, shadeTerrainHit(grid, *hits[k], dirs[k], lit[k] == 1, s.sun, s.ambient));
        }
    return m;
}

namespace {

// Builds one method's surface and traces it.
MethodComparison traceMethod(const HeightGrid& grid, SurfaceMethod method, const TerrainRenderSettings& s) {
    const TerrainSurface surface(grid, method, s.threads);
    return traceSurface(grid, surface, s);
}

}  // namespace

std::string comparisonName(const MethodComparison& m) {
    std::string name = surfaceMethodName(m.method);
    if (m.lodPixels > 0.0) name += fmt::format("+lod{:g}", m.lodPixels);
    return name;
}

const std::vector<SurfaceMethod>& compareMethods() {
    static const std::vector<SurfaceMethod> methods{SurfaceMethod::Bilinear, SurfaceMethod::BilinearDouble,
                                                    SurfaceMethod::Triangles, SurfaceMethod::Nearest,
                                                    SurfaceMethod::Embree, SurfaceMethod::EmbreeGrid};
    return methods;
}

std::vector<SurfaceMethod> parseCompareMethods(const std::string& text) {
    std::vector<SurfaceMethod> methods;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = text.find(',', start);
        const std::string name = text.substr(start, comma - start);
        const auto m = parseSurfaceMethod(name);
        if (!m)
            throw InputError("--methods: expected names from " + std::string(surfaceMethodList()) + ", found '" +
                             name + "'");
        methods.push_back(*m);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return methods;
}

CompareReport compareSurfaces(const HeightGrid& grid, const CompareSettings& settings) {
    CompareReport report;
    report.width = settings.render.width;
    report.height = settings.render.height;
    report.rays = int64_t(report.width) * report.height;
    report.reference = settings.reference;

    std::vector<SurfaceMethod> methods = settings.methods;
    if (std::find(methods.begin(), methods.end(), settings.reference) == methods.end())
        methods.insert(methods.begin(), settings.reference);
    const size_t count = methods.size() + (settings.lodPixels > 0.0 ? 1 : 0);
    // Tiles read from the DEM so far (a DEM held as tiles).
    const auto loads = [&grid] { return grid.tiled() ? grid.tileSource()->cacheStats().loads : int64_t(-1); };
    for (size_t k = 0; k < methods.size(); ++k) {
        if (settings.onMethod) settings.onMethod(methods[k], k, count);
        const int64_t before = loads();
        report.methods.push_back(traceMethod(grid, methods[k], settings.render));
        if (grid.tiled()) report.methods.back().tileLoads = loads() - before;
    }
    if (settings.lodPixels > 0.0) {
        if (settings.onMethod) settings.onMethod(SurfaceMethod::Bilinear, methods.size(), count);
        const auto start = std::chrono::steady_clock::now();
        const int64_t before = loads();
        TerrainSurface surface(grid, SurfaceMethod::Bilinear, settings.render.threads);
        const PinholeCamera& camera = settings.render.camera;
        surface.setLevelOfDetail({camera.eyeM,
                                  2.0 * std::tan(0.5 * radians(camera.fovYDeg)) / double(settings.render.height),
                                  settings.lodPixels});
        const double built = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        MethodComparison m = traceSurface(grid, surface, settings.render);
        m.lodPixels = settings.lodPixels;
        m.buildSeconds = built;  // the coarser grids (the grid's own pyramid is built with it)
        if (grid.tiled()) m.tileLoads = loads() - before;  // the coarser grids' reads too
        report.methods.push_back(std::move(m));
    }

    const MethodComparison* ref = nullptr;
    const MethodComparison* embree = nullptr;
    for (const auto& m : report.methods) {
        if (m.method == settings.reference && m.lodPixels == 0.0) ref = &m;
        if (m.method == SurfaceMethod::Embree) embree = &m;
    }
    for (auto& m : report.methods) {
        int64_t agree = 0;
        std::vector<double> absErr, relErr;
        double sq = 0.0;
        for (size_t k = 0; k < m.hitT.size(); ++k) {
            const bool a = !std::isnan(m.hitT[k]), b = !std::isnan(ref->hitT[k]);
            agree += a == b;
            if (a && b) {
                const double e = std::abs(m.hitT[k] - ref->hitT[k]);
                absErr.push_back(e);
                relErr.push_back(ref->hitT[k] > 0.0 ? e / ref->hitT[k] : (e > 0.0 ? kInfinity : 0.0));
            }
        }
        for (size_t k = 0; k < m.image.rgb.size(); ++k) {
            const double d = std::clamp(double(m.image.rgb[k]), 0.0, 1.0) - std::clamp(double(ref->image.rgb[k]), 0.0, 1.0);
            sq += d * d;
        }
        m.hitAgreement = double(agree) / double(m.hitT.size());
        m.tErrorM = summariseErrors(std::move(absErr));
        m.tErrorRel = summariseErrors(std::move(relErr));
        m.imageRmse = std::sqrt(sq / double(m.image.rgb.size()));
        m.imagePsnrDb = m.imageRmse > 0.0 ? 20.0 * std::log10(1.0 / m.imageRmse) : std::numeric_limits<double>::infinity();
        m.ratioToEmbreePrimary = m.ratioToEmbreeShadow = std::numeric_limits<double>::quiet_NaN();
        if (embree) {
            m.ratioToEmbreePrimary = embree->primaryRaysPerSecond > 0 ? m.primaryRaysPerSecond / embree->primaryRaysPerSecond : 0.0;
            m.ratioToEmbreeShadow = embree->shadowRaysPerSecond > 0 ? m.shadowRaysPerSecond / embree->shadowRaysPerSecond : 0.0;
        }
    }
    return report;
}

namespace {

// A 3 x 5 pixel font for legend labels: each glyph is five rows of three bits, top row first.
struct Glyph {
    char c;
    std::array<uint8_t, 5> rows;
};
constexpr Glyph kFont[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
    {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
    {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
    {'+', {0, 2, 7, 2, 0}}, {'e', {7, 5, 7, 4, 7}}, {'m', {0, 0, 7, 7, 5}}, {'h', {4, 4, 7, 5, 5}},
    {'i', {2, 0, 2, 2, 2}}, {'t', {2, 7, 2, 2, 3}}, {'s', {3, 4, 2, 1, 6}}, {'/', {1, 1, 2, 4, 4}},
    {'o', {0, 7, 5, 5, 7}}, {'n', {0, 6, 5, 5, 5}}, {'r', {0, 7, 4, 4, 4}}, {'a', {0, 7, 1, 7, 7}},
    {'l', {6, 2, 2, 2, 7}}, {'g', {7, 5, 7, 1, 7}}, {'x', {0, 5, 2, 2, 5}}, {'p', {0, 7, 5, 7, 4}},
};

// Draws `text` with its top-left corner at (x, y), each font pixel `scale` x `scale` film pixels.
void drawText(Film& film, int x, int y, const std::string& text, int scale, const glm::vec3& colour) {
    for (char c : text) {
        for (const Glyph& g : kFont) {
            if (g.c != c) continue;
            for (int row = 0; row < 5; ++row)
                for (int col = 0; col < 3; ++col)
                    if (g.rows[size_t(row)] & (4 >> col))
                        for (int dy = 0; dy < scale; ++dy)
                            for (int dx = 0; dx < scale; ++dx) {
                                const int px = x + col * scale + dx, py = y + row * scale + dy;
                                if (px >= 0 && py >= 0 && px < film.width && py < film.height) film.set(px, py, colour);
                            }
        }
        x += 4 * scale;
    }
}

// A perceptually ordered ramp (dark blue, teal, green, yellow) for w in [0, 1], in linear RGB.
glm::vec3 heatColour(double w) {
    static const glm::vec3 stops[] = {{0.02f, 0.02f, 0.20f}, {0.03f, 0.20f, 0.45f}, {0.02f, 0.45f, 0.35f},
                                      {0.35f, 0.70f, 0.05f}, {1.00f, 0.85f, 0.02f}};
    w = std::clamp(w, 0.0, 1.0) * 4.0;
    const int k = std::min(3, int(w));
    const float f = float(w - k);
    return stops[k] + (stops[k + 1] - stops[k]) * f;
}

std::string shortNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0e", v);
    return buf;
}

}  // namespace

Film differenceHeatMap(const MethodComparison& method, const MethodComparison& reference) {
    const int w = method.image.width, h = method.image.height;
    const int legend = 36;
    Film map(w, h + legend);
    // Scale: from 1e-6 m (or the smallest error) to the largest error, in decades.
    double lo = kInfinity, hi = 0.0;
    for (size_t k = 0; k < method.hitT.size(); ++k) {
        const double e = std::abs(method.hitT[k] - reference.hitT[k]);
        if (std::isnan(e) || e <= 0.0) continue;
        lo = std::min(lo, e);
        hi = std::max(hi, e);
    }
    if (!(hi > 0.0)) lo = 1e-9, hi = 1e-6;
    // At most seven decades, ending at the largest error.
    const double decHi = std::ceil(std::log10(hi));
    const double decLo = std::clamp(std::floor(std::log10(lo)), decHi - 7.0, decHi - 1.0);
    const glm::vec3 mismatch{0.9f, 0.0f, 0.9f}, bothMiss{0.05f, 0.05f, 0.05f};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = size_t(y) * size_t(w) + size_t(x);
            const bool a = !std::isnan(method.hitT[k]), b = !std::isnan(reference.hitT[k]);
            if (a != b) map.set(x, y, mismatch);
            else if (!a) map.set(x, y, bothMiss);
            else {
                const double e = std::abs(method.hitT[k] - reference.hitT[k]);
                const double wgt = e > 0.0 ? (std::log10(e) - decLo) / (decHi - decLo) : 0.0;
                map.set(x, y, heatColour(wgt));
            }
        }
    // Legend: a colour bar labelled with its ends in metres, and the hit/miss swatch. Everything is clipped
    // to the picture, so narrow images get a cut-off legend rather than a write out of bounds.
    const glm::vec3 white{1.0f, 1.0f, 1.0f};
    auto fill = [&](int x0, int y0, int x1, int y1, auto colourAt) {
        for (int y = std::max(y0, 0); y < std::min(y1, map.height); ++y)
            for (int x = std::max(x0, 0); x < std::min(x1, map.width); ++x) map.set(x, y, colourAt(x));
    };
    fill(0, h, w, h + legend, [](int) { return glm::vec3(0.0f); });
    const int scale = 2, barX0 = 8 * 4 * scale + 12, barX1 = std::max(barX0 + 20, w - 8 * 4 * scale - 80);
    fill(barX0, h + 6, barX1, h + 18, [&](int x) { return heatColour(double(x - barX0) / double(barX1 - barX0 - 1)); });
    drawText(map, 4, h + 7, shortNumber(std::pow(10.0, decLo)) + " m", scale, white);
    drawText(map, barX1 + 6, h + 7, shortNumber(std::pow(10.0, decHi)) + " m", scale, white);
    fill(barX0, h + 22, barX0 + 10, h + 32, [&](int) { return mismatch; });
    drawText(map, barX0 + 16, h + 22, "hit/miss", scale, white);
    return map;
}

std::string tradeoffSvg(const CompareReport& report) {
    // Log axes: x = primary rays/s, y = p99 |t - t_ref| (m). Exact zeros are drawn at the bottom edge.
    const double W = 640, H = 420, left = 80, right = 30, top = 30, bottom = 60;
    double xLo = kInfinity, xHi = 0, yLo = kInfinity, yHi = 0;
    for (const auto& m : report.methods) {
        xLo = std::min(xLo, m.primaryRaysPerSecond);
        xHi = std::max(xHi, m.primaryRaysPerSecond);
        if (m.tErrorM.p99 > 0) {
            yLo = std::min(yLo, m.tErrorM.p99);
            yHi = std::max(yHi, m.tErrorM.p99);
        }
    }
    if (!(yHi > 0)) yLo = 1e-9, yHi = 1e-6;
    const double dxLo = std::floor(std::log10(std::max(xLo, 1.0))), dxHi = std::max(dxLo + 1, std::ceil(std::log10(std::max(xHi, 1.0))));
    const double dyLo = std::floor(std::log10(yLo)) - 1, dyHi = std::max(dyLo + 1, std::ceil(std::log10(yHi)));
    auto px = [&](double v) { return left + (std::log10(std::max(v, 1.0)) - dxLo) / (dxHi - dxLo) * (W - left - right); };
    auto py = [&](double v) {
        const double l = v > 0 ? std::log10(v) : dyLo;
        return H - bottom - (l - dyLo) / (dyHi - dyLo) * (H - top - bottom);
    };
    SvgChart svg(W, H);
    svg.add("<text x=\"%.0f\" y=\"18\" font-size=\"14\">Speed against error: %dx%d camera rays</text>\n", left,
            report.width, report.height);
    for (double d = dxLo; d <= dxHi; ++d) {
        const double x = px(std::pow(10.0, d));
        svg.add("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#ddd\"/>\n<text x=\"%.1f\" y=\"%.0f\" "
                "text-anchor=\"middle\">1e%d</text>\n",
                x, top, x, H - bottom, x, H - bottom + 16, int(d));
    }
    for (double d = dyLo; d <= dyHi; ++d) {
        const double y = py(std::pow(10.0, d));
        svg.add("<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n<text x=\"%.0f\" y=\"%.1f\" "
                "text-anchor=\"end\">1e%d</text>\n",
                left, y, W - right, y, left - 6, y + 4, int(d));
    }
    svg.frame(left, top, W - left - right, H - top - bottom);
    svg.xTitle((left + W - right) / 2, H - 16, "primary rays per second (log)");
    svg.yTitle(18, (top + H - bottom) / 2, "p99 hit-distance error, m (log; 0 at the bottom)");
    for (const auto& m : report.methods) {
        const double x = px(m.primaryRaysPerSecond), y = py(m.tErrorM.p99);
        svg.add("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"#1f77b4\"/>\n<text x=\"%.1f\" y=\"%.1f\">%s</text>\n", x,
                y, x + 8, y - 6, comparisonName(m).c_str());
    }
    return svg.finish();
}

}  // namespace terracast
