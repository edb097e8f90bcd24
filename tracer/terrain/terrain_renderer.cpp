#include "tracer/terrain/terrain_renderer.h"

#include "tracer/core/cancel.h"
#include "tracer/core/parallel.h"
#include "tracer/core/ranks.h"
#include "tracer/core/ticks.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include <tbb/global_control.h>

namespace terracast {

BlockOrder blocksBySpans(int blocksX, int blocksY, int spans) {
    BlockOrder order;
    order.blocks.reserve(size_t(std::max(blocksX, 0)) * size_t(std::max(blocksY, 0)));
    for (int r = 0; r < spans; ++r) {
        const int c0 = int(int64_t(blocksX) * r / spans), c1 = int(int64_t(blocksX) * (r + 1) / spans);
        for (int y = 0; y < blocksY; ++y)
            for (int x = c0; x < c1; ++x) order.blocks.emplace_back(x, y);
        order.spanEnds.push_back(int64_t(order.blocks.size()));
    }
    return order;
}

Film renderTerrain(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& s,
                   RenderStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    // The thread limit covers the sky's tables too, which the shader builds in parallel: with --threads 1 (as
    // each MPI rank of a machine runs) they had taken every core, twice as long under two ranks.
    std::unique_ptr<tbb::global_control> threadLimit;
    if (s.threads > 0)
        threadLimit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                            static_cast<size_t>(s.threads));
    Film film(s.width, s.height);
    // Every rank of a render gets here alike: the sky's tables are shared out over the ranks.
    std::optional<TerrainShader> made = [&] {
        const ranks::SharedWork share;
        return std::optional<TerrainShader>(std::in_place, grid, surface, s.sun, s.sky, s.camera.eyeM.z, s.seed,
                                            s.smoothNormals, s.look);
    }();
    TerrainShader& shader = *made;
    shader.timeSecondaryRays(s.timePhases);
    const double setupSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::atomic<int64_t> primary{0}, shadow{0}, sky{0}, hits{0}, pixelsDone{0};
    // Ticks (tracer/core/ticks.h) of the work tiles, of shading (secondary rays included) and of the secondary
    // rays: each interval timed by two reads of the time-stamp counter less what the reads add, so that timing
    // every sample and every ray costs a few per cent rather than the tenth the steady clock's reads took.
    std::atomic<uint64_t> tileTicks{0}, shadeTicks{0}, shadowTicks{0}, skyTicks{0};
    const TickRate tickRate;
    const uint64_t readCost = s.timePhases ? tickReadCost() : 0;
    std::mutex progressMutex;
    const int64_t totalPixels = int64_t(s.width) * s.height;

    // One sample per pixel through a pinhole: the pixels' centres, traced in bundles. Otherwise each pixel takes
    // its samples (placed by the pixel filter, as many as the sampling asks or the adaptive rule needs) through
    // whichever camera the view has.
    const auto sampler = s.sampling.makeSampler(s.seed);
    const bool centresOnly = !s.view && !sampler;
    const double aspect = double(s.width) / double(s.height);
    const auto renderTile = [&](int x0, int y0, int x1, int y1) {
        int64_t nPrimary = 0, nShadow = 0, nSky = 0, nHits = 0;
        uint64_t nShadeTicks = 0;
        const uint64_t tileStart = s.timePhases ? readTicks() : 0;
        if (s.timePhases) TerrainShader::takeSecondaryRayTicks();  // this thread's count starts here
        // What camera sample k of pixel (x, y) brings back: the base's wall in front, the terrain, or the backdrop.
        const auto shade = [&](const Ray& ray, const std::optional<HeightFieldHit>& hit, int x, int y, int k) {
            if (const auto wall = shader.base(ray, hit ? hit->t : kInfinity, nShadow)) return *wall;
            if (!hit) return shader.miss(ray.dir);
            ++nHits;
            return shader.hit(*hit, ray, x, y, nShadow, nSky, k);
        };
        const auto radiance = [&](const Ray& ray, const std::optional<HeightFieldHit>& hit, int x, int y, int k) {
            ++nPrimary;
            if (!s.timePhases) return shade(ray, hit, x, y, k);
            const uint64_t t0 = readTicks();
            const glm::vec3 value = shade(ray, hit, x, y, k);
            nShadeTicks += ticksSince(t0, readCost);
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
            tileTicks += ticksSince(tileStart, readCost);
            shadeTicks += nShadeTicks;
            const auto rays = TerrainShader::takeSecondaryRayTicks();
            shadowTicks += rays.shadow;
            skyTicks += rays.sky;
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
        // Each rank starts on its own columns of blocks, a part of the picture and so mostly a part of the DEM;
        // once they are done it helps with the others' (ranks::SpanTasks). One process: picture order.
        const BlockOrder order = blocksBySpans(blocksX, blocksY, ranks::size());
        ranks::SpanTasks tasks(order.spanEnds);
        for (int64_t k = tasks.next(); k < int64_t(order.blocks.size()); k = tasks.next()) {
            const int bx = order.blocks[size_t(k)].first * block, by = order.blocks[size_t(k)].second * block;
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
            const double perTick = 1.0 / tickRate.ticksPerSecond();
            const auto seconds = [perTick](uint64_t whole, uint64_t part) {
                return double(whole - std::min(whole, part)) * perTick;
            };
            stats->shadowRaySeconds = double(shadowTicks.load()) * perTick;
            stats->skyRaySeconds = double(skyTicks.load()) * perTick;
            // A secondary ray's own two reads fall inside its sample's interval: take them out of the shading.
            const uint64_t rayReads = uint64_t(shadow.load() + sky.load()) * readCost;
            stats->shadingSeconds = seconds(shadeTicks.load(), shadowTicks.load() + skyTicks.load() + rayReads);
            stats->cameraRaySeconds = seconds(tileTicks.load(), shadeTicks.load());
        }
    }
    return film;
}

}  // namespace terracast
