// Scene-file parser. toml++ turns the text into a tree that remembers where every key and value was written;
// each table is then checked against a schema of the keys it takes (per object, camera or light type) before
// any value is read, so a misspelt key is reported as such rather than as a missing one. Values are read with
// their type and range checked, and every error names the scene file, the line and column of the offending
// key or value, what was expected and what was found. docs/scene-format.md is the reference for the format.
#include "loaders/scene_file.h"

#include "loaders/input_files.h"
#include "loaders/toml_reader.h"
#include "tracer/core/errors.h"
#include "tracer/core/text.h"
#include "tracer/sky/calendar.h"
#include "tracer/core/surface_method.h"
#include "tracer/sampling/filters.h"
#include "tracer/sampling/samplers.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace terracast {
namespace {

using namespace toml_reader;

// The option that lets a scene file name paths outside its folder.
constexpr const char* kAllowPathsFlag = "--allow-paths";
// A polygon is planar when no vertex lies farther than this fraction of its bounding box's largest side from
// its plane, and degenerate when twice its area is below this fraction of that side squared.
constexpr double kPlanarTolerance = 1e-6;
constexpr double kDegenerateArea = 1e-10;

// ---- Camera ----

constexpr std::array<Choice<CameraKind>, 5> kCameraKinds{{
    {"pinhole", CameraKind::Pinhole},
    {"orthographic", CameraKind::Orthographic},
    {"thin-lens", CameraKind::ThinLens},
    {"panorama", CameraKind::Panorama},
    {"fisheye", CameraKind::Fisheye},
}};

const std::vector<KeyRule> kCameraKeys{
    {"type", {}},
    {"eye", {}},
    {"look_at", {}},
    {"up", {}},
    {"fov", {"pinhole", "thin-lens", "fisheye"}},
    {"height", {"orthographic"}},
    {"aperture", {"thin-lens"}},
    {"focus_distance", {"thin-lens"}},
    {"shutter", {}},
    {"velocity", {}},
};

constexpr double kFisheyeDefaultFovDeg = 180.0;
constexpr double kParallelSine = 1e-9;  // up is parallel to the view when the sine of their angle is below this

CameraDescription parseCamera(const TableReader& t) {
    CameraDescription camera;
    camera.where = t.where();
    camera.kind = t.choice<CameraKind>("type", kCameraKinds).value_or(CameraKind::Pinhole);
    const std::string_view type = choiceName<CameraKind>(kCameraKinds, camera.kind);
    checkKeys(t, kCameraKeys, type, fmt::format("a camera of type {}", quoteString(type)));

    camera.eye = t.vector3("eye");
    camera.lookAt = t.vector3("look_at");
    if (const auto up = t.direction("up")) camera.up = *up;
    const bool fisheye = camera.kind == CameraKind::Fisheye;
    if (fisheye) camera.fovDeg = kFisheyeDefaultFovDeg;
    if (const auto fov = t.number("fov", fisheye ? Range{0.0, 360.0, false, true} : Range{0.0, 180.0, false, false}))
        camera.fovDeg = *fov;
    if (const auto h = t.number("height", kLength)) camera.orthoHeightM = *h;
    if (const auto a = t.number("aperture", Range{0.0, 1e9})) camera.apertureRadiusM = *a;
    if (const auto f = t.number("focus_distance", Range{0.0, 1e9})) camera.focusDistanceM = *f;
    if (const auto s = t.orderedPair("shutter", "[open, close]")) {
        camera.shutterOpen = (*s)[0];
        camera.shutterClose = (*s)[1];
    }
    if (const auto v = t.vector3("velocity")) camera.velocity = *v;

    if (camera.eye && camera.lookAt) {
        const glm::dvec3 view = *camera.lookAt - *camera.eye;
        if (view == glm::dvec3(0.0))
            t.fail(t.valueWhere("look_at"), "look_at: expected a point other than eye, found the same point "
                                            "(the view direction has zero length)");
        // Without an explicit `up` the camera picks its own for a view along the default one (a map view).
        const double sine = glm::length(glm::cross(glm::normalize(view), glm::normalize(camera.up)));
        if (t.has("up") && sine < kParallelSine)
            t.fail(t.valueWhere("up"),
                   fmt::format("up: expected a direction not parallel to the view from eye to look_at, found "
                               "[{}, {}, {}]",
                               camera.up.x, camera.up.y, camera.up.z));
    }
    return camera;
}

// ---- Files ----

// Refuses a path that names no file, or a folder, at the key's location.
void checkInputFile(const TableReader& t, std::string_view key, const std::string& path) {
    if (path.starts_with("/vsi")) return;  // GDAL virtual file systems: GDAL checks them
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    const SourceLocation where = t.keyWhere(key);
    if (status.type() == std::filesystem::file_type::not_found)
        t.fail(where, fmt::format("{}: {}: no such file", key, printable(path, std::string::npos)));
    if (status.type() == std::filesystem::file_type::directory)
        t.fail(where, fmt::format("{}: {}: is a directory, expected a file", key, printable(path, std::string::npos)));
    if (ec)
        t.fail(where, fmt::format("{}: {}: cannot be accessed ({})", key, printable(path, std::string::npos), ec.message()));
}

// The file a key names (a height field's DEM, a drape, a texture, a sky image): resolved against the scene's
// folder (confined to it unless --allow-paths), checked to exist, and the key's location kept for later errors.
std::string inputFile(const TomlFile& scene, const TableReader& t, std::string_view key, SourceLocation& where) {
    std::string path = scene.resolveConfined(t.valueWhere(key), key, *t.path(key), kAllowPathsFlag);
    where = t.keyWhere(key);
    checkInputFile(t, key, path);
    return path;
}

// ---- Materials ----

constexpr std::array<Choice<FresnelModel>, 2> kFresnelModels{{
    {"schlick", FresnelModel::Schlick},
    {"exact", FresnelModel::Exact},
}};

constexpr std::array<Choice<TerrainColouring>, 4> kTerrainColourings{{
    {"elevation", TerrainColouring::Elevation},
    {"slope", TerrainColouring::Slope},
    {"drape", TerrainColouring::Drape},
    {"color", TerrainColouring::Plain},
}};

const std::vector<KeyRule> kMaterialKeys{
    {"name", {}},     {"color", {}}, {"kd", {}},         {"ks", {}},      {"exponent", {}},
    {"mirror", {}},   {"gloss", {}}, {"ior", {}},        {"ior_rgb", {}}, {"absorption", {}},
    {"fresnel", {}},  {"terrain", {}}, {"drape", {}},    {"texture", {}}, {"checker", {}},
    {"texture_scale", {}},
};

void parseDielectric(const TableReader& t, MaterialDescription& m) {
    if (const toml::node* n = t.node("ior"); n && n->is_array())
        t.fail(t.whereOf(*n), "ior: expected a number > 0, found an array (ior_rgb takes one index per channel)");
    if (const auto ior = t.singleNumber("ior", kPositive)) {
        m.dielectric = true;
        m.ior = glm::vec3(*ior);
    }
    if (const auto iorRgb = t.rgb("ior_rgb", kPositive, false)) {
        if (m.dielectric) t.fail(t.keyWhere("ior_rgb"), "ior_rgb: give either ior or ior_rgb, not both");
        m.dielectric = true;
        m.ior = *iorRgb;
        m.dispersive = !(m.ior.r == m.ior.g && m.ior.g == m.ior.b);
    }
    if (const auto a = t.rgb("absorption", kNonNegative, true)) m.absorptionPerM = *a;
    if (const auto f = t.choice<FresnelModel>("fresnel", kFresnelModels)) m.fresnel = *f;
    for (const std::string_view key : {"absorption", "fresnel"})
        if (t.has(key) && !m.dielectric)
            t.fail(t.keyWhere(key), fmt::format("key {} applies only to a dielectric material (one with ior or "
                                                "ior_rgb)",
                                                quoteKey(key)));
}

void parseTerrainColouring(const TomlFile& scene, const TableReader& t, MaterialDescription& m) {
    const auto colouring = t.choice<TerrainColouring>("terrain", kTerrainColourings);
    if (t.has("drape")) {
        if (colouring && *colouring != TerrainColouring::Drape)
            t.fail(t.keyWhere("drape"), fmt::format("drape: applies only with terrain = \"drape\", found terrain = {}",
                                                    quoteString(choiceName<TerrainColouring>(kTerrainColourings,
                                                                                             *colouring))));
        m.terrain = TerrainColouring::Drape;
        m.drapePath = inputFile(scene, t, "drape", m.drapeWhere);
    } else if (colouring == TerrainColouring::Drape) {
        t.fail(t.valueWhere("terrain"), "terrain: \"drape\" needs a raster to drape (drape = \"file.tif\")");
    } else if (colouring) {
        m.terrain = *colouring;
    } else if (t.has("color")) {
        m.terrain = TerrainColouring::Plain;  // a colour given for terrain is the terrain's colour
    }
}

void parseTexture(const TomlFile& scene, const TableReader& t, MaterialDescription& m) {
    if (t.has("texture")) {
        m.texturePath = inputFile(scene, t, "texture", m.textureWhere);
    }
    if (const auto c = t.rgb("checker", kNonNegative, false)) {
        if (!m.texturePath.empty()) t.fail(t.keyWhere("checker"), "checker: give either texture or checker, not both");
        m.checker = true;
        m.checkerColour = *c;
    }
    if (const auto scale = t.singleNumber("texture_scale", kPositive)) {
        if (m.texturePath.empty() && !m.checker)
            t.fail(t.keyWhere("texture_scale"), "texture_scale: applies only with texture or checker");
        m.textureScale = *scale;
    }
}

// Energy (docs/scene-format.md, "Energy"): the light a surface sends back, over all its terms, is at most what
// it receives when kd x max(color) + ks + max(mirror) + (1 for a dielectric, whose Fresnel reflection and
// transmission sum to one) is at most 1. The diffuse weight not given is the largest up to 1 that the other
// terms leave room for; a sum above 1 from weights the file gives is a warning.
void balanceEnergy(const TableReader& t, MaterialDescription& m, std::vector<std::string>& warnings) {
    const float mirror = std::max({m.mirror.r, m.mirror.g, m.mirror.b});
    const float others = m.ks + mirror + (m.dielectric ? 1.0f : 0.0f);
    // A texture's values reach 1; a checker's two colours both show.
    const float colour = !m.texturePath.empty() ? 1.0f
                         : m.checker ? std::max({m.colour.r, m.colour.g, m.colour.b, m.checkerColour.r,
                                                 m.checkerColour.g, m.checkerColour.b})
                                     : std::max({m.colour.r, m.colour.g, m.colour.b});
    if (!t.has("kd")) m.kd = colour <= 1.0f - others ? 1.0f : std::max(0.0f, (1.0f - others) / colour);
    const double sum = double(m.kd) * colour + others;
    if (sum > 1.0 + 1e-6)
        warnings.push_back(t.located(
            t.where(), fmt::format("material {}: kd x max(color) + ks + max(mirror){} = {:.3g}, above 1: the surface "
                                   "sends back more light than it receives (lower kd, color, ks or mirror)",
                                   quoteString(m.name), m.dielectric ? " + 1 (dielectric)" : "", sum)));
}

MaterialDescription parseMaterial(const TomlFile& scene, const TableReader& t, std::vector<std::string>& warnings) {
    checkKeys(t, kMaterialKeys, "", "");
    MaterialDescription m;
    m.where = t.where();
    t.require("name", "in [[material]]");
    m.name = *t.nonEmptyString("name");
    if (const auto c = t.rgb("color", kNonNegative, false)) m.colour = *c;
    if (const auto kd = t.singleNumber("kd", kNonNegative)) m.kd = *kd;
    if (const auto ks = t.singleNumber("ks", kNonNegative)) m.ks = *ks;
    if (const auto e = t.singleNumber("exponent", kPositive)) m.exponent = *e;
    if (const auto mirror = t.rgb("mirror", Range{0.0, 1.0, true, true}, true)) m.mirror = *mirror;
    if (const auto g = t.singleNumber("gloss", kNonNegative)) m.gloss = *g;
    parseDielectric(t, m);
    parseTerrainColouring(scene, t, m);
    parseTexture(scene, t, m);
    balanceEnergy(t, m, warnings);
    return m;
}

// ---- Objects ----

constexpr std::array<Choice<ObjectKind>, 7> kObjectKinds{{
    {"heightfield", ObjectKind::HeightField},
    {"sphere", ObjectKind::Sphere},
    {"plane", ObjectKind::Plane},
    {"triangle", ObjectKind::Triangle},
    {"polygon", ObjectKind::Polygon},
    {"box", ObjectKind::Box},
    {"water", ObjectKind::Water},
}};

const std::vector<KeyRule> kObjectKeys{
    {"type", {}},
    {"name", {}},
    {"material", {}},
    {"velocity", {}},
    {"file", {"heightfield"}},
    {"offset", {"heightfield"}},
    {"exaggeration", {"heightfield"}},
    {"method", {"heightfield"}},
    {"cell_size", {"heightfield"}},
    {"height_scale", {"heightfield"}},
    {"normals", {"heightfield"}},
    {"center", {"sphere"}},
    {"radius", {"sphere"}},
    {"point", {"plane"}},
    {"normal", {"plane"}},
    {"vertices", {"triangle", "polygon"}},
    {"min", {"box"}},
    {"max", {"box"}},
    {"level", {"water"}},
};


void parseHeightField(const TomlFile& scene, const TableReader& t, const std::string& subject,
                      ObjectDescription& o) {
    t.require("file", subject);
    o.filePath = inputFile(scene, t, "file", o.fileWhere);
    if (const auto offset = t.vector3("offset")) o.offsetM = *offset;
    if (const auto k = t.number("exaggeration", kPositive)) o.exaggeration = *k;
    static const auto methods = namedChoices(surfaceMethods(), surfaceMethodName);
    if (const auto method = t.choice<SurfaceMethod>("method", methods)) o.method = *method;
    if (const auto cell = t.number("cell_size", kPositive)) o.cellSizeM = *cell;
    if (const auto scale = t.number("height_scale", kPositive)) o.heightScale = *scale;
    static constexpr std::array<Choice<bool>, 2> kNormals{{{"smooth", true}, {"facet", false}}};
    if (const auto smooth = t.choice<bool>("normals", kNormals)) o.smoothNormals = *smooth;
}

// Refuses a triangle or polygon without area, or a polygon whose vertices do not share a plane. The plane is
// Newell's: its normal sums the edges' cross terms, which for a planar polygon, convex or not, is twice its
// vector area (Tampieri, "Newell's Method for Computing the Plane Equation of a Polygon", Graphics Gems III,
// 1992), and it passes through the vertices' centroid. Coordinates are taken relative to the first vertex and
// scaled by the bounding box's largest side, so the tolerances are relative to the polygon's size.
void checkPlanarPolygon(const TableReader& t, const std::vector<glm::dvec3>& vertices, bool triangle) {
    const SourceLocation where = t.valueWhere("vertices");
    const char* shape = triangle ? "triangle" : "polygon";
    glm::dvec3 lo = vertices[0];
    glm::dvec3 hi = vertices[0];
    for (const auto& v : vertices) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    const double size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    if (!std::isfinite(size))
        t.fail(where, fmt::format("vertices: expected a {} whose size fits a double, found one wider than {:.3g} m",
                                  shape, std::numeric_limits<double>::max()));
    std::vector<glm::dvec3> p;
    for (const auto& v : vertices) p.push_back(size > 0.0 ? (v - vertices[0]) / size : glm::dvec3(0.0));
    glm::dvec3 normal(0.0);
    glm::dvec3 centroid(0.0);
    for (size_t i = 0; i < p.size(); ++i) {
        const glm::dvec3& a = p[i];
        const glm::dvec3& b = p[(i + 1) % p.size()];
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
        centroid += a / static_cast<double>(p.size());
    }
    if (!(glm::length(normal) > kDegenerateArea))
        t.fail(where, fmt::format("vertices: expected a {} with an area, found a degenerate one (zero area: its "
                                  "vertices coincide or lie on one line)",
                                  shape));
    const glm::dvec3 unit = glm::normalize(normal);
    size_t worst = 0;
    double worstDistance = 0.0;
    for (size_t i = 0; i < p.size(); ++i) {
        const double d = std::abs(glm::dot(p[i] - centroid, unit));
        if (d > worstDistance) {
            worstDistance = d;
            worst = i;
        }
    }
    if (worstDistance > kPlanarTolerance)
        t.fail(where, fmt::format("vertices: expected a planar polygon, found vertices[{}] {:.6g} m from the "
                                  "polygon's plane (tolerance {:.3g} m)",
                                  worst, worstDistance * size, kPlanarTolerance * size));
}

void parseVertices(const TableReader& t, const std::string& subject, bool triangle, ObjectDescription& o) {
    t.require("vertices", subject);
    o.vertices = *t.points("vertices");
    const size_t n = o.vertices.size();
    if (triangle && n != 3)
        t.fail(t.valueWhere("vertices"), fmt::format("vertices: expected exactly 3 points, found {}", n));
    if (!triangle && n < 3)
        t.fail(t.valueWhere("vertices"), fmt::format("vertices: expected at least 3 points, found {}", n));
    checkPlanarPolygon(t, o.vertices, triangle);
}

void parseBox(const TableReader& t, ObjectDescription& o) {
    if (const auto lo = t.vector3("min")) o.boxMin = *lo;
    if (const auto hi = t.vector3("max")) o.boxMax = *hi;
    static constexpr char kAxes[] = "xyz";
    for (int axis = 0; axis < 3; ++axis)
        if (!(o.boxMin[axis] < o.boxMax[axis]))
            t.fail(t.has("max") ? t.valueWhere("max") : t.valueWhere("min"),
                   fmt::format("max: expected a corner above min on every axis, found {} = {} for min and {} for "
                               "max",
                               kAxes[axis], o.boxMin[axis], o.boxMax[axis]));
}

// The material names and where each was defined.
using MaterialIndex = std::map<std::string, SourceLocation>;

ObjectDescription parseObject(const TomlFile& scene, const TableReader& t, size_t index,
                              const MaterialIndex& materials) {
    ObjectDescription o;
    o.where = t.where();
    const auto names = choiceNames<ObjectKind>(kObjectKinds);
    if (!t.has("type")) refuseMisspeltKey(t, kObjectKeys, "type");
    t.require("type", fmt::format("in [[object]] (one of {})", quoteAll(names)));
    o.kind = *t.choice<ObjectKind>("type", kObjectKinds);
    const std::string_view type = choiceName<ObjectKind>(kObjectKinds, o.kind);
    const std::string subject = fmt::format("an object of type {}", quoteString(type));
    checkKeys(t, kObjectKeys, type, subject);
    const std::string required = "for " + subject;

    o.name = t.nonEmptyString("name").value_or(fmt::format("{} {}", type, index + 1));
    if (const auto material = t.nonEmptyString("material")) {
        if (!materials.contains(*material)) {
            std::vector<std::string> known;
            for (const auto& [name, where] : materials) known.push_back(name);
            t.fail(t.valueWhere("material"),
                   fmt::format("material: no [[material]] is named {}{}", quoteString(*material),
                               known.empty() ? std::string(" (the scene defines no [[material]])")
                                             : didYouMean(*material, known, false)));
        }
        o.material = *material;
        o.materialWhere = t.keyWhere("material");
    }
    if (const auto v = t.vector3("velocity")) o.velocity = *v;

    switch (o.kind) {
        case ObjectKind::HeightField: parseHeightField(scene, t, required, o); break;
        case ObjectKind::Sphere:
            t.require("center", required);
            t.require("radius", required);
            o.centre = *t.vector3("center");
            o.radiusM = *t.number("radius", kLength);
            break;
        case ObjectKind::Plane:
            if (const auto p = t.vector3("point")) o.point = *p;
            if (const auto n = t.direction("normal")) o.normal = *n;
            break;
        case ObjectKind::Triangle: parseVertices(t, required, true, o); break;
        case ObjectKind::Polygon: parseVertices(t, required, false, o); break;
        case ObjectKind::Box: parseBox(t, o); break;
        case ObjectKind::Water:
            if (const auto level = t.number("level", kCoordinate)) o.levelM = *level;
            break;
    }
    return o;
}

// ---- Lights ----

constexpr std::array<Choice<LightKind>, 3> kLightKinds{{
    {"sun", LightKind::Sun},
    {"point", LightKind::Point},
    {"sphere", LightKind::Sphere},
}};

const std::vector<KeyRule> kLightKeys{
    {"type", {}},
    {"color", {}},
    {"intensity", {}},
    {"azimuth", {"sun"}},
    {"elevation", {"sun"}},
    {"time", {"sun"}},
    {"angular_radius", {"sun"}},
    {"position", {"point", "sphere"}},
    {"radius", {"sphere"}},
};

// The sun's `time`, as a string or a TOML offset date-time, normalised to UTC.
UtcInstant parseSunTime(const TableReader& t) {
    const toml::node& n = *t.node("time");
    ZonedTime zoned;
    if (const auto* native = n.as_date_time()) {
        const toml::date_time& dt = native->get();
        if (!dt.offset)
            t.fail(t.whereOf(n), "time: expected a time with a zone, such as 2026-06-21T19:30:00Z, found a local "
                                 "date-time");
        zoned = {dt.date.year, dt.date.month, dt.date.day, dt.time.hour, dt.time.minute, dt.time.second,
                 dt.offset->minutes};
        zoned.second = std::min<int64_t>(zoned.second, 59);  // a leap second counts as the second before it
    } else {
        const auto* s = n.as_string();
        if (!s)
            t.fail(t.whereOf(n), fmt::format("time: expected an ISO 8601 time such as \"2026-06-21T19:30Z\", found {}",
                                             describeType(n)));
        if (const auto why = readIsoTime(s->get(), zoned))
            t.fail(t.whereOf(n), fmt::format("time: expected an ISO 8601 time such as \"2026-06-21T19:30Z\", found "
                                             "{} ({})",
                                             quoteString(s->get()), *why));
    }
    const auto utc = toUtc(zoned);
    if (!utc) t.fail(t.whereOf(n), "time: expected a time whose UTC date falls in the years 0001..9999");
    return *utc;
}

LightDescription parseLight(const TableReader& t) {
    LightDescription light;
    light.where = t.where();
    light.kind = t.choice<LightKind>("type", kLightKinds).value_or(LightKind::Sun);
    const std::string_view type = choiceName<LightKind>(kLightKinds, light.kind);
    const std::string subject = fmt::format("a light of type {}", quoteString(type));
    checkKeys(t, kLightKeys, type, subject);

    if (const auto c = t.rgb("color", kNonNegative, false)) light.colour = *c;
    if (const auto i = t.singleNumber("intensity", kNonNegative)) light.intensity = *i;
    switch (light.kind) {
        case LightKind::Sun:
            if (const auto az = t.number("azimuth")) light.azimuthDeg = *az;
            if (const auto el = t.number("elevation", Range{-90.0, 90.0, true, true})) light.elevationDeg = *el;
            if (const auto r = t.number("angular_radius", Range{0.0, 90.0, true, false})) light.angularRadiusDeg = *r;
            if (t.has("time")) {
                light.time = parseSunTime(t);
                for (const std::string_view key : {"azimuth", "elevation"})
                    if (t.has(key))
                        t.fail(t.keyWhere(key), fmt::format("key {} conflicts with 'time', which sets the sun's "
                                                            "position; give one or the other",
                                                            quoteKey(key)));
            }
            break;
        case LightKind::Point:
            t.require("position", "for " + subject);
            light.position = *t.vector3("position");
            break;
        case LightKind::Sphere:
            t.require("position", "for " + subject);
            t.require("radius", "for " + subject);
            light.position = *t.vector3("position");
            light.radiusM = *t.number("radius", kLength);
            break;
    }
    return light;
}

// ---- Sky and render settings ----

constexpr int64_t kMaxSkySamples = 1024;

const std::vector<Choice<SkyKind>> kSkyKinds = namedChoices(sceneSkyKinds(), skyKindName);

const std::vector<KeyRule> kSkyKeys{
    {"model", {}},
    {"color", {"flat"}},
    {"haze", {"physical"}},
    {"aerial_perspective", {"physical"}},
    {"ambient", {"physical", "gradient", "flat", "image"}},
    {"samples", {"physical", "gradient", "flat", "image"}},
    {"file", {"image"}},
    {"rotation", {"image"}},
    {"intensity", {"image"}},
};

SkyDescription parseSky(const TomlFile& scene, const TableReader& t) {
    SkyDescription sky;
    sky.where = t.where();
    sky.kind = t.choice<SkyKind>("model", std::span<const Choice<SkyKind>>(kSkyKinds)).value_or(SkyKind::Physical);
    const std::string_view model = choiceName<SkyKind>(std::span<const Choice<SkyKind>>(kSkyKinds), sky.kind);
    checkKeys(t, kSkyKeys, model, fmt::format("a sky of model {}", quoteString(model)));
    if (const auto c = t.rgb("color", kNonNegative, false)) sky.colour = *c;
    if (const auto h = t.number("haze", kNonNegative)) sky.haze = *h;
    if (const auto a = t.boolean("aerial_perspective")) sky.aerialPerspective = *a;
    if (const auto a = t.singleNumber("ambient", kNonNegative)) sky.ambient = *a;
    if (const auto n = t.integer("samples", 0, kMaxSkySamples)) sky.samples = static_cast<int>(*n);
    if (sky.kind == SkyKind::Image) {
        t.require("file", "for a sky of model \"image\" (an equirectangular EXR, HDR or PNG)");
        sky.imagePath = inputFile(scene, t, "file", sky.imageWhere);
        if (const auto r = t.number("rotation")) sky.rotationDeg = *r;
        if (const auto i = t.singleNumber("intensity", kNonNegative)) sky.intensity = float(*i);
    }
    return sky;
}

const std::vector<KeyRule> kRenderKeys{
    {"width", {}},     {"height", {}}, {"samples", {}}, {"sampler", {}}, {"filter", {}},   {"max_depth", {}},
    {"min_weight", {}}, {"seed", {}},  {"threads", {}}, {"output", {}},  {"exposure", {}},
};

constexpr int64_t kMaxImageSide = 16384;
constexpr int64_t kMaxSamples = 65536;
constexpr int64_t kMaxDepth = 64;
constexpr int64_t kMaxThreads = 4096;

RenderDescription parseRender(const TomlFile& scene, const TableReader& t) {
    checkKeys(t, kRenderKeys, "", "");
    RenderDescription r;
    r.where = t.where();
    if (const auto w = t.integer("width", 1, kMaxImageSide)) r.width = static_cast<int>(*w);
    if (const auto h = t.integer("height", 1, kMaxImageSide)) r.height = static_cast<int>(*h);
    if (const auto s = t.integer("samples", 1, kMaxSamples)) r.samples = static_cast<int>(*s);
    static const auto samplers = namedChoices(samplePatterns(), samplePatternName);
    static const auto filters = namedChoices(filterKinds(), filterKindName);
    if (const auto s = t.choice<SamplePattern>("sampler", samplers)) r.sampler = *s;
    if (const auto f = t.choice<FilterKind>("filter", filters)) r.filter = *f;
    if (const auto d = t.integer("max_depth", 0, kMaxDepth)) r.maxDepth = static_cast<int>(*d);
    if (const auto w = t.number("min_weight", Range{0.0, 1.0, true, false})) r.minWeight = *w;
    if (const auto s = t.integer("seed", 0, std::numeric_limits<int64_t>::max())) r.seed = static_cast<uint64_t>(*s);
    if (const auto n = t.integer("threads", 0, kMaxThreads)) r.threads = static_cast<int>(*n);
    if (const auto o = t.path("output")) r.output = scene.resolveConfined(t.valueWhere("output"), "output", *o, kAllowPathsFlag);
    if (const auto e = t.singleNumber("exposure", kPositive)) r.exposure = *e;
    return r;
}

// ---- The whole file ----

enum class SectionForm { Table, ArrayOfTables };

struct Section {
    std::string_view name;
    SectionForm form;
};

constexpr std::array<Section, 6> kSections{{
    {"camera", SectionForm::Table},
    {"material", SectionForm::ArrayOfTables},
    {"object", SectionForm::ArrayOfTables},
    {"light", SectionForm::ArrayOfTables},
    {"sky", SectionForm::Table},
    {"render", SectionForm::Table},
}};

std::string sectionHeader(std::string_view name, SectionForm form) {
    return form == SectionForm::Table ? fmt::format("[{}]", name) : fmt::format("[[{}]]", name);
}

// Refuses top-level keys that are not one of the sections, or a section written in the wrong form.
void checkSections(const TomlFile& scene, const toml::table& root) {
    const TableReader top(scene, root, "the top level", SourceLocation{1, 1});
    std::vector<std::string> names;
    std::string headers;
    for (const auto& s : kSections) {
        names.emplace_back(s.name);
        headers += (headers.empty() ? "" : ", ") + sectionHeader(s.name, s.form);
    }
    for (const auto& [key, where] : top.keysInOrder()) {
        const toml::node& n = *root.get(key);
        const auto section = std::find_if(kSections.begin(), kSections.end(),
                                          [&k = key](const Section& s) { return s.name == k; });
        if (section == kSections.end()) {
            const auto best = nearMiss(key, names);
            std::string hint;
            if (best) {
                const auto match = std::find_if(kSections.begin(), kSections.end(),
                                                [&](const Section& s) { return s.name == *best; });
                hint = fmt::format(" (did you mean {}?)", sectionHeader(match->name, match->form));
            }
            if (n.is_table() || n.is_array_of_tables())
                scene.fail(where, fmt::format("unknown table {}{}",
                                              sectionHeader(printable(key), n.is_table() ? SectionForm::Table
                                                                                          : SectionForm::ArrayOfTables),
                                              hint));
            scene.fail(where, fmt::format("unknown top-level key {}{}; a scene holds only the tables {}", quoteKey(key),
                                          hint, headers));
        }
        const std::string header = sectionHeader(section->name, section->form);
        if (section->form == SectionForm::Table && !n.is_table())
            scene.fail(where, fmt::format("{}: expected one table {}, found {}", key, header, describeType(n)));
        if (section->form == SectionForm::ArrayOfTables) {
            const auto* array = n.as_array();
            if (!array)
                scene.fail(where, fmt::format("{}: expected {} tables (an array of tables), found {}", key, header,
                                              describeType(n)));
            for (size_t i = 0; i < array->size(); ++i)
                if (!array->get(i)->is_table())
                    scene.fail(top.whereOf(*array->get(i)),
                               fmt::format("{}[{}]: expected a table, found {}", key, i, describeType(*array->get(i))));
        }
    }
}

// Calls `parse(reader, index)` for each table of an array-of-tables section.
template <typename Parse>
void forEachTable(const TomlFile& scene, const toml::table& root, std::string_view name, Parse&& parse) {
    const auto* array = root.get_as<toml::array>(name);
    if (!array) return;
    const SourceLocation fallback = locationOf(array->source(), SourceLocation{1, 1});
    for (size_t i = 0; i < array->size(); ++i)
        parse(TableReader(scene, *array->get(i)->as_table(), sectionHeader(name, SectionForm::ArrayOfTables),
                          fallback),
              i);
}

}  // namespace

SceneDescription parseSceneText(std::string_view text, const std::string& pathForMessages, const std::string& baseDir,
                                bool anyPath) {
    const TomlFile scene(pathForMessages, baseDir, anyPath);
    toml::table root;
    if (text.size() > size_t(kMaxSceneFileBytes))
        scene.fail(SourceLocation{1, 1}, fmt::format("a scene file may hold at most {}, this text holds {}",
                                                     humanBytes(double(kMaxSceneFileBytes)), humanBytes(double(text.size()))));
    if (const auto deep = findExcessiveNesting(text, kMaxSceneNesting))
        scene.fail(*deep, fmt::format("keys, tables and arrays nest more than {} levels deep here", kMaxSceneNesting));
    try {
        root = toml::parse(text, std::string_view(pathForMessages));
    } catch (const toml::parse_error& e) {
        scene.fail(locationOf(e.source(), SourceLocation{1, 1}),
                   "invalid TOML: " + printable(e.description(), std::string::npos));
    }
    checkSections(scene, root);

    SceneDescription description;
    description.path = pathForMessages;
    if (const auto* camera = root.get_as<toml::table>("camera"))
        description.camera = parseCamera(TableReader(scene, *camera, "[camera]", SourceLocation{1, 1}));

    MaterialIndex materials;
    forEachTable(scene, root, "material", [&](const TableReader& t, size_t) {
        MaterialDescription m = parseMaterial(scene, t, description.warnings);
        const auto [first, inserted] = materials.emplace(m.name, t.valueWhere("name"));
        if (!inserted)
            t.fail(t.valueWhere("name"), fmt::format("name: material {} is already defined at line {}",
                                                     quoteString(m.name), first->second.line));
        description.materials.push_back(std::move(m));
    });
    forEachTable(scene, root, "object", [&](const TableReader& t, size_t i) {
        description.objects.push_back(parseObject(scene, t, i, materials));
    });
    forEachTable(scene, root, "light",
                 [&](const TableReader& t, size_t) { description.lights.push_back(parseLight(t)); });
    if (const auto* sky = root.get_as<toml::table>("sky"))
        description.sky = parseSky(scene, TableReader(scene, *sky, "[sky]", SourceLocation{1, 1}));
    if (const auto* render = root.get_as<toml::table>("render"))
        description.render = parseRender(scene, TableReader(scene, *render, "[render]", SourceLocation{1, 1}));

    const auto& objects = description.objects;
    const bool hasTerrain = std::any_of(objects.begin(), objects.end(),
                                        [](const ObjectDescription& o) { return o.kind == ObjectKind::HeightField; });
    if (objects.empty())
        description.warnings.push_back(pathForMessages + ": the scene has no [[object]]: the picture shows only the sky");
    for (const auto& o : objects)
        if (o.kind == ObjectKind::Water && !hasTerrain)
            scene.fail(o.where, "a water object needs a heightfield object in the scene (it is clipped to the "
                                "terrain's footprint)");
    return description;
}

SceneDescription loadSceneFile(const std::string& path, bool anyPath) {
    const std::string text = readTextFile(path, "a scene file", kMaxSceneFileBytes);
    return parseSceneText(text, path, std::filesystem::path(path).parent_path().string(), anyPath);
}

}  // namespace terracast
