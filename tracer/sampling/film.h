// The film: linear-light RGB pixels, row 0 at the top of the picture.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace terracast {

struct Film {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width * height * 3 linear values

    Film() = default;
    Film(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(w) * static_cast<size_t>(h) * 3, 0.0f) {}

    void set(int x, int y, const glm::vec3& c) {
        const size_t k = (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3;
        rgb[k] = c.r;
        rgb[k + 1] = c.g;
        rgb[k + 2] = c.b;
    }
    glm::vec3 get(int x, int y) const {
        const size_t k = (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3;
        return {rgb[k], rgb[k + 1], rgb[k + 2]};
    }
    size_t memoryBytes() const { return rgb.capacity() * sizeof(float); }
};

}  // namespace terracast
