// render.cpp — the walkthrough renderers (VLF §6; DESIGN §7): primary visibility by ray
// casting, then a lookup in the bake per mode, or the path-traced reference.
#include "vlf/render/render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/field/lightmap.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/render/pathtrace.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/smooth_groups.hpp"
#include "vlf/scene/specular_turn.hpp"

namespace vlf {

namespace {

// raytrace: a Fresnel split (glass) follows a branch only while its throughput, the product
// of the R, 1 - R, mirror reflectances and absorption on the way from the eye, is at least
// this in some channel. At glass's R = 0.04 that keeps the paths of up to two internal
// reflections (weight ~1.5e-3) and drops the third (~6e-5): the slab test's T is the
// series (1 - R)^2 (1 + R^2) to within R^4.
constexpr double kMinBranchWeight = 1e-4;

double max_channel(const Rgb& c) {
    return std::max({c.x, c.y, c.z});
}

}  // namespace

std::string to_string(RenderMode m) {
    switch (m) {
        case RenderMode::Rays:
            return "rays";
        case RenderMode::Texture:
            return "texture";
        case RenderMode::Raytrace:
            return "raytrace";
        case RenderMode::Pathtrace:
            return "pathtrace";
    }
    return "?";
}

RenderMode render_mode_from_string(const std::string& s) {
    if (s == "rays") return RenderMode::Rays;
    if (s == "texture") return RenderMode::Texture;
    if (s == "raytrace") return RenderMode::Raytrace;
    if (s == "pathtrace") return RenderMode::Pathtrace;
    throw ParameterError("--mode: unknown mode '" + s +
                         "' (expected rays, texture, raytrace or pathtrace)");
}

struct Renderer::Impl {
    const Bake& bake;
    const Scene& scene;
    RayCaster caster;
    PathTracer tracer;
    std::vector<Mat3> rotation;     // per PSF direction: R with R * omega_d = +z
    std::vector<char> stored_rays;  // per face: the bake holds L_T rays of it (or its surface)
    SmoothGroups smooth;            // the smooth mirror and glass surfaces
    int N = 0;

    // What the lookup of x on face `face` reads in PSF d (from_rays): the travel direction
    // (the face's front sense of omega_d), the face's plane in the PSF and, for a face of a
    // smooth surface, its group.
    struct Probe {
        const Face& face;
        Vec3 travel;
        PlaneInPsf plane;
        int group;
    };

    explicit Impl(const Bake& b)
        : bake(b), scene(b.scene), caster(b.scene), tracer(b.scene, caster) {
        const int l = bake.directions.size();
        if (bake.rays.directions != 0 && bake.rays.directions != l)
            throw Error("bake: ray images hold " + std::to_string(bake.rays.directions) +
                        " directions, the direction set " + std::to_string(l));
        if (bake.texel_offset.size() != scene.charts.size() + 1 ||
            bake.lightmap_radiance.size() != bake.texel_offset.back())
            throw Error("bake: light maps do not match the scene's texel grids");
        rotation.resize(l);
        for (int d = 0; d < l; ++d) rotation[d] = rotation_to_z(bake.directions.direction(d));
        N = bake.rays.resolution;
        stored_rays.assign(scene.faces.size(), 0);
        for (int32_t f : bake.rays.face)
            if (f >= 0 && size_t(f) < stored_rays.size()) stored_rays[f] = 1;
        smooth = group_smooth_specular_faces(scene);
        for (const std::vector<int>& group : smooth.faces) {
            bool any = false;
            for (int f : group) any = any || stored_rays[size_t(f)];
            for (int f : group) stored_rays[size_t(f)] = any;
        }
    }

    // P^T of face f at x, bilinear on its chart's grid (VLF §6.2/§6.3).
    // A textured chart shows its texture at full resolution: the reflected part
    // (irradiance x texel albedo) times the albedo at x over the texels' albedo, looked up
    // the same way (issue 12).
    Rgb lightmap(const Face& f, const Vec3& x) const {
        if (bake.vertex_light.has(f.id))  // final_gather.hpp: light gathered at its vertices
            return scene.material_of(f).emission +
                   scene.albedo_at(f, x) * bake.vertex_light.at(f, x);
        const Chart& c = scene.chart_of(f);
        const Rgb L =
            sample_lightmap(c, bake.lightmap_radiance.data() + bake.texel_offset[f.chart], x);
        if (c.texel_albedo.empty()) return L;
        const Material& m = scene.material_of(f);
        const Rgb texel_rho = sample_lightmap(c, c.texel_albedo.data(), x);
        const Rgb rho = scene.albedo_at(f, x);
        Rgb out = m.emission;
        for (int ch = 0; ch < 3; ++ch)
            out[ch] += texel_rho[ch] > 0 ? (L[ch] - m.emission[ch]) * rho[ch] / texel_rho[ch] : 0.0;
        return out;
    }

    // Diffuse contribution of a face: P^T where it reflects diffusely or emits (P^T
    // includes the emission), nothing for a pure mirror.
    Rgb diffuse_part(const Face& f, const Vec3& x) const {
        const Material& m = scene.material_of(f);
        return (m.is_diffuse() || m.is_emitter()) ? lightmap(f, x) : Rgb(0.0);
    }

    // VLF §6.3: diffuse from P^T, specular faces by recursive ray tracing up to max_depth
    // specular events. A mirror: its reflectance times what the reflected ray sees
    // (iterative). Glass (Material::dielectric): the Fresnel split, R times the reflected
    // ray's radiance plus (1 - R) times the refracted ray's (core/fresnel.hpp; R = 1 on total
    // internal reflection), each branch followed while its throughput is at least
    // kMinBranchWeight; Beer-Lambert absorption on every segment inside glass. Reflection
    // and refraction turn by the engine's one rule (scene/specular_turn.hpp).
    Rgb raytrace(const Vec3& o, const Vec3& dir, int max_depth) const {
        return trace(o, glm::normalize(dir), 0, max_depth, Rgb(1.0), nullptr, o);
    }

    // `dir` unit; `depth` specular events so far; `weight` the throughput from the eye to o
    // (for the branch cut only); `medium` the glass the ray travels in, or null for air.
    // A ray leaves a surface from kSurfaceOffset off it (so as not to meet it again); the length it
    // travels through glass is taken from the surface point itself, `from`.
    Rgb trace(Vec3 o, Vec3 dir, int depth, int max_depth, Rgb weight, const Material* medium,
              Vec3 from) const {
        Rgb L(0.0), beta(1.0);
        for (;; ++depth) {
            RayHit hit;
            if (!caster.intersect(o, dir, 0.0, kInfinity, hit)) break;
            const Face& f = scene.faces[hit.face];
            if (glm::dot(dir, f.normal) >= 0.0) break;  // back side: black
            const Material& m = scene.material_of(f);
            // An inner face met from air: the ray started inside the glass (an eye in it).
            if (!medium && f.inner) medium = &m;
            if (medium && medium->is_absorbing()) {  // Beer-Lambert, per user unit of length
                const double length = glm::length(hit.point - from) / scene.normalisation.scale;
                beta *= glm::exp(-medium->absorption * length);
            }
            L += beta * diffuse_part(f, hit.point);
            if (!m.is_specular() || depth >= max_depth) break;
            const SpecularTurn turn = specular_turn(scene, f, hit.point, dir);
            const Vec3 above = hit.point + kSurfaceOffset * f.normal,
                       below = hit.point - kSurfaceOffset * f.normal;
            if (!m.dielectric) {
                beta *= m.specular;
                o = above;
                from = hit.point;
                dir = turn.reflected;
                continue;
            }
            const double R = turn.R;
            const Rgb through = weight * beta * (1.0 - R);
            if (turn.refracts && max_channel(through) >= kMinBranchWeight)
                L += beta * (1.0 - R) *
                     trace(below, turn.refracted, depth + 1, max_depth, through,
                           f.inner ? nullptr : &m, hit.point);
            beta *= R;
            if (max_channel(weight * beta) < kMinBranchWeight) break;
            o = above;
            from = hit.point;
            dir = turn.reflected;
        }
        return L;
    }

    // The light ray (d, i, j) holds of x's surface, leaving along the probe's travel
    // direction. A face's own sample; on a smooth mirror or glass surface, whose light the
    // field carries per surface and not per facet (docs/propagation.md §13), the sample of
    // whichever of the surface's faces showing their front to the travel direction the ray
    // meets nearest the probe face's plane, within two ray spacings of it along the ray (a
    // neighbouring facet, not another sheet of the surface behind or in front).
    bool sample(int d, int i, int j, const Probe& p, RgbF& out) const {
        if (p.group < 0) return bake.rays.lookup(d, i, j, p.face.id, out);
        uint64_t b = 0, e = 0;
        if (!bake.rays.samples(d, i, j, b, e)) return false;
        const double depth = p.plane.depth(i, j);
        double best = 4.0 / N;  // two ray spacings (PSF coordinates span [-1, 1])
        bool found = false;
        for (uint64_t k = b; k < e; ++k) {
            const int q = bake.rays.face[k];
            if (q < 0 || size_t(q) >= smooth.of_face.size() || smooth.of_face[size_t(q)] != p.group)
                continue;
            if (q == p.face.id) {  // the face's own ray: on its sheet by definition
                out = bake.rays.radiance[k];
                return true;
            }
            const Face& g = scene.faces[size_t(q)];
            if (glm::dot(p.travel, g.normal) <= 0.0) continue;
            const double gap = std::abs(PlaneInPsf(g, rotation[d], N).depth(i, j) - depth);
            if (!(gap <= best) || (found && gap == best)) continue;
            best = gap;
            out = bake.rays.radiance[k];
            found = true;
        }
        return found;
    }

    // L_T of the probe's surface in PSF d at continuous pixel-centre coordinates (cx, cy)
    // (pixel (i, j) has its centre at (i, j)): bilinear between the four nearest pixel
    // centres that hold a sample of it (renormalised), else inverse-square-distance weights
    // over the 8-neighbourhood of the pixel containing the point (VLF §6.1 "interpolated
    // from the 8-neighbourhood").
    bool interpolate(int d, double cx, double cy, const Probe& p, Rgb& out) const {
        const int i0 = static_cast<int>(std::floor(cx)), j0 = static_cast<int>(std::floor(cy));
        const double fx = cx - i0, fy = cy - j0;
        Rgb sum(0.0);
        double wsum = 0.0;
        RgbF v;
        for (int b = 0; b < 2; ++b)
            for (int a = 0; a < 2; ++a) {
                const double w = (a ? fx : 1.0 - fx) * (b ? fy : 1.0 - fy);
                if (w <= 1e-9 || !sample(d, i0 + a, j0 + b, p, v)) continue;
                sum += w * Rgb(v);
                wsum += w;
            }
        if (wsum > 0.0) {
            out = sum / wsum;
            return true;
        }
        const int ic = static_cast<int>(std::floor(cx + 0.5)),
                  jc = static_cast<int>(std::floor(cy + 0.5));
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                if (!sample(d, ic + di, jc + dj, p, v)) continue;
                const double ex = ic + di - cx, ey = jc + dj - cy;
                const double w = 1.0 / (1e-6 + ex * ex + ey * ey);
                sum += w * Rgb(v);
                wsum += w;
            }
        if (wsum > 0.0) {
            out = sum / wsum;
            return true;
        }
        return false;
    }

    // VLF §6.1: radiance leaving x on face f towards the eye (travel direction t, on f's
    // front side) from the three PSFs enclosing t. A face's L_T in PSF d is the radiance
    // leaving it along its front sense of omega_d, so only vertices whose travel direction
    // sense * omega_d lies on the front side are usable; weights are renormalised.
    bool from_rays(const Face& f, const Vec3& x, const Vec3& t, Rgb& out) const {
        if (N <= 0) return false;
        const EnclosingTriangle e = bake.directions.enclosing(t);
        Rgb sum(0.0);
        double wsum = 0.0;
        const int group = smooth.of_face[size_t(f.id)];
        for (int k = 0; k < 3; ++k) {
            const int d = e.index[k];
            if (e.weight[k] <= 0.0) continue;
            const Vec3 travel = double(e.sense[k]) * bake.directions.direction(d);
            if (glm::dot(travel, f.normal) <= 0.0) continue;
            const Probe p{f, travel, PlaneInPsf(f, rotation[d], N), group};
            const Vec3 q = rotation[d] * x;
            const double cx = (q.x + 1.0) * N * 0.5 - 0.5, cy = (q.y + 1.0) * N * 0.5 - 0.5;
            Rgb v;
            if (!interpolate(d, cx, cy, p, v)) continue;
            sum += e.weight[k] * v;
            wsum += e.weight[k];
        }
        if (wsum <= 0.0) return false;
        out = sum / wsum;
        return true;
    }

    // Rays (all faces from their stored rays where they have any, VLF §6.1) or Texture
    // (VLF §6.2: diffuse faces from P^T, specular ones "by 6.1 or 6.3": flat mirrors and
    // glass from their rays, smooth ones by backward ray tracing, §6.3). A curved mirror or
    // glass sends light into directions that vary faster than the direction set samples
    // them (a glass ball is a lens: a step of 3 degrees in the eye's direction moves what is
    // seen through it by a large part of the room), so its rays show it blurred; tracing it
    // reads the same bake, the P^T of the diffuse faces it shows (docs/rendering.md).
    Rgb lookup_shade(const Vec3& eye, const Vec3& dir, bool rays_everywhere, int max_depth) const {
        RayHit hit;
        if (!caster.intersect(eye, dir, 0.0, kInfinity, hit)) return Rgb(0.0);
        const Face& f = scene.faces[hit.face];
        if (glm::dot(dir, f.normal) >= 0.0) return Rgb(0.0);  // back side: black
        const Material& m = scene.material_of(f);
        const bool smooth_specular = smooth.of_face[size_t(f.id)] >= 0;
        const bool use_rays =
            stored_rays[f.id] && (rays_everywhere || (m.is_specular() && !smooth_specular));
        if (use_rays) {
            Rgb v;
            if (from_rays(f, hit.point, -dir, v)) return v;
        }
        // A smooth mirror or glass in texture mode, or no stored ray of this face near x in
        // any usable direction: a mirror is ray traced (its L_T would otherwise be missing),
        // a diffuse face shows P^T.
        if (m.is_specular()) return raytrace(eye, dir, max_depth);
        return lightmap(f, hit.point);
    }
};

Renderer::Renderer(const Bake& bake) : m_bake(bake), m_impl(std::make_unique<Impl>(bake)) {}

Renderer::~Renderer() = default;

Image Renderer::render(const Camera& camera, const RenderSettings& s) const {
    if (s.spp < 1 && s.mode == RenderMode::Pathtrace)
        throw ParameterError("--spp: must be at least 1");
    if (s.max_depth < 0) throw ParameterError("max_depth: must be >= 0");
    if (s.pixel_samples < 1) throw ParameterError("--pixel-samples: must be at least 1");
    const PinholeCamera cam(camera, m_bake.scene.normalisation, s.width, s.height);
    if (s.mode == RenderMode::Pathtrace)  // eye paths, and the light tracer's caustics
        return m_impl->tracer.render(cam,
                                     {s.width, s.height, s.spp, s.seed, s.light_paths_per_sample});
    Image im;
    im.width = s.width;
    im.height = s.height;
    im.pixels.assign(size_t(s.width) * s.height, Rgb(0.0));
    const Impl& r = *m_impl;
    const int k = s.pixel_samples;
    // Radiance along the primary ray through the image point (px, py).
    auto shade = [&](double px, double py) {
        const Vec3 dir = cam.direction(px, py);
        switch (s.mode) {
            case RenderMode::Rays:
                return r.lookup_shade(cam.origin(), dir, true, s.max_depth);
            case RenderMode::Texture:
                return r.lookup_shade(cam.origin(), dir, false, s.max_depth);
            case RenderMode::Raytrace:
                return r.raytrace(cam.origin(), dir, s.max_depth);
            case RenderMode::Pathtrace:
                break;
        }
        return Rgb(0.0);
    };
    parallel_for(0, s.height, [&](long y) {
        for (int x = 0; x < s.width; ++x) {
            Rgb& px = im.at(x, int(y));
            Rgb sum(0.0);
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) sum += shade(x + (i + 0.5) / k, y + (j + 0.5) / k);
            px = sum / double(k * k);
        }
    });
    return im;
}

std::vector<Rgb> Renderer::shade(const std::vector<PrimaryRay>& rays,
                                 const RenderSettings& s) const {
    if (s.spp < 1 && s.mode == RenderMode::Pathtrace)
        throw ParameterError("--spp: must be at least 1");
    if (s.max_depth < 0) throw ParameterError("max_depth: must be >= 0");
    const Impl& r = *m_impl;
    std::vector<Rgb> out(rays.size(), Rgb(0.0));
    parallel_for(0, long(rays.size()), [&](long i) {
        const PrimaryRay& ray = rays[size_t(i)];
        switch (s.mode) {
            case RenderMode::Rays:
                out[size_t(i)] = r.lookup_shade(ray.origin, ray.dir, true, s.max_depth);
                break;
            case RenderMode::Texture:
                out[size_t(i)] = r.lookup_shade(ray.origin, ray.dir, false, s.max_depth);
                break;
            case RenderMode::Raytrace:
                out[size_t(i)] = r.raytrace(ray.origin, ray.dir, s.max_depth);
                break;
            case RenderMode::Pathtrace: {
                Pcg32 rng(s.seed, uint64_t(i));
                Rgb sum(0.0);
                for (int k = 0; k < s.spp; ++k) sum += r.tracer.radiance(ray.origin, ray.dir, rng);
                out[size_t(i)] = sum / double(s.spp);
                break;
            }
        }
    });
    return out;
}

Rgb Renderer::gather_radiance(const Vec3& origin, const Vec3& dir, int max_depth,
                              bool* back) const {
    const Impl& r = *m_impl;
    RayHit hit;
    if (!r.caster.intersect(origin, dir, 0.0, kInfinity, hit)) return Rgb(0.0);
    const Face& f = m_bake.scene.faces[hit.face];
    if (glm::dot(dir, f.normal) >= 0.0) {
        if (back && f.twin < 0) *back = true;
        return Rgb(0.0);
    }
    const Material& m = m_bake.scene.material_of(f);
    // A diffuse face met first is what raytrace mode would read there: no second cast.
    Rgb L = m.is_specular() ? r.raytrace(origin, dir, max_depth) : r.diffuse_part(f, hit.point);
    if (m.is_emitter()) L = glm::max(L - m.emission, Rgb(0.0));  // the light samples' part
    return L;
}

const PathTracer& Renderer::path_tracer() const {
    return m_impl->tracer;
}

PixelMask Renderer::emitter_mask(const Camera& camera, int width, int height, int k) const {
    if (k < 1) throw ParameterError("emitter_mask: k must be at least 1");
    const PinholeCamera cam(camera, m_bake.scene.normalisation, width, height);
    const Scene& scene = m_bake.scene;
    PixelMask mask;
    mask.width = width;
    mask.height = height;
    mask.on.assign(size_t(width) * height, 0);
    parallel_for(0, height, [&](long y) {
        for (int x = 0; x < width; ++x) {
            bool seen = false;
            for (int j = 0; j < k && !seen; ++j)
                for (int i = 0; i < k && !seen; ++i) {
                    const Vec3 dir = cam.direction(x + (i + 0.5) / k, y + (j + 0.5) / k);
                    RayHit hit;
                    if (!m_impl->caster.intersect(cam.origin(), dir, 0.0, kInfinity, hit)) continue;
                    const Face& f = scene.faces[hit.face];
                    seen = glm::dot(dir, f.normal) < 0.0 && scene.material_of(f).is_emitter();
                }
            mask.on[size_t(y) * width + x] = seen ? 1 : 0;
        }
    });
    return mask;
}

double Renderer::back_face_fraction(const Camera& camera, int n) const {
    const PinholeCamera cam(camera, m_bake.scene.normalisation, n, n);
    long backs = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const Vec3 dir = cam.direction(x + 0.5, y + 0.5);
            RayHit hit;
            if (!m_impl->caster.intersect(cam.origin(), dir, 0.0, kInfinity, hit)) continue;
            const Face& f = m_bake.scene.faces[hit.face];
            if (glm::dot(dir, f.normal) >= 0.0 && f.twin < 0) ++backs;
        }
    return double(backs) / (double(n) * n);
}

}  // namespace vlf
