#include "tracer/bench.h"

#include "tracer/compare.h"
#include "tracer/terrain_renderer.h"

#include <algorithm>
#include <cmath>
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

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

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
    const double pitch = 8.0 * kRadiansPerDegree;
    PinholeCamera cam;
    cam.eyeM = {peakM.x, peakM.y, double(top) + clearanceM};
    cam.lookAtM = cam.eyeM + glm::dvec3(heading.x * std::cos(pitch), heading.y * std::cos(pitch), -std::sin(pitch));
    (void)aspect;
    return cam;
}

FlushDenormalsScope::FlushDenormalsScope() {
#ifdef TERRACAST_HAVE_MXCSR
    savedCsr_ = _mm_getcsr();
#endif
    setFlushModes();
    observe(true);
}

FlushDenormalsScope::~FlushDenormalsScope() {
    observe(false);
#ifdef TERRACAST_HAVE_MXCSR
    _mm_setcsr(savedCsr_);
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

BenchGridResult benchGrid(const HeightGrid& grid, const BenchSettings& s) {
    BenchGridResult out;
    out.width = grid.width();
    out.height = grid.height();
    out.cells = grid.cellsX() * grid.cellsY();
    const double aspect = double(s.width) / double(s.height);
    const int buildThreads = s.threadCounts.empty() ? 0 : *std::max_element(s.threadCounts.begin(), s.threadCounts.end());
    const FlushDenormalsScope flush;

    std::vector<double> referenceT;  // the first measured method's hit distances in the first pass
    for (BenchMethod method : s.methods) {
        BenchMethodResult r;
        r.method = method;
        if (s.refuse)
            if (const auto need = s.refuse(method)) {
                r.skipped = true;
                r.neededBytes = *need;
                out.methods.push_back(std::move(r));
                continue;
            }
        if (s.onStep) s.onStep(std::string("building ") + benchMethodName(method));
        const TerrainSurface surface(grid, benchSurfaceMethod(method), buildThreads, benchTraversal(method));
        r.buildSeconds = surface.buildSeconds();
        r.memoryBytes = surface.memoryBytes();
        r.peakMemoryBytes = std::max(surface.peakMemoryBytes(), r.memoryBytes);
        r.bytesPerCell = double(r.memoryBytes) / double(out.cells);
        r.peakBytesPerCell = double(r.peakMemoryBytes) / double(out.cells);
        for (BenchCamera camera : s.cameras)
            for (int threads : s.threadCounts) {
                if (s.onStep)
                    s.onStep(std::string(benchMethodName(method)) + ", " + benchCameraName(camera) + " camera, " +
                             std::to_string(threads) + (threads == 1 ? " thread" : " threads"));
                TerrainRenderSettings rs;
                rs.width = s.width;
                rs.height = s.height;
                rs.threads = threads;
                rs.sun.azimuthDeg = s.sunAzimuthDeg;
                rs.sun.elevationDeg = s.sunElevationDeg;
                rs.camera = benchCamera(grid, camera, aspect);
                const MethodComparison m = traceSurface(grid, surface, rs, false);  // rates and hit distances only
                BenchPass p;
                p.camera = camera;
                p.threads = threads;
                p.primaryRays = m.primaryRays;
                p.shadowRays = m.shadowRays;
                p.primaryRaysPerSecond = m.primaryRaysPerSecond;
                p.shadowRaysPerSecond = m.shadowRaysPerSecond;
                if (r.passes.empty()) {
                    if (referenceT.empty()) referenceT = m.hitT;
                    int64_t agree = 0;
                    for (size_t k = 0; k < m.hitT.size(); ++k) agree += std::isnan(m.hitT[k]) == std::isnan(referenceT[k]);
                    r.hitAgreement = m.hitT.empty() ? 0.0 : double(agree) / double(m.hitT.size());
                }
                r.passes.push_back(p);
            }
        out.methods.push_back(std::move(r));
    }

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

}  // namespace terracast
