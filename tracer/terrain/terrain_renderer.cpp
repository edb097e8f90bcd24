#include "tracer/terrain/terrain_renderer.h"

#include "tracer/core/cancel.h"
#include "tracer/core/parallel.h"
#include "tracer/core/ranks.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>

#include <tbb/global_control.h>

namespace terracast {

Film renderTerrain(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& s,
                   RenderStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    Film film(s.width, s.height);
    TerrainShader shader(grid, surface, s.sun, s.sky, s.camera.eyeM.z, s.seed, s.smoothNormals, s.look);
    shader.timeSecondaryRays(s.timePhases);
    const double setupSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::atomic<int64_t> primary{0}, shadow{0}, sky{0}, hits{0}, pixelsDone{0};
    // Thread-nanoseconds of the work tiles, of shading (secondary rays included) and of the secondary rays.
    std::atomic<int64_t> tileNs{0}, shadeNs{0}, shadowNs{0}, skyNs{0};
    using Clock = std::chrono::steady_clock;
    const auto nanoseconds = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration_cast<std::chrono::nanoseconds>(b - a).count();
    };
    std::mutex progressMutex;
    const int64_t totalPixels = int64_t(s.width) * s.height;

    // One sample per pixel through a pinhole: the pixels' centres, traced in bundles. Otherwise each pixel takes
    // its samples (placed by the pixel filter, as many as the sampling asks or the adaptive rule needs) through
    // whichever camera the view has.
    const auto sampler = s.sampling.makeSampler(s.seed);
    const bool centresOnly = !s.view && !sampler;
    const double aspect = double(s.width) / double(s.height);
    // With timePhases, camera samples drawn at random (TerrainShader::timeThisOne) are timed (their shading,
    // secondary rays included), the secondary rays likewise on their own (TerrainShader::timeSecondaryRays), and
    // the sums scaled by the samples over those timed: reading the clock (about 25 ns here) around every sample
    // and every secondary ray would add a tenth to the render, most of it counted as shading.
    const double clockNs = s.timePhases ? TerrainShader::clockReadNanoseconds() : 0.0;
    const auto renderTile = [&](int x0, int y0, int x1, int y1) {
        int64_t nPrimary = 0, nShadow = 0, nSky = 0, nHits = 0, nTimed = 0;
        double nShadeNs = 0.0;
        const auto tileStart = s.timePhases ? Clock::now() : Clock::time_point{};
        if (s.timePhases) TerrainShader::takeSecondaryRaySeconds();  // this thread's count starts here
        // What camera sample k of pixel (x, y) brings back: the base's wall in front, the terrain, or the backdrop.
        const auto shade = [&](const Ray& ray, const std::optional<HeightFieldHit>& hit, int x, int y, int k) {
            if (const auto wall = shader.base(ray, hit ? hit->t : kInfinity, nShadow)) return *wall;
            if (!hit) return shader.miss(ray.dir);
            ++nHits;
            return shader.hit(*hit, ray, x, y, nShadow, nSky, k);
        };
        const auto radiance = [&](const Ray& ray, const std::optional<HeightFieldHit>& hit, int x, int y, int k) {
            ++nPrimary;
            if (!s.timePhases || !TerrainShader::timeThisOne()) return shade(ray, hit, x, y, k);
            ++nTimed;
            const auto t0 = Clock::now();
            const glm::vec3 value = shade(ray, hit, x, y, k);
            nShadeNs += double(nanoseconds(t0, Clock::now())) - clockNs;
            return value;
        };
        if (centresOnly) {
            traceCameraRays(surface, s.camera, s.width, s.height, x0, y0, x1, y1,
                            [&](int x, int y, const Ray& ray, const std::optional<HeightFieldHit>& hit) {
                                film.set(x, y, radiance(ray, hit, x, y, 0));
                            });
        } else {
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    if (cancelFlag().load(std::memory_order_relaxed)) return;  // parallelForTiles throws Cancelled
                    film.set(x, y, estimatePixel(s.sampling, sampler.get(), cancelFlag(), [&](int k) {
                                 const glm::dvec2 offset =
                                     sampler ? s.sampling.filter.offsetOf(sampler->sample(x, y, k, 0)) : glm::dvec2(0.0);
                                 const double fx = (x + 0.5 + offset.x) / s.width, fy = (y + 0.5 + offset.y) / s.height;
                                 const std::optional<Ray> ray =
                                     s.view ? s.view->generate(fx, fy) : std::optional<Ray>(s.camera.generate(fx, fy, aspect));
                                 if (!ray) return glm::vec3(0.0f);  // outside a fisheye's circle: black
                                 return radiance(*ray, surface.intersect(*ray, {0.0, kInfinity}), x, y, k);
                             }));
                }
        }
        primary += nPrimary;
        shadow += nShadow;
        sky += nSky;
        hits += nHits;
        if (s.timePhases) {
            tileNs += nanoseconds(tileStart, Clock::now());
            const double scale = nTimed > 0 ? double(nPrimary) / double(nTimed) : 0.0;
            shadeNs += int64_t(nShadeNs * scale);
            const auto rays = TerrainShader::takeSecondaryRaySeconds();
            shadowNs += int64_t(rays.shadow * 1e9);
            skyNs += int64_t(rays.sky * 1e9);
        }
        const int64_t done = pixelsDone += int64_t(x1 - x0) * (y1 - y0);
        if (s.progress) {
            std::lock_guard lock(progressMutex);
            // A rank renders about its share of the pixels.
            s.progress(std::min(1.0, double(done) / double(totalPixels) * double(ranks::size())),
                       primary.load() + shadow.load() + sky.load());
        }
    };

    if (ranks::size() == 1 && !grid.tiled()) {
        parallelForTiles(s.width, s.height, s.tileSize, s.threads, renderTile);
    } else {
        // The ranks of an MPI launch (docs/architecture.md, "Ranks") draw blocks of 4 x 4 work tiles from a shared
        // count and render them into films of the whole picture, black elsewhere; the leader's film becomes the sum,
        // which is every pixel exactly as one process renders it (each pixel is rendered once, and x + 0 = x).
        // A single process renders a DEM held as tiles this way too: its threads share one block at a time, in
        // picture order, so that they read the same DEM tiles rather than those of two far parts of the picture.
        const int block = 4 * std::max(s.tileSize, 1);
        const int blocksX = (s.width + block - 1) / block, blocksY = (s.height + block - 1) / block;
        std::unique_ptr<tbb::global_control> limit;
        if (s.threads > 0)
            limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                          static_cast<size_t>(s.threads));
        ranks::resetTasks();
        for (int64_t k = ranks::nextTask(); k < int64_t(blocksX) * blocksY; k = ranks::nextTask()) {
            const int bx = int(k % blocksX) * block, by = int(k / blocksX) * block;
            const int bw = std::min(block, s.width - bx), bh = std::min(block, s.height - by);
            // The thread limit is set above, once for every block.
            parallelForTiles(bw, bh, s.tileSize, 0, [&](int x0, int y0, int x1, int y1) {
                renderTile(bx + x0, by + y0, bx + x1, by + y1);
            });
        }
        ranks::sumToLeader(film.rgb.data(), film.rgb.size());
        int64_t counts[4] = {primary.load(), shadow.load(), sky.load(), hits.load()};
        ranks::sum(counts, 4);
        primary = counts[0];
        shadow = counts[1];
        sky = counts[2];
        hits = counts[3];
    }

    if (stats) {
        stats->primaryRays = primary;
        stats->shadowRays = shadow;
        stats->skyVisibilityRays = sky;
        stats->hits = hits;
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (s.timePhases) {
            // A rank's own threads (the film's sums are the leader's; these are not summed over ranks).
            stats->setupSeconds = setupSeconds;
            stats->shadowRaySeconds = double(shadowNs.load()) * 1e-9;
            stats->skyRaySeconds = double(skyNs.load()) * 1e-9;
            // Estimates, each from its own draw: on a tiny render their difference can dip below zero.
            stats->shadingSeconds = std::max(0.0, double(shadeNs.load() - shadowNs.load() - skyNs.load()) * 1e-9);
            stats->cameraRaySeconds = double(tileNs.load() - shadeNs.load()) * 1e-9;
        }
    }
    return film;
}

}  // namespace terracast
