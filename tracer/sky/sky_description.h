// The sky a scene or a terrain render asks for: plain data, every field with its documented default.
#pragma once

#include "tracer/core/source_location.h"
#include "tracer/sky/environment.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace terracast {

enum class SkyKind { Physical, Gradient, Flat, None, Image };

// The name of a sky model as options and scene files spell it, and back.
inline const char* skyKindName(SkyKind kind) {
    switch (kind) {
    case SkyKind::Physical: return "physical";
    case SkyKind::Gradient: return "gradient";
    case SkyKind::Flat: return "flat";
    case SkyKind::None: return "none";
    case SkyKind::Image: return "image";
    }
    return "physical";
}
// The sky models that need nothing more than their name (`render --sky`), in the order lists show them.
inline std::span<const SkyKind> skyKinds() {
    static constexpr SkyKind kAll[] = {SkyKind::Physical, SkyKind::Gradient, SkyKind::Flat, SkyKind::None};
    return kAll;
}
// Every sky model a scene file may name: the above and an environment image.
inline std::span<const SkyKind> sceneSkyKinds() {
    static constexpr SkyKind kAll[] = {SkyKind::Physical, SkyKind::Gradient, SkyKind::Flat, SkyKind::None,
                                       SkyKind::Image};
    return kAll;
}
inline std::optional<SkyKind> parseSkyKind(std::string_view name) {
    for (SkyKind k : skyKinds())
        if (name == skyKindName(k)) return k;
    return std::nullopt;
}

struct SkyDescription {
    SkyKind kind = SkyKind::Physical;
    glm::vec3 colour{0.6f, 0.7f, 0.9f};  // flat sky colour
    double haze = 1.0;                 // multiplies Mie scattering (physical sky)
    bool aerialPerspective = true;     // haze in front of distant terrain (physical sky)
    // Multiplies the sky's light on surfaces (all skies but none); unset = 1 for the physical sky (its true
    // radiance) and 0.15 for the others (their colours are not radiances).
    std::optional<float> ambient;
    int samples = 4;                   // sky-visibility rays per diffuse hit; 0 = no occlusion of sky light
    // Image: an equirectangular environment (environment.h), its path, turn and brightness.
    std::string imagePath;
    std::shared_ptr<const EnvironmentImage> image;  // loaded from imagePath (scene assets)
    double rotationDeg = 0.0;          // turns the image about the vertical, clockwise seen from above
    float intensity = 1.0f;            // multiplies the image's radiance
    SourceLocation where;
    SourceLocation imageWhere;         // of the `file` key

    // Physical and image skies are radiances: their light counts at full strength.
    float ambientScale() const {
        return ambient.value_or(kind == SkyKind::Physical || kind == SkyKind::Image ? 1.0f : 0.15f);
    }
};

}  // namespace terracast
