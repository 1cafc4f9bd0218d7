// light_beams.cpp — the first shot of delta lights by adaptive beam tracing (light_beams.hpp).
#include "vlf/transport/light_beams.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/core/rotation.hpp"
#include "vlf/scene/sealed_areas.hpp"
#include "vlf/scene/specular_turn.hpp"
#include "vlf/transport/small_emitters.hpp"

namespace vlf {

namespace {

// Root beams per side of a cube face (point, spot) and of a directional light's grid: at
// least these, and at least kRootsPerTexel per texel across (at the scene's radius from a
// point light), so that little of a texel's size falls between the root beams' rays
// unseen (a corner poking into a beam between its rays); at most kMaxRoots.
constexpr int kPointRoots = 16;
constexpr int kParallelRoots = 32;
constexpr int kMaxRoots = 2048;
constexpr double kRootsPerTexel = 1.0;
// A spot's beam splits while its falloff varies across it by more than this fraction.
// (relative to the larger of its value and kFalloffFloor: where the falloff nears zero, a
// small absolute variation).
constexpr double kFalloffVariation = 0.05;
constexpr double kFalloffFloor = 0.02;
// A directional light's root grid lies this far behind the scene's centre (outside the
// unit ball) and spans [-1, 1]^2 across it.
constexpr double kParallelBase = 2.0;
// A leaf beam's footprint is at most this many texels (and rim reaches) wide; a leaf
// across an edge at most kEdgeTexels.
constexpr double kFootprintTexels = 0.5;
constexpr double kEdgeTexels = 1.0 / 32.0;
// A beam that meets nothing splits until it is this many texels wide across the scene: a
// face's corner poking in between its rays is then at most a small part of a texel.
constexpr double kMissTexels = 0.125;
// A parallel light's shadow grid (LightBeams::Source::shadow): cells per side.
constexpr int kShadowGrid = 1024;

// The shadow grid's cell of a coordinate x in [-1, 1], clamped.
int shadow_cell(double x) {
    return std::clamp(int(std::floor((x + 1.0) * 0.5 * kShadowGrid)), 0, kShadowGrid - 1);
}
// Dim beams land coarse (power-aware splitting). A beam whose irradiance on the diffuse
// face it lands on (its power over its footprint's area) is below the fraction `dim`
// (PropagateParams::light_dim, 10^-3) of its light's mean irradiance over the scene's
// diffuse surfaces (the light's power over their area; a directional light's E) splits
// only until its footprint is kDimFootprintTexels wide, and across an edge kDimEdgeTexels:
// it deposits by area over a few texels instead of half of one. These are the light a
// glass ball sprays out after several internal reflections: on the Cornell box with a
// glass ball under a point light, 0.14 % of the emission in 75 % of the leaf beams.
constexpr double kDimFootprintTexels = 4.0;
constexpr double kDimEdgeTexels = 0.5;

// sum of atan(u v / sqrt(1 + u^2 + v^2)) over the corners (the solid angle of a rectangle
// on the plane z = 1 seen from the origin; Girard for a spherical quadrilateral).
double corner_angle(double u, double v) {
    return std::atan2(u * v, std::sqrt(1.0 + u * u + v * v));
}

// The direction through (u, v) of cube face `side` (axis side / 2, sign + for even).
Vec3 cube_direction(int side, double u, double v) {
    const int a = side / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    Vec3 d(0.0);
    d[a] = side % 2 == 0 ? 1.0 : -1.0;
    d[b] = u;
    d[c] = v;
    return d;
}

}  // namespace

double cube_solid_angle(double u0, double u1, double v0, double v1) {
    return corner_angle(u1, v1) - corner_angle(u0, v1) - corner_angle(u1, v0) +
           corner_angle(u0, v0);
}

LightBeams::LightBeams(const Scene& scene, const RayCaster& caster, const TextureMaps& tex,
                       const std::vector<FaceInTexels>& polygons, double reach, double dim)
    : m_scene(scene), m_caster(caster), m_tex(tex), m_polygons(polygons), m_reach(reach) {
    const double s2 = scene.normalisation.scale * scene.normalisation.scale;
    const double texel = m_texel = scene.texel_size_user * scene.normalisation.scale;
    const int per_texel =
        texel > 0.0 ? int(std::min<double>(kMaxRoots, std::ceil(2.0 * kRootsPerTexel / texel))) : 1;
    double diffuse_area = 0.0;  // normalised units^2
    for (const Chart& c : scene.charts)
        if (scene.material_of(c).is_diffuse()) diffuse_area += c.area;
    auto brightest = [](const Rgb& c) { return std::max({c.x, c.y, c.z}); };
    // The loader's bounds of the faces, normalised (misses_bounds' margin covers rounding).
    m_lo = scene.normalisation.to_normalised(scene.user_bounds_min);
    m_hi = scene.normalisation.to_normalised(scene.user_bounds_max);
    m_surface.resize(scene.faces.size());
    for (const Face& f : scene.faces) {
        const Chart& c = scene.chart_of(f);
        const int charts = int(scene.charts.size()), faces = int(scene.faces.size());
        if (!f.vertex_normals.empty())  // a smooth surface: one side of its object
            m_surface[size_t(f.id)] =
                charts + faces + 2 * f.object + (f.twin >= 0 && f.twin < f.id);
        else
            m_surface[size_t(f.id)] = c.planar ? c.id : charts + f.id;
    }
    int64_t total = 0;
    for (const Light& l : scene.lights) {
        if (!l.emits()) continue;
        if (l.type == LightType::Directional) {
            // The source's disc as subfields, evenly by area (a Vogel spiral): their
            // shadows add up to the penumbra.
            const int K = l.angular_diameter_deg > 0
                              ? std::clamp(int(std::ceil(16.0 * l.angular_diameter_deg)), 8, 64)
                              : 1;
            Vec3 a, b;
            orthonormal_basis(l.direction, a, b);
            const double half = 0.5 * l.angular_diameter_deg * kPi / 180.0;
            // E is the irradiance on a plane facing the disc's centre: the subfields share
            // it by their cosines to that plane's normal.
            double cos_sum = 0.0;
            for (int k = 0; k < K; ++k)
                cos_sum += std::cos(K == 1 ? 0.0 : half * std::sqrt((k + 0.5) / K));
            for (int k = 0; k < K; ++k) {
                Source s;
                s.light = &l;
                s.parallel = true;
                const double r = K == 1 ? 0.0 : half * std::sqrt((k + 0.5) / K);
                const double phi = k * 2.399963229728653;  // the golden angle
                s.direction = glm::normalize(l.direction +
                                             std::tan(r) * (std::cos(phi) * a + std::sin(phi) * b));
                orthonormal_basis(s.direction, s.e1, s.e2);
                s.base = -kParallelBase * s.direction;
                s.unit_power = l.irradiance / cos_sum;  // E x normalised area
                s.resolution = std::max(kParallelRoots, per_texel);
                s.dim_irradiance = dim * brightest(l.irradiance);
                fill_shadow(s);
                total += int64_t(s.resolution) * s.resolution;
                m_sources.push_back(s);
                m_first.push_back(total);
            }
            continue;
        }
        Source s;
        s.light = &l;
        s.position = scene.normalisation.to_normalised(l.position);
        s.unit_power = l.intensity * s2;  // W/sr x (normalised / user area)
        if (diffuse_area > 0.0)
            s.dim_irradiance = dim * brightest(s.unit_power) * l.solid_angle() / diffuse_area;
        // A spot's cone spans several root beams at least.
        const double outer_deg = std::acos(std::clamp(l.cos_outer, -1.0, 1.0)) * 180.0 / kPi;
        s.resolution = std::max(kPointRoots, per_texel);
        if (l.type == LightType::Spot)
            s.resolution =
                std::min(kMaxRoots,
                         std::max(s.resolution, int(std::ceil(360.0 / std::max(outer_deg, 0.5)))));
        total += 6 * int64_t(s.resolution) * s.resolution;
        m_sources.push_back(s);
        m_first.push_back(total);
    }
}

void LightBeams::fill_shadow(Source& s) const {
    s.shadow.assign(size_t(kShadowGrid) * kShadowGrid, 0);
    for (const Face& f : m_scene.faces) {
        double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
        for (const Vec3& p : f.vertices) {
            const double u = glm::dot(p - s.base, s.e1), v = glm::dot(p - s.base, s.e2);
            u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
        }
        if (u1 < -1.0 || u0 > 1.0 || v1 < -1.0 || v0 > 1.0) continue;
        // One cell of margin on each side: a ray on a cell's boundary is in both.
        const int i0 = std::max(0, shadow_cell(u0) - 1),
                  i1 = std::min(kShadowGrid - 1, shadow_cell(u1) + 1);
        const int j0 = std::max(0, shadow_cell(v0) - 1),
                  j1 = std::min(kShadowGrid - 1, shadow_cell(v1) + 1);
        for (int j = j0; j <= j1; ++j)
            std::fill(s.shadow.begin() + j * kShadowGrid + i0,
                      s.shadow.begin() + j * kShadowGrid + i1 + 1, uint8_t(1));
    }
}

bool LightBeams::meets_nothing(const Source& s, const Rect& r) const {
    if (!s.parallel || s.shadow.empty()) return false;
    const int i0 = shadow_cell(r.u0), i1 = shadow_cell(r.u1), j0 = shadow_cell(r.v0),
              j1 = shadow_cell(r.v1);
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i)
            if (s.shadow[size_t(j) * kShadowGrid + size_t(i)]) return false;
    return true;
}

bool LightBeams::misses_bounds(const Source& s, const Vec3 d[5]) const {
    if (s.parallel) return false;
    // Margins above the ray caster's single-precision geometry (about 1e-7 of the scene,
    // raycaster.hpp), far below a texel: a pyramid that only grazes the box is not taken as
    // missing it.
    const double eps = 1e-6;
    const Vec3& e = s.position;
    // A face plane of the box with the light outside it and every corner ray heading
    // away from the box (the pyramid is convex: its corner rays span it).
    for (int a = 0; a < 3; ++a) {
        bool above = e[a] > m_hi[a] + eps, below = e[a] < m_lo[a] - eps;
        for (int k = 1; k < 5; ++k) above &= d[k][a] >= 0.0, below &= d[k][a] <= 0.0;
        if (above || below) return true;
    }
    // A side plane of the pyramid (through the light and two neighbouring corner rays)
    // with every corner of the box strictly outside it.
    for (int k = 1; k < 5; ++k) {
        const Vec3 n = glm::cross(d[k], d[k % 4 + 1]);
        const double centre = glm::dot(n, d[0]);  // the centre ray's side
        if (!(std::abs(centre) > 0.0)) continue;
        const double inside = centre > 0.0 ? 1.0 : -1.0;
        bool outside = true;
        for (int c = 0; c < 8 && outside; ++c) {
            const Vec3 p((c & 1) ? m_hi.x : m_lo.x, (c & 2) ? m_hi.y : m_lo.y,
                         (c & 4) ? m_hi.z : m_lo.z);
            outside = glm::dot(n, p - e) * inside < -eps * glm::length(n);
        }
        if (outside) return true;
    }
    return false;
}

void LightBeams::ray(const Source& s, const Segment&, int side, double u, double v, Vec3& o,
                     Vec3& d) const {
    if (s.parallel) {
        o = s.base + u * s.e1 + v * s.e2;
        d = s.direction;
    } else {
        o = s.position;
        d = glm::normalize(cube_direction(side, u, v));
    }
}

// The shares of a beam's four quarters (in the order of trace's split): their solid
// angles (point), with the spot's falloff at the centres of their quarters (a 2 x 2 rule),
// or their areas (parallel). The corner terms of the exact solid angles are shared
// between neighbouring cells.
void LightBeams::child_weights(const Source& s, const Rect& r, double w[4]) const {
    if (s.parallel) {
        w[0] = w[1] = w[2] = w[3] = 1.0;
        return;
    }
    const bool spot = s.light->type == LightType::Spot;
    const int n = spot ? 4 : 2;  // cells per side of the beam
    double F[5][5];
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            F[j][i] = corner_angle(r.u0 + (r.u1 - r.u0) * i / n, r.v0 + (r.v1 - r.v0) * j / n);
    const int h = n / 2;  // cells per side of a quarter
    for (int q = 0; q < 4; ++q) {
        const int i0 = (q % 2) * h, j0 = (q / 2) * h;
        double sum = 0.0;
        for (int j = j0; j < j0 + h; ++j)
            for (int i = i0; i < i0 + h; ++i) {
                const double cell = F[j + 1][i + 1] - F[j + 1][i] - F[j][i + 1] + F[j][i];
                if (!spot) {
                    sum += cell;
                    continue;
                }
                const double u = r.u0 + (r.u1 - r.u0) * (i + 0.5) / n;
                const double v = r.v0 + (r.v1 - r.v0) * (j + 0.5) / n;
                sum += cell * s.light->falloff(glm::normalize(cube_direction(r.side, u, v)));
            }
        w[q] = sum;
    }
}

void LightBeams::deposit(const Face& f, const Vec3 foot[4], bool foot_ok, const Vec3& centre,
                         const Rgb& power, LightShotResult& out, Rgb& reflected) const {
    const Chart& chart = m_scene.chart_of(f);
    const Material& m = m_scene.material_of(f);
    const size_t tb = m_tex.begin(chart.id);
    const std::vector<Rgb>& albedo = chart.texel_albedo;
    const std::vector<double>& open = chart.texel_open;
    auto land = [&](size_t texel, const Rgb& q) {
        reflected += q;
        if (!open.empty() && open[texel] < kSealedTexel)
            out.absorbed_back += q;  // sealed behind another face (receive_step.cpp)
        else
            out.next[tb + texel] += q;
    };
    if (foot_ok) {
        Vec2 quad[4];
        for (int k = 0; k < 4; ++k) quad[k] = chart.texels.to_texel(foot[k]);
        thread_local std::vector<TexelOverlap> ov;
        ov.clear();
        clip_footprint_to_grid(quad, m_polygons[f.id].rim, chart.texels.width, chart.texels.height,
                               ov);
        double sum = 0.0;
        for (const TexelOverlap& o : ov) sum += o.area;
        if (sum > 0.0) {
            for (const TexelOverlap& o : ov)
                land(o.texel, power * (albedo.empty() ? m.diffuse : albedo[o.texel]) *
                                  (double(o.area) / sum));
            return;
        }
    }
    // A footprint that does not lie on the plane ahead (a ray grazing it): the centre's
    // texel takes the beam.
    const long t = nearest_texel(chart, centre);
    if (t < 0) {
        out.lost.empty_footprint += power * m.diffuse;
        reflected += power * m.diffuse;
        return;
    }
    land(size_t(t), power * (albedo.empty() ? m.diffuse : albedo[size_t(t)]));
}

LightBeams::Traced LightBeams::cast(const Source& s, const Segment& g, int side, double u,
                                    double v) const {
    Traced t;
    ray(s, g, side, u, v, t.o, t.d);
    // Through the segment's specular surfaces: each met on its front, the ray's point on it
    // put exactly on the face's plane (the ray caster works in single precision), then
    // reflected or refracted there.
    int last = -1;
    // The next surface along the ray. From a specular surface the search skips 1e-7; where
    // the surface touches another (a mirror box on the floor, two faces of a glass block
    // at their edge) that one may lie within the skipped part: look again from just behind.
    // The same rule for every event of the path and for its end, so a ray traced again
    // through a path meets the surfaces the path was recorded with.
    auto next = [&](bool from_surface, RayHit& h) {
        if (m_caster.intersect(t.o, t.d, from_surface ? 1e-7 : 0.0, 1e30, h)) return true;
        if (!from_surface) return false;
        constexpr double kBack = 1e-6;
        RayHit near;
        if (!m_caster.intersect(t.o - kBack * t.d, t.d, 0.0, 1e30, near) || near.t > 2.0 * kBack)
            return false;
        // Not the surface it leaves: that face, or its twin (glass's inner face) in its plane.
        if (last >= 0 && (near.face == last || near.face == m_scene.faces[size_t(last)].twin))
            return false;
        near.t -= kBack;
        h = near;
        return true;
    };
    for (int e = 0; e < g.count; ++e) {
        RayHit h;
        if (!next(e > 0, h)) {
            t.cls = -3;
            return t;
        }
        const Face& f = m_scene.faces[size_t(h.face)];
        const double denom = glm::dot(f.normal, t.d);
        if (denom >= 0.0 || surface_key(f) != g.events[e].surface) {
            t.cls = -3;  // beyond the surface's rim: it was not there for this ray
            return t;
        }
        const double to_plane = (f.plane_offset - glm::dot(f.normal, t.o)) / denom;
        t.o += to_plane * t.d;
        t.length += to_plane;
        const SpecularTurn turn = specular_turn(m_scene, f, t.o, t.d);  // the engine's rule
        if (!g.events[e].refract) {
            t.d = turn.reflected;
        } else if (turn.refracts) {
            t.d = turn.refracted;
        } else {
            t.cls = -3;  // totally reflected where the beam's centre was refracted
            return t;
        }
        last = h.face;
    }
    if (!next(g.count > 0, t.hit)) {
        t.cls = -1;  // leaves the scene
        return t;
    }
    const Face& f = m_scene.faces[size_t(t.hit.face)];
    t.cls = glm::dot(f.normal, t.d) >= 0.0 ? -2 : f.chart;  // a back face, or a front
    return t;
}

void LightBeams::trace(const Source& s, const Rect& r, const Segment& g, const Rgb& power,
                       int depth, LightShotResult& out, const Traced* known) const {
    if (!(power.x > 0 || power.y > 0 || power.z > 0)) return;
    // The centre ray, then the corners (counter-clockwise in (u, v)); a split beam's
    // quarters inherit the corners already cast (`known`).
    const double us[5] = {0.5 * (r.u0 + r.u1), r.u0, r.u1, r.u1, r.u0};
    const double vs[5] = {0.5 * (r.v0 + r.v1), r.v0, r.v0, r.v1, r.v1};
    Traced tr[5];
    for (int k = 0; k < 5; ++k)
        tr[k] = known && k > 0 ? known[k - 1] : cast(s, g, r.side, us[k], vs[k]);
    Vec3 o[5], d[5];
    RayHit hit[5];
    int cls[5];
    for (int k = 0; k < 5; ++k)
        o[k] = tr[k].o, d[k] = tr[k].d, hit[k] = tr[k].hit, cls[k] = tr[k].cls;
    bool across = false;  // the beam's rays meet more than one surface (or the void)
    for (int k = 1; k < 5; ++k) across |= cls[k] != cls[0];
    // The beam's width where its centre ray ends: its corner rays' spread there.
    const double t_end = cls[0] >= 0 || cls[0] == -2 ? hit[0].t : 2.0;
    const double spread = std::max(glm::length((o[3] + t_end * d[3]) - (o[1] + t_end * d[1])),
                                   glm::length((o[4] + t_end * d[4]) - (o[2] + t_end * d[2])));
    // Across an edge the beam splits until it is a fraction of a texel wide there; below
    // that the nearer face's rim decides the shares (rim_share). A beam of a specular path
    // may be across an edge it met on the way (a facet's edge, a mirror's rim), past which
    // its rays part: its width there, not where its rays end, is what must be small (at
    // most its cross-section at its last specular surface, as if it had spread from the
    // light unfocused).
    double width = spread;
    if (g.count > 0)
        width = std::min(width, s.parallel ? std::max(r.u1 - r.u0, r.v1 - r.v0)
                                           : std::max(r.u1 - r.u0, r.v1 - r.v0) * tr[0].length);
    // A corner ray that left the specular path (cls -3) stopped where it left it: it
    // spans no footprint.
    const bool cut = std::count(cls + 1, cls + 5, -3) > 0;
    Vec3 foot[4];
    const bool foot_ok = cls[0] >= 0 && !cut && footprint(hit[0].face, o, d, foot);
    const bool diffuse =
        cls[0] >= 0 && m_scene.material_of(m_scene.charts[size_t(cls[0])]).is_diffuse();
    // A dim beam (Source::dim_irradiance) may land coarse: by its irradiance, its power over its
    // footprint's area where it has one on a diffuse face, else (a beam cut by a path's
    // rim, grazing, or meeting nothing) over its width squared. Either is the same for a
    // beam and its quarters, so a beam does not become dim by being split.
    const double brightest = std::max({power.x, power.y, power.z});
    bool dim = false;
    if (diffuse && foot_ok)
        dim = brightest < s.dim_irradiance * 0.5 *
                              glm::length(glm::cross(foot[2] - foot[0], foot[3] - foot[1]));
    else if (!foot_ok)
        dim = brightest < s.dim_irradiance * width * width;
    bool split = across && width > (dim ? kDimEdgeTexels : kEdgeTexels) * m_texel;
    // Only a face that keeps light in texels needs the beam narrower than a texel: at a
    // mirror or glass the beam goes on whole (its quarters are traced afresh through it
    // where they land, and split there as they need).
    if (diffuse) {
        const double texel = m_scene.charts[size_t(cls[0])].texels.size;
        if (foot_ok)
            split |= std::max(glm::length(foot[2] - foot[0]), glm::length(foot[3] - foot[1])) >
                     (dim ? kDimFootprintTexels : kFootprintTexels) * std::min(texel, m_reach);
        else  // a corner ray misses the plane ahead (a grazing or cut beam): as at an edge
            split |= width > (dim ? kDimEdgeTexels : kEdgeTexels) * m_texel;
    }
    if (cls[0] == -1 && !split && !(g.count == 0 && (meets_nothing(s, r) || misses_bounds(s, d)))) {
        // A beam that meets nothing with all its rays may still hold a corner of the scene
        // poking in between them: it splits until it is as narrow as a leaf where it
        // crosses the scene (the unit ball). Straight from a light, a beam that cannot
        // reach a face ends here: from a parallel light, one whose cross-section covers no
        // face's shadow (shadow grid); from a point or spot light, one whose pyramid is
        // disjoint from the box around the faces (misses_bounds). A light outside that box
        // (above an open scene, outside a window) sends most of its beams past it, each of
        // which would split down to the leaves' width at the scene's distance.
        const double across =
            s.parallel ? r.u1 - r.u0 : (r.u1 - r.u0) * (glm::length(s.position) + 1.0);
        split = across > (dim ? kDimEdgeTexels : kMissTexels) * m_texel;
    }
    if (!split && !s.parallel && s.light->type == LightType::Spot) {
        // In the falloff the irradiance curves across a footprint (f ~ t^2 near the outer
        // cone): the beam splits until the falloff is nearly flat over it.
        double f[5];
        for (int k = 0; k < 5; ++k)
            f[k] = s.light->falloff(glm::normalize(cube_direction(r.side, us[k], vs[k])));
        for (int k = 1; k < 5; ++k)
            split |= std::abs(f[k] - f[0]) > kFalloffVariation * std::max(f[0], kFalloffFloor);
    }
    if (split && depth < kMaxDepth) {
        const double um = 0.5 * (r.u0 + r.u1), vm = 0.5 * (r.v0 + r.v1);
        const Rect kids[4] = {{r.side, r.u0, um, r.v0, vm},
                              {r.side, um, r.u1, r.v0, vm},
                              {r.side, r.u0, um, vm, r.v1},
                              {r.side, um, r.u1, vm, r.v1}};
        double w[4];
        child_weights(s, r, w);
        // The edges' midpoints: bottom, right, top, left.
        const Traced b = cast(s, g, r.side, um, r.v0), rt = cast(s, g, r.side, r.u1, vm),
                     t = cast(s, g, r.side, um, r.v1), l = cast(s, g, r.side, r.u0, vm);
        const Traced corners[4][4] = {{tr[1], b, tr[0], l},
                                      {b, tr[2], rt, tr[0]},
                                      {l, tr[0], t, tr[4]},
                                      {tr[0], rt, tr[3], t}};
        // On a specular path, a quarter whose corner rays all left the path (past a rim
        // where the path split, cls -3) lies in the part of the beam that the split gave to
        // the rim's other side (rim_share there): the quarters still on the path share the
        // beam's power.
        if (g.count > 0) {
            bool off[4];
            double kept = 0.0;
            for (int k = 0; k < 4; ++k) {
                off[k] = std::all_of(corners[k], corners[k] + 4,
                                     [](const Traced& c) { return c.cls == -3; });
                if (!off[k]) kept += w[k];
            }
            if (kept > 0.0)
                for (int k = 0; k < 4; ++k)
                    if (off[k]) w[k] = 0.0;
        }
        const double sum = w[0] + w[1] + w[2] + w[3];
        for (int k = 0; k < 4; ++k)
            trace(s, kids[k], g, power * (sum > 0.0 ? w[k] / sum : 0.25), depth + 1, out,
                  corners[k]);
        return;
    }
    ++out.leaves;
    // A corner that meets something else than the centre, if any: a face's front before
    // the void (a corner ray slipping through the seam between two faces is not a hole).
    int other = 0;
    for (int k = 1; k < 5 && other == 0; ++k)
        if (cls[k] != cls[0] && cls[k] >= 0) other = k;
    for (int k = 1; k < 5 && other == 0; ++k)
        if (cls[k] != cls[0]) other = k;
    if (other == 0) {
        land(s, r, g, depth, cls[0], hit[0], d[0], foot, foot_ok, power, out);
        return;
    }
    // A leaf across an edge (a face's rim, a shadow's edge) even at the finest level: the
    // nearer of the two faces it meets decides by the part of the beam its rim holds (the
    // farther one, or the void, gets the rest), so edges aligned with the beam grid do not
    // all fall on one side.
    Vec3 other_foot[4];
    const bool other_ok = cls[other] >= 0 && !cut && footprint(hit[other].face, o, d, other_foot);
    const bool centre_near = cls[0] >= 0 && (cls[other] < 0 || hit[0].t <= hit[other].t);
    double share = 0.0;  // the centre's part of the beam
    if (cls[0] == -3 || cls[other] == -3)
        // The part of the beam that left the path past a rim was given to the rim's other
        // side where the path split (rim_share there): the part on the path takes it all.
        share = cls[0] == -3 ? 0.0 : 1.0;
    else if (centre_near)
        share = foot_ok ? rim_share(hit[0].face, foot) : 1.0;
    else if (cls[other] >= 0)
        share = 1.0 - (other_ok ? rim_share(hit[other].face, other_foot) : 1.0);
    else  // neither meets a front face: by the rays' votes
        share = double(1 + std::count(cls + 1, cls + 5, cls[0])) / 5.0;
    land(s, r, g, depth, cls[0], hit[0], d[0], foot, foot_ok, power * share, out);
    land(s, r, g, depth, cls[other], hit[other], d[other], other_foot, other_ok,
         power * (1.0 - share), out);
}

// The footprint of a beam (its corner rays o[1..4] + t d[1..4]) on the plane of face f;
// false when a corner ray does not meet that plane ahead from its front.
bool LightBeams::footprint(int face, const Vec3 o[5], const Vec3 d[5], Vec3 foot[4]) const {
    const Face& f = m_scene.faces[size_t(face)];
    for (int k = 0; k < 4; ++k) {
        const double denom = glm::dot(f.normal, d[k + 1]);
        const double t = (f.plane_offset - glm::dot(f.normal, o[k + 1])) / denom;
        if (!(denom < 0.0 && t > 0.0 && std::isfinite(t))) return false;
        foot[k] = o[k + 1] + t * d[k + 1];
    }
    return true;
}

// The part of a footprint on face f within its chart: the quad clipped by the face's
// edges on the chart's rim (an edge shared inside the chart lets it run on), over the
// quad's area; in the chart's texel coordinates, where area ratios are the plane's.
double LightBeams::rim_share(int face, const Vec3 foot[4]) const {
    const Face& f = m_scene.faces[size_t(face)];
    const TexelFrame& frame = m_scene.chart_of(f).texels;
    std::vector<Vec2> poly(4), next;
    for (int k = 0; k < 4; ++k) poly[size_t(k)] = frame.to_texel(foot[k]);
    auto area = [](const std::vector<Vec2>& p) {
        double a = 0.0;
        for (size_t k = 0; k < p.size(); ++k) {
            const Vec2 &u = p[k], &v = p[(k + 1) % p.size()];
            a += u.x * v.y - u.y * v.x;
        }
        return 0.5 * std::abs(a);
    };
    const double whole = area(poly);
    if (!(whole > 0.0)) return 1.0;
    const size_t n = f.vertices.size();
    for (size_t e = 0; e < n && !poly.empty(); ++e) {
        if (e < 64 && (f.inner_edges >> e) & 1u) continue;
        const Vec2 a = frame.to_texel(f.vertices[e]), b = frame.to_texel(f.vertices[(e + 1) % n]);
        // Sutherland-Hodgman against the left of a -> b (the face is counter-clockwise).
        auto side = [&](const Vec2& p) {
            return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        };
        next.clear();
        for (size_t k = 0; k < poly.size(); ++k) {
            const Vec2 &p = poly[k], &q = poly[(k + 1) % poly.size()];
            const double sp = side(p), sq = side(q);
            if (sp >= 0) next.push_back(p);
            if ((sp >= 0) != (sq >= 0)) next.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        poly.swap(next);
    }
    return std::clamp(area(poly) / whole, 0.0, 1.0);
}

// What a beam (or part of one) does where it lands: escapes (cls -1), is absorbed by a
// back face (-2), or reaches the front of a face: rho_d of it into the texels under its
// footprint, rho_s of it on as the reflected beam, the rest absorbed; at glass, Fresnel's
// R of it on as the reflected beam and 1 - R as the refracted one (all of it reflected past
// the critical angle). A beam that ran inside absorbing glass keeps exp(-sigma d) of its
// power, d its centre ray's length there.
void LightBeams::land(const Source& s, const Rect& r, const Segment& g, int depth, int cls,
                      const RayHit& hit, const Vec3& dir, const Vec3 foot[4], bool foot_ok,
                      Rgb power, LightShotResult& out) const {
    if (!(power.x > 0 || power.y > 0 || power.z > 0)) return;
    if (cls == -3) {
        out.lost.cut_beam += power;
        return;
    }
    double transmitted = 1.0;  // the glass's transmittance on this segment (channel mean)
    if (g.medium >= 0 && cls != -1) {
        const Material& glass = m_scene.materials[size_t(g.medium)];
        if (glass.is_absorbing()) {
            const Rgb T = glm::exp(-glass.absorption * (hit.t / m_scene.normalisation.scale));
            const Rgb kept = power * T;
            out.absorbed += power - kept;
            power = kept;
            transmitted = (T.x + T.y + T.z) / 3.0;
        }
    }
    if (cls == -1) {
        out.escaped += power;
        return;
    }
    if (cls == -2) {
        out.absorbed_back += power;  // a one-sided face's black back
        return;
    }
    const Face& f = m_scene.faces[size_t(hit.face)];
    const Material& m = m_scene.material_of(f);
    if (!m.dielectric) {
        Rgb reflected(0.0);
        if (m.is_diffuse()) deposit(f, foot, foot_ok, hit.point, power, out, reflected);
        out.absorbed += power * (Rgb(1.0) - m.specular) - reflected;
        if (m.is_specular())
            go_on(s, r, g, depth, f, false, power * m.specular,
                  (m.specular.x + m.specular.y + m.specular.z) / 3.0, out);
        return;
    }
    const double R = specular_turn(m_scene, f, hit.point, dir).R;
    go_on(s, r, g, depth, f, false, power * R, R * transmitted, out);
    if (R < 1.0) go_on(s, r, g, depth, f, true, power * (1.0 - R), (1.0 - R) * transmitted, out);
}

// A beam on from specular face f, reflected or refracted, carrying `power` (its branch's
// weight times `weight`).
void LightBeams::go_on(const Source& s, const Rect& r, const Segment& g, int depth, const Face& f,
                       bool refract, const Rgb& power, double weight, LightShotResult& out) const {
    if (!(power.x > 0 || power.y > 0 || power.z > 0)) return;
    if (g.count >= kMaxBounces) {
        out.absorbed += power;
        return;
    }
    Segment next = g;
    next.events[next.count++] = {surface_key(f), refract};
    next.weight *= weight;
    if (next.weight < kMinWeight) {
        out.lost.cut_beam += power;
        return;
    }
    if (refract) next.medium = f.inner ? -1 : f.material;  // into the glass, or out of it
    trace(s, r, next, power, depth, out);
}

void LightBeams::shoot(int64_t k0, int64_t k1, LightShotResult& out) const {
    for (int64_t k = k0; k < k1; ++k) {
        const size_t si =
            size_t(std::upper_bound(m_first.begin(), m_first.end(), k) - m_first.begin());
        const Source& s = m_sources[si];
        const int64_t local = k - (si == 0 ? 0 : m_first[si - 1]);
        const int R = s.resolution;
        const int64_t per_side = int64_t(R) * R;
        Rect r;
        r.side = int(local / per_side);
        const int64_t p = local % per_side;
        const int i = int(p % R), j = int(p / R);
        r.u0 = -1.0 + 2.0 * i / R;
        r.u1 = -1.0 + 2.0 * (i + 1) / R;
        r.v0 = -1.0 + 2.0 * j / R;
        r.v1 = -1.0 + 2.0 * (j + 1) / R;
        Rgb power;
        if (s.parallel) {
            // Squares wholly outside the unit ball's shadow cannot meet the scene.
            const double cu = std::clamp(0.0, r.u0, r.u1), cv = std::clamp(0.0, r.v0, r.v1);
            if (cu * cu + cv * cv > 1.0) continue;
            power = s.unit_power * ((r.u1 - r.u0) * (r.v1 - r.v0));
        } else {  // its solid angle, with a spot's falloff: the sum of its quarters' shares
            double w[4];
            child_weights(s, r, w);
            const double sum = w[0] + w[1] + w[2] + w[3];
            if (!(sum > 0.0)) continue;
            power = s.unit_power * sum;
        }
        out.emitted += power;
        trace(s, r, Segment{}, power, 0, out);
    }
}

}  // namespace vlf
