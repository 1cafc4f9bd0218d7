// light_tracer.cpp — particles from the delta lights, splatted at diffuse vertices
// (light_tracer.hpp; Veach's thesis §10.2).
#include "vlf/render/light_tracer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vlf/core/parallel.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/render/glass_vertex.hpp"
#include "vlf/render/pathtrace.hpp"

namespace vlf {

namespace {

// Batches traced together before their splats are added (in batch order) to the image:
// bounds the memory the splat lists hold.
constexpr long long kBatchesPerRound = 64;
// A stream family of its own, apart from the eye paths' (seed, pixel) streams.
constexpr uint64_t kLightStreamSalt = 0x4c69676874547261ULL;

double mean(const Rgb& c) {
    return (c.x + c.y + c.z) / 3.0;
}

bool is_mirror(const Material& m) {
    return !m.dielectric && (m.specular.x > 0 || m.specular.y > 0 || m.specular.z > 0);
}

// A particle's mirror bounce at x on face f, about the shading normal of a smooth face; its
// weight takes the shading-normal correction (glass_vertex.hpp).
Vec3 mirror_turn(const Scene& scene, const Face& f, const Vec3& x, const Vec3& dir, Rgb& beta) {
    const SpecularTurn t = specular_turn(scene, f, x, dir);
    beta *= shading_normal_correction(-dir, t.reflected, t.reflect_normal, f.normal);
    return t.reflected;
}

// A unit direction within angle acos(cos_max) of unit `axis`, uniform in solid angle
// (pdf 1 / (2 pi (1 - cos_max)); cos_max = -1 is the whole sphere).
Vec3 sample_cone(const Vec3& axis, double cos_max, double u1, double u2) {
    const double c = 1.0 - u1 * (1.0 - cos_max);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c)), phi = 2.0 * kPi * u2;
    Vec3 e1, e2;
    orthonormal_basis(axis, e1, e2);
    return glm::normalize(c * axis + s * (std::cos(phi) * e1 + std::sin(phi) * e2));
}

// The half-angle of a directional light's disc, radians (0: a parallel beam).
double disc_half_angle(const Light& l) {
    return 0.5 * l.angular_diameter_deg * kPi / 180.0;
}

// A directional light's radiance x solid angle over the irradiance E it gives a plane
// facing the disc's centre: E = L pi sin^2(half), Omega = 2 pi (1 - cos half), so
// L Omega = E 2 / (1 + cos half) (as PathTracer::delta_source). 1 for a parallel beam.
double disc_factor(const Light& l) {
    const double half = disc_half_angle(l);
    return half > 0.0 ? 2.0 / (1.0 + std::cos(half)) : 1.0;
}

}  // namespace

// The pinhole's frame, read back from PinholeCamera::direction (so the projection is the
// exact inverse of the rays the eye pass shoots), and the footprint of one pixel.
struct LightTracer::View {
    Vec3 eye{0.0}, forward{0, 0, 1}, right{1, 0, 0}, up{0, 1, 0};
    double tan_x = 1.0, tan_y = 1.0;  // half-width and half-height of the image at distance 1
    int width = 1, height = 1;
    // Importance normalisation: 1 / (area of one pixel on the image plane at distance 1).
    double inv_pixel_area = 1.0;
    double scale = 1.0;  // normalised length per user length

    View(const PinholeCamera& camera, int w, int h, double norm_scale)
        : width(w), height(h), scale(norm_scale) {
        eye = camera.origin();
        forward = camera.direction(0.5 * w, 0.5 * h);
        const Vec3 r = camera.direction(double(w), 0.5 * h);  // = normalize(f + tan_x right)
        const Vec3 u = camera.direction(0.5 * w, 0.0);        // = normalize(f + tan_y up)
        const double cr = glm::dot(r, forward), cu = glm::dot(u, forward);
        right = glm::normalize(r - cr * forward);
        up = glm::normalize(u - cu * forward);
        tan_x = glm::length(r - cr * forward) / cr;
        tan_y = glm::length(u - cu * forward) / cu;
        inv_pixel_area = double(w) * double(h) / (4.0 * tan_x * tan_y);
    }
};

LightTracer::LightTracer(const Scene& scene, const RayCaster& caster, int image_source_order)
    : m_scene(scene), m_caster(caster), m_image_order(image_source_order) {
    const double scale = scene.normalisation.scale;
    double total = 0.0;
    for (const Light& l : scene.lights) {
        double power = 0.0;
        if (l.emits()) {
            if (l.type == LightType::Directional) {
                // The flux through the disc the particles start on, user units.
                const double r_user = kBeamRadius / scale;
                power = mean(l.irradiance) * disc_factor(l) * kPi * r_user * r_user;
            } else {
                power = mean(l.power());
            }
        }
        if (!(power > 0.0) || !std::isfinite(power)) power = 0.0;
        m_power.push_back(power);
        total += power;
    }
    double c = 0.0;
    for (double p : m_power) {
        m_probability.push_back(total > 0.0 ? p / total : 0.0);
        c += m_probability.back();
        m_cdf.push_back(c);
    }
    int mirrors = 0;
    bool glass = false;  // or a smooth mirror: no image source goes through either
    for (const Face& f : scene.faces) {
        const Material& m = scene.material_of(f);
        glass = glass || m.dielectric || (is_mirror(m) && !f.vertex_normals.empty());
        if (is_mirror(m)) ++mirrors;
    }
    // A mirror chain longer than image_source_order >= 1 visits at least two faces.
    m_needed = total > 0.0 && (glass || mirrors >= 2);
}

int LightTracer::choose_light(double u) const {
    const auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), u);
    int i = it == m_cdf.end() ? int(m_cdf.size()) - 1 : int(it - m_cdf.begin());
    while (i > 0 && m_probability[size_t(i)] <= 0.0) --i;  // rounding at the end of the cdf
    return i;
}

void LightTracer::connect(const View& v, const Vec3& x, const Vec3& n, const Rgb& power_rho,
                          std::vector<Splat>& out) const {
    const Vec3 to_eye = v.eye - x;
    const double d = glm::length(to_eye);
    if (!(d > kSurfaceOffset)) return;
    const Vec3 w = to_eye / d;
    const double cos_x = glm::dot(n, w);
    if (cos_x <= 0.0) return;  // the eye is behind the face: it sees the back
    // The pixel the eye sees x in: invert direction(px, py) = normalize(f + a tan_x right +
    // b tan_y up), a = 2 px / width - 1, b = 1 - 2 py / height.
    const Vec3 look = -w;
    const double cos_cam = glm::dot(look, v.forward);
    if (cos_cam <= 0.0) return;
    const double a = glm::dot(look, v.right) / (cos_cam * v.tan_x);
    const double b = glm::dot(look, v.up) / (cos_cam * v.tan_y);
    const double px = 0.5 * (a + 1.0) * v.width, py = 0.5 * (1.0 - b) * v.height;
    if (!(px >= 0.0 && px < v.width && py >= 0.0 && py < v.height)) return;
    const int ix = std::min(v.width - 1, int(px)), iy = std::min(v.height - 1, int(py));
    if (m_caster.occluded(x + kSurfaceOffset * n, w, 0.0, d - 2.0 * kSurfaceOffset))
        return;  // glass blocks too
    // The pixel's value is (1 / A_pix) times the integral of L over its area on the image
    // plane at distance 1, whose element is dA_plane = dw / cos^3 (Veach §10.2's W_e =
    // 1 / (A_pix cos^4) times the cos of the camera's side); the solid angle x subtends is
    // dw = cos_x dA / d^2. A particle of power P at x stands for P f_r = P rho/pi of the
    // integral of L_o over area, so it adds P rho/pi cos_x / (d^2 cos^3 A_pix) — radiance,
    // with d in user units like the power's area.
    const double d_user = d / v.scale;
    const double g = cos_x * v.inv_pixel_area / (d_user * d_user * cos_cam * cos_cam * cos_cam);
    out.push_back({uint32_t(size_t(iy) * size_t(v.width) + size_t(ix)), power_rho * (g / kPi)});
}

void LightTracer::trace(const View& view, long long particles, Pcg32& rng,
                        std::vector<Splat>& out) const {
    const int li = choose_light(rng.uniform());
    const Light& light = m_scene.lights[size_t(li)];
    const double select = m_probability[size_t(li)];
    if (!(select > 0.0)) return;
    Vec3 o, dir;
    Rgb power(0.0);  // W, this particle's share of the light's power
    if (light.type == LightType::Directional) {
        const double half = disc_half_angle(light);
        dir = half > 0.0
                  ? sample_cone(light.direction, std::cos(half), rng.uniform(), rng.uniform())
                  : light.direction;
        // A point uniform on the disc of radius R across the beam, outside the unit ball.
        Vec3 e1, e2;
        orthonormal_basis(dir, e1, e2);
        const double r = kBeamRadius * std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
        o = -2.0 * kBeamRadius * dir + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
        const double r_user = kBeamRadius / m_scene.normalisation.scale;
        power = light.irradiance * (disc_factor(light) * kPi * r_user * r_user);
    } else {
        o = m_scene.normalisation.to_normalised(light.position);
        // Uniform over the sphere (a point light) or the spot's outer cone: weight I(w) / pdf.
        const double cos_max = light.type == LightType::Spot ? light.cos_outer : -1.0;
        dir = sample_cone(light.type == LightType::Spot ? light.direction : Vec3(0, 1, 0), cos_max,
                          rng.uniform(), rng.uniform());
        power = light.intensity_towards(dir) * (2.0 * kPi * (1.0 - cos_max));
    }
    power /= select * double(particles);
    Rgb beta(1.0);                               // throughput since the light
    bool through_glass = false, tagged = false;  // through glass or a smooth mirror
    int mirrors = 0;
    for (int vertex = 0; vertex < kMaxPathVertices; ++vertex) {
        RayHit hit;
        if (!m_caster.intersect(o, dir, 0.0, kInfinity, hit)) break;
        const Face& f = m_scene.faces[size_t(hit.face)];
        const Vec3& n = f.normal;
        if (glm::dot(dir, n) >= 0.0) break;  // the back of a face absorbs
        const Material& m = m_scene.material_of(f);
        beta *= glass_transmittance(m_scene, f, hit.t);
        if (m.dielectric) {
            const GlassStep g =
                glass_scatter(m_scene, f, hit.point, dir, rng.uniform(), kSurfaceOffset);
            beta *= shading_normal_correction(-dir, g.dir, g.normal, n);
            dir = g.dir;
            o = g.origin;
            through_glass = true;
            // No Russian roulette at glass: its weight is 1, and a survival probability
            // capped at 0.95 would let paths caught by total internal reflection grow by
            // 1/0.95 a bounce into fireflies; they end at the next diffuse vertex, or at
            // kMaxPathVertices.
            continue;
        }
        const Vec3& x = hit.point;
        const Rgb rho_d = m.is_diffuse() ? m_scene.albedo_at(f, x) : Rgb(0.0);
        const double pd = std::max(0.0, mean(rho_d)), ps = std::max(0.0, mean(m.specular));
        // The prefix ends at the first diffuse vertex: the eye tracer's when its chain is
        // mirrors only, at most image_source_order of them; the light tracer's otherwise.
        if (pd > 0.0 && !tagged) tagged = through_glass || mirrors > m_image_order;
        if (!tagged) {
            // Untagged: the diffuse part is the eye tracer's, with all that follows from
            // it; the mirror part goes on (its chain may yet need the light tracer).
            if (!(ps > 0.0)) break;
            beta *= m.specular;
            ++mirrors;
            through_glass = through_glass || !f.vertex_normals.empty();
            dir = mirror_turn(m_scene, f, x, dir, beta);
            o = x + kSurfaceOffset * n;
        } else {
            if (pd > 0.0) connect(view, x, n, power * beta * rho_d, out);
            if (pd + ps <= 0.0) break;
            const double p_diffuse = pd / (pd + ps);
            if (rng.uniform() < p_diffuse) {  // Lambertian, cosine-weighted: f cos / pdf = rho
                const double r = std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
                Vec3 e1, e2;
                orthonormal_basis(n, e1, e2);
                const double cz = std::sqrt(std::max(0.0, 1.0 - r * r));
                dir = glm::normalize(r * std::cos(phi) * e1 + r * std::sin(phi) * e2 + cz * n);
                beta *= rho_d / p_diffuse;
            } else {
                dir = mirror_turn(m_scene, f, x, dir, beta);
                beta *= m.specular / (1.0 - p_diffuse);
            }
            o = x + kSurfaceOffset * n;
        }
        if (vertex >= 3 && !russian_roulette(beta, rng)) break;
    }
}

void LightTracer::splat(const PinholeCamera& camera, int width, int height, long long particles,
                        uint64_t seed, Image& image) const {
    if (!m_needed || particles <= 0 || width < 1 || height < 1) return;
    const View view(camera, width, height, m_scene.normalisation.scale);
    const long long batches = (particles + kBatchParticles - 1) / kBatchParticles;
    std::vector<std::vector<Splat>> lists(size_t(std::min(batches, kBatchesPerRound)));
    for (long long first = 0; first < batches; first += kBatchesPerRound) {
        const long long count = std::min(kBatchesPerRound, batches - first);
        parallel_for(0, long(count), [&](long k) {
            const long long b = first + k;
            std::vector<Splat>& out = lists[size_t(k)];
            out.clear();
            Pcg32 rng(seed ^ kLightStreamSalt, uint64_t(b));
            const long long end = std::min(particles, (b + 1) * kBatchParticles);
            for (long long p = b * kBatchParticles; p < end; ++p) trace(view, particles, rng, out);
        });
        // The reduction, in batch order: the sums do not depend on the scheduling.
        for (long long k = 0; k < count; ++k)
            for (const Splat& s : lists[size_t(k)]) image.pixels[s.pixel] += s.value;
    }
}

}  // namespace vlf
