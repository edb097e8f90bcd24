// What a scene description names but cannot hold, once loaded: the height grids of its height fields and the
// images its materials drape over the terrain. Plain data, filled by the loaders.
#pragma once

#include "heightfield/height_grid.h"
#include "tracer/sky/environment.h"

#include <glm/glm.hpp>

#include <cmath>
#include <memory>
#include <vector>

namespace terracast {

// An RGB raster: a draped orthophoto over a height field's footprint (row 0 at the north edge), or a
// material's image texture (row 0 at the top, at v = 1).
struct DrapeImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // linear RGB, width * height * 3

    // Bilinear lookup at (u, v) in [0, 1]^2 over the footprint, v growing northward.
    glm::vec3 sample(double u, double v) const;
    // The same lookup repeating the image: (u, v) taken modulo 1 (a texture tiles the surface).
    glm::vec3 sampleRepeated(double u, double v) const { return sample(u - std::floor(u), v - std::floor(v)); }
};

// What a description names but cannot hold: loaded height grids (one per height-field object, in object
// order) and draped images (one per material, empty where none).
struct SceneAssets {
    std::vector<std::shared_ptr<const HeightGrid>> grids;
    std::vector<std::shared_ptr<const DrapeImage>> drapes;
    std::vector<std::shared_ptr<const DrapeImage>> textures;  // one per material, empty where none
    std::shared_ptr<const EnvironmentImage> environment;      // the image sky's picture, when it has one
};

}  // namespace terracast
