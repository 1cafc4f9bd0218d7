// light.hpp — lights without area (issue 14): point, spot and directional lights, the
// scene file's top-level "lights" array (docs/scenes.md "Lights").
//
// Units are the scene's (DESIGN §5): a point or spot light's intensity is in W sr^-1, its
// power in W; a directional light's irradiance is in W per square scene unit on a plane
// facing it. They are delta lights: nothing sees them directly, they light surfaces.
// Propagation sends their light into the scene in cycle 1 by beam tracing
// (transport/light_beams.hpp); the path tracer reaches them by next-event estimation.
#pragma once

#include <string>

#include "vlf/core/math.hpp"

namespace vlf {

enum class LightType { Point, Spot, Directional };

const char* light_type_name(LightType type);

struct Light {
    std::string name;  // "name" or "light#<index>"
    LightType type = LightType::Point;
    Vec3 position{0.0};        // point, spot: user units
    Vec3 direction{0, -1, 0};  // spot: the axis; directional: the way the light travels (unit)
    Rgb intensity{0.0};        // point, spot: W sr^-1 (a spot's on its axis)
    // Spot: full intensity within inner, none beyond outer, a smoothstep in cos theta
    // between (the cosines of the half-angles).
    double cos_inner = 1.0, cos_outer = 1.0;
    Rgb irradiance{0.0};                // directional: W per square unit, on a plane facing it
    double angular_diameter_deg = 0.0;  // directional: the source's disc (the sun: 0.53)

    // Point, spot: the intensity towards unit direction w (from the light), and its ratio
    // to `intensity` (the spot's falloff; 1 for a point light).
    Rgb intensity_towards(const Vec3& w) const;
    double falloff(const Vec3& w) const;
    // Point, spot: the emitted power, W (the integral of the intensity over the sphere).
    Rgb power() const;
    // Point, spot: the solid angle its falloff integrates to, power = intensity x this
    // (4 pi; a spot's 2 pi [(1 - cos_inner) + (cos_inner - cos_outer) / 2]).
    double solid_angle() const;
    bool emits() const;
};

}  // namespace vlf
