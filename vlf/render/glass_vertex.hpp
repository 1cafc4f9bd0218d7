// glass_vertex.hpp — a Monte-Carlo path's vertex on smooth glass (scene.hpp
// Material::dielectric), shared by the path tracer (pathtrace.hpp) and the light tracer
// (light_tracer.hpp): reflection or refraction chosen with the exact unpolarised Fresnel
// reflectance as probability (core/fresnel.hpp; pbrt-v4 §9.5 "specular BSDF sampling" does
// the same), and the Beer-Lambert attenuation of a segment that ran inside the glass.
//
// The raycaster resolves a face and its twin, so a ray always meets the face whose front
// looks at it: an outer face when it enters glass, an inner face (Face::inner) when it
// leaves. Normalised coordinates; absorption is per *user* unit of length.
#pragma once

#include <cmath>

#include "vlf/core/fresnel.hpp"
#include "vlf/core/math.hpp"
#include "vlf/scene/glass.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/scene/specular_turn.hpp"

namespace vlf {

struct GlassStep {
    Vec3 dir{0.0};     // the new travel direction, unit
    Vec3 origin{0.0};  // the new ray's origin: x lifted off the face to the side it goes to
    Vec3 normal{0.0};  // the normal it turned about: the shading normal, or the face's
    bool refracted = false;
};

// At x on dielectric face f (the ray travelling `travel`, unit, towards its front): reflect
// with probability F = fresnel_dielectric(cos_i, eta), else refract (eta = n_front / n_back,
// interface_eta). Total internal reflection has F = 1. The path's weight is unchanged
// either way: F / F and (1 - F) / (1 - F) — the estimator stays unbiased and no light is
// lost at the interface (pbrt-v4 §9.5.2, the lobe chosen by F).
// Both turn by the engine's one rule (scene/specular_turn.hpp): about the smooth shading
// normal, or the face's where that would cross its plane the wrong way.
// The (n_t / n_i)^2 radiance scaling of refraction (Veach §5.2) is left out: it cancels on
// every path whose two ends (camera or light, and the surfaces they see) lie outside glass,
// which is every path of a scene whose diffuse faces are all in air.
// `u` is uniform in [0, 1); `eps` the origin offset (normalised units).
inline GlassStep glass_scatter(const Scene& scene, const Face& f, const Vec3& x, const Vec3& travel,
                               double u, double eps) {
    GlassStep s;
    const SpecularTurn turn = specular_turn(scene, f, x, travel);
    if (turn.refracts && u >= turn.R) {
        s.refracted = true;
        s.dir = turn.refracted;
        s.normal = turn.refract_normal;
        s.origin = x - eps * f.normal;  // behind the face: into the glass, or out of it
        return s;
    }
    s.dir = turn.reflected;
    s.normal = turn.reflect_normal;
    s.origin = x + eps * f.normal;
    return s;
}

// The factor a *particle* (importance, light_tracer.hpp) takes at a vertex scattered about
// shading normal ns instead of the face's ng (Veach §5.3.2, eq. 5.18; pbrt-v3 §16.1
// "CorrectShadingNormal"): |w_o.ns| |w_i.ng| / (|w_o.ng| |w_i.ns|), w_o towards where it came
// from, w_i where it goes. Without it a smooth-shaded surface would not carry the power the
// eye's paths see through it. 1 when ns is ng.
inline double shading_normal_correction(const Vec3& from, const Vec3& to, const Vec3& ns,
                                        const Vec3& ng) {
    const double den = std::abs(glm::dot(from, ng)) * std::abs(glm::dot(to, ns));
    if (!(den > 0.0)) return 0.0;
    return std::abs(glm::dot(from, ns)) * std::abs(glm::dot(to, ng)) / den;
}

}  // namespace vlf
