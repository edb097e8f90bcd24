// A bounding volume hierarchy over the scene's bounded objects, built once over exactly the objects present.
#pragma once

#include "tracer/scene/primitives.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace terracast {

class Bvh {
public:
    // Builds over items 0..n-1 with the given bounds (all finite), splitting at the median of the centroids
    // along the widest axis until a leaf holds at most two items.
    explicit Bvh(const std::vector<Bounds3>& bounds);

    // Visits the items whose boxes the ray enters within `interval`, nearest box first. `visit(item, hi)`
    // returns the new upper end of the interval (lower after a hit), so farther boxes are culled.
    template <class Visit>
    void traverse(const Ray& ray, Interval interval, Visit&& visit) const {
        if (nodes_.empty()) return;
        int32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[size_t(stack[--top])];
            if (node.box.clip(ray, interval).empty()) continue;
            if (node.count > 0) {
                for (int32_t k = 0; k < node.count; ++k) interval.hi = visit(items_[size_t(node.first + k)], interval.hi);
                continue;
            }
            // Children: the nearer one (along the split axis and the ray's direction) is visited first.
            const bool flip = ray.dir[node.axis] < 0.0;
            stack[top++] = flip ? node.first : node.second;
            stack[top++] = flip ? node.second : node.first;
        }
    }

    size_t nodeCount() const { return nodes_.size(); }
    size_t memoryBytes() const { return nodes_.capacity() * sizeof(Node) + items_.capacity() * sizeof(int32_t); }

private:
    struct Node {
        Bounds3 box;
        int32_t first = 0;   // leaf: first item index in items_; inner: the child on the low side of the split
        int32_t second = 0;  // inner: the child on the high side
        int32_t count = 0;   // leaf: number of items; 0 for an inner node
        int32_t axis = 0;   // inner: the split axis
    };
    int32_t build(const std::vector<Bounds3>& bounds, int32_t begin, int32_t end, int depth);

    std::vector<Node> nodes_;
    std::vector<int32_t> items_;
};

}  // namespace terracast
