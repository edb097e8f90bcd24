#include "tracer/terrain/terrain_renderer.h"

#include "tracer/core/parallel.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

namespace terracast {

Film renderTerrain(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& s,
                   RenderStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    Film film(s.width, s.height);
    const TerrainShader shader(grid, surface, s.sun, s.sky, s.camera.eyeM.z, s.seed);

    std::atomic<int64_t> primary{0}, shadow{0}, sky{0}, hits{0}, pixelsDone{0};
    std::mutex progressMutex;
    const int64_t totalPixels = int64_t(s.width) * s.height;

    parallelForTiles(s.width, s.height, s.tileSize, s.threads, [&](int x0, int y0, int x1, int y1) {
        int64_t nPrimary = 0, nShadow = 0, nSky = 0, nHits = 0;
        traceCameraRays(surface, s.camera, s.width, s.height, x0, y0, x1, y1,
                        [&](int x, int y, const Ray& ray, const std::optional<HeightFieldHit>& hit) {
                            ++nPrimary;
                            if (!hit) {
                                film.set(x, y, shader.miss(ray.dir));
                                return;
                            }
                            ++nHits;
                            film.set(x, y, shader.hit(*hit, ray, x, y, nShadow, nSky));
                        });
        primary += nPrimary;
        shadow += nShadow;
        sky += nSky;
        hits += nHits;
        const int64_t done = pixelsDone += int64_t(x1 - x0) * (y1 - y0);
        if (s.progress) {
            std::lock_guard lock(progressMutex);
            s.progress(double(done) / double(totalPixels), primary.load() + shadow.load() + sky.load());
        }
    });

    if (stats) {
        stats->primaryRays = primary;
        stats->shadowRays = shadow;
        stats->skyVisibilityRays = sky;
        stats->hits = hits;
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return film;
}

}  // namespace terracast
