// lamp_caustics.cpp — the area lamps' direct light on smooth mirrors and glass, traced on
// (lamp_caustics.hpp, docs/propagation.md §14).
#include "vlf/transport/lamp_caustics.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/core/parallel.hpp"
#include "vlf/scene/glass.hpp"
#include "vlf/scene/sealed_areas.hpp"
#include "vlf/scene/specular_turn.hpp"
#include "vlf/transport/small_emitters.hpp"

namespace vlf {

namespace {

double largest(const Rgb& c) {
    return std::max(c.x, std::max(c.y, c.z));
}

// Unit vectors t, b completing unit n to a right-handed frame.
void frame(const Vec3& n, Vec3& t, Vec3& b) {
    const Vec3 a = std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    t = glm::normalize(glm::cross(n, a));
    b = glm::cross(n, t);
}

// What one ray of the shot does from its first hit on: the tree of its reflected and
// refracted branches, followed depth first.
struct Walk {
    const Scene& scene;
    const RayCaster& caster;
    const SmoothSurfaces& surfaces;
    const TextureMaps& tex;
    double floor;  // branches carrying less than this (any channel) are cut
    ShotResult& out;

    void go(const Vec3& from, const Vec3& dir, const Rgb& power, int bounce) const {
        if (largest(power) < floor) {
            out.lost.cut_beam += power;
            return;
        }
        RayHit hit;
        // tmin: past the surface the ray leaves (the scene is in the unit ball).
        if (!caster.intersect(from, dir, 1e-7, 1e30, hit)) {
            out.escaped += power;
            return;
        }
        arrive(hit, dir, power, bounce);
    }

    // `bounce` 0: the ray's first hit, whose segment first_ray has attenuated already.
    void arrive(const RayHit& hit, const Vec3& dir, Rgb power, int bounce) const {
        const Face& f = scene.faces[hit.face];
        if (glm::dot(f.normal, dir) >= 0.0) {
            out.absorbed_back += power;  // a one-sided face's back
            return;
        }
        const Material& m = scene.material_of(f);
        if (m.dielectric) {
            // Glass (docs/propagation.md §13): Beer-Lambert over the segment that ended on
            // an inner face, then Fresnel's split, both branches followed.
            const Rgb kept = bounce == 0 ? power : power * glass_transmittance(scene, f, hit.t);
            out.absorbed += power - kept;
            if (bounce >= LampCaustics::kMaxBounces) {
                out.absorbed += kept;
                return;
            }
            const SpecularTurn turn = specular_turn(scene, f, hit.point, dir);
            if (turn.refracts && turn.R < 1.0) {
                go(hit.point, turn.reflected, kept * turn.R, bounce + 1);
                go(hit.point, turn.refracted, kept * (1.0 - turn.R), bounce + 1);
            } else {
                go(hit.point, turn.reflected, kept, bounce + 1);  // total internal reflection
            }
            return;
        }
        // A smooth surface turns all it does not absorb (the field's rule, receive_step);
        // another face reflects rho_d of it into the texel under the hit.
        Rgb diffuse(0.0);
        if (surfaces.of_face[size_t(hit.face)] < 0 && m.is_diffuse()) {
            const Chart& c = scene.chart_of(f);
            const long texel = nearest_texel(c, hit.point);
            if (texel >= 0) {
                diffuse =
                    power * (c.texel_albedo.empty() ? m.diffuse : c.texel_albedo[size_t(texel)]);
                // A texel sealed behind another face has no open area to hold light: what it
                // reflects goes to the sealing face's black back (receive_step's rule).
                if (!c.texel_open.empty() && c.texel_open[size_t(texel)] < kSealedTexel) {
                    out.absorbed_back += diffuse;
                } else {
                    out.next[tex.begin(c.id) + size_t(texel)] += diffuse;
                    if (out.landed != nullptr) ++(*out.landed)[tex.begin(c.id) + size_t(texel)];
                }
            }
        }
        const Rgb reflected = m.is_specular() ? power * m.specular : Rgb(0.0);
        out.absorbed += power - diffuse - reflected;
        if (!m.is_specular()) return;
        if (bounce >= LampCaustics::kMaxBounces) {
            out.absorbed += reflected;
            return;
        }
        go(hit.point, specular_turn(scene, f, hit.point, dir).reflected, reflected, bounce + 1);
    }
};

}  // namespace

std::vector<uint8_t> caustic_faces(const Scene& scene, const SmoothSurfaces& surfaces) {
    std::vector<uint8_t> out(scene.faces.size(), 0);
    // Per object: the plane of its first flat specular face, and whether another leaves it.
    struct Plane {
        int first = -1;
        bool curved = false;
    };
    std::vector<Plane> planes(scene.objects.size());
    // Pure mirrors and glass only: a face that also reflects diffusely keeps the field's
    // exact clipping of the lamp's light on it.
    const auto flat_specular = [&](const Face& f) {
        const Material& m = scene.material_of(f);
        return surfaces.of_face[size_t(f.id)] < 0 && m.is_specular() && !m.is_emitter() &&
               !m.is_diffuse();
    };
    for (const Face& f : scene.faces) {
        if (!flat_specular(f)) continue;
        Plane& p = planes[size_t(f.object)];
        if (p.first < 0) {
            p.first = f.id;
            continue;
        }
        const Face& g = scene.faces[size_t(p.first)];
        // The scene is in the unit ball: 1e-6 is far below any facet and above the rounding
        // of single-precision mesh data.
        const bool same = std::abs(glm::dot(f.normal, g.normal)) > 1.0 - 1e-6 &&
                          std::abs(glm::dot(g.normal, f.vertices[0] - g.vertices[0])) < 1e-6;
        p.curved = p.curved || !same;
    }
    for (const Face& f : scene.faces)
        out[size_t(f.id)] = surfaces.of_face[size_t(f.id)] >= 0 ||
                            (flat_specular(f) && planes[size_t(f.object)].curved);
    return out;
}

LampCaustics::LampCaustics(const Scene& scene, const RayCaster& caster, const TextureMaps& tex,
                           const SmoothSurfaces& surfaces, const std::vector<uint8_t>& caustic,
                           const std::vector<int>& skip)
    : m_scene(scene), m_caster(caster), m_tex(tex), m_surfaces(surfaces), m_caustic(caustic) {
    // The objects with faces that take part, and their bounding balls (about the boxes of
    // those faces).
    std::vector<Vec3> lo(scene.objects.size(), Vec3(1e300)), hi(scene.objects.size(), Vec3(-1e300));
    std::vector<int> objects;
    for (const Face& f : scene.faces) {
        if (!caustic[size_t(f.id)]) continue;
        objects.push_back(f.object);
        for (const Vec3& v : f.vertices) {
            lo[size_t(f.object)] = glm::min(lo[size_t(f.object)], v);
            hi[size_t(f.object)] = glm::max(hi[size_t(f.object)], v);
        }
    }
    std::sort(objects.begin(), objects.end());
    objects.erase(std::unique(objects.begin(), objects.end()), objects.end());
    std::vector<double> radius(scene.objects.size(), 0.0);
    for (const Face& f : scene.faces)
        if (caustic[size_t(f.id)])
            for (const Vec3& v : f.vertices) {
                const Vec3 centre = 0.5 * (lo[size_t(f.object)] + hi[size_t(f.object)]);
                radius[size_t(f.object)] =
                    std::max(radius[size_t(f.object)], glm::length(v - centre));
            }
    for (const Chart& c : scene.charts) {
        if (!scene.material_of(c).is_emitter()) continue;
        if (std::find(skip.begin(), skip.end(), c.id) != skip.end()) continue;
        for (int object : objects)
            m_pairs.push_back({c.id, object, 0.5 * (lo[size_t(object)] + hi[size_t(object)]),
                               radius[size_t(object)]});
    }
}

bool LampCaustics::first_ray(uint64_t K, uint64_t k, Vec3& from, Vec3& dir, Rgb& power,
                             RayHit& hit) const {
    const Pair& p = m_pairs[size_t(k / K)];
    const uint64_t j = k % K;
    const Chart& lamp = m_scene.charts[size_t(p.chart)];
    // Hammersley: (j + 1/2) / K and base 2 for the direction in the cone, bases 3, 5, 7
    // for the point on the lamp.
    int face = 0;
    from = point_on(m_scene, lamp, radical_inverse(j, 3), radical_inverse(j, 5),
                    radical_inverse(j, 7), &face);
    const Vec3 to = p.centre - from;
    const double dist = glm::length(to);
    // Uniform over the cone of directions from `from` that can meet the bounding ball (the
    // whole sphere of directions if `from` is inside it; those below the lamp carry nothing).
    const double cos_max =
        dist > p.radius ? std::sqrt(1.0 - (p.radius / dist) * (p.radius / dist)) : -1.0;
    const Vec3 axis = dist > 0.0 ? to / dist : m_scene.faces[size_t(face)].normal;
    const double u1 = (double(j) + 0.5) / double(K), u2 = radical_inverse(j, 2);
    const double cos_t = 1.0 - u1 * (1.0 - cos_max);
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    Vec3 t, b;
    frame(axis, t, b);
    const double phi = 2.0 * kPi * u2;
    dir = glm::normalize(axis * cos_t + t * (sin_t * std::cos(phi)) + b * (sin_t * std::sin(phi)));
    const double cos_lamp = glm::dot(m_scene.faces[size_t(face)].normal, dir);
    if (cos_lamp <= 0.0) return false;
    if (!m_caster.intersect(from, dir, 1e-7, 1e30, hit)) return false;
    const Face& met = m_scene.faces[size_t(hit.face)];
    if (met.object != p.object || !m_caustic[size_t(hit.face)] || glm::dot(met.normal, dir) >= 0.0)
        return false;  // the field's light: not this object's
    const double solid_angle = 2.0 * kPi * (1.0 - cos_max);
    // L_e A cos(theta) Omega / K: the lamp's exitance integral, sampled uniformly; a lamp
    // inside absorbing glass loses exp(-sigma d) on the way, as the field's rays do
    // (attenuate_step) before they hand their power over.
    power = m_scene.material_of(lamp).emission * (lamp.area * cos_lamp * solid_angle / double(K)) *
            glass_transmittance(m_scene, met, hit.t);
    return true;
}

Rgb LampCaustics::estimate(uint64_t K, uint64_t k0, uint64_t k1) const {
    Rgb sum(0.0);
    Vec3 from, dir;
    Rgb power;
    RayHit hit;
    for (uint64_t k = k0; k < k1; ++k)
        if (first_ray(K, k, from, dir, power, hit)) sum += power;
    return sum;
}

void LampCaustics::shoot(uint64_t K, uint64_t k0, uint64_t k1, const Rgb& scale,
                         ShotResult& out) const {
    Vec3 from, dir;
    Rgb power;
    RayHit hit;
    for (uint64_t k = k0; k < k1; ++k) {
        if (!first_ray(K, k, from, dir, power, hit)) continue;
        power *= scale;
        const Walk walk{m_scene, m_caster, m_surfaces, m_tex, kMinWeight * largest(power), out};
        walk.arrive(hit, dir, power, 0);
    }
}

uint64_t LampCaustics::rays_for(double noise) const {
    constexpr int kPilotChunks = 4;
    // Per pair: the pilot's 2^16 rays and the shot's 2^18 to 2^24, fewer when there are so
    // many pairs that the shot would pass 2^25 rays in all (the pilot 2^20).
    const size_t pairs = m_pairs.size();
    if (pairs == 0) return 0;
    const auto share = [&](int total_log2, int each_log2) {
        return std::max<uint64_t>(
            uint64_t(1) << 12,
            std::min(uint64_t(1) << each_log2, (uint64_t(1) << total_log2) / uint64_t(pairs)));
    };
    const uint64_t kPilot = share(20, 16), kMax = share(25, 24);
    const uint64_t kMin = std::min(uint64_t(1) << 18, kMax);
    const TextureMaps& tex = m_tex;
    const uint64_t K = kPilot * pairs;
    std::vector<std::vector<Rgb>> lit(kPilotChunks);
    std::vector<std::vector<uint32_t>> landed(kPilotChunks);
    parallel_for(0, kPilotChunks, [&](long c) {
        lit[size_t(c)].assign(tex.texels(), Rgb(0.0));
        landed[size_t(c)].assign(tex.texels(), 0);
        ShotResult out{lit[size_t(c)]};
        out.landed = &landed[size_t(c)];
        shoot(kPilot, K * uint64_t(c) / kPilotChunks, K * uint64_t(c + 1) / kPilotChunks, Rgb(1.0),
              out);
    });
    double weighted = 0.0, weight = 0.0;
    for (size_t t = 0; t < tex.texels(); ++t) {
        double E = 0.0, n = 0.0;
        for (int c = 0; c < kPilotChunks; ++c) {
            E += luminance(lit[size_t(c)][t]);
            n += double(landed[size_t(c)][t]);
        }
        if (n <= 0.0 || E <= 0.0) continue;
        const double T = luminance(tex.next[t]) + E;
        weighted += T * (E / T) * (E / T) / n;
        weight += T;
    }
    const double factor = weight > 0.0 ? weighted / weight / (noise * noise) : 0.0;
    return uint64_t(std::clamp(std::ceil(double(kPilot) * factor), double(kMin), double(kMax)));
}

}  // namespace vlf
