// `bench`: the direct tracer against Embree on one grid, under fixed cameras and a low sun, at several thread
// counts. Each method traces the same camera rays and one shadow ray per hit facing the sun; every pass is
// timed on its own, so rays per second compare like with like.
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/traversal.h"
#include "tracer/terrain/camera.h"
#include "tracer/terrain/surface.h"

#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace terracast {

// The methods `bench` measures.
enum class BenchMethod {
    Bilinear,      // direct, exact patch, through the pyramids
    BilinearFlat,  // the same, walking every cell (the pyramid's ablation)
    Triangles,     // direct, two triangles per cell, through the pyramid
    Embree,        // Embree triangle mesh
    EmbreeGrid,    // Embree grid geometry
};

// "bilinear", "bilinear-flat", "triangles", "embree", "embree-grid".
const char* benchMethodName(BenchMethod method);
std::optional<BenchMethod> parseBenchMethod(std::string_view name);
// All of them, in report order.
const std::vector<BenchMethod>& benchMethods();
// The surface and traversal a method traces with.
SurfaceMethod benchSurfaceMethod(BenchMethod method);
Traversal benchTraversal(BenchMethod method);

// The two views of every grid.
enum class BenchCamera {
    Corner,   // from outside the south-west corner, 30 degrees down, framing the whole grid (autoCamera)
    Grazing,  // just above the highest vertex, looking 8 degrees down towards the grid's centre
};
const char* benchCameraName(BenchCamera camera);
// The pinhole camera of a view of `grid` for a film of the given aspect ratio (width / height).
PinholeCamera benchCamera(const HeightGrid& grid, BenchCamera camera, double aspect);

namespace detail {
// Sets FTZ and DAZ on the calling thread, keeping its previous modes, and then makes a task arena: an arena
// hands the modes of the thread that makes it to every task it runs, on any thread.
struct FlushedArena {
    FlushedArena();
    unsigned savedCsr = 0;
    tbb::task_arena arena;
};
}  // namespace detail

// While alive, flushes denormals to zero (FTZ and DAZ in MXCSR) on the calling thread and, for work started
// through run(), on every TBB thread that takes part, so the direct tracer and Embree run under the same
// floating-point modes. Work goes through its own arena because TBB's shared arena hands out the modes of
// whichever thread created it first; the observer also sets them on each thread that joins. The calling
// thread's modes are restored on destruction. A no-op where SSE is absent.
class FlushDenormalsScope : private detail::FlushedArena, public tbb::task_scheduler_observer {
public:
    FlushDenormalsScope();
    ~FlushDenormalsScope() override;
    FlushDenormalsScope(const FlushDenormalsScope&) = delete;
    FlushDenormalsScope& operator=(const FlushDenormalsScope&) = delete;
    void on_scheduler_entry(bool isWorker) override;
    // Runs f in the scope's arena and returns what it returns.
    template <class F>
    decltype(auto) run(F&& f) {
        return arena.execute(std::forward<F>(f));
    }
};

// True when the calling thread flushes denormal results and operands to zero.
bool denormalsFlushed();

// Parses "513,2049,8193" into sizes of 2^n + 1 vertices from 3 to 65537; throws InputError naming --sizes.
std::vector<int64_t> parseBenchSizes(const std::string& text);
// Parses "bilinear,triangles" into bench methods, in report order, embree always among them (the ratios'
// reference); throws InputError naming --methods.
std::vector<BenchMethod> parseBenchMethods(const std::string& text);

struct BenchSettings {
    int width = 1024;                                   // pixels
    int height = 768;                                   // pixels
    double sunAzimuthDeg = 315.0;                       // clockwise from north
    double sunElevationDeg = 20.0;                      // above the horizon
    std::vector<int> threadCounts{1, 2};                // each pass is run at each of these
    int repeat = 5;  // each pass is traced this many times, after one untimed trace
    // Each timed trace covers the picture in this many bands of rows, every band taken in turn with the other
    // methods; a pass's time is the sum over the bands of each band's fastest time (primary and shadow apart).
    int bands = 8;
    std::vector<BenchCamera> cameras{BenchCamera::Corner, BenchCamera::Grazing};
    std::vector<BenchMethod> methods = benchMethods();  // measured in this order
    // Asked before a method is built: the bytes it would need when it cannot run here, or none when it can.
    std::function<std::optional<double>(BenchMethod)> refuse;
    // Called before each build and each trace (warm-up or timed) with a short description (for progress).
    std::function<void(const std::string& step)> onStep;
};

// The time of a pass traced in bands: seconds[r][b] is repetition r's time for band b, and the pass takes the sum
// over the bands of each band's fastest repetition (0 for no band).
double bandedSeconds(const std::vector<std::vector<double>>& seconds);

// One timed pass: one camera, one thread count.
struct BenchPass {
    BenchCamera camera = BenchCamera::Corner;
    int threads = 1;
    int64_t primaryRays = 0;
    int64_t shadowRays = 0;             // one per primary hit facing the sun
    double primaryRaysPerSecond = 0.0;
    double shadowRaysPerSecond = 0.0;
    double ratioToEmbreePrimary = 0.0;  // over Embree's rays/s in the same pass of this run; NaN without Embree
    double ratioToEmbreeShadow = 0.0;
};

struct BenchMethodResult {
    BenchMethod method = BenchMethod::Bilinear;
    bool skipped = false;          // refused by settings.refuse; nothing below is measured
    double neededBytes = 0.0;      // when skipped: what it would have needed
    double buildSeconds = 0.0;     // the pyramids, or Embree's scene (buffers and BVH)
    int64_t memoryBytes = 0;       // kept for tracing: the grid with its pyramid, or Embree's own bytes
    int64_t peakMemoryBytes = 0;   // the most held at once while building
    double bytesPerCell = 0.0;     // memoryBytes over the grid's cells
    double peakBytesPerCell = 0.0; // peakMemoryBytes over the grid's cells
    double hitAgreement = 0.0;     // share of the first pass's camera rays with the first measured method's hit/miss
                                   // verdict (the settings' first method, or the first but embree-grid, which is
                                   // measured last)
    std::vector<BenchPass> passes; // cameras outer, thread counts inner, as in settings
};

struct BenchGridResult {
    int64_t width = 0;  // vertices
    int64_t height = 0;
    int64_t cells = 0;
    std::vector<BenchMethodResult> methods;
};

// Builds and times every method of `settings` on `grid`, each pass under FlushDenormalsScope.
BenchGridResult benchGrid(const HeightGrid& grid, const BenchSettings& settings);

// An SVG chart of camera (primary) rays per second against grid size: one panel per camera (corner on the
// left, grazing on the right), grid size in vertices per side on a log x axis, millions of rays per second on
// a log y axis, one line with markers per method (its pass at the most threads measured on each grid) and a
// legend. Meant for square synthetic grids, given in increasing size; methods skipped on a grid leave a gap in
// their line. Each line is a <polyline> carrying data-method and data-camera attributes, one point per grid
// the method was measured on. `machine` (the processor, its threads) goes into the title as given.
std::string benchRatesSvg(const std::vector<BenchGridResult>& grids, const std::string& machine);

}  // namespace terracast
