// specular_turn.hpp — how a ray turns where it meets a mirror or glass, one rule for the
// whole engine: the lights' beams and the small lamps' rays of the propagation, the
// walkthrough's raytrace mode, and the path and light tracers of the reference.
//
// Reflection and refraction turn about the smooth shading normal (Scene::shading_normal: a
// tessellated sphere reflects and refracts as a sphere), except where that would send the
// ray the wrong way through the face's plane (near a silhouette, where the interpolated
// normal leans away from the facet's):
//  * met from behind its shading normal (d . n_s >= 0): both about the plane's normal;
//  * a reflection that would go behind the plane: about the plane's normal;
//  * a refraction that would stay in front of the plane (or not refract at all about n_s
//    while it would about the plane): about the plane's normal, with Fresnel's R of that
//    normal (docs/propagation.md section 13).
#pragma once

#include "vlf/core/fresnel.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct SpecularTurn {
    Vec3 reflected{0.0};       // unit
    Vec3 reflect_normal{0.0};  // the normal it was reflected about
    // Glass only (Material::dielectric): Fresnel's reflectance (1 under total internal
    // reflection) and, when R < 1, the refracted direction (unit) and its normal.
    double R = 1.0;
    bool refracts = false;
    Vec3 refracted{0.0};
    Vec3 refract_normal{0.0};
};

// Ray travelling along unit `d` meets the front of specular face f at x.
inline SpecularTurn specular_turn(const Scene& scene, const Face& f, const Vec3& x, const Vec3& d) {
    const Vec3& ng = f.normal;
    Vec3 ns = scene.shading_normal(f, x);
    if (glm::dot(d, ns) >= 0.0) ns = ng;
    SpecularTurn t;
    t.reflect_normal = ns;
    t.reflected = reflect(d, ns);
    if (glm::dot(t.reflected, ng) <= 0.0) {
        t.reflect_normal = ng;
        t.reflected = reflect(d, ng);
    }
    t.reflected = glm::normalize(t.reflected);
    const Material& m = scene.material_of(f);
    if (!m.dielectric) return t;
    const double eta = interface_eta(f.inner, m.ior);
    t.refract_normal = ns;
    t.R = fresnel_dielectric(-glm::dot(d, ns), eta);
    t.refracts = t.R < 1.0 && refract(d, ns, eta, t.refracted) && glm::dot(t.refracted, ng) < 0.0;
    if (t.R < 1.0 && !t.refracts) {
        t.refract_normal = ng;
        t.R = fresnel_dielectric(-glm::dot(d, ng), eta);
        t.refracts = t.R < 1.0 && refract(d, ng, eta, t.refracted);
    }
    if (!t.refracts) t.R = 1.0;
    if (t.refracts) t.refracted = glm::normalize(t.refracted);
    return t;
}

}  // namespace vlf
