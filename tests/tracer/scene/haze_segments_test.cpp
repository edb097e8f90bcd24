// Aerial perspective on every segment through the air: a wall seen in a mirror is hazed over the whole path,
// mirror and all, as the same wall seen directly at the same distance, and neither is hazed at a short distance.
#include "support/scene_builders.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;
using namespace terracast::testing;

namespace {

// The centre pixel of a camera at (0, 0, 100) looking north (+y) at a grey wall `distance` metres away: straight
// ahead, or (with `mirror`) through a mirror 1 m ahead that turns the view west, the wall then distance - 1 m
// west of it. The sun is at the zenith, so that the air scatters alike towards both horizontal views, and the
// vertical walls take only the sky's light.
glm::vec3 wallPixel(double distance, bool mirror, bool aerial) {
    SceneDescription d;
    MaterialDescription grey;
    grey.name = "grey";
    grey.colour = glm::vec3(0.5f);
    d.materials.push_back(grey);
    MaterialDescription glass;
    glass.name = "mirror";
    glass.kd = 0.0f;
    glass.mirror = glm::vec3(1.0f);
    d.materials.push_back(glass);
    const double far = 5000.0;
    if (mirror) {
        // A square in the vertical plane x + y = 1 around (0, 1, 100), facing the camera.
        ObjectDescription m;
        m.kind = ObjectKind::Polygon;
        m.vertices = {{-0.5, 1.5, 99.5}, {0.5, 0.5, 99.5}, {0.5, 0.5, 100.5}, {-0.5, 1.5, 100.5}};
        m.material = "mirror";
        d.objects.push_back(m);
        d.objects.push_back(box({-(distance - 1.0) - 10.0, -far, -far}, {-(distance - 1.0), far, far}, "grey"));
    } else {
        d.objects.push_back(box({-far, distance, -far}, {far, distance + 10.0, far}, "grey"));
    }
    LightDescription sun;
    sun.elevationDeg = 90.0;
    d.lights.push_back(sun);
    d.sky.kind = SkyKind::Physical;
    d.sky.aerialPerspective = aerial;
    d.sky.samples = 0;
    d.camera.eye = glm::dvec3(0.0, 0.0, 100.0);
    d.camera.lookAt = glm::dvec3(0.0, 1.0, 100.0);
    d.camera.fovDeg = 1.0;
    const Scene scene(d, {});
    SceneRenderSettings s;
    s.width = s.height = 1;
    return tracePixel(scene, makeSceneCamera(scene, d.camera, 1.0), s, 0, 0, nullptr);
}

}  // namespace

TEST_CASE("A wall seen in a mirror is hazed over the whole path, as the same wall seen directly", "[scene][haze]") {
    const glm::vec3 clear = wallPixel(20000.0, false, false);
    const glm::vec3 direct = wallPixel(20000.0, false, true);
    const glm::vec3 mirrored = wallPixel(20000.0, true, true);
    INFO("clear " << clear.r << " " << clear.g << " " << clear.b << ", direct " << direct.r << " " << direct.g << " "
                  << direct.b << ", in the mirror " << mirrored.r << " " << mirrored.g << " " << mirrored.b);
    // At 20 km the haze changes the wall's colour by a large amount: the comparison below can tell.
    CHECK(std::abs(direct.b - clear.b) > 0.3f * clear.b);
    for (int c = 0; c < 3; ++c) CHECK(mirrored[c] == Approx(direct[c]).epsilon(0.01));
    // Without aerial perspective the mirror changes nothing either.
    const glm::vec3 mirroredClear = wallPixel(20000.0, true, false);
    for (int c = 0; c < 3; ++c) CHECK(mirroredClear[c] == Approx(clear[c]).epsilon(1e-4));
}
