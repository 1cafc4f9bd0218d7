#include "vlf/render/pathtrace.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vlf/core/rotation.hpp"

namespace vlf {

namespace {

// Offset of a ray origin from its surface along the normal, normalised units: well above
// Embree's single-precision error (~1e-7 at |x| ~ 1), well below any feature of the scenes
// (>= 1e-4).
constexpr double kEps = 1e-5;

uint64_t splitmix64(uint64_t& x) {
    uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

double mean(const Rgb& c) {
    return (c.x + c.y + c.z) / 3.0;
}

}  // namespace

Pcg32::Pcg32(uint64_t seed, uint64_t stream) {
    uint64_t s = seed ^ (stream * 0xd1342543de82ef95ULL);
    m_state = splitmix64(s);
    m_inc = (splitmix64(s) << 1) | 1u;
    next_u32();
}

uint32_t Pcg32::next_u32() {
    const uint64_t old = m_state;
    m_state = old * 6364136223846793005ULL + m_inc;
    const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
}

double Pcg32::uniform() {
    return next_u32() * (1.0 / 4294967296.0);
}

PathTracer::PathTracer(const Scene& scene, const RayCaster& caster)
    : m_scene(scene), m_caster(caster) {
    for (const Face& f : scene.faces) {
        if (!scene.material_of(f).is_emitter()) continue;
        for (size_t k = 1; k + 1 < f.vertices.size(); ++k) {  // convex: fan
            LightTriangle t{f.vertices[0], f.vertices[k], f.vertices[k + 1], f.id, 0.0};
            const double a = 0.5 * glm::length(glm::cross(t.b - t.a, t.c - t.a));
            if (!(a > 0.0)) continue;
            m_light_area += a;
            t.cdf = m_light_area;
            m_lights.push_back(t);
        }
    }
}

Rgb PathTracer::direct(const Vec3& x, const Vec3& n, double bsdf_pdf_scale, Pcg32& rng) const {
    if (m_lights.empty()) return Rgb(0.0);
    const double u = rng.uniform() * m_light_area;
    auto it = std::upper_bound(m_lights.begin(), m_lights.end(), u,
                               [](double v, const LightTriangle& t) { return v < t.cdf; });
    if (it == m_lights.end()) --it;
    const LightTriangle& t = *it;
    double s1 = rng.uniform(), s2 = rng.uniform();
    if (s1 + s2 > 1.0) {
        s1 = 1.0 - s1;
        s2 = 1.0 - s2;
    }
    const Vec3 y = t.a + s1 * (t.b - t.a) + s2 * (t.c - t.a);
    const Face& lf = m_scene.faces[t.face];
    const Vec3 w = y - x;
    const double d2 = glm::dot(w, w);
    if (!(d2 > 0.0)) return Rgb(0.0);
    const double d = std::sqrt(d2);
    const Vec3 wn = w / d;
    const double cos_x = glm::dot(n, wn), cos_y = -glm::dot(lf.normal, wn);
    if (cos_x <= 0.0 || cos_y <= 0.0) return Rgb(0.0);  // behind x, or the emitter's back
    const Vec3 o = x + kEps * n;
    const Vec3 to = y - o;
    const double dist = glm::length(to);
    if (m_caster.occluded(o, to / dist, 0.0, dist - kEps)) return Rgb(0.0);
    // MIS, power heuristic, against the Lambertian lobe that could have found y too.
    const double p_light = d2 / (cos_y * m_light_area);  // solid angle
    const double p_bsdf = bsdf_pdf_scale * cos_x / kPi;
    const double mis = p_light * p_light / (p_light * p_light + p_bsdf * p_bsdf);
    return m_scene.material_of(lf).emission * (cos_x / p_light * mis);
}

Rgb PathTracer::radiance(const Vec3& origin, const Vec3& dir_in, Pcg32& rng) const {
    Rgb L(0.0), beta(1.0);
    Vec3 o = origin, dir = dir_in;
    // Solid-angle pdf of the Lambertian bounce that chose `dir`, 0 for the camera ray and
    // after a mirror (then emission counts in full: no light sample could find it).
    double bsdf_pdf = 0.0;
    for (int vertex = 0; vertex < kMaxPathVertices; ++vertex) {
        RayHit hit;
        if (!m_caster.intersect(o, dir, 0.0, std::numeric_limits<double>::infinity(), hit))
            break;  // escaped
        const Face& f = m_scene.faces[hit.face];
        const Vec3& n = f.normal;
        const double cos_hit = -glm::dot(dir, n);
        if (cos_hit <= 0.0) break;  // back side: absorbs, emits nothing
        const Material& m = m_scene.material_of(f);
        if (m.is_emitter()) {
            double w = 1.0;
            if (bsdf_pdf > 0.0) {  // MIS against next-event estimation from the previous vertex
                const double d2 = hit.t * hit.t * glm::dot(dir, dir);
                const double p_light = d2 / (cos_hit * m_light_area);
                w = bsdf_pdf * bsdf_pdf / (bsdf_pdf * bsdf_pdf + p_light * p_light);
            }
            L += beta * m.emission * w;
        }
        const Vec3& x = hit.point;
        const Rgb rho_d = m.is_diffuse() ? m_scene.albedo_at(f, x) : Rgb(0.0);  // textured too
        const double pd = std::max(0.0, mean(rho_d)), ps = std::max(0.0, mean(m.specular));
        if (pd + ps <= 0.0) break;
        const double p_diffuse = pd / (pd + ps);  // probability of the Lambertian lobe
        if (pd > 0.0) L += beta * rho_d * (1.0 / kPi) * direct(x, n, p_diffuse, rng);
        if (rng.uniform() < p_diffuse) {  // Lambertian lobe, cosine-weighted
            const double r = std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
            Vec3 e1, e2;
            orthonormal_basis(n, e1, e2);
            const double cz = std::sqrt(std::max(0.0, 1.0 - r * r));
            dir = glm::normalize(r * std::cos(phi) * e1 + r * std::sin(phi) * e2 + cz * n);
            beta *= rho_d / p_diffuse;  // f cos / pdf = rho_d, over the lobe choice
            bsdf_pdf = p_diffuse * glm::dot(dir, n) / kPi;
            if (!(bsdf_pdf > 0.0)) break;
        } else {  // ideal mirror
            dir = dir - 2.0 * glm::dot(dir, n) * n;
            beta *= m.specular / (1.0 - p_diffuse);
            bsdf_pdf = 0.0;
        }
        o = x + kEps * n;
        if (vertex >= 3) {  // Russian roulette
            const double q = std::min(0.95, std::max({beta.x, beta.y, beta.z}));
            if (!(q > 0.0) || rng.uniform() >= q) break;
            beta /= q;
        }
    }
    return L;
}

Rgb PathTracer::pixel(const PinholeCamera& camera, int x, int y, int width, int spp,
                      uint64_t seed) const {
    Pcg32 rng(seed, uint64_t(y) * uint64_t(width) + uint64_t(x));
    const int n = std::max(1, static_cast<int>(std::floor(std::sqrt(double(spp)))));
    const int strat = std::min(spp, n * n);
    Rgb sum(0.0);
    for (int s = 0; s < spp; ++s) {
        double sx, sy;
        if (s < strat) {
            sx = ((s % n) + rng.uniform()) / n;
            sy = ((s / n) + rng.uniform()) / n;
        } else {
            sx = rng.uniform();
            sy = rng.uniform();
        }
        sum += radiance(camera.origin(), camera.direction(x + sx, y + sy), rng);
    }
    return sum / double(std::max(1, spp));
}

}  // namespace vlf
