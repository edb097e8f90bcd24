#include "tracer/scene/bvh.h"

#include <algorithm>
#include <numeric>

namespace terracast {

Bvh::Bvh(const std::vector<Bounds3>& bounds) {
    if (bounds.empty()) return;
    items_.resize(bounds.size());
    std::iota(items_.begin(), items_.end(), 0);
    nodes_.reserve(2 * bounds.size());
    build(bounds, 0, int32_t(bounds.size()), 0);
}

int32_t Bvh::build(const std::vector<Bounds3>& bounds, int32_t begin, int32_t end, int depth) {
    const auto index = int32_t(nodes_.size());
    nodes_.push_back({});
    Bounds3 box, centres;
    for (int32_t k = begin; k < end; ++k) {
        box.extend(bounds[size_t(items_[size_t(k)])]);
        centres.extend(bounds[size_t(items_[size_t(k)])].centre());
    }
    nodes_[size_t(index)].box = box;
    // The traversal stack holds 64 entries; a median split keeps depth near log2(n), far below that.
    if (end - begin <= 2 || depth >= 48) {
        nodes_[size_t(index)].first = begin;
        nodes_[size_t(index)].count = end - begin;
        return index;
    }
    const glm::dvec3 extent = centres.hi - centres.lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const int32_t mid = begin + (end - begin) / 2;
    std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end, [&](int32_t a, int32_t b) {
        return bounds[size_t(a)].centre()[axis] < bounds[size_t(b)].centre()[axis];
    });
    const int32_t low = build(bounds, begin, mid, depth + 1);
    const int32_t high = build(bounds, mid, end, depth + 1);
    Node& node = nodes_[size_t(index)];
    node.first = low;
    node.second = high;
    node.count = 0;
    node.axis = axis;
    return index;
}

}  // namespace terracast
