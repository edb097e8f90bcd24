#include "tracer/measure/bench.h"

#include "heightfield/fractal_terrain.h"
#include "tracer/core/errors.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sstream>

#include "tracer/core/angles.h"

#include "tracer/measure/compare.h"
#include "tracer/measure/svg_chart.h"
#include "tracer/terrain/terrain_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#if defined(__SSE__) || defined(__x86_64__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#define TERRACAST_HAVE_MXCSR 1
#endif

namespace terracast {

namespace {

struct MethodInfo {
    BenchMethod method;
    const char* name;
    SurfaceMethod surface;
    Traversal traversal;
};
constexpr MethodInfo kMethods[] = {
    {BenchMethod::Bilinear, "bilinear", SurfaceMethod::Bilinear, Traversal::Pyramid},
    {BenchMethod::BilinearFlat, "bilinear-flat", SurfaceMethod::Bilinear, Traversal::Flat},
    {BenchMethod::Triangles, "triangles", SurfaceMethod::Triangles, Traversal::Pyramid},
    {BenchMethod::Embree, "embree", SurfaceMethod::Embree, Traversal::Pyramid},
    {BenchMethod::EmbreeGrid, "embree-grid", SurfaceMethod::EmbreeGrid, Traversal::Pyramid},
};

const MethodInfo& info(BenchMethod m) {
    for (const auto& i : kMethods)
        if (i.method == m) return i;
    return kMethods[0];
}


void setFlushModes() {
#ifdef TERRACAST_HAVE_MXCSR
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
}

}  // namespace

const char* benchMethodName(BenchMethod method) { return info(method).name; }

std::optional<BenchMethod> parseBenchMethod(std::string_view name) {
    for (const auto& i : kMethods)
        if (name == i.name) return i.method;
    return std::nullopt;
}

const std::vector<BenchMethod>& benchMethods() {
    static const std::vector<BenchMethod> all{BenchMethod::Bilinear, BenchMethod::BilinearFlat, BenchMethod::Triangles,
                                              BenchMethod::Embree, BenchMethod::EmbreeGrid};
    return all;
}

SurfaceMethod benchSurfaceMethod(BenchMethod method) { return info(method).surface; }
Traversal benchTraversal(BenchMethod method) { return info(method).traversal; }

const char* benchCameraName(BenchCamera camera) { return camera == BenchCamera::Corner ? "corner" : "grazing"; }

// Parses "513,2049,8193" into sizes of 2^n + 1 vertices from 3 to 65537.
std::vector<int64_t> parseBenchSizes(const std::string& text) {
    std::vector<int64_t> sizes;
    std::stringstream in(text);
    std::string item;
    const auto bad = [&] {
        return InputError(fmt::format("--sizes: expected comma-separated grid sizes of 2^n + 1 vertices from 3 to "
                                      "65537 (such as 513,2049,8193), found '{}'",
                                      text));
    };
    while (std::getline(in, item, ',')) {
        size_t used = 0;
        int64_t v = 0;
        try {
            v = std::stoll(item, &used);
        } catch (const std::exception&) {
            throw bad();
        }
        if (used != item.size() || !isFractalTerrainSize(v) || v > 65537) throw bad();
        sizes.push_back(v);
    }
    if (sizes.empty() || (!text.empty() && text.back() == ',')) throw bad();
    return sizes;
}

// Parses "bilinear,triangles" into bench methods, in report order; embree is always measured (the ratios'
// reference).
std::vector<BenchMethod> parseBenchMethods(const std::string& text) {
    const auto benchMethodNames = [] {
        std::vector<std::string> names;
        for (BenchMethod m : benchMethods()) names.emplace_back(benchMethodName(m));
        return names;
    };
    std::vector<bool> wanted(benchMethods().size(), false);
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        const auto m = parseBenchMethod(item);
        if (!m)
            throw InputError(fmt::format("--methods: expected a comma-separated list of {}, found '{}'",
                                         fmt::join(benchMethodNames(), ", "), item));
        wanted[size_t(std::find(benchMethods().begin(), benchMethods().end(), *m) - benchMethods().begin())] = true;
    }
    if (text.empty() || text.back() == ',')
        throw InputError(fmt::format("--methods: expected a comma-separated list of methods, found '{}'", text));
    std::vector<BenchMethod> methods;
    for (size_t k = 0; k < wanted.size(); ++k)
        if (wanted[k] || benchMethods()[k] == BenchMethod::Embree) methods.push_back(benchMethods()[k]);
    return methods;
}

PinholeCamera benchCamera(const HeightGrid& grid, BenchCamera camera, double aspect) {
    if (camera == BenchCamera::Corner) return autoCamera(grid, aspect);
    // The highest valid vertex (the first one, scanning rows from the south, when several tie).
    int64_t pi = 0, pj = 0;
    float top = -std::numeric_limits<float>::infinity();
    for (int64_t j = 0; j < grid.height(); ++j)
        for (int64_t i = 0; i < grid.width(); ++i)
            if (grid.vertexValid(i, j) && grid.at(i, j) > top) {
                top = grid.at(i, j);
                pi = i;
                pj = j;
            }
    const glm::dvec2 peakM{double(pi) * grid.cellSizeXM(), double(pj) * grid.cellSizeYM()};
    const glm::dvec2 centreM{0.5 * grid.extentXM(), 0.5 * grid.extentYM()};
    // Towards the centre; north-east when the peak stands on it.
    glm::dvec2 heading = centreM - peakM;
    const double across = std::hypot(grid.extentXM(), grid.extentYM());
    heading = glm::length(heading) > 1e-6 * across ? glm::normalize(heading) : glm::dvec2(std::sqrt(0.5));
    // "Just above": clear of the peak by a hundredth of the relief, and by at least a metre.
    const double clearanceM = std::max(1.0, 0.01 * (double(grid.maxHeightM()) - grid.minHeightM()));
    const double pitch = radians(8.0);
    PinholeCamera cam;
    cam.eyeM = {peakM.x, peakM.y, double(top) + clearanceM};
    cam.lookAtM = cam.eyeM + glm::dvec3(heading.x * std::cos(pitch), heading.y * std::cos(pitch), -std::sin(pitch));
    (void)aspect;
    return cam;
}

detail::FlushedArena::FlushedArena() {
#ifdef TERRACAST_HAVE_MXCSR
    savedCsr = _mm_getcsr();
#endif
    setFlushModes();
    arena.initialize();
}

FlushDenormalsScope::FlushDenormalsScope() : tbb::task_scheduler_observer(arena) { observe(true); }

FlushDenormalsScope::~FlushDenormalsScope() {
    observe(false);
#ifdef TERRACAST_HAVE_MXCSR
    _mm_setcsr(savedCsr);
#endif
}

void FlushDenormalsScope::on_scheduler_entry(bool) { setFlushModes(); }

bool denormalsFlushed() {
#ifdef TERRACAST_HAVE_MXCSR
    return _MM_GET_FLUSH_ZERO_MODE() == _MM_FLUSH_ZERO_ON && _MM_GET_DENORMALS_ZERO_MODE() == _MM_DENORMALS_ZERO_ON;
#else
    return false;
#endif
}

double bandedSeconds(const std::vector<std::vector<double>>& seconds) {
    size_t bands = 0;
    for (const auto& repetition : seconds) bands = std::max(bands, repetition.size());
    double total = 0.0;
    for (size_t b = 0; b < bands; ++b) {
        double fastest = std::numeric_limits<double>::infinity();
        for (const auto& repetition : seconds)
            if (b < repetition.size()) fastest = std::min(fastest, repetition[b]);
        total += fastest;
    }
    return total;
}

BenchGridResult benchGrid(const HeightGrid& grid, const BenchSettings& s) {
    BenchGridResult out;
    out.width = grid.width();
    out.height = grid.height();
    out.cells = grid.cellsX() * grid.cellsY();
    const double aspect = double(s.width) / double(s.height);
    const int buildThreads = s.threadCounts.empty() ? 0 : *std::max_element(s.threadCounts.begin(), s.threadCounts.end());
    FlushDenormalsScope flush;

    // Methods are measured in groups whose surfaces are alive together, and within a group each pass's traces go
    // round the methods in turn (see below): a stretch in which a shared machine runs slow then falls on every
    // method of the group alike instead of on one method's whole pass. The methods on the grid
    // itself cost no memory of their own, so they share a group with Embree's triangle mesh, the baseline of
    // every ratio; Embree's grid geometry is measured in a group of its own afterwards, so that no two Embree
    // scenes are held at once. Its ratios are therefore over the mesh's passes of the first group, taken minutes
    // earlier, not in turn with it.
    std::vector<std::vector<size_t>> groups(1);
    for (size_t k = 0; k < s.methods.size(); ++k) {
        if (s.methods[k] == BenchMethod::EmbreeGrid) groups.push_back({k});
        else groups.front().push_back(k);
    }
    out.methods.resize(s.methods.size());
    std::vector<double> referenceT;  // the first measured method's hit distances in the first pass
    flush.run([&] {
        for (const std::vector<size_t>& group : groups) {
            // Built in the settings' order; refused methods are skipped.
            std::vector<std::pair<size_t, std::unique_ptr<TerrainSurface>>> built;
            for (size_t k : group) {
                const BenchMethod method = s.methods[k];
                BenchMethodResult& r = out.methods[k];
                r.method = method;
                if (s.refuse)
                    if (const auto need = s.refuse(method)) {
                        r.skipped = true;
                        r.neededBytes = *need;
                        continue;
                    }
                if (s.onStep) s.onStep(std::string("building ") + benchMethodName(method));
                auto surface = std::make_unique<TerrainSurface>(grid, benchSurfaceMethod(method), buildThreads,
                                                                benchTraversal(method));
                r.buildSeconds = surface->buildSeconds();
                r.memoryBytes = surface->memoryBytes();
                r.peakMemoryBytes = std::max(surface->peakMemoryBytes(), r.memoryBytes);
                r.bytesPerCell = double(r.memoryBytes) / double(out.cells);
                r.peakBytesPerCell = double(r.peakMemoryBytes) / double(out.cells);
                built.emplace_back(k, std::move(surface));
            }
            for (BenchCamera camera : s.cameras)
                for (int threads : s.threadCounts) {
                    TerrainRenderSettings rs;
                    rs.width = s.width;
                    rs.height = s.height;
                    rs.threads = threads;
                    rs.sun.azimuthDeg = s.sunAzimuthDeg;
                    rs.sun.elevationDeg = s.sunElevationDeg;
                    rs.camera = benchCamera(grid, camera, aspect);
                    const std::string passName = std::string(benchCameraName(camera)) + " camera, " +
                                                 std::to_string(threads) + (threads == 1 ? " thread" : " threads");
                    // Rates and hit distances only, for every method alike. One untimed trace per method first,
                    // so that every method's timed traces start with the threads awake; its hit distances give the
                    // agreement. Then each repetition traces the picture band by band (`bands` bands of rows),
                    // every band going round the methods in turn, and a method's time is the sum of each band's
                    // fastest time (bandedSeconds): a stretch in which a shared machine runs slow then costs only
                    // the band traces it falls on, which other repetitions replace. The order (a, b, c, or c, b,
                    // a) alternates from one band to the next within a repetition, and for each band from one
                    // repetition to the next, so that no method always follows the same one, nor always runs
                    // first or last.
                    for (const auto& [k, surface] : built) {
                        BenchMethodResult& r = out.methods[k];
                        r.passes.push_back({.camera = camera, .threads = threads});
                        if (s.onStep)
                            s.onStep(std::string(benchMethodName(s.methods[k])) + ", " + passName + ", warm-up");
                        const MethodComparison m = traceSurface(grid, *surface, rs, false);
                        if (r.passes.size() == 1) {
                            if (referenceT.empty()) referenceT = m.hitT;
                            int64_t agree = 0;
                            for (size_t q = 0; q < m.hitT.size(); ++q)
                                agree += std::isnan(m.hitT[q]) == std::isnan(referenceT[q]);
                            r.hitAgreement = m.hitT.empty() ? 0.0 : double(agree) / double(m.hitT.size());
                        }
                    }
                    const int bands = std::clamp(s.bands, 1, std::max(1, s.height));
                    const int repeat = std::max(1, s.repeat);
                    // Per method (in `built` order), per repetition and band: seconds. The rays are counted from
                    // the first repetition, as every repetition traces the same ones.
                    using Times = std::vector<std::vector<double>>;
                    std::vector<Times> primarySeconds(built.size(),
                                                      Times(size_t(repeat), std::vector<double>(size_t(bands))));
                    std::vector<Times> shadowSeconds = primarySeconds;
                    for (int rep = 0; rep < repeat; ++rep)
                        for (int band = 0; band < bands; ++band) {
                            const int y0 = int(int64_t(s.height) * band / bands);
                            const int y1 = int(int64_t(s.height) * (band + 1) / bands);
                            const std::string rows = bands == 1 ? std::string()
                                                                : ", rows " + std::to_string(y0) + " to " +
                                                                      std::to_string(y1 - 1);
                            for (size_t q = 0; q < built.size(); ++q) {
                                const size_t at = (rep + band) % 2 == 0 ? q : built.size() - 1 - q;
                                const auto& [k, surface] = built[at];
                                if (s.onStep)
                                    s.onStep(std::string(benchMethodName(out.methods[k].method)) + ", " + passName +
                                             rows);
                                const MethodComparison m = traceSurface(grid, *surface, rs, false, y0, y1);
                                primarySeconds[at][size_t(rep)][size_t(band)] = m.primarySeconds;
                                shadowSeconds[at][size_t(rep)][size_t(band)] = m.shadowSeconds;
                                if (rep == 0) {
                                    BenchPass& p = out.methods[k].passes.back();
                                    p.primaryRays += m.primaryRays;
                                    p.shadowRays += m.shadowRays;
                                }
                            }
                        }
                    for (size_t q = 0; q < built.size(); ++q) {
                        BenchPass& p = out.methods[built[q].first].passes.back();
                        const double primary = bandedSeconds(primarySeconds[q]);
                        const double shadow = bandedSeconds(shadowSeconds[q]);
                        p.primaryRaysPerSecond = primary > 0.0 ? double(p.primaryRays) / primary : 0.0;
                        p.shadowRaysPerSecond = shadow > 0.0 ? double(p.shadowRays) / shadow : 0.0;
                    }
                }
        }
    });

    // Ratios to Embree's triangle mesh, pass by pass.
    const BenchMethodResult* embree = nullptr;
    for (const auto& m : out.methods)
        if (m.method == BenchMethod::Embree && !m.skipped) embree = &m;
    for (auto& m : out.methods)
        for (size_t k = 0; k < m.passes.size(); ++k) {
            auto& p = m.passes[k];
            p.ratioToEmbreePrimary = p.ratioToEmbreeShadow = std::numeric_limits<double>::quiet_NaN();
            if (!embree) continue;
            const auto& e = embree->passes[k];
            if (e.primaryRaysPerSecond > 0.0) p.ratioToEmbreePrimary = p.primaryRaysPerSecond / e.primaryRaysPerSecond;
            if (e.shadowRaysPerSecond > 0.0) p.ratioToEmbreeShadow = p.shadowRaysPerSecond / e.shadowRaysPerSecond;
        }
    return out;
}

namespace {

// One colour per method, in benchMethods() order; Embree's lines are dashed, so the baseline stands out.
const char* methodColour(BenchMethod m) {
    switch (m) {
    case BenchMethod::Bilinear: return "#1f77b4";
    case BenchMethod::BilinearFlat: return "#17becf";
    case BenchMethod::Triangles: return "#2ca02c";
    case BenchMethod::Embree: return "#d62728";
    case BenchMethod::EmbreeGrid: return "#ff7f0e";
    }
    return "#000000";
}

bool isEmbree(BenchMethod m) { return m == BenchMethod::Embree || m == BenchMethod::EmbreeGrid; }

// A method's pass on `camera` at the most threads it was measured with, or none.
const BenchPass* mostThreadsPass(const BenchMethodResult& m, BenchCamera camera) {
    const BenchPass* best = nullptr;
    for (const auto& p : m.passes)
        if (p.camera == camera && (!best || p.threads > best->threads)) best = &p;
    return best;
}

}  // namespace

std::string benchRatesSvg(const std::vector<BenchGridResult>& grids, const std::string& machine) {
    // Two plot areas side by side, sharing the y scale so that the panels compare at a glance.
    const double W = 1000, H = 480, plotW = 400, top = 74, bottom = 390;
    const double plotLeft[2] = {70, 570};
    const BenchCamera cameras[2] = {BenchCamera::Corner, BenchCamera::Grazing};

    // Methods in report order, as they first appear; rates and sizes for the axes.
    std::vector<BenchMethod> methods;
    double rateLo = std::numeric_limits<double>::infinity(), rateHi = 0.0;
    double sizeLo = std::numeric_limits<double>::infinity(), sizeHi = 0.0;
    int threads = 0;
    for (const auto& g : grids) {
        sizeLo = std::min(sizeLo, double(g.width));
        sizeHi = std::max(sizeHi, double(g.width));
        for (const auto& m : g.methods) {
            if (m.skipped) continue;
            if (std::find(methods.begin(), methods.end(), m.method) == methods.end()) methods.push_back(m.method);
            for (BenchCamera c : cameras)
                if (const BenchPass* p = mostThreadsPass(m, c); p && p->primaryRaysPerSecond > 0.0) {
                    rateLo = std::min(rateLo, p->primaryRaysPerSecond * 1e-6);
                    rateHi = std::max(rateHi, p->primaryRaysPerSecond * 1e-6);
                    threads = std::max(threads, p->threads);
                }
        }
    }
    std::sort(methods.begin(), methods.end(), [](BenchMethod a, BenchMethod b) { return int(a) < int(b); });
    if (!(rateHi > 0.0)) rateLo = 0.1, rateHi = 10.0;
    if (!(sizeHi > 0.0)) sizeLo = 3.0, sizeHi = 3.0;
    // x: log10 of the size, half an octave of room on either side; y: whole decades around the rates.
    const double xLo = std::log10(sizeLo) - 0.15, xHi = std::log10(sizeHi) + 0.15;
    const double dLo = std::floor(std::log10(rateLo)), dHi = std::max(dLo + 1.0, std::ceil(std::log10(rateHi)));
    auto px = [&](int panel, double size) { return plotLeft[panel] + (std::log10(size) - xLo) / (xHi - xLo) * plotW; };
    auto py = [&](double mrays) { return bottom - (std::log10(mrays) - dLo) / (dHi - dLo) * (bottom - top); };

    SvgChart svg(W, H);
    char buf[768];
    const auto add = [&](const char* format, auto... args) { svg.add(format, args...); };
    const std::string title = "Camera rays per second against grid size" +
                              (threads > 0 ? " at " + std::to_string(threads) + (threads == 1 ? " thread" : " threads") : "");
    add("<text x=\"%.0f\" y=\"22\" font-size=\"15\">%s</text>\n", plotLeft[0], xmlEscaped(title).c_str());
    if (!machine.empty())
        add("<text x=\"%.0f\" y=\"40\" fill=\"#444\">%s</text>\n", plotLeft[0], xmlEscaped(machine).c_str());

    for (int panel = 0; panel < 2; ++panel) {
        const double x0 = plotLeft[panel], x1 = x0 + plotW;
        add("<g data-camera=\"%s\">\n<text x=\"%.0f\" y=\"%.0f\" font-size=\"13\" text-anchor=\"middle\">%s camera</text>\n",
            benchCameraName(cameras[panel]), (x0 + x1) / 2, top - 8, benchCameraName(cameras[panel]));
        // Grid lines and labels: 1, 2 and 5 of every decade on y, the measured sizes on x.
        for (double d = dLo; d <= dHi; ++d)
            for (double mant : {1.0, 2.0, 5.0}) {
                const double v = mant * std::pow(10.0, d);
                if (std::log10(v) > dHi + 1e-9) continue;
                const double y = py(v);
                add("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/>\n", x0, y, x1, y,
                    mant == 1.0 ? "#ccc" : "#eee");
                add("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", x0 - 6, y + 4, v);
            }
        std::vector<int64_t> sizes;
        for (const auto& g : grids)
            if (std::find(sizes.begin(), sizes.end(), g.width) == sizes.end()) sizes.push_back(g.width);
        for (int64_t size : sizes) {
            const double x = px(panel, double(size));
            add("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#eee\"/>\n<text x=\"%.1f\" y=\"%.0f\" "
                "text-anchor=\"middle\">%lld</text>\n",
                x, top, x, bottom, x, bottom + 16, (long long)size);
        }
        svg.frame(x0, top, plotW, bottom - top);
        svg.xTitle((x0 + x1) / 2, bottom + 36, "grid size, vertices per side (log)");
        svg.yTitle(x0 - 48, (top + bottom) / 2, "million camera rays per second (log)");
        // One line per method, then its markers on top.
        for (BenchMethod method : methods) {
            std::string points, markers;
            for (const auto& g : grids)
                for (const auto& m : g.methods) {
                    if (m.method != method || m.skipped) continue;
                    const BenchPass* p = mostThreadsPass(m, cameras[panel]);
                    if (!p || !(p->primaryRaysPerSecond > 0.0)) continue;
                    const double x = px(panel, double(g.width)), y = py(p->primaryRaysPerSecond * 1e-6);
                    std::snprintf(buf, sizeof buf, "%s%.2f,%.2f", points.empty() ? "" : " ", x, y);
                    points += buf;
                    std::snprintf(buf, sizeof buf, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"3.5\" fill=\"%s\"/>\n", x, y,
                                  methodColour(method));
                    markers += buf;
                }
            if (points.empty()) continue;
            add("<polyline data-method=\"%s\" data-camera=\"%s\" fill=\"none\" stroke=\"%s\" stroke-width=\"2\"%s "
                "points=\"%s\"/>\n",
                benchMethodName(method), benchCameraName(cameras[panel]), methodColour(method),
                isEmbree(method) ? " stroke-dasharray=\"6 3\"" : "", points.c_str());
            svg.raw(markers);
        }
        svg.raw("</g>\n");
    }

    // The legend: one entry per method, in a row under both panels.
    double lx = plotLeft[0];
    const double ly = H - 24;
    for (BenchMethod method : methods) {
        add("<g data-legend=\"%s\"><line x1=\"%.0f\" y1=\"%.0f\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"%s\" stroke-width=\"2\"%s/>"
            "<circle cx=\"%.0f\" cy=\"%.0f\" r=\"3.5\" fill=\"%s\"/><text x=\"%.0f\" y=\"%.0f\">%s</text></g>\n",
            benchMethodName(method), lx, ly, lx + 28, ly, methodColour(method),
            isEmbree(method) ? " stroke-dasharray=\"6 3\"" : "", lx + 14, ly, methodColour(method), lx + 34, ly + 4,
            benchMethodName(method));
        lx += 44 + 8.0 * double(std::string(benchMethodName(method)).size()) + 24;
    }
    return svg.finish();
}

}  // namespace terracast
