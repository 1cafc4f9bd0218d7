// small_emitters.cpp — the first shot of lamps smaller than a ray (small_emitters.hpp).
#include "vlf/transport/small_emitters.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/scene/glass.hpp"
#include "vlf/scene/specular_turn.hpp"

namespace vlf {

namespace {

// A mirror path ends after this many reflections; what is left (rho_s^16) is absorbed.
constexpr int kMaxMirrorBounces = 16;

}  // namespace

double radical_inverse(uint64_t k, uint64_t base) {
    double inv = 1.0 / double(base), f = inv, r = 0.0;
    for (; k > 0; k /= base, f *= inv) r += double(k % base) * f;
    return r;
}

Vec3 point_on(const Scene& scene, const Chart& c, double u, double v, double w, int* face) {
    double pick = u * c.area;
    if (face != nullptr) *face = c.faces[0];
    for (int fi : c.faces) {
        const Face& f = scene.faces[fi];
        if (pick > f.area && fi != c.faces.back()) {
            pick -= f.area;
            continue;
        }
        if (face != nullptr) *face = fi;
        // The face's fan of triangles, by area; then a uniform point in the triangle.
        double t = w * f.area;
        for (size_t k = 1; k + 1 < f.vertices.size(); ++k) {
            const Vec3 &a = f.vertices[0], &b = f.vertices[k], &d = f.vertices[k + 1];
            const double tri = 0.5 * glm::length(glm::cross(b - a, d - a));
            if (t > tri && k + 2 < f.vertices.size()) {
                t -= tri;
                continue;
            }
            const double su = std::sqrt(v), s = t / std::max(tri, 1e-300);
            return a + (b - a) * (su * (1 - std::min(1.0, s))) + (d - a) * (su * std::min(1.0, s));
        }
    }
    return scene.faces[c.faces[0]].vertices[0];
}

long nearest_texel(const Chart& c, const Vec3& p) {
    const Vec2 uv = c.texels.to_texel(p);
    const int i = std::clamp(int(std::floor(uv.x)), 0, c.texels.width - 1);
    const int j = std::clamp(int(std::floor(uv.y)), 0, c.texels.height - 1);
    long best = -1;
    double best_d = 1e300;
    for (int y = std::max(0, j - 1); y <= std::min(c.texels.height - 1, j + 1); ++y)
        for (int x = std::max(0, i - 1); x <= std::min(c.texels.width - 1, i + 1); ++x) {
            const size_t k = size_t(y) * c.texels.width + x;
            if (c.texel_area[k] <= 0) continue;
            const double d = std::hypot(x + 0.5 - uv.x, y + 0.5 - uv.y);
            if (d < best_d) best = long(k), best_d = d;
        }
    return best;
}

std::vector<int> small_emitter_charts(const Scene& scene, int resolution, double pixels) {
    const double pixel = 2.0 / resolution;
    std::vector<int> out;
    for (const Chart& c : scene.charts)
        if (scene.material_of(c).is_emitter() && c.area < pixels * pixel * pixel)
            out.push_back(c.id);
    return out;
}

void shoot_rays(const Scene& scene, const RayCaster& caster, const TextureMaps& tex, int chart,
                const Rgb& power, uint64_t k0, uint64_t k1, uint64_t K, ShotResult& out) {
    const Chart& c = scene.charts[chart];
    const Rgb each = power / double(K);
    for (uint64_t k = k0; k < k1; ++k) {
        // Hammersley: (k + 1/2) / K and base 2 for the direction (cosine-weighted, Malley),
        // bases 3, 5, 7 for the point.
        const double u1 = (double(k) + 0.5) / double(K), u2 = radical_inverse(k, 2);
        const Vec3 p =
            point_on(scene, c, radical_inverse(k, 3), radical_inverse(k, 5), radical_inverse(k, 7));
        const Face& emitter = scene.faces[c.faces[0]];
        const Vec3 n = emitter.normal;
        const Vec3 a = std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        const Vec3 t = glm::normalize(glm::cross(n, a)), b = glm::cross(n, t);
        const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
        Vec3 dir = t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(1.0 - u1);
        Vec3 from = p;
        Rgb carried = each;
        for (int bounce = 0;; ++bounce) {
            RayHit hit;
            // tmin: past the surface the ray leaves (the scene is in the unit ball).
            if (!caster.intersect(from, dir, 1e-7, 1e30, hit)) {
                out.escaped += carried;
                break;
            }
            const Face& f = scene.faces[hit.face];
            if (glm::dot(f.normal, dir) >= 0.0) {
                out.absorbed_back += carried;  // a one-sided face's back
                break;
            }
            const Material& m = scene.material_of(f);
            const Chart& hc = scene.chart_of(f);
            const long texel = m.is_diffuse() ? nearest_texel(hc, hit.point) : -1;
            // A textured chart's texel albedo (texel_albedo.hpp), else the material's.
            Rgb diffuse =
                carried * (texel >= 0 && !hc.texel_albedo.empty() ? hc.texel_albedo[size_t(texel)]
                                                                  : m.diffuse);
            if (texel >= 0)
                out.next[tex.begin(hc.id) + size_t(texel)] += diffuse;
            else
                diffuse = Rgb(0.0);  // no texel to hold it: absorbed below
            if (m.dielectric) {
                // Glass (docs/propagation.md §13): the ray goes on whole, reflected with
                // Fresnel's probability R, else refracted (a fixed hash of the ray and the
                // bounce decides, so the shot stays deterministic), attenuated inside.
                if (bounce >= kMaxMirrorBounces) {
                    out.absorbed += carried;
                    break;
                }
                const Rgb kept = carried * glass_transmittance(scene, f, hit.t);
                out.absorbed += carried - kept;
                carried = kept;
                const SpecularTurn turn = specular_turn(scene, f, hit.point, dir);
                const double u = radical_inverse(k * 17 + uint64_t(bounce) + 1, 11);
                dir = turn.refracts && u >= turn.R ? turn.refracted : turn.reflected;
                from = hit.point;
                continue;
            }
            const Rgb reflected = carried * m.specular;
            out.absorbed += carried - diffuse - reflected;
            if (!m.is_specular() || bounce >= kMaxMirrorBounces) {
                out.absorbed += m.is_specular() ? reflected : Rgb(0.0);
                break;
            }
            carried = reflected;
            dir = specular_turn(scene, f, hit.point, dir).reflected;
            from = hit.point;
        }
    }
}

}  // namespace vlf
