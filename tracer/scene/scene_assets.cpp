#include "tracer/scene/scene_assets.h"

#include <algorithm>

namespace terracast {

glm::vec3 DrapeImage::sample(double u, double v) const {
    if (width <= 0 || height <= 0) return glm::vec3(0.5f);
    const double x = std::clamp(u, 0.0, 1.0) * (width - 1);
    const double y = (1.0 - std::clamp(v, 0.0, 1.0)) * (height - 1);
    const int x0 = std::min(int(x), width - 1), y0 = std::min(int(y), height - 1);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const float fx = float(x - x0), fy = float(y - y0);
    auto at = [&](int i, int j) {
        const size_t k = (size_t(j) * size_t(width) + size_t(i)) * 3;
        return glm::vec3(rgb[k], rgb[k + 1], rgb[k + 2]);
    };
    return glm::mix(glm::mix(at(x0, y0), at(x1, y0), fx), glm::mix(at(x0, y1), at(x1, y1), fx), fy);
}

}  // namespace terracast
