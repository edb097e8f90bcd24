// Scene descriptions built in code for the scene tracer's tests: objects, cameras, materials and render
// settings with the values each test states.
#pragma once

#include "tracer/scene/scene_renderer.h"

#include <string>

namespace terracast::testing {

inline ObjectDescription sphere(glm::dvec3 c, double r, const std::string& material = "") {
    ObjectDescription o;
    o.kind = ObjectKind::Sphere;
    o.centre = c;
    o.radiusM = r;
    o.material = material;
    return o;
}

inline ObjectDescription box(glm::dvec3 lo, glm::dvec3 hi, const std::string& material = "") {
    ObjectDescription o;
    o.kind = ObjectKind::Box;
    o.boxMin = lo;
    o.boxMax = hi;
    o.material = material;
    return o;
}

inline ObjectDescription plane(glm::dvec3 p, glm::dvec3 n, const std::string& material = "") {
    ObjectDescription o;
    o.kind = ObjectKind::Plane;
    o.point = p;
    o.normal = n;
    o.material = material;
    return o;
}

inline CameraDescription lookingAt(glm::dvec3 eye, glm::dvec3 look, double fov = 40.0) {
    CameraDescription c;
    c.eye = eye;
    c.lookAt = look;
    c.fovDeg = fov;
    return c;
}

// Clear glass of index 1.5 with no diffuse part, named "glass".
inline MaterialDescription clearGlass() {
    MaterialDescription glass;
    glass.name = "glass";
    glass.kd = 0.0f;
    glass.dielectric = true;
    glass.ior = glm::vec3(1.5f);
    return glass;
}

// The description's size, depth and weight cut-off, on two threads.
inline SceneRenderSettings settingsFor(const SceneDescription& d) {
    SceneRenderSettings s;
    s.width = d.render.width;
    s.height = d.render.height;
    s.maxDepth = d.render.maxDepth;
    s.minWeight = d.render.minWeight;
    s.threads = 2;
    return s;
}

}  // namespace terracast::testing
