// Warps: maps from the unit square [0, 1)^2 onto disks, spheres, cones and lobes. A well-spread set of
// points in the square stays well spread after the warp, which is how one sample pattern serves the pixel,
// the lens, an area light and a glossy lobe alike. Every warp comes with the density (pdf) of the point it
// returns, with respect to area for the disk and to solid angle for directions, when the square's points
// are uniform.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

namespace terracast {

// A right-handed orthonormal frame (s, t, n) around a unit axis n, to turn directions sampled around +z
// into directions around any axis.
struct Frame {
    glm::dvec3 s{1, 0, 0};
    glm::dvec3 t{0, 1, 0};
    glm::dvec3 n{0, 0, 1};

    // The frame around a unit vector. Valid for every axis, with no cross product against a fixed vector
    // that could vanish (Duff et al. 2017, "Building an orthonormal basis, revisited").
    static Frame around(const glm::dvec3& unitAxis);
    glm::dvec3 toWorld(const glm::dvec3& local) const { return local.x * s + local.y * t + local.z * n; }
    glm::dvec3 toLocal(const glm::dvec3& world) const {
        return {glm::dot(world, s), glm::dot(world, t), glm::dot(world, n)};
    }
};

// The unit disk, uniform by area (pdf 1 / pi), by Shirley and Chiu's concentric map (1997, "A low
// distortion map between disk and square"): squares around the centre become rings, so strata stay compact
// and the map is continuous and area preserving.
glm::dvec2 squareToConcentricDisk(glm::dvec2 u);

// The unit sphere, uniform by solid angle (pdf 1 / (4 pi)): z uniform in [-1, 1] (Archimedes' hat-box
// theorem), azimuth uniform.
glm::dvec3 squareToUniformSphere(glm::dvec2 u);
inline double uniformSpherePdf() { return 1.0 / (4.0 * glm::pi<double>()); }

// The spherical cap of directions within an angle theta_max of +z, uniform by solid angle: cos(theta)
// uniform in [cos theta_max, 1]. cosThetaMax = 0 is the hemisphere, -1 the whole sphere. u.x = 0 gives
// the axis itself. pdf = 1 / (2 pi (1 - cos theta_max)), the inverse of the cap's solid angle.
glm::dvec3 squareToUniformCone(glm::dvec2 u, double cosThetaMax);
double uniformConePdf(double cosThetaMax);

// Cosine of the half-angle of the cone a sphere of radius `radius` subtends from a point `distance` from
// its centre: the cone to sample for a spherical light. A point inside the sphere sees it all around (-1).
double sphereConeCosine(double distance, double radius);

// Phong's power-cosine lobe around +z: pdf(w) = (n + 1) / (2 pi) cos^n(theta) over the hemisphere z > 0,
// sampled by cos(theta) = u.x^(1 / (n + 1)) (Lafortune and Willems 1994, "Using the modified Phong
// reflectance model for physically based rendering"). n = 0 is the uniform hemisphere; larger exponents
// give tighter, glossier lobes.
glm::dvec3 squareToPhongLobe(glm::dvec2 u, double exponent);
double phongLobePdf(double cosTheta, double exponent);

// The hemisphere z > 0 with pdf cos(theta) / pi (Malley's method: the concentric disk lifted onto the
// hemisphere), for diffuse light such as sky visibility.
glm::dvec3 squareToCosineHemisphere(glm::dvec2 u);
double cosineHemispherePdf(double cosTheta);

}  // namespace terracast
