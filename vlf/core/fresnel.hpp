// fresnel.hpp — smooth dielectric interfaces: Snell refraction and the exact unpolarised
// Fresnel reflectance (Born & Wolf §1.5; pbrt-v4 §9.3 writes the same equations), with
// total internal reflection. Shared by propagation, every render mode and the path tracer.
#pragma once

#include <algorithm>
#include <cmath>

#include "vlf/core/math.hpp"

namespace vlf {

// Reflectance of unpolarised light arriving at cos_i (> 0, the angle to the normal on the
// side it comes from) at an interface with eta = n_incident / n_transmitted: the mean of
// the s and p reflectances. 1 beyond the critical angle (total internal reflection).
inline double fresnel_dielectric(double cos_i, double eta) {
    cos_i = std::clamp(cos_i, 0.0, 1.0);
    const double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if (sin2_t >= 1.0) return 1.0;
    const double cos_t = std::sqrt(1.0 - sin2_t);
    // r_s = (n_i cos_i - n_t cos_t) / (n_i cos_i + n_t cos_t), divided through by n_t.
    const double rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const double rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

// The refracted travel direction of unit `travel` meeting a surface whose unit normal `n`
// faces the incoming light (dot(travel, n) < 0), eta = n_incident / n_transmitted (Snell:
// n_i sin_i = n_t sin_t). False on total internal reflection.
inline bool refract(const Vec3& travel, const Vec3& n, double eta, Vec3& out) {
    const double cos_i = -glm::dot(travel, n);
    const double sin2_t = eta * eta * std::max(0.0, 1.0 - cos_i * cos_i);
    if (sin2_t >= 1.0) return false;
    const double cos_t = std::sqrt(1.0 - sin2_t);
    out = glm::normalize(eta * travel + (eta * cos_i - cos_t) * n);
    return true;
}

// The mirror reflection of a travel direction about the unit normal n (either side).
inline Vec3 reflect(const Vec3& travel, const Vec3& n) {
    return travel - 2.0 * glm::dot(travel, n) * n;
}

// For light arriving on the front of face with normal n (front medium index n_front, back
// n_back): eta = n_front / n_back.
inline double interface_eta(bool inner, double ior) {
    return inner ? ior : 1.0 / ior;
}

}  // namespace vlf
