// light.cpp — point, spot and directional lights (light.hpp).
#include "vlf/scene/light.hpp"

#include <algorithm>

namespace vlf {

const char* light_type_name(LightType type) {
    switch (type) {
        case LightType::Point:
            return "point";
        case LightType::Spot:
            return "spot";
        case LightType::Directional:
            return "directional";
    }
    return "?";
}

Rgb Light::intensity_towards(const Vec3& w) const {
    return intensity * falloff(w);
}

double Light::falloff(const Vec3& w) const {
    if (type == LightType::Point) return 1.0;
    if (type != LightType::Spot) return 0.0;
    const double c = glm::dot(w, direction);
    if (c >= cos_inner) return 1.0;
    if (c <= cos_outer) return 0.0;
    const double t = (c - cos_outer) / (cos_inner - cos_outer);
    return t * t * (3.0 - 2.0 * t);  // smoothstep
}

double Light::solid_angle() const {
    if (type == LightType::Point) return 4.0 * kPi;
    if (type != LightType::Spot) return 0.0;
    // The smoothstep integrates to one half over its interval of cos theta.
    return 2.0 * kPi * ((1.0 - cos_inner) + 0.5 * (cos_inner - cos_outer));
}

Rgb Light::power() const {
    return intensity * solid_angle();
}

bool Light::emits() const {
    const Rgb& v = type == LightType::Directional ? irradiance : intensity;
    return v.x > 0 || v.y > 0 || v.z > 0;
}

}  // namespace vlf
