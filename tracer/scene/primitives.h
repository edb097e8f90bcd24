// The scene's geometric primitives: height field, sphere, infinite plane, triangle, planar polygon,
// axis-aligned box and a water surface. Each answers nearest-hit queries in scene metres (double precision).
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"
#include "tracer/terrain/surface.h"

#include <memory>
#include <string>
#include <vector>

namespace terracast {

// An axis-aligned bounding box; empty when lo > hi on any axis.
struct Bounds3 {
    glm::dvec3 lo{kInfinity};
    glm::dvec3 hi{-kInfinity};

    void extend(const glm::dvec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Bounds3& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    bool finite() const;
    glm::dvec3 centre() const { return 0.5 * (lo + hi); }
    // The parameter range where `ray` is inside the box, clipped to `interval` (empty when it misses).
    Interval clip(const Ray& ray, Interval interval) const;
};

// A ray's nearest hit on one primitive.
struct SurfaceHit {
    double t = kInfinity;        // ray parameter (rays carry unit directions, so metres)
    glm::dvec3 point{0.0};       // hit position, scene metres
    glm::dvec3 normal{0, 0, 1};  // unit geometric normal on the primitive's outer side (not flipped to the ray)
    glm::dvec2 uv{0.0};          // surface coordinates: for a height field, the position over the grid in [0, 1]^2
    glm::dvec3 shading{0.0};     // unit shading normal on the outer side where it differs from `normal` (a height
                                 // field's smooth normal); zero where shading uses `normal`
    double errorM = 0.0;         // bound on the position's rounding error: spawned rays start this far off
    int object = -1;             // index of the object hit, set by the scene

    // The normal shading reads, on the outer side: `shading` where set, else `normal`.
    glm::dvec3 shadingNormal() const { return shading == glm::dvec3(0.0) ? normal : shading; }
};

// The origin of a ray leaving `hit` in direction `dir`: pushed off the surface, to the side `dir` goes.
glm::dvec3 offsetOrigin(const SurfaceHit& hit, const glm::dvec3& dir);

class Primitive {
public:
    virtual ~Primitive() = default;
    // The nearest hit in `interval`, filling `hit` (t, point, normal, uv, errorM); false when none.
    virtual bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const = 0;
    // Whether anything is hit in `interval`; primitives may answer faster than intersect().
    virtual bool occluded(const Ray& ray, Interval interval) const {
        SurfaceHit hit;
        return intersect(ray, interval, hit);
    }
    // The primitive's extent; not finite for unbounded primitives (the plane).
    virtual Bounds3 bounds() const = 0;
};

class SpherePrimitive final : public Primitive {
public:
    SpherePrimitive(const glm::dvec3& centre, double radius) : centre_(centre), radius_(radius) {}
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const override;
    Bounds3 bounds() const override;

private:
    glm::dvec3 centre_;
    double radius_;
};

// An infinite plane through `point` with unit normal `normal`; its outer side is the normal's side.
class PlanePrimitive final : public Primitive {
public:
    PlanePrimitive(const glm::dvec3& point, const glm::dvec3& normal);
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const override;
    Bounds3 bounds() const override;

private:
    glm::dvec3 point_, normal_;
    glm::dvec3 uAxis_, vAxis_;  // texture axes in the plane: east and north on a level plane
};

// A triangle; its outer side follows the right-hand rule on the vertex order.
class TrianglePrimitive final : public Primitive {
public:
    TrianglePrimitive(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const override;
    Bounds3 bounds() const override;

private:
    glm::dvec3 a_, e1_, e2_, normal_;
};

// A planar polygon of any vertex count, convex or not: the ray meets the polygon's plane and the point is
// classified by the even-odd rule after projecting onto the coordinate plane most parallel to the polygon.
class PolygonPrimitive final : public Primitive {
public:
    // Vertices must be planar (checked by the scene file reader); the normal is Newell's.
    explicit PolygonPrimitive(std::vector<glm::dvec3> vertices);
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const override;
    Bounds3 bounds() const override;
    // Newell's normal of a vertex loop (unit length; zero for a degenerate loop).
    static glm::dvec3 newellNormal(const std::vector<glm::dvec3>& vertices);
    // Whether `p` (on the plane) lies inside, by the even-odd rule in the projection that drops axis `drop`.
    bool contains(const glm::dvec3& p) const;

private:
    std::vector<glm::dvec3> vertices_;
    glm::dvec3 normal_;
    int dropAxis_ = 2;
    Bounds3 bounds_;
};

class BoxPrimitive final : public Primitive {
public:
    BoxPrimitive(const glm::dvec3& lo, const glm::dvec3& hi) : box_{lo, hi} {}
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const override;
    Bounds3 bounds() const override { return box_; }

private:
    Bounds3 box_;
};

// A height grid placed in the scene with its vertex (0, 0) at `offsetM`, traced directly or through Embree.
// The terrain is solid: occlusion queries treat everything below the surface as blocking.
class HeightFieldPrimitive final : public Primitive {
public:
    HeightFieldPrimitive(std::shared_ptr<const HeightGrid> grid, const glm::dvec3& offsetM, SurfaceMethod method,
                         int threads = 0, bool smoothNormals = true);
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const override;
    bool occluded(const Ray& ray, Interval interval) const override;
    Bounds3 bounds() const override;
    const HeightGrid& grid() const { return *grid_; }
    const glm::dvec3& offset() const { return offset_; }
    const TerrainSurface& surface() const { return surface_; }

private:
    std::shared_ptr<const HeightGrid> grid_;
    glm::dvec3 offset_;
    TerrainSurface surface_;
    bool smoothNormals_;
};

// A body of water over a height field's footprint: a horizontal surface at `levelM` over the footprint's
// rectangle, closed at the rectangle's edges by vertical sides wherever the terrain's edge lies below the
// level (from the terrain up to the level), so that no ray reaches terrain under the water without crossing
// the water's boundary; where the edge rises above the level, or has no data, there is no side. Normals point
// out of the water: rays from below the surface, or from inside the sides, are in it.
class WaterPrimitive final : public Primitive {
public:
    WaterPrimitive(double levelM, const HeightFieldPrimitive& terrain);
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const override;
    Bounds3 bounds() const override;
    double level() const { return level_; }
    // Whether (x, y) lies over the water's rectangle.
    bool covers(double x, double y) const { return x >= x0_ && x <= x1_ && y >= y0_ && y <= y1_; }

private:
    // The terrain's height along side `side` (0: x = x0, 1: x = x1, 2: y = y0, 3: y = y1) at position `along`
    // (y for sides 0 and 1, x for 2 and 3): linear between the edge's vertices, +infinity beside a missing one.
    double edgeHeight(int side, double along) const;

    double level_, x0_, y0_, x1_, y1_;
    double lowest_;                     // the lowest point of any side
    double stepX_, stepY_;              // the terrain's cell sizes
    std::vector<double> edges_[4];      // the terrain's heights along each side, scene metres
};

}  // namespace terracast
