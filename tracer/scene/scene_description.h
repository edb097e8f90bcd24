// A scene as the scene file states it: plain data, every field with its documented default. The scene file
// parser fills it; loaders attach the height grids it names; the scene renderer turns it into traceable objects.
#pragma once

#include "tracer/camera/camera.h"
#include "tracer/core/source_location.h"
#include "tracer/core/surface_method.h"
#include "tracer/sampling/filters.h"
#include "tracer/sampling/samplers.h"
#include "tracer/sky/calendar.h"
#include "tracer/sky/sky_description.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terracast {

enum class FresnelModel { Schlick, Exact };
enum class TerrainColouring { Elevation, Slope, Drape, Plain };

struct MaterialDescription {
    std::string name;
    glm::vec3 colour{0.8f};            // diffuse albedo (linear RGB)
    float kd = 1.0f;                   // diffuse weight
    float ks = 0.0f;                   // Phong specular weight
    float exponent = 32.0f;            // Phong exponent
    glm::vec3 mirror{0.0f};            // mirror reflectance per channel (0 = none)
    float gloss = 0.0f;                // glossy reflection lobe exponent; 0 = perfect mirror
    bool dielectric = false;           // refracts: set by giving `ior`
    glm::vec3 ior{1.5f};               // index of refraction; one per channel when dispersive
    bool dispersive = false;           // true when the three indices differ (`ior_rgb`)
    glm::vec3 absorptionPerM{0.0f};    // Beer-Lambert absorption coefficient inside the medium, per metre
    FresnelModel fresnel = FresnelModel::Schlick;
    // Terrain colouring (height fields only).
    TerrainColouring terrain = TerrainColouring::Elevation;
    std::string drapePath;             // RGB raster draped over the terrain (Drape), resolved to a usable path
    // Surface textures (spheres, planes, boxes, triangles, polygons): an image or a checker of `colour` and
    // `checkerColour`, repeating every `textureScale` units of the primitive's (u, v): metres on planes, boxes and
    // polygons, barycentric weights on triangles, longitude and latitude in [0, 1]^2 on spheres
    // (docs/scene-format.md, "Textures"). The texture gives the albedo.
    std::string texturePath;           // image texture, resolved to a usable path; empty = none
    bool checker = false;
    glm::vec3 checkerColour{0.1f};     // the checker's second colour (linear RGB)
    double textureScale = 1.0;
    SourceLocation where;
    SourceLocation drapeWhere;         // of the `drape` key, for file errors
    SourceLocation textureWhere;       // of the `texture` key
};

enum class ObjectKind { HeightField, Sphere, Plane, Triangle, Polygon, Box, Water };

struct ObjectDescription {
    ObjectKind kind = ObjectKind::Sphere;
    std::string name;                  // for the debug ray tree; defaults to "<kind> <index>"
    std::string material;              // material name; empty = the kind's default material
    // Height field.
    std::string filePath;              // resolved against the scene file's folder
    glm::dvec3 offsetM{0.0};           // placement: where the grid's vertex (0, 0) goes
    double exaggeration = 1.0;         // vertical exaggeration (heights times this)
    SurfaceMethod method = SurfaceMethod::Bilinear;
    double cellSizeM = 1.0;            // PNG height maps: metres between samples
    double heightScale = 1.0;          // PNG height maps: metres per stored unit
    bool smoothNormals = true;         // shade with smooth normals ("smooth") or each cell's own ("facet")
    // Sphere.
    glm::dvec3 centre{0.0};
    double radiusM = 1.0;
    // Plane: a point on it and its normal.
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0, 0, 1};
    // Triangle and polygon: vertices in order.
    std::vector<glm::dvec3> vertices;
    // Box: opposite corners.
    glm::dvec3 boxMin{0.0};
    glm::dvec3 boxMax{1.0};
    // Water: a horizontal surface at this level, clipped to the first height field's footprint.
    double levelM = 0.0;
    // Motion blur: linear velocity, metres per second.
    glm::dvec3 velocity{0.0};
    SourceLocation where;
    SourceLocation fileWhere;          // of the `file` key, for file errors
    SourceLocation materialWhere;      // of the `material` key
};

enum class LightKind { Sun, Point, Sphere };

struct LightDescription {
    LightKind kind = LightKind::Sun;
    glm::vec3 colour{1.0f};
    float intensity = 1.0f;            // sun: irradiance scale; point and sphere: radiant intensity scale (W/sr-like)
    // Sun: direction towards it, by azimuth (clockwise from north) and elevation, or by a date and time.
    double azimuthDeg = 315.0;
    double elevationDeg = 35.0;
    std::optional<UtcInstant> time;    // overrides azimuth/elevation when set
    double angularRadiusDeg = 0.2679;  // the sun's apparent radius (soft shadows)
    // Point and sphere lights.
    glm::dvec3 position{0.0};
    double radiusM = 0.0;              // sphere light radius
    SourceLocation where;
};

struct RenderDescription {
    int width = 960;
    int height = 540;
    int samples = 1;                   // samples per pixel
    SamplePattern sampler = SamplePattern::Stratified;
    FilterKind filter = FilterKind::Box;
    int maxDepth = 6;                  // reflection/refraction bounces
    double minWeight = 0.01;           // stop a path whose weight falls below this
    uint64_t seed = 0;
    int threads = 0;                   // 0 = all cores
    std::string output;                // resolved against the scene file's folder; empty = not set
    float exposure = 1.0f;             // multiplies radiance before encoding
    SourceLocation where;
};

struct SceneDescription {
    std::string path;                  // the scene file
    CameraDescription camera;
    std::vector<MaterialDescription> materials;
    std::vector<ObjectDescription> objects;
    std::vector<LightDescription> lights;  // empty = one default sun (none under an image sky)
    SkyDescription sky;
    RenderDescription render;
    std::vector<std::string> warnings;  // what the file asks that is allowed but likely a mistake, one line each
};

}  // namespace terracast
