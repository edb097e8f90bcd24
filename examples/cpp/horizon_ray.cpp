// terracast as a library: load a DEM, look around from 2 m above its centre with eight rays 1 degree above the
// horizon (exact bilinear surface against Embree's triangles), and render a small picture of it.
//   horizon_ray DEM [PICTURE.png]
#include "loaders/dem_loader.h"
#include "loaders/image_io.h"
#include "tracer/core/angles.h"
#include "tracer/terrain/surface.h"
#include "tracer/terrain/terrain_renderer.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s DEM [PICTURE.png]\n", argv[0]);
        return 2;
    }
    try {
        using namespace terracast;
        const LoadedDem dem = loadDem(argv[1]);
        const HeightGrid& grid = dem.grid;
        const int64_t i = (grid.width() - 1) / 2, j = (grid.height() - 1) / 2;
        const double ground = grid.vertexValid(i, j) ? grid.at(i, j) : grid.maxHeightM();
        const glm::dvec3 eye{double(i) * grid.cellSizeXM(), double(j) * grid.cellSizeYM(), ground + 2.0};
        std::printf("%s: %lld x %lld vertices; eye at %.1f m above sea level\n", argv[1], (long long)grid.width(),
                    (long long)grid.height(), eye.z);
        const TerrainSurface exact(grid, SurfaceMethod::Bilinear), triangles(grid, SurfaceMethod::Embree);
        for (int azimuth = 0; azimuth < 360; azimuth += 45) {
            const Ray ray{eye, directionFromDegrees(azimuth, 1.0)};
            const auto a = exact.intersect(ray, {0.0, kInfinity}), b = triangles.intersect(ray, {0.0, kInfinity});
            std::printf("azimuth %3d: bilinear %s, embree %s\n", azimuth,
                        a ? (std::to_string(int(a->t)) + " m").c_str() : "open",
                        b ? (std::to_string(int(b->t)) + " m").c_str() : "open");
        }
        if (argc > 2) {
            TerrainRenderSettings s;
            s.width = 160;
            s.height = 90;
            s.camera = autoCamera(grid, 160.0 / 90.0);
            const Film film = renderTerrain(grid, exact, s);
            writeImage(argv[2], RgbImage{film.width, film.height, film.rgb});
            std::printf("wrote %s\n", argv[2]);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "horizon_ray: %s\n", e.what());
        return 1;
    }
    return 0;
}
