// A scene ready to trace: its objects (behind a BVH built over exactly the objects present), materials,
// lights and sky, made from a SceneDescription and the rasters the description names.
#pragma once

#include "heightfield/height_grid.h"
#include "tracer/scene/bvh.h"
#include "tracer/scene/primitives.h"
#include "tracer/scene/scene_description.h"
#include "tracer/scene/scene_assets.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace terracast {

// A light as the tracer uses it.
struct SceneLight {
    LightKind kind = LightKind::Sun;
    glm::vec3 radiance{1.0f};      // colour times intensity
    glm::dvec3 direction{0, 0, 1}; // sun: unit vector towards it
    glm::dvec3 position{0.0};      // point and sphere lights
    double radiusM = 0.0;          // sphere light
    double cosAngularRadius = 1.0; // sun: cosine of its apparent radius
};

struct SceneObject {
    ObjectKind kind = ObjectKind::Sphere;
    std::string name;
    int material = 0;
    glm::dvec3 velocity{0.0};        // metres per second
    std::unique_ptr<Primitive> primitive;
    bool moving() const { return velocity != glm::dvec3(0.0); }
};

class Scene {
public:
    // Builds the objects and the BVH. Throws InputError-free std::invalid_argument on inconsistent input that a
    // parsed description cannot have (a missing grid); the scene file reader reports user errors first.
    Scene(const SceneDescription& description, const SceneAssets& assets);

    // The nearest hit of any object in `interval`; `hit.object` names it.
    bool intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const;
    // Whether an opaque object (anything but a dielectric) blocks the ray within `interval`.
    bool occludedByOpaque(const Ray& ray, Interval interval) const;

    const std::vector<SceneObject>& objects() const { return objects_; }
    const std::vector<MaterialDescription>& materials() const { return materials_; }
    const std::vector<std::shared_ptr<const DrapeImage>>& drapes() const { return drapes_; }
    const std::vector<std::shared_ptr<const DrapeImage>>& textures() const { return textures_; }
    const std::vector<SceneLight>& lights() const { return lights_; }
    const SkyDescription& sky() const { return sky_; }
    bool hasDielectric() const { return hasDielectric_; }
    // The water object whose surface lies above `p` (the lowest such surface over p's x and y), or none.
    const SceneObject* waterAbove(const glm::dvec3& p) const;
    // The first height field, if any (for framing, water and terrain colouring).
    const HeightFieldPrimitive* terrain() const { return terrain_; }
    // The extent of every bounded object (for automatic framing).
    const Bounds3& bounds() const { return bounds_; }
    size_t bvhNodes() const { return bvh_.nodeCount(); }
    // Whether a scene-level BVH was built (more than one bounded object).
    bool usesBvh() const { return bvh_.nodeCount() > 0; }

private:
    bool hitObject(size_t k, const Ray& ray, Interval interval, SurfaceHit& hit) const;

    std::vector<SceneObject> objects_;
    std::vector<MaterialDescription> materials_;
    std::vector<std::shared_ptr<const DrapeImage>> drapes_;
    std::vector<std::shared_ptr<const DrapeImage>> textures_;  // per material, as drapes_
    std::vector<SceneLight> lights_;
    SkyDescription sky_;
    std::vector<int32_t> bounded_;    // objects behind the BVH
    std::vector<int32_t> unbounded_;  // planes: tested one by one
    std::vector<Bounds3> objectBounds_;
    Bvh bvh_{std::vector<Bounds3>{}};
    Bounds3 bounds_;
    std::vector<int32_t> waters_;     // the water objects
    bool hasDielectric_ = false;
    const HeightFieldPrimitive* terrain_ = nullptr;
};


// The default material of an object kind when its description names none: grey Phong for solids, clear
// water for water, elevation colouring for terrain.
MaterialDescription defaultMaterial(ObjectKind kind);

}  // namespace terracast
