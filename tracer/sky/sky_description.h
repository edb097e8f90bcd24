// The sky a scene or a terrain render asks for: plain data, every field with its documented default.
#pragma once

#include "tracer/core/source_location.h"

#include <glm/glm.hpp>

#include <optional>

namespace terracast {

enum class SkyKind { Physical, Gradient, Flat, None };

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
