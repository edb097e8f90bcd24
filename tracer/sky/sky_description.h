// The sky a scene or a terrain render asks for: plain data, every field with its documented default.
#pragma once

#include "tracer/core/source_location.h"

#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <string_view>

namespace terracast {

enum class SkyKind { Physical, Gradient, Flat, None };

// The name of a sky model as options and scene files spell it, and back.
inline const char* skyKindName(SkyKind kind) {
    switch (kind) {
    case SkyKind::Physical: return "physical";
    case SkyKind::Gradient: return "gradient";
    case SkyKind::Flat: return "flat";
    case SkyKind::None: return "none";
    }
    return "physical";
}
// Every sky model, in the order lists and messages show them.
inline std::span<const SkyKind> skyKinds() {
    static constexpr SkyKind kAll[] = {SkyKind::Physical, SkyKind::Gradient, SkyKind::Flat, SkyKind::None};
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
    SourceLocation where;

    float ambientScale() const { return ambient.value_or(kind == SkyKind::Physical ? 1.0f : 0.15f); }
};

}  // namespace terracast
