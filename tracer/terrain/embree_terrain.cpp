#include "tracer/terrain/embree_terrain.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace terracast {

namespace {

// The first error Embree reported through the device callback, waiting to be thrown.
struct ErrorSink {
    std::mutex mutex;
    std::string message;
};

void onEmbreeError(void* user, RTCError code, const char* text) noexcept {
    // Nothing may escape into Embree's C code: a failed allocation here only loses the message text.
    try {
        auto* sink = static_cast<ErrorSink*>(user);
        std::lock_guard lock(sink->mutex);
        if (sink->message.empty()) sink->message = "error " + std::to_string(int(code)) + ": " + (text ? text : "");
    } catch (...) {
    }
}

// Owns one RTCGeometry until it is attached, so an exception in between cannot leak it.
class GeometryHolder {
public:
    explicit GeometryHolder(RTCGeometry g) : g_(g) {}
    ~GeometryHolder() {
        if (g_) rtcReleaseGeometry(g_);
    }
    GeometryHolder(const GeometryHolder&) = delete;
    GeometryHolder& operator=(const GeometryHolder&) = delete;
    RTCGeometry get() const { return g_; }

private:
    RTCGeometry g_;
};

}  // namespace

bool embreeMemoryMonitor(void* user, long bytes, bool /*post*/) {
    auto* self = static_cast<EmbreeTerrain*>(user);
    const int64_t now = self->embreeBytes_ += bytes;
    int64_t peak = self->peakBytes_.load();
    while (now > peak && !self->peakBytes_.compare_exchange_weak(peak, now)) {
    }
    return true;
}

namespace {
bool memoryMonitorThunk(void* user, ssize_t bytes, bool post) { return embreeMemoryMonitor(user, long(bytes), post); }
}  // namespace

struct EmbreeTerrain::Impl {
    ErrorSink errors;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;

    // Throws if Embree reported an error since the last check, naming the call that was made.
    void check(const char* call) {
        std::lock_guard lock(errors.mutex);
        if (!errors.message.empty()) {
            const std::string m = "Embree " + std::string(call) + ": " + errors.message;
            errors.message.clear();
            throw std::runtime_error(m);
        }
    }
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

EmbreeTerrain::EmbreeTerrain(const HeightGrid& grid, EmbreeLayout layout, int threads)
    : impl_(std::make_unique<Impl>()), cellSizeXM_(grid.cellSizeXM()), cellSizeYM_(grid.cellSizeYM()), grid_(&grid) {
    const auto start = std::chrono::steady_clock::now();
    if (grid.width() * grid.height() > int64_t(std::numeric_limits<unsigned>::max()))
        throw std::runtime_error("Embree: the grid has more vertices than 32-bit indices can address");
    const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : std::string();
    impl_->device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!impl_->device) throw std::runtime_error("Embree rtcNewDevice: error " + std::to_string(int(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(impl_->device, onEmbreeError, &impl_->errors);
    rtcSetDeviceMemoryMonitorFunction(impl_->device, memoryMonitorThunk, this);
    impl_->scene = rtcNewScene(impl_->device);
    impl_->check("rtcNewScene");
    rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
    // Medium is Embree's own default for static scenes and the baseline `bench` measures against.
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_MEDIUM);

    const int64_t W = grid.width(), H = grid.height();
    // Vertices in the grid's local frame, in float (the frame keeps coordinates small).
    auto fillVertices = [&](RTCGeometry geom) {
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), size_t(W * H)));
        impl_->check("rtcSetNewGeometryBuffer(vertex)");
        for (int64_t j = 0; j < H; ++j)
            for (int64_t i = 0; i < W; ++i) {
                float* p = v + 3 * (j * W + i);
                p[0] = float(double(i) * grid.cellSizeXM());
                p[1] = float(double(j) * grid.cellSizeYM());
                // Nodata vertices belong to no emitted cell; a finite height keeps Embree's bounds sane.
                p[2] = grid.vertexValid(i, j) ? grid.at(i, j) : grid.minHeightM();
            }
    };

    if (layout == EmbreeLayout::TriangleMesh) {
        const GeometryHolder holder(rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE));
        impl_->check("rtcNewGeometry(TRIANGLE)");
        RTCGeometry geom = holder.get();
        fillVertices(geom);
        const int64_t cells = grid.validCellCount();
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(unsigned), size_t(2 * cells)));
        impl_->check("rtcSetNewGeometryBuffer(index)");
        int64_t t = 0;
        for (int64_t j = 0; j < H - 1; ++j)
            for (int64_t i = 0; i < W - 1; ++i) {
                if (!grid.cellValid(i, j)) continue;
                const unsigned v00 = unsigned(j * W + i), v10 = v00 + 1, v01 = unsigned((j + 1) * W + i), v11 = v01 + 1;
                unsigned* a = idx + 6 * t;
                a[0] = v00, a[1] = v10, a[2] = v01;  // lower-left triangle, u + v <= 1
                a[3] = v10, a[4] = v11, a[5] = v01;  // upper-right triangle
                ++t;
            }
        triangles_ = 2 * t;
        rtcCommitGeometry(geom);
        impl_->check("rtcCommitGeometry");
        rtcAttachGeometry(impl_->scene, geom);
    } else {
        // Grids of at most kTile x kTile cells; a tile with holes becomes one strip per run of valid cells.
        constexpr int64_t kTile = 256;
        std::vector<RTCGrid> grids;
        auto runIsValid = [&](int64_t i0, int64_t i1, int64_t j0, int64_t j1) {
            for (int64_t j = j0; j < j1; ++j)
                for (int64_t i = i0; i < i1; ++i)
                    if (!grid.cellValid(i, j)) return false;
            return true;
        };
        for (int64_t tj = 0; tj < H - 1; tj += kTile)
            for (int64_t ti = 0; ti < W - 1; ti += kTile) {
                const int64_t i1 = std::min(ti + kTile, W - 1), j1 = std::min(tj + kTile, H - 1);
                if (runIsValid(ti, i1, tj, j1)) {
                    grids.push_back({unsigned(tj * W + ti), unsigned(W), (unsigned short)(i1 - ti + 1),
                                     (unsigned short)(j1 - tj + 1)});
                    continue;
                }
                for (int64_t j = tj; j < j1; ++j)
                    for (int64_t i = ti; i < i1;) {
                        if (!grid.cellValid(i, j)) {
                            ++i;
                            continue;
                        }
                        int64_t e = i;
                        while (e < i1 && grid.cellValid(e, j)) ++e;
                        grids.push_back({unsigned(j * W + i), unsigned(W), (unsigned short)(e - i + 1), 2});
                        i = e;
                    }
            }
        const GeometryHolder holder(rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_GRID));
        impl_->check("rtcNewGeometry(GRID)");
        RTCGeometry geom = holder.get();
        fillVertices(geom);
        auto* g = static_cast<RTCGrid*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID,
                                                               sizeof(RTCGrid), grids.size()));
        impl_->check("rtcSetNewGeometryBuffer(grid)");
        std::copy(grids.begin(), grids.end(), g);
        triangles_ = 2 * grid.validCellCount();
        rtcCommitGeometry(geom);
        impl_->check("rtcCommitGeometry");
        rtcAttachGeometry(impl_->scene, geom);
    }
    rtcCommitScene(impl_->scene);
    impl_->check("rtcCommitScene");
    buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EmbreeTerrain::~EmbreeTerrain() = default;

namespace {
// An Embree ray from ours: float origin and direction in the grid's local frame, the interval's ends.
RTCRay toEmbreeRay(const Ray& ray, Interval interval) {
    RTCRay r{};
    r.org_x = float(ray.origin.x);
    r.org_y = float(ray.origin.y);
    r.org_z = float(ray.origin.z);
    r.dir_x = float(ray.dir.x);
    r.dir_y = float(ray.dir.y);
    r.dir_z = float(ray.dir.z);
    r.tnear = float(std::max(0.0, interval.lo));
    r.tfar = std::isfinite(interval.hi) ? float(interval.hi) : std::numeric_limits<float>::infinity();
    r.mask = 0xFFFFFFFFu;
    r.time = float(ray.time);
    return r;
}
}  // namespace

std::optional<HeightFieldHit> EmbreeTerrain::intersect(const Ray& ray, Interval interval) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray = toEmbreeRay(ray, interval);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    HeightFieldHit hit;
    hit.t = rh.ray.tfar;
    hit.pointM = ray.at(hit.t);
    glm::dvec3 n{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    if (n.z < 0.0) n = -n;
    hit.normal = glm::normalize(n);
    const double gx = hit.pointM.x / cellSizeXM_, gy = hit.pointM.y / cellSizeYM_;
    hit.cellX = std::clamp<int64_t>(int64_t(std::floor(gx)), 0, grid_->cellsX() - 1);
    hit.cellY = std::clamp<int64_t>(int64_t(std::floor(gy)), 0, grid_->cellsY() - 1);
    hit.u = std::clamp(gx - double(hit.cellX), 0.0, 1.0);
    hit.v = std::clamp(gy - double(hit.cellY), 0.0, 1.0);
    // Embree works in float on absolute local coordinates: the error bound scales with their magnitude.
    const double magnitude = std::abs(hit.pointM.x) + std::abs(hit.pointM.y) + std::abs(hit.pointM.z);
    hit.errorM = 32.0 * double(std::numeric_limits<float>::epsilon()) * magnitude;
    return hit;
}

bool EmbreeTerrain::occluded(const Ray& ray, Interval interval) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r = toEmbreeRay(ray, interval);
    rtcOccluded1(impl_->scene, &context, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace terracast
