// Glass in propagation (issue 14, docs/propagation.md §13): the lights' beams through
// dielectric slabs against the closed forms of a slab's reflectance and transmittance with
// every internal reflection, Beer-Lambert inside, the focus of a ball lens, and the ledger.
//
// Closed forms. One interface reflects R (unpolarised Fresnel, fresnel_dielectric); a slab
// of parallel faces, with a = exp(-sigma d / cos theta_t) the transmittance of one crossing,
// transmits and reflects (the light bounces between its faces; VLF splits power at each
// interface by the unpolarised R, so the series is taken with that R):
//     T = (1 - R)^2 a / (1 - R^2 a^2),   R_slab = R + (1 - R)^2 R a^2 / (1 - R^2 a^2).
// At 45 deg and n = 1.5 the polarisation-resolved slab (s and p summed separately) transmits
// 0.3 % more than this unpolarised series; the tests check the series VLF implements.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "test_util.hpp"
#include "vlf/core/fresnel.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

using test::params;
using test::run_transport;
using test::scene_from_json;
using test::texel_irradiance;

// The user-space bounds of texel k of chart c.
void texel_bounds(const Scene& scene, const Chart& c, size_t k, Vec3& lo, Vec3& hi) {
    const int i = int(k % c.texels.width), j = int(k / c.texels.width);
    const Vec3 a = scene.normalisation.to_user(c.texels.to_plane(Vec2(i, j)));
    const Vec3 b = scene.normalisation.to_user(c.texels.to_plane(Vec2(i + 1, j + 1)));
    lo = glm::min(a, b);
    hi = glm::max(a, b);
}

const Chart& chart_named(const Scene& scene, const std::string& name) {
    for (const SceneObject& o : scene.objects)
        if (o.name == name) return scene.chart_of(scene.faces[size_t(o.first_face)]);
    ADD_FAILURE() << "no object " << name;
    return scene.charts[0];
}

// Worst relative error, over the texels of chart `name` wholly inside the user-space box
// [lo, hi], of their irradiance against `want`; `count` gets how many were checked.
double worst_in_box(const Transport& t, const Scene& scene, const std::string& name, const Vec3& lo,
                    const Vec3& hi, double want, int& count) {
    const Chart& c = chart_named(scene, name);
    const double full = c.texels.size * c.texels.size;
    double worst = 0.0;
    count = 0;
    for (size_t k = 0; k < size_t(c.texels.count()); ++k) {
        Vec3 a, b;
        texel_bounds(scene, c, k, a, b);
        const bool inside =
            a.x >= lo.x && a.y >= lo.y && a.z >= lo.z && b.x <= hi.x && b.y <= hi.y && b.z <= hi.z;
        if (!inside || c.texel_area[k] < 0.999 * full) continue;
        worst = std::max(worst, std::abs(texel_irradiance(t, c, k) / want - 1.0));
        ++count;
    }
    return worst;
}

// A slab of thickness d (rotated by `tilt_deg` about z, centred at height 1.5) over a
// 4 x 4 floor and beside a wall at x = -2.5 facing +x; a directional light straight down.
std::string slab_scene(double tilt_deg, double d, double sigma) {
    return fmt::format(
        R"({{"materials": {{"white": {{"diffuse": [0.5, 0.5, 0.5]}},
                           "glass": {{"dielectric": {{"ior": 1.5, "absorption": [{}, {}, {}]}}}}}},
              "settings": {{"texel_size": 0.05}},
              "objects": [
                {{"type": "polygon", "material": "white", "name": "floor",
                  "vertices": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]}},
                {{"type": "polygon", "material": "white", "name": "wall",
                  "vertices": [[-2.5, 0.5, -2], [-2.5, 2.5, -2], [-2.5, 2.5, 2], [-2.5, 0.5, 2]]}},
                {{"type": "box", "material": "glass", "name": "slab",
                  "min": [-1, {}, -1], "max": [1, {}, 1], "rotate_z_deg": {},
                  "translate": [0, 1.5, 0]}}],
              "lights": [{{"type": "directional", "direction": [0, -1, 0],
                          "irradiance": [1, 1, 1]}}]}})",
        sigma, sigma, sigma, -0.5 * d, 0.5 * d, tilt_deg);
}

struct SlabForms {
    double T, R;
};
SlabForms slab_forms(double cos_i, double n, double d, double sigma) {
    const double R = fresnel_dielectric(cos_i, 1.0 / n);
    const double sin_t = std::sqrt(1.0 - cos_i * cos_i) / n;
    const double a = std::exp(-sigma * d / std::sqrt(1.0 - sin_t * sin_t));
    const double q = 1.0 - R * R * a * a;
    return {(1.0 - R) * (1.0 - R) * a / q, R + (1.0 - R) * (1.0 - R) * R * a * a / q};
}

// The interface itself (core/fresnel.hpp) against closed forms: R = ((n - 1) / (n + 1))^2
// at normal incidence; the same R for light crossing either way along a refracted pair
// (Stokes reciprocity); total reflection beyond the critical angle; Snell's law and the
// plane of incidence for the refracted direction; Brewster's angle, where the p
// reflectance vanishes (R = R_s / 2).
TEST(Fresnel, ClosedFormsSnellAndReciprocity) {
    for (const double n : {1.33, 1.5, 2.5}) {
        const double r0 = (n - 1.0) / (n + 1.0);
        EXPECT_NEAR(fresnel_dielectric(1.0, 1.0 / n), r0 * r0, 1e-15) << n;
        EXPECT_NEAR(fresnel_dielectric(1.0, n), r0 * r0, 1e-15) << n;
        const double critical = std::asin(1.0 / n);
        EXPECT_EQ(fresnel_dielectric(std::cos(critical + 1e-6), n), 1.0) << n;
        EXPECT_LT(fresnel_dielectric(std::cos(critical - 1e-3), n), 1.0) << n;
        for (const double deg : {10.0, 30.0, 45.0, 60.0, 80.0}) {
            const double ti = deg * kPi / 180.0;
            const Vec3 normal(0.0, 0.0, 1.0);
            const Vec3 travel(std::sin(ti), 0.0, -std::cos(ti));  // into the glass
            Vec3 t;
            ASSERT_TRUE(refract(travel, normal, 1.0 / n, t));
            EXPECT_NEAR(glm::length(t), 1.0, 1e-12);
            EXPECT_NEAR(t.y, 0.0, 1e-15);               // in the plane of incidence
            EXPECT_NEAR(n * t.x, std::sin(ti), 1e-12);  // n_t sin_t = n_i sin_i
            EXPECT_LT(t.z, 0.0);                        // on through the surface
            const double cos_t = -t.z;
            EXPECT_NEAR(fresnel_dielectric(std::cos(ti), 1.0 / n), fresnel_dielectric(cos_t, n),
                        1e-12)
                << n << " " << deg;
        }
        const double brewster = std::atan(n);
        const double ci = std::cos(brewster),
                     ct = std::sqrt(1.0 - std::pow(std::sin(brewster) / n, 2));
        const double rs = (ci - n * ct) / (ci + n * ct);
        EXPECT_NEAR(fresnel_dielectric(ci, 1.0 / n), 0.5 * rs * rs, 1e-12) << n;
    }
}

// Normal incidence: the floor under the slab gets E T, with and without absorption; the
// rest of the floor E; the ledger closes with the light reflected up booked as escaped.
TEST(GlassTransport, SlabTransmittanceAtNormalIncidence) {
    for (const double sigma : {0.0, 2.0}) {
        const double d = 0.1;
        const Scene scene = scene_from_json(slab_scene(0.0, d, sigma));
        const auto t = run_transport(scene, params(33, 32, 8, 1));
        const SlabForms want = slab_forms(1.0, 1.5, d, sigma);
        int n_in = 0, n_out = 0;
        const double under =
            worst_in_box(*t, scene, "floor", Vec3(-0.9, -1, -0.9), Vec3(0.9, 1, 0.9), want.T, n_in);
        const double open =
            worst_in_box(*t, scene, "floor", Vec3(1.1, -1, -1.9), Vec3(1.9, 1, 1.9), 1.0, n_out);
        EXPECT_GT(n_in, 1000);
        EXPECT_GT(n_out, 300);
        EXPECT_LT(under, 0.01) << "sigma " << sigma << ": T " << want.T;
        EXPECT_LT(open, 0.01);
        const LedgerEntry& e = t->ledger().back();
        EXPECT_LE(e.relative_error(), 1e-9) << format_ledger(e);
        std::printf("slab 0 deg, sigma %.1f: T %.5f, worst texel under it %.2e (%d), beside %.2e\n",
                    sigma, want.T, under, n_in, open);
    }
}

// 45 deg: the slab turned about z, the light straight down. What it transmits goes on
// straight down onto the floor (shifted sideways by less than its thickness); what it
// reflects leaves horizontally towards the wall, whose texels get E R_slab (the beam keeps
// its cross-section: irradiance E across it, the wall facing it).
TEST(GlassTransport, SlabReflectanceAndTransmittanceAt45Degrees) {
    const double d = 0.1;
    const Scene scene = scene_from_json(slab_scene(45.0, d, 0.0));
    const auto t = run_transport(scene, params(33, 32, 8, 1));
    const SlabForms want = slab_forms(std::cos(kPi / 4), 1.5, d, 0.0);
    int n_floor = 0, n_wall = 0;
    // The slab covers x in [-0.707, 0.707]; its shadow shifts by at most d.
    const double floor_err = worst_in_box(*t, scene, "floor", Vec3(-0.55, -1, -0.9),
                                          Vec3(0.55, 1, 0.9), want.T, n_floor);
    // The reflected band on the wall: heights 1.5 -+ 0.707, shifted by at most d.
    const double wall_err =
        worst_in_box(*t, scene, "wall", Vec3(-3, 0.95, -0.9), Vec3(-2, 2.05, 0.9), want.R, n_wall);
    EXPECT_GT(n_floor, 500);
    EXPECT_GT(n_wall, 500);
    EXPECT_LT(floor_err, 0.01) << "T " << want.T;
    EXPECT_LT(wall_err, 0.01) << "R " << want.R;
    const LedgerEntry& e = t->ledger().back();
    EXPECT_LE(e.relative_error(), 1e-9) << format_ledger(e);
    std::printf("slab 45 deg: T %.5f worst %.2e (%d texels), R %.5f worst %.2e (%d texels)\n",
                want.T, floor_err, n_floor, want.R, wall_err, n_wall);
}

// Where a ray parallel to the axis at height h crosses the axis behind a ball of radius R
// and index n, from its centre (exact: Snell at entry and exit).
double marginal_focus(double R, double n, double h) {
    const double i = std::asin(h / R), t = std::asin(std::sin(i) / n);
    const double deviation = 2.0 * (i - t), exit = 2.0 * t - i;  // exit point's polar angle
    const double x = R * std::sin(exit), y = R * std::cos(exit);
    return y + x / std::tan(deviation);
}

// A ball lens (n = 1.5, radius 0.5, smooth) under parallel light through a small aperture
// (a square hole of half-width 0.08): the paraxial focus lies f = n R / (2 (n - 1)) = 0.75
// below its centre (the aperture's marginal rays, traced exactly, cross the axis 0.006 to
// 0.012 closer). Floors (texels of 0.005) are placed at f + 0.02 k, k = -3..3; the
// caustic's spot on each has the mean square radius r^2(k) (the texels near the axis
// weighted by their power), which a converging and then diverging cone makes quadratic in
// k. Its vertex is the focus.
TEST(GlassTransport, BallLensFocusesAtTheParaxialFocalLength) {
    const double R = 0.5, n = 1.5, f = n * R / (2.0 * (n - 1.0)), texel = 0.005, step = 0.02;
    const double centre = 2.0;
    // A black screen at height 2.6 with the hole over the ball: four quads facing up.
    std::string screen;
    auto quad = [&](double x0, double x1, double z0, double z1) {
        screen += fmt::format(
            R"(, {{"type": "polygon", "material": "black", "vertices": [[{}, 2.6, {}],
               [{}, 2.6, {}], [{}, 2.6, {}], [{}, 2.6, {}]]}})",
            x0, z0, x0, z1, x1, z1, x1, z0);
    };
    quad(-1, -0.08, -1, 1);
    quad(0.08, 1, -1, 1);
    quad(-0.08, 0.08, -1, -0.08);
    quad(-0.08, 0.08, 0.08, 1);
    // Least squares of r^2 = a k^2 + b k + c over the seven floors.
    double S[5] = {0, 0, 0, 0, 0}, Sy[3] = {0, 0, 0}, peak = 0.0;
    for (int k = -3; k <= 3; ++k) {
        const double y = centre - f - k * step;
        const std::string json = fmt::format(
            R"({{"materials": {{"white": {{"diffuse": [0.5, 0.5, 0.5]}},
                               "black": {{"diffuse": [0, 0, 0]}},
                               "glass": {{"dielectric": {{"ior": {}}}}}}},
                  "settings": {{"texel_size": {}}},
                  "objects": [
                    {{"type": "polygon", "material": "white", "name": "floor",
                      "vertices": [[-0.075, {}, -0.075], [-0.075, {}, 0.075], [0.075, {}, 0.075], [0.075, {}, -0.075]]}},
                    {{"type": "sphere", "material": "glass", "center": [0, {}, 0], "radius": {},
                      "subdivisions": 4}}{}],
                  "lights": [{{"type": "directional", "direction": [0, -1, 0],
                              "irradiance": [1, 1, 1]}}]}})",
            n, texel, y, y, y, y, centre, R, screen);
        const Scene scene = scene_from_json(json);
        const auto t = run_transport(scene, params(33, 16, 4, 1));
        EXPECT_LE(t->ledger().back().relative_error(), 1e-9);
        const Chart& c = chart_named(scene, "floor");
        double power = 0.0, moment = 0.0;
        for (size_t q = 0; q < size_t(c.texels.count()); ++q) {
            Vec3 lo, hi;
            texel_bounds(scene, c, q, lo, hi);
            const Vec3 mid = 0.5 * (lo + hi);
            const double r2 = mid.x * mid.x + mid.z * mid.z;
            if (r2 > 0.05 * 0.05) continue;
            const double p = t->texture_maps().total[t->texture_maps().begin(c.id) + q].x;
            power += p;
            moment += p * r2;
            peak = std::max(peak, texel_irradiance(*t, c, q));
        }
        const double r2 = moment / power;
        std::printf("ball lens: floor %+.2f from f: spot rms radius %.4f\n", k * step,
                    std::sqrt(r2));
        for (int e = 0; e < 5; ++e) S[e] += std::pow(double(k), e);
        for (int e = 0; e < 3; ++e) Sy[e] += r2 * std::pow(double(k), e);
    }
    // Normal equations [S4 S3 S2; S3 S2 S1; S2 S1 S0] (a b c) = (Sy2 Sy1 Sy0); odd sums
    // vanish over k = -3..3, so b = Sy1 / S2 and a, c from the even pair.
    const double b = Sy[1] / S[2];
    const double a = (Sy[2] * S[0] - Sy[0] * S[2]) / (S[4] * S[0] - S[2] * S[2]);
    ASSERT_GT(a, 0.0) << "no minimum of the spot's size";
    // The spot is smallest at the circle of least confusion, between the marginal rays'
    // focus (the aperture's corners, h = 0.08 sqrt 2) and the paraxial one: within a texel
    // of that range.
    const double at = -b / (2.0 * a) * step, marginal = marginal_focus(R, n, 0.08 * std::sqrt(2.0));
    std::printf(
        "ball lens: the spot is smallest %+.4f from the paraxial f (marginal focus %+.4f)\n", at,
        marginal - f);
    EXPECT_GE(at, marginal - f - texel);
    EXPECT_LE(at, texel);
    // Focused: the aperture's light (E over 0.16^2, less two surfaces' reflection) on a few
    // texels, far above the E = 1 of the open floor.
    EXPECT_GT(peak, 10.0);
}

// Point and spot lights through absorbing glass (a faceted ball, whose facets' edges cut
// beams and whose internal reflections chain): every watt is booked, each cycle, and what
// the lights' beams leave unresolved (cut at a facet's edge, or a branch too weak to
// follow) stays a small part of what they emit.
TEST(GlassTransport, LedgerClosesWithPointAndSpotThroughGlass) {
    const Scene scene = scene_from_json(R"({
      "materials": {"white": {"diffuse": [0.5, 0.5, 0.5]},
                    "glass": {"dielectric": {"ior": 1.5, "absorption": [0.5, 0.1, 0.0]}}},
      "settings": {"texel_size": 0.15},
      "objects": [
        {"type": "polygon", "material": "white", "name": "floor",
         "vertices": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]},
        {"type": "sphere", "material": "glass", "center": [0, 0.5, 0], "radius": 0.3,
         "subdivisions": 0, "smooth": false}],
      "lights": [
        {"type": "point", "position": [0.1, 1.7, 0.2], "power": [20, 15, 10]},
        {"type": "spot", "position": [-0.4, 1.5, 0.1], "direction": [0.4, -1, -0.1],
         "inner_deg": 10, "outer_deg": 25, "intensity": [4, 4, 4]}]})");
    const auto t = run_transport(scene, params(33, 16, 4, 2));
    for (const LedgerEntry& e : t->ledger()) {
        EXPECT_LE(e.relative_error(), 1e-9) << format_ledger(e);
        for (int c = 0; c < 3; ++c) EXPECT_LT(e.lost.cut_beam[c], 0.01 * e.emitted[c]);
    }
    const LedgerEntry& e = t->ledger().back();
    std::printf("point + spot through glass: cut %.2e of the emission\n",
                e.lost.cut_beam.x / e.emitted.x);
}

// Dim beams land coarse (PropagateParams::light_dim): a smooth glass ball under a point light
// in a closed room, whose light after several internal reflections sprays over the walls in
// beams far dimmer than the direct light. Against the same shot with every beam split to
// half a texel (light_dim 0): the texels' sum agrees within 10^-5 (what differs is the
// part booked as cut where a beam crosses a path's rim, lost.cut_beam: a dim beam is cut
// coarser), no texel's first-cycle light moves by more than 1 % of the mean texel's (a dim
// beam carries under 10^-3 of the mean irradiance and lands over at most 4 texels: 1 %
// allows ten such layers on one texel), and the shot needs fewer beams.
TEST(GlassTransport, DimBeamsLandWithinAHundredthOfTheMeanTexel) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "a numerical comparison of two 10-second shots; nothing new for ASan";
#endif
    const Scene scene = scene_from_json(R"({
      "materials": {"white": {"diffuse": [0.5, 0.5, 0.5]},
                    "glass": {"dielectric": {"ior": 1.5}}},
      "settings": {"texel_size": 0.1},
      "objects": [
        {"type": "box", "material": "white", "min": [-1, 0, -1], "max": [1, 2, 1], "flip": true},
        {"type": "sphere", "material": "glass", "center": [0, 0.5, 0], "radius": 0.3,
         "subdivisions": 3}],
      "lights": [{"type": "point", "position": [0.2, 1.5, 0.1], "power": [20, 20, 20]}]})");
    auto p = params(33, 16, 4, 1);
    p.light_dim = 0.0;
    const auto exact = run_transport(scene, p);
    p.light_dim = 1e-3;
    const auto dim = run_transport(scene, p);
    const std::vector<Rgb>& a = exact->texture_maps().total;
    const std::vector<Rgb>& b = dim->texture_maps().total;
    ASSERT_EQ(a.size(), b.size());
    double sum_a = 0.0, sum_b = 0.0, worst = 0.0;
    for (size_t k = 0; k < a.size(); ++k) sum_a += a[k].x, sum_b += b[k].x;
    const double mean = sum_a / double(a.size());
    for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(b[k].x - a[k].x) / mean);
    const int64_t leaves_exact = exact->light_beams().leaves,
                  leaves_dim = dim->light_beams().leaves;
    std::printf(
        "dim beams: worst texel moved by %.2e of the mean texel, all texels' sum by "
        "%.2e; %lld leaf beams, %lld with every beam split to half a texel\n",
        worst, sum_b / sum_a - 1.0, (long long)leaves_dim, (long long)leaves_exact);
    EXPECT_NEAR(sum_b, sum_a, 1e-5 * sum_a);
    EXPECT_LE(worst, 0.01);
    EXPECT_LT(leaves_dim, leaves_exact);
    for (const auto* t : {exact.get(), dim.get()})
        EXPECT_LE(t->ledger().back().relative_error(), 1e-9);
}

}  // namespace
}  // namespace vlf
