#include "tracer/scene/scene.h"

#include "tracer/core/angles.h"

#include <cmath>
#include <stdexcept>

namespace terracast {

namespace {

std::unique_ptr<Primitive> makePrimitive(const ObjectDescription& o, const SceneAssets& assets, size_t& nextGrid,
                                         const HeightFieldPrimitive* terrain, int threads) {
    switch (o.kind) {
    case ObjectKind::HeightField: {
        if (nextGrid >= assets.grids.size() || !assets.grids[nextGrid])
            throw std::invalid_argument("scene: no height grid loaded for object '" + o.name + "'");
        return std::make_unique<HeightFieldPrimitive>(assets.grids[nextGrid++], o.offsetM, o.method, threads,
                                                      o.smoothNormals);
    }
    case ObjectKind::Sphere: return std::make_unique<SpherePrimitive>(o.centre, o.radiusM);
    case ObjectKind::Plane: return std::make_unique<PlanePrimitive>(o.point, o.normal);
    case ObjectKind::Triangle:
        if (o.vertices.size() != 3) throw std::invalid_argument("scene: a triangle needs 3 vertices");
        return std::make_unique<TrianglePrimitive>(o.vertices[0], o.vertices[1], o.vertices[2]);
    case ObjectKind::Polygon: return std::make_unique<PolygonPrimitive>(o.vertices);
    case ObjectKind::Box: return std::make_unique<BoxPrimitive>(o.boxMin, o.boxMax);
    case ObjectKind::Water: {
        if (!terrain) throw std::invalid_argument("scene: water needs a height field");
        return std::make_unique<WaterPrimitive>(o.levelM, *terrain);
    }
    }
    throw std::invalid_argument("scene: unknown object kind");
}

const char* kindName(ObjectKind kind) {
    switch (kind) {
    case ObjectKind::HeightField: return "heightfield";
    case ObjectKind::Sphere: return "sphere";
    case ObjectKind::Plane: return "plane";
    case ObjectKind::Triangle: return "triangle";
    case ObjectKind::Polygon: return "polygon";
    case ObjectKind::Box: return "box";
    case ObjectKind::Water: return "water";
    }
    return "object";
}
}  // namespace

MaterialDescription defaultMaterial(ObjectKind kind) {
    MaterialDescription m;
    m.name = std::string("default ") + kindName(kind);
    if (kind == ObjectKind::Water) {
        // Clear fresh water: index 1.333, absorbing red most (Pope and Fry 1997 give about 0.45 per metre at
        // 680 nm, 0.06 at 550 nm and 0.01 at 440 nm; a little dissolved matter is added to green and blue).
        m.colour = glm::vec3(0.0f);
        m.kd = 0.0f;
        m.dielectric = true;
        m.ior = glm::vec3(1.333f);
        m.absorptionPerM = {0.45f, 0.08f, 0.05f};
    } else if (kind != ObjectKind::HeightField) {
        m.colour = glm::vec3(0.7f);
        m.ks = 0.2f;
    }
    return m;
}

Scene::Scene(const SceneDescription& d, const SceneAssets& assets)
    : materials_(d.materials), drapes_(assets.drapes), textures_(assets.textures), sky_(d.sky) {
    drapes_.resize(materials_.size());
    textures_.resize(materials_.size());
    if (assets.environment) sky_.image = assets.environment;
    for (const auto& m : materials_) hasDielectric_ = hasDielectric_ || m.dielectric;

    // Height fields first so that water can clip itself to the terrain's footprint whatever the order.
    size_t nextGrid = 0;
    std::vector<std::unique_ptr<Primitive>> prims(d.objects.size());
    for (size_t k = 0; k < d.objects.size(); ++k) {
        if (d.objects[k].kind != ObjectKind::HeightField) continue;
        prims[k] = makePrimitive(d.objects[k], assets, nextGrid, nullptr, d.render.threads);
        if (!terrain_) terrain_ = static_cast<const HeightFieldPrimitive*>(prims[k].get());
    }
    for (size_t k = 0; k < d.objects.size(); ++k)
        if (!prims[k]) prims[k] = makePrimitive(d.objects[k], assets, nextGrid, terrain_, d.render.threads);

    const double shutter = std::max(std::abs(d.camera.shutterOpen), std::abs(d.camera.shutterClose));
    for (size_t k = 0; k < d.objects.size(); ++k) {
        const ObjectDescription& o = d.objects[k];
        SceneObject obj;
        obj.kind = o.kind;
        obj.name = o.name.empty() ? std::string(kindName(o.kind)) + " " + std::to_string(k + 1) : o.name;
        obj.velocity = o.velocity;
        obj.primitive = std::move(prims[k]);
        int material = -1;
        for (size_t m = 0; m < materials_.size(); ++m)
            if (!o.material.empty() && materials_[m].name == o.material) material = int(m);
        if (material < 0) {
            if (!o.material.empty()) throw std::invalid_argument("scene: unknown material '" + o.material + "'");
            // One shared default material per kind.
            const MaterialDescription def = defaultMaterial(o.kind);
            for (size_t m = 0; m < materials_.size(); ++m)
                if (materials_[m].name == def.name) material = int(m);
            if (material < 0) {
                materials_.push_back(def);
                drapes_.push_back(nullptr);
                textures_.push_back(nullptr);
                hasDielectric_ = hasDielectric_ || def.dielectric;
                material = int(materials_.size() - 1);
            }
        }
        obj.material = material;
        Bounds3 b = obj.primitive->bounds();
        if (b.finite() && obj.moving()) {
            // The swept box over the shutter interval.
            Bounds3 swept = b;
            swept.extend(Bounds3{b.lo - shutter * glm::abs(o.velocity), b.hi + shutter * glm::abs(o.velocity)});
            b = swept;
        }
        objectBounds_.push_back(b);
        if (b.finite()) {
            bounded_.push_back(int32_t(k));
            bounds_.extend(b);
        } else {
            unbounded_.push_back(int32_t(k));
        }
        if (o.kind == ObjectKind::Water) waters_.push_back(int32_t(k));
        objects_.push_back(std::move(obj));
    }
    // A hierarchy pays off only with several bounded objects; one or two are tested directly.
    if (bounded_.size() > 2) {
        std::vector<Bounds3> boxes;
        for (int32_t k : bounded_) boxes.push_back(objectBounds_[size_t(k)]);
        bvh_ = Bvh(boxes);
    }

    // A scene without lights gets one default sun, unless an environment image lights it.
    const std::vector<LightDescription> defaults(d.sky.kind == SkyKind::Image ? 0 : 1);
    for (const auto& l : d.lights.empty() ? defaults : d.lights) {
        SceneLight light;
        light.kind = l.kind;
        light.radiance = l.colour * l.intensity;
        light.direction = directionFromDegrees(l.azimuthDeg, l.elevationDeg);
        light.position = l.position;
        light.radiusM = l.radiusM;
        light.cosAngularRadius = std::cos(radians(l.angularRadiusDeg));
        lights_.push_back(light);
    }
}

bool Scene::hitObject(size_t k, const Ray& ray, Interval interval, SurfaceHit& hit) const {
    const SceneObject& obj = objects_[k];
    if (!obj.moving()) return obj.primitive->intersect(ray, interval, hit);
    // A moving object is hit in its own frame at the ray's time: shift the ray instead of the object.
    const glm::dvec3 shift = ray.time * obj.velocity;
    if (!obj.primitive->intersect({ray.origin - shift, ray.dir, ray.time}, interval, hit)) return false;
    hit.point += shift;
    return true;
}

bool Scene::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    bool found = false;
    auto test = [&](int32_t k, double hi) {
        SurfaceHit h;
        if (hitObject(size_t(k), ray, {interval.lo, hi}, h)) {
            h.object = k;
            hit = h;
            found = true;
            return h.t;
        }
        return hi;
    };
    if (usesBvh()) {
        bvh_.traverse(ray, interval, [&](int32_t item, double hi) { return test(bounded_[size_t(item)], hi); });
    } else {
        for (int32_t k : bounded_) {
            const Interval clipped = objectBounds_[size_t(k)].clip(ray, interval);
            if (!clipped.empty()) interval.hi = test(k, interval.hi);
        }
    }
    for (int32_t k : unbounded_) interval.hi = test(k, found ? hit.t : interval.hi);
    return found;
}

const SceneObject* Scene::waterAbove(const glm::dvec3& p) const {
    const SceneObject* found = nullptr;
    double lowest = kInfinity;
    for (const int32_t k : waters_) {
        const auto& water = static_cast<const WaterPrimitive&>(*objects_[size_t(k)].primitive);
        if (water.level() > p.z && water.level() < lowest && water.covers(p.x, p.y)) {
            found = &objects_[size_t(k)];
            lowest = water.level();
        }
    }
    return found;
}

bool Scene::occludedByOpaque(const Ray& ray, Interval interval) const {
    auto blocks = [&](size_t k) {
        const SceneObject& obj = objects_[k];
        if (materials_[size_t(obj.material)].dielectric) return false;
        if (!obj.moving()) return obj.primitive->occluded(ray, interval);
        return obj.primitive->occluded({ray.origin - ray.time * obj.velocity, ray.dir, ray.time}, interval);
    };
    bool blocked = false;
    if (usesBvh()) {
        bvh_.traverse(ray, interval, [&](int32_t item, double hi) {
            if (blocked) return -kInfinity;
            if (blocks(size_t(bounded_[size_t(item)]))) {
                blocked = true;
                return -kInfinity;  // empties the interval: the traversal stops culling everything
            }
            return hi;
        });
    } else {
        for (int32_t k : bounded_)
            if (!objectBounds_[size_t(k)].clip(ray, interval).empty() && blocks(size_t(k))) return true;
    }
    if (blocked) return true;
    for (int32_t k : unbounded_)
        if (blocks(size_t(k))) return true;
    return false;
}

}  // namespace terracast
