#include "vlf/render/pathtrace.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vlf/core/parallel.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/render/glass_vertex.hpp"
#include "vlf/render/light_tracer.hpp"
#include "vlf/scene/specular_turn.hpp"

namespace vlf {

namespace {

uint64_t splitmix64(uint64_t& x) {
    uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

double mean(const Rgb& c) {
    return (c.x + c.y + c.z) / 3.0;
}

// An ideal mirror face (rho_s > 0): is_specular() holds for glass too, which reflects by
// Fresnel instead and is no image-source mirror.
bool is_mirror(const Material& m) {
    return !m.dielectric && (m.specular.x > 0 || m.specular.y > 0 || m.specular.z > 0);
}

// Height of p above face f's plane (normalised units; > 0 on its front side).
double height(const Face& f, const Vec3& p) {
    return glm::dot(f.normal, p) - f.plane_offset;
}

// p reflected in face f's plane (an image source's position).
Vec3 mirror_point(const Face& f, const Vec3& p) {
    return p - 2.0 * height(f, p) * f.normal;
}

// Whether point p of face f's plane lies inside its convex polygon (counter-clockwise
// seen from the front), its rim included.
bool inside_face(const Face& f, const Vec3& p) {
    const size_t k = f.vertices.size();
    for (size_t i = 0; i < k; ++i) {
        const Vec3& a = f.vertices[i];
        const Vec3& b = f.vertices[(i + 1) % k];
        if (glm::dot(glm::cross(b - a, p - a), f.normal) < 0.0) return false;
    }
    return true;
}

// Whether some vertex of face a lies in front of face b's plane (by more than kSurfaceOffset): a
// necessary condition for light to go from one mirror to the other.
bool partly_in_front(const Face& a, const Face& b) {
    return std::any_of(a.vertices.begin(), a.vertices.end(),
                       [&](const Vec3& v) { return height(b, v) > kSurfaceOffset; });
}

}  // namespace

bool russian_roulette(Rgb& beta, Pcg32& rng) {
    const double q = std::min(0.95, std::max({beta.x, beta.y, beta.z}));
    if (!(q > 0.0) || rng.uniform() >= q) return false;
    beta /= q;
    return true;
}

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
    m_scale2 = scene.normalisation.scale * scene.normalisation.scale;
    // Image sources are planar mirrors' (a smooth one turns each ray about its own shading
    // normal: the light tracer has the delta lights' paths through it).
    for (const Face& f : scene.faces)
        if (is_mirror(scene.material_of(f)) && f.vertex_normals.empty()) m_mirrors.push_back(f.id);
    // Second-order image sources: the ordered pairs (a, b) where light can go from mirror
    // b to mirror a, b's front facing a's and a's facing b's. None for a convex mirror
    // (a tessellated sphere seen from outside); a concave one may give too many (see
    // kMaxMirrorPairs in the header): then none at all, rather than an arbitrary subset.
    if (kMaxMirrorOrder >= 2 && m_mirrors.size() <= size_t(kMaxMirrorFacesForPairs)) {
        for (int a : m_mirrors)
            for (int b : m_mirrors) {
                const Face &fa = scene.faces[a], &fb = scene.faces[b];
                if (a == b || !partly_in_front(fa, fb) || !partly_in_front(fb, fa)) continue;
                m_mirror_pairs.push_back(a);
                m_mirror_pairs.push_back(b);
            }
        if (m_mirror_pairs.size() > 2 * size_t(kMaxMirrorPairs)) {
            m_mirror_pairs.clear();
        } else {
            m_image_order = kMaxMirrorOrder;  // every chain of two mirrors is covered
        }
    }
}

bool PathTracer::segment_clear(const Vec3& o, const Vec3& y) const {
    const Vec3 to = y - o;
    const double dist = glm::length(to);
    if (!(dist > kSurfaceOffset)) return true;
    return !m_caster.occluded(o, to / dist, 0.0, dist - kSurfaceOffset);
}

PathTracer::DeltaSource PathTracer::delta_source(const Light& light, Pcg32& rng) const {
    DeltaSource s;
    s.light = &light;
    if (light.type != LightType::Directional) {
        s.position = m_scene.normalisation.to_normalised(light.position);
        return s;
    }
    s.parallel = true;
    s.travel = light.direction;
    s.irradiance = light.irradiance;
    const double half = 0.5 * light.angular_diameter_deg * kPi / 180.0;
    if (half > 0.0) {
        // A disc of uniform radiance L_s over the cone of half-angle `half`: E on a plane
        // facing its centre is L_s pi sin^2(half), the cone's solid angle Omega =
        // 2 pi (1 - cos half). One direction, uniform in solid angle (pdf 1/Omega),
        // carries L_s Omega = E 2 / (1 + cos half) on a plane facing it.
        const double cos_half = std::cos(half);
        const double c = 1.0 - rng.uniform() * (1.0 - cos_half);
        const double sn = std::sqrt(std::max(0.0, 1.0 - c * c)), phi = 2.0 * kPi * rng.uniform();
        Vec3 e1, e2;
        orthonormal_basis(light.direction, e1, e2);
        s.travel =
            glm::normalize(c * light.direction + sn * (std::cos(phi) * e1 + std::sin(phi) * e2));
        s.irradiance *= 2.0 / (1.0 + cos_half);
    }
    return s;
}

// Image sources (Allen & Berkley 1979; VLF §6.3 treats mirrors as planes the same way):
// light that reaches x after ideal reflections in the planar mirrors f_1, ..., f_k (f_1
// nearest x) comes from the source's image v = R_1 R_2 ... R_k p, R_i the reflection in
// f_i's plane (for a directional light, the direction of travel reflected likewise). The
// straight line from x towards v is the unfolded path: it must meet f_1's plane at m_1 on
// the front of f_1 (x in front, the line heading into the plane, the crossing before v)
// and inside its polygon; reflected there it must meet f_2 the same way, and so on; every
// leg x -> m_1 -> ... -> m_k -> p must be unoccluded. The path's length is |x - v| — so a
// point or spot light gives E = rho_s,1 ... rho_s,k I(w) cos_x / |x - v|^2, w the
// direction from p to m_k; a directional light gives rho_s,1 ... rho_s,k E cos_x.
Rgb PathTracer::delta_path(const DeltaSource& s, const Vec3& x, const Vec3& n, const int* chain,
                           int k) const {
    // Unfold: the image of the source, last mirror first.
    Vec3 w;                                                 // from x towards the image, unit
    double left = std::numeric_limits<double>::infinity();  // distance to the image
    if (s.parallel) {
        Vec3 t = s.travel;
        for (int i = k - 1; i >= 0; --i) {
            const Vec3& m = m_scene.faces[chain[i]].normal;
            t -= 2.0 * glm::dot(t, m) * m;
        }
        w = -t;
    } else {
        Vec3 v = s.position;
        for (int i = k - 1; i >= 0; --i) v = mirror_point(m_scene.faces[chain[i]], v);
        w = v - x;
        left = glm::length(w);
        if (!(left > 0.0)) return Rgb(0.0);
        w /= left;
    }
    const double length = left;
    const double cos_x = glm::dot(n, w);
    if (cos_x <= 0.0) return Rgb(0.0);  // arrives at the back of x's face
    // Follow it mirror by mirror.
    Rgb weight(1.0);
    Vec3 c = x, o = x + kSurfaceOffset * n;  // the path's current point, and it lifted off its face
    for (int i = 0; i < k; ++i) {
        const Face& f = m_scene.faces[chain[i]];
        const double h = height(f, c), toward = -glm::dot(w, f.normal);
        if (h <= kSurfaceOffset || toward <= 0.0) return Rgb(0.0);  // behind f or leaving its plane
        const double t = h / toward;
        if (t >= left) return Rgb(0.0);  // the source (image) lies before f's plane
        const Vec3 m = c + t * w;
        if (!inside_face(f, m) || !segment_clear(o, m)) return Rgb(0.0);
        weight *= m_scene.material_of(f).specular;
        left -= t;
        c = m;
        o = m + kSurfaceOffset * f.normal;
        w += 2.0 * toward * f.normal;  // reflected
    }
    if (s.parallel) {  // a shadow ray to infinity: escaping = lit
        if (m_caster.occluded(o, w, 0.0, std::numeric_limits<double>::infinity())) return Rgb(0.0);
        return weight * s.irradiance * cos_x;
    }
    if (!segment_clear(o, s.position)) return Rgb(0.0);
    const Vec3 from_light = c - s.position;  // the direction the light leaves in
    const double d = glm::length(from_light);
    if (!(d > 0.0)) return Rgb(0.0);
    // I / r_user^2 = I scale^2 / r_n^2 (Normalisation: r_n = r_user scale).
    return weight * s.light->intensity_towards(from_light / d) *
           (cos_x * m_scale2 / (length * length));
}

Rgb PathTracer::delta_irradiance(const Vec3& x, const Vec3& n, Pcg32& rng) const {
    Rgb E(0.0);
    for (const Light& light : m_scene.lights) {
        if (!light.emits()) continue;
        const DeltaSource s = delta_source(light, rng);
        E += delta_path(s, x, n, nullptr, 0);
        for (const int& f : m_mirrors) E += delta_path(s, x, n, &f, 1);
        for (size_t p = 0; p < m_mirror_pairs.size(); p += 2)
            E += delta_path(s, x, n, &m_mirror_pairs[p], 2);
    }
    return E;
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
    const Vec3 o = x + kSurfaceOffset * n;
    const Vec3 to = y - o;
    const double dist = glm::length(to);
    if (m_caster.occluded(o, to / dist, 0.0, dist - kSurfaceOffset)) return Rgb(0.0);
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
        beta *= glass_transmittance(m_scene, f, hit.t);  // the segment ran inside glass
        if (m.dielectric) {  // Fresnel-chosen reflection or refraction; no NEE here
            const GlassStep g =
                glass_scatter(m_scene, f, hit.point, dir, rng.uniform(), kSurfaceOffset);
            dir = g.dir;
            o = g.origin;
            bsdf_pdf = 0.0;  // a delta lobe: emission seen next counts in full
            // No Russian roulette at glass: its weight is 1, and a survival probability
            // capped at 0.95 would let paths caught by total internal reflection grow by
            // 1/0.95 a bounce into fireflies; they end at the next diffuse vertex, or at
            // kMaxPathVertices.
            continue;
        }
        if (m.is_emitter()) {
            double w = 1.0;
            // MIS against next-event estimation from the previous vertex (which had none
            // when no face emits: a scene lit by its delta lights alone).
            if (bsdf_pdf > 0.0 && m_light_area > 0.0) {
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
        if (pd > 0.0)
            L += beta * rho_d * (1.0 / kPi) *
                 (direct(x, n, p_diffuse, rng) + delta_irradiance(x, n, rng));
        if (rng.uniform() < p_diffuse) {  // Lambertian lobe, cosine-weighted
            const double r = std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
            Vec3 e1, e2;
            orthonormal_basis(n, e1, e2);
            const double cz = std::sqrt(std::max(0.0, 1.0 - r * r));
            dir = glm::normalize(r * std::cos(phi) * e1 + r * std::sin(phi) * e2 + cz * n);
            beta *= rho_d / p_diffuse;  // f cos / pdf = rho_d, over the lobe choice
            bsdf_pdf = p_diffuse * glm::dot(dir, n) / kPi;
            if (!(bsdf_pdf > 0.0)) break;
        } else {  // ideal mirror, about the shading normal of a smooth face
            dir = specular_turn(m_scene, f, x, dir).reflected;
            beta *= m.specular / (1.0 - p_diffuse);
            bsdf_pdf = 0.0;
        }
        o = x + kSurfaceOffset * n;
        if (vertex >= 3 && !russian_roulette(beta, rng)) break;
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

Image PathTracer::render(const PinholeCamera& camera, const PathTraceSettings& s) const {
    Image im;
    im.width = s.width;
    im.height = s.height;
    im.pixels.assign(size_t(s.width) * size_t(s.height), Rgb(0.0));
    parallel_for(0, s.height, [&](long y) {
        for (int x = 0; x < s.width; ++x)
            im.at(x, int(y)) = pixel(camera, x, int(y), s.width, s.spp, s.seed);
    });
    if (s.light_paths_per_sample > 0.0) {
        const LightTracer lights(m_scene, m_caster, m_image_order);
        if (lights.needed()) {
            const double n = s.light_paths_per_sample * double(s.width) * double(s.height) *
                             double(std::max(1, s.spp));
            lights.splat(camera, s.width, s.height, static_cast<long long>(std::ceil(n)), s.seed,
                         im);
        }
    }
    return im;
}

}  // namespace vlf
