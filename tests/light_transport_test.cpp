// Delta lights in propagation (issue 14, light_beams.hpp): per-texel irradiance against
// closed forms — a point light's I cos(theta) / r^2 integrated over each texel (its exact
// solid angle), a spot's falloff, a directional light's E cos(theta) with a shadow whose
// edge texels are lit in proportion to their lit area, a mirror's image source — and the
// ledger with every light type.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "test_util.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/light_beams.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

using test::params;
using test::run_transport;
using test::scene_from_json;

// A 4 x 4 floor at y = 0 (rho_d 0.5, facing up), texels of 0.05, and `more` (objects,
// then lights).
std::string floor_scene(const std::string& objects, const std::string& lights) {
    return R"({"materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]},
                             "white": {"diffuse": [0.5, 0.5, 0.5]},
                             "mirror": {"specular": [0.8, 0.8, 0.8]}},
               "settings": {"texel_size": 0.05},
               "objects": [{"type": "polygon", "material": "floor", "name": "floor",
                            "vertices": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]})" +
           objects + R"(], "lights": [)" + lights + "]}";
}

// A texel of the floor as a rectangle [x0, x1] x [z0, z1] (user units), clipped to the
// floor.
struct TexelRect {
    double x0, x1, z0, z1;
    double area() const { return (x1 - x0) * (z1 - z0); }
};
TexelRect texel_rect(const Scene& scene, const Chart& c, size_t k) {
    const int i = int(k % c.texels.width), j = int(k / c.texels.width);
    const Vec3 a = scene.normalisation.to_user(c.texels.to_plane(Vec2(i, j)));
    const Vec3 b = scene.normalisation.to_user(c.texels.to_plane(Vec2(i + 1, j + 1)));
    return {std::max(-2.0, std::min(a.x, b.x)), std::min(2.0, std::max(a.x, b.x)),
            std::max(-2.0, std::min(a.z, b.z)), std::min(2.0, std::max(a.z, b.z))};
}

using test::texel_irradiance;

const Chart& floor_chart(const Scene& scene) {
    return scene.chart_of(scene.faces[size_t(scene.objects[0].first_face)]);
}

// A point light (intensity I, user units) over the floor: a texel's mean irradiance is I x
// its solid angle / its area (cube_solid_angle: the texel on the plane at distance h, scaled
// by 1/h). Checks every texel within 1 % and the ledger; returns the shot's beam counts.
// `objects` (more objects, each after a comma) must cast no shadow on the floor; `check`
// then looks at the finished transport.
template <class Check>
LightBeamStats check_point_light(const Vec3& light, double I, const std::string& objects,
                                 Check&& check) {
    char json[160];
    std::snprintf(json, sizeof json,
                  R"({"type": "point", "position": [%g, %g, %g], "intensity": [%g, %g, %g]})",
                  light.x, light.y, light.z, I, I, I);
    const Scene scene = scene_from_json(floor_scene(objects, json));
    const auto t = run_transport(scene, params(33, 64, 8, 1));
    check(scene, *t);
    const Chart& c = floor_chart(scene);
    double worst = 0.0;
    int checked = 0;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        if (c.texel_area[k] <= 0.0) continue;
        const TexelRect r = texel_rect(scene, c, k);
        const double h = light.y;
        const double exact = I *
                             cube_solid_angle((r.x0 - light.x) / h, (r.x1 - light.x) / h,
                                              (r.z0 - light.z) / h, (r.z1 - light.z) / h) /
                             r.area();
        const double got = texel_irradiance(*t, c, k);
        worst = std::max(worst, std::abs(got / exact - 1.0));
        ++checked;
    }
    EXPECT_EQ(checked, 80 * 80);
    EXPECT_LT(worst, 0.01) << "worst texel " << worst;
    std::printf(
        "point light at height %g: worst texel error %.2e over %d texels, %lld leaf beams\n",
        light.y, worst, checked, static_cast<long long>(t->light_beams().leaves));
    // Every watt is booked: 4 pi I emitted.
    const LedgerEntry& e = t->ledger().back();
    EXPECT_NEAR(e.emitted.x, 4.0 * kPi * I, 1e-9 * 4.0 * kPi * I);
    EXPECT_LE(e.relative_error(), 1e-9);
    return t->light_beams();
}

TEST(LightTransport, PointLightIrradiancePerTexel) {
    check_point_light(Vec3(0.3, 0.7, -0.2), 2.0, "", [](const Scene&, const Transport&) {});
}

// The solid angle of triangle abc seen from e (Van Oosterom and Strackee).
double triangle_solid_angle(const Vec3& e, const Vec3& a0, const Vec3& b0, const Vec3& c0) {
    const Vec3 a = a0 - e, b = b0 - e, c = c0 - e;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den =
        la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return 2.0 * std::abs(std::atan2(num, den));
}

// A light far outside the box around the faces (above an open scene, outside a window)
// sends most of its beams past it. Such a beam cannot hold a corner of the scene between
// its rays, so it escapes whole (LightBeams::misses_bounds) instead of splitting down to
// the leaves' width at the scene's distance: at 20 units over the 4 x 4 floor alone, the
// beams that miss (all but a few hundred of the 6 x 114^2 roots) split into thousands of
// leaves each before: 1.28e9 leaves in 204 s, against 2.4e5 in 0.14 s now, the same worst
// texel (7.9e-6). The floor's texels stay exact, and the shot's leaves stay under 1e6: the
// 1.0e5 roots, the floor's 6,400 texels at up to 16 leaves each (footprints of half a texel
// on a quadtree not aligned with them), its rim and the chip's (below) at 1/32 texel, and
// the beams around the chip split to 1/8 texel.
// Beside the floor, a chip (a triangle 6 cm across, its shadow off the floor) lies inside one
// root beam (35 cm wide there): where the beam's five rays all pass it, only the splitting
// of beams that meet nothing finds it, so a beam wrongly taken as missing the box would
// lose its light. The chip receives I times its solid angle within 1 %.
TEST(LightTransport, FarPointLightSendsItsMissingBeamsWhole) {
    const Vec3 light(0.3, 20.0, -0.2), a(3.0, 1.0, 0.0), b(3.0, 1.0, 0.06), c(3.06, 1.0, 0.0);
    const double I = 500.0;
    const std::string chip =
        R"(, {"type": "polygon", "material": "white", "name": "chip",
              "vertices": [[3.0, 1.0, 0.0], [3.0, 1.0, 0.06], [3.06, 1.0, 0.0]]})";
    const LightBeamStats beams =
        check_point_light(light, I, chip, [&](const Scene& scene, const Transport& t) {
            const Chart& ch =
                scene.chart_of(scene.faces[size_t(test::object_named(scene, "chip").first_face)]);
            double power = 0.0;  // rho_d of the light it receives is in P^T (user units)
            for (size_t k = 0; k < size_t(ch.texels.count()); ++k)
                power += t.texture_maps().total[t.texture_maps().begin(ch.id) + k].x / 0.5;
            power /= scene.normalisation.scale * scene.normalisation.scale;
            const double exact = I * triangle_solid_angle(light, a, b, c);
            EXPECT_NEAR(power / exact, 1.0, 0.01) << power << " W against " << exact;
            std::printf("the chip: %.6g W against %.6g W\n", power, exact);
        });
    std::printf("%lld root beams\n", static_cast<long long>(beams.roots));
    EXPECT_LT(beams.leaves, 1000000);
}

// ---- exact references by polygon clipping: a lit part of a texel and its solid angle ----

using Poly2 = std::vector<Vec2>;  // (x, z) on the floor, counter-clockwise

// The convex polygon p clipped by the convex polygon clip (both counter-clockwise).
Poly2 clip_convex(Poly2 p, const Poly2& clip) {
    for (size_t e = 0; e < clip.size() && !p.empty(); ++e) {
        const Vec2 a = clip[e], b = clip[(e + 1) % clip.size()];
        auto side = [&](const Vec2& q) {
            return (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
        };
        Poly2 next;
        for (size_t k = 0; k < p.size(); ++k) {
            const Vec2 &u = p[k], &v = p[(k + 1) % p.size()];
            const double su = side(u), sv = side(v);
            if (su >= 0) next.push_back(u);
            if ((su >= 0) != (sv >= 0)) next.push_back(u + (v - u) * (su / (su - sv)));
        }
        p.swap(next);
    }
    return p;
}

double area(const Poly2& p) {
    double a = 0.0;
    for (size_t k = 0; k < p.size(); ++k)
        a += p[k].x * p[(k + 1) % p.size()].y - p[k].y * p[(k + 1) % p.size()].x;
    return 0.5 * std::abs(a);
}

// Counter-clockwise seen from +y... as (x, z) with x right, z down: make it positive area.
Poly2 ccw(Poly2 p) {
    double a = 0.0;
    for (size_t k = 0; k < p.size(); ++k)
        a += p[k].x * p[(k + 1) % p.size()].y - p[k].y * p[(k + 1) % p.size()].x;
    if (a < 0) std::reverse(p.begin(), p.end());
    return p;
}

// The solid angle of a convex polygon on the floor (y = 0) seen from e (Van Oosterom and
// Strackee, over the fan of triangles).
double solid_angle(const Vec3& e, const Poly2& p) {
    double omega = 0.0;
    for (size_t k = 1; k + 1 < p.size(); ++k) {
        const Vec3 a = Vec3(p[0].x, 0, p[0].y) - e, b = Vec3(p[k].x, 0, p[k].y) - e,
                   c = Vec3(p[k + 1].x, 0, p[k + 1].y) - e;
        const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const double num = glm::dot(a, glm::cross(b, c));
        const double den =
            la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
        omega += 2.0 * std::abs(std::atan2(num, den));
    }
    return omega;
}

Poly2 texel_poly(const TexelRect& r) {
    return ccw({{r.x0, r.z0}, {r.x1, r.z0}, {r.x1, r.z1}, {r.x0, r.z1}});
}

// The polygon `vertices` seen from e, projected onto the floor (every vertex below e).
Poly2 shadow_of(const Vec3& e, const std::vector<Vec3>& vertices) {
    Poly2 out;
    for (const Vec3& m : vertices) {
        const double t = e.y / (e.y - m.y);
        const Vec3 p = e + t * (m - e);
        out.push_back({p.x, p.z});
    }
    return ccw(out);
}

// A planar mirror (rho_s 0.8) beside a point light: every floor texel gets the direct
// light, less the mirror's shadow, plus the light of the image source behind the mirror
// through the mirror's outline — each exact by clipping and solid angle — within 1 %
// (in the mirror's shadow: of the texel's unshadowed value), including the texels the
// mirror's image and shadow edges cross.
TEST(LightTransport, MirrorImageSourcePerTexel) {
    const Vec3 light(0.0, 1.0, 0.0), image(2.0, 1.0, 0.0);
    const std::vector<Vec3> mirror = {{1, 0.1, -0.6}, {1, 0.1, 0.6}, {1, 0.9, 0.6}, {1, 0.9, -0.6}};
    const Scene scene = scene_from_json(floor_scene(
        R"(, {"type": "polygon", "material": "mirror",
              "vertices": [[1, 0.1, -0.6], [1, 0.1, 0.6], [1, 0.9, 0.6], [1, 0.9, -0.6]]})",
        R"({"type": "point", "position": [0, 1, 0], "intensity": [1, 1, 1]})"));
    const auto t = run_transport(scene, params(33, 64, 8, 1));
    const Chart& c = floor_chart(scene);
    const Poly2 lit_by_image = shadow_of(image, mirror), shadow = shadow_of(light, mirror);
    double worst = 0.0, worst_edge = 0.0;
    int edges = 0;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        if (c.texel_area[k] <= 0.0) continue;
        const TexelRect r = texel_rect(scene, c, k);
        const Poly2 q = texel_poly(r);
        // Only the part of the image region on the mirror's front side (x < 1) is real.
        const Poly2 front = {{-2, -2}, {1, -2}, {1, 2}, {-2, 2}};
        const Poly2 via_mirror = clip_convex(clip_convex(q, lit_by_image), ccw(front));
        const double unshadowed = solid_angle(light, q) / r.area();
        const double exact = unshadowed + (0.8 * solid_angle(image, via_mirror) -
                                           solid_angle(light, clip_convex(q, shadow))) /
                                              r.area();
        // Relative to the texel's value, or in the mirror's shadow to its value unshadowed.
        const double err =
            std::abs(texel_irradiance(*t, c, k) - exact) / std::max(exact, unshadowed);
        worst = std::max(worst, err);
        const double part = area(via_mirror) / r.area();
        if (part > 1e-9 && part < 1.0 - 1e-9) worst_edge = std::max(worst_edge, err), ++edges;
    }
    EXPECT_GT(edges, 20);
    EXPECT_LT(worst, 0.01);
    std::printf("mirror: worst texel error %.2e (%.2e on %d texels across the image's edge)\n",
                worst, worst_edge, edges);
    EXPECT_LE(t->ledger().back().relative_error(), 1e-9);
}

// A directional light through a square occluder: the floor is lit with E cos(theta), and
// every texel the shadow's edge crosses in proportion to its lit area (exact by clipping),
// within 1 % of the full value.
TEST(LightTransport, DirectionalLightShadowEdgeTexels) {
    const Vec3 d = glm::normalize(Vec3(0.5, -1.0, 0.3));
    const double E = 4.0;
    const Scene scene = scene_from_json(floor_scene(
        R"(, {"type": "polygon", "material": "white",
              "vertices": [[-0.5, 0.5, -0.5], [-0.5, 0.5, 0.5], [0.5, 0.5, 0.5], [0.5, 0.5, -0.5]]})",
        R"({"type": "directional", "direction": [0.5, -1, 0.3], "irradiance": [4, 4, 4]})"));
    const auto t = run_transport(scene, params(33, 64, 8, 1));
    const Chart& c = floor_chart(scene);
    const double full = E * -d.y, shift = 0.5 / -d.y;
    const Poly2 shadow = ccw({{-0.5 + d.x * shift, -0.5 + d.z * shift},
                              {0.5 + d.x * shift, -0.5 + d.z * shift},
                              {0.5 + d.x * shift, 0.5 + d.z * shift},
                              {-0.5 + d.x * shift, 0.5 + d.z * shift}});
    double worst = 0.0;
    int edges = 0;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        if (c.texel_area[k] <= 0.0) continue;
        const TexelRect r = texel_rect(scene, c, k);
        const double lit = 1.0 - area(clip_convex(texel_poly(r), shadow)) / r.area();
        if (lit > 0.0 && lit < 1.0) ++edges;
        worst = std::max(worst, std::abs(texel_irradiance(*t, c, k) - full * lit) / full);
    }
    EXPECT_GT(edges, 60);
    EXPECT_LT(worst, 0.01);
    std::printf("directional: worst texel error %.2e of E cos(theta)\n", worst);
    EXPECT_LE(t->ledger().back().relative_error(), 1e-9);
}

// A spot light straight down: each texel's mean of I f(w) cos(theta) / r^2, with f the
// smoothstep falloff between the cones (a 24 x 24 midpoint rule per texel: the integrand
// is smooth, its error far below the tolerance) within 1 % where the texel gets at least
// 1 % of the peak, within 1e-4 of the peak elsewhere; and the power emitted is the spot's.
TEST(LightTransport, SpotLightFalloffPerTexel) {
    const Vec3 pos(0.1, 1.0, -0.1);
    const Scene scene = scene_from_json(
        floor_scene("", R"({"type": "spot", "position": [0.1, 1, -0.1], "direction": [0, -1, 0],
                "inner_deg": 20, "outer_deg": 40, "power": [3, 3, 3]})"));
    const Light& l = scene.lights[0];
    const auto t = run_transport(scene, params(33, 64, 8, 1));
    const Chart& c = floor_chart(scene);
    const double peak = l.intensity.x / (pos.y * pos.y);
    double worst = 0.0, worst_dim = 0.0;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        if (c.texel_area[k] <= 0.0) continue;
        const TexelRect r = texel_rect(scene, c, k);
        constexpr int n = 24;
        double sum = 0.0;
        for (int b = 0; b < n; ++b)
            for (int a = 0; a < n; ++a) {
                const Vec3 x(r.x0 + (a + 0.5) / n * (r.x1 - r.x0), 0.0,
                             r.z0 + (b + 0.5) / n * (r.z1 - r.z0));
                const Vec3 w = x - pos;
                const double r2 = glm::dot(w, w);
                sum += l.intensity.x * l.falloff(w / std::sqrt(r2)) * (pos.y / std::sqrt(r2)) / r2;
            }
        const double exact = sum / (n * n), got = texel_irradiance(*t, c, k);
        if (exact >= 0.01 * peak)
            worst = std::max(worst, std::abs(got / exact - 1.0));
        else
            worst_dim = std::max(worst_dim, std::abs(got - exact) / peak);
    }
    EXPECT_LT(worst, 0.01);
    EXPECT_LT(worst_dim, 1e-4);
    std::printf("spot: worst texel error %.2e (dim texels %.2e of the peak)\n", worst, worst_dim);
    EXPECT_NEAR(t->ledger().back().emitted.x, 3.0, 3.0 * 1e-3);
}

// A directional light with a wide disc (30 degrees) straight down on the floor: E is the
// irradiance on a plane facing the disc's centre, so every texel away from the rims (where
// the disc's slanted beams overhang) gets E within 1 %, as the path tracer's sun does.
TEST(LightTransport, SunDiscIrradianceOnAFacingPlane) {
    const Scene scene = load_scene_from_string(
        R"({"materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]}},
            "settings": {"texel_size": 0.2},
            "objects": [{"type": "polygon", "material": "floor",
                         "vertices": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]}],
            "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [5, 5, 5],
                        "angular_diameter_deg": 30}]})",
        "sun.json", "");
    const auto t = run_transport(scene, params(33, 32, 8, 1));
    const Chart& c = floor_chart(scene);
    double worst = 0.0;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        if (c.texel_area[k] <= 0.0) continue;
        const TexelRect r = texel_rect(scene, c, k);
        if (std::max(std::abs(r.x0), std::abs(r.x1)) > 1.9 ||
            std::max(std::abs(r.z0), std::abs(r.z1)) > 1.9)
            continue;
        worst = std::max(worst, std::abs(texel_irradiance(*t, c, k) / 5.0 - 1.0));
    }
    EXPECT_LT(worst, 0.01);
    EXPECT_LE(t->ledger().back().relative_error(), 1e-9);
}

}  // namespace
}  // namespace vlf
