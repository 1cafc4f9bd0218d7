// The path-traced reference with glass (render/pathtrace.hpp, render/light_tracer.hpp,
// render/glass_vertex.hpp): a glass slab transmits the multiple-reflection slab
// transmittance, with Beer-Lambert absorption, both for a directional light (light-traced
// caustic) and for an area light (eye paths refracting through it); a glass ball lens
// focuses a directional light at f = nR / (2 (n - 1)) as exact ray optics predicts; a
// closed furnace with glass inside still gives Le / (1 - rho); mirror chains are counted
// once between image sources and the light tracer; and the light tracer's image does not
// depend on the thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "test_util.hpp"
#include "vlf/core/fresnel.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/render/light_tracer.hpp"
#include "vlf/render/pathtrace.hpp"
#include "vlf/scene/raycaster.hpp"

namespace vlf {
namespace {

constexpr double kN = 1.5;  // the glass's index in every scene here

// The mean of an image's pixels.
Rgb image_mean(const Image& im) {
    Rgb sum(0.0);
    for (const Rgb& p : im.pixels) sum += p;
    return sum / double(im.pixels.size());
}

// The path-traced image of `scene` through `camera` (user units), w x h pixels, with
// `light_paths` particles in all for the caustic pass (0: none).
Image trace(const Scene& scene, const Camera& camera, int w, int h, int spp, double light_paths,
            uint64_t seed = 1) {
    const RayCaster caster(scene);
    const PathTracer tracer(scene, caster);
    const PinholeCamera cam(camera, scene.normalisation, w, h);
    PathTraceSettings s;
    s.width = w;
    s.height = h;
    s.spp = spp;
    s.seed = seed;
    s.light_paths_per_sample = light_paths / (double(w) * h * spp);
    return tracer.render(cam, s);
}

// Transmittance of a parallel glass slab for light meeting it at cos_i, per channel: the
// interface reflectance R (unpolarised Fresnel, the same at both faces) and the internal
// transmittance tau = exp(-sigma d / cos_t) summed over the internal reflections:
// T = (1 - R)^2 tau / (1 - R^2 tau^2) (Born & Wolf §1.6; (1 - R)^2 / (1 - R^2) without
// absorption). Unpolarised R at every bounce is what the renderer models.
Rgb slab_transmittance(double cos_i, double d, const Rgb& sigma) {
    const double R = fresnel_dielectric(cos_i, 1.0 / kN);
    const double sin_t = std::sqrt(1.0 - cos_i * cos_i) / kN;
    const double cos_t = std::sqrt(1.0 - sin_t * sin_t);
    Rgb T;
    for (int c = 0; c < 3; ++c) {
        const double tau = std::exp(-sigma[c] * d / cos_t);
        T[c] = (1.0 - R) * (1.0 - R) * tau / (1.0 - R * R * tau * tau);
    }
    return T;
}

void expect_rel(double got, double want, double rel, const std::string& what) {
    EXPECT_NEAR(got / want, 1.0, rel) << what << ": got " << got << ", want " << want;
}

// A diffuse patch (rho 0.5, 0.3 x 0.3 at y = 0 around the origin) under a glass slab
// (thickness 0.1, bottom at y = 0.5), seen from a camera at y = 0.4 looking straight down
// at the patch's middle (the image covers +-0.1 of it). Nothing else: light that misses the
// patch escapes, and the patch's light coming back to it off the slab's underside is
// R(0) x its solid angle (0.09 sr) x rho/pi ~ 6e-4 of it.
std::string slab_scene(const std::string& extra_objects, const std::string& lights,
                       const std::string& slab_x = "0.8", const std::string& slab_z = "0.4") {
    return R"({
  "materials": {"patch": {"diffuse": [0.5, 0.5, 0.5]},
                "glass": {"dielectric": {"ior": 1.5, "absorption": [0, 2, 6]}},
                "lamp": {"emission": [3, 3, 3]}},
  "objects": [
    {"type": "polygon", "material": "patch",
     "vertices": [[-0.15, 0, -0.15], [-0.15, 0, 0.15], [0.15, 0, 0.15], [0.15, 0, -0.15]]},
    {"type": "box", "min": [-)" +
           slab_x + ", 0.5, -" + slab_z + R"(], "max": [)" + slab_x + ", 0.6, " + slab_z +
           R"(], "material": "glass"})" + extra_objects + R"(],
  "lights": [)" +
           lights + R"(],
  "cameras": [{"name": "down", "eye": [0, 0.4, 0], "look_at": [0, 0, 0], "up": [0, 0, 1],
               "fov_y_deg": 28}]
})";
}

// (a) A directional light at 40 deg through the slab: the patch's radiance is
// rho/pi E cos 40 T_slab(40 deg), per channel (sigma = 0, 2, 6 per unit: tau = 1, 0.80,
// 0.51). Only the light tracer can find it (the eye's shadow ray meets glass). Noise: about
// 1e4 particles reach the seen part of the patch, < 1 % per channel.
TEST(RenderPathtraceGlass, SlabTransmitsDirectionalLightWithFresnelAndAbsorption) {
    const double th = 40.0 * kPi / 180.0;
    const Scene scene = test::scene_from_json(slab_scene(
        "", R"({"type": "directional", "direction": [)" + std::to_string(std::sin(th)) + R"(, )" +
                std::to_string(-std::cos(th)) + R"(, 0], "irradiance": [2, 2, 2]})"));
    const Image im = trace(scene, scene.cameras[0], 8, 8, 1, 1.2e6);
    const Rgb got = image_mean(im);
    const Rgb T = slab_transmittance(std::cos(th), 0.1, Rgb(0, 2, 6));
    const Rgb want = 0.5 / kPi * 2.0 * std::cos(th) * T;
    std::printf(
        "slab, directional 40 deg: T_slab = (%.4f %.4f %.4f); radiance got (%.5f %.5f %.5f)"
        " want (%.5f %.5f %.5f)\n",
        T.x, T.y, T.z, got.x, got.y, got.z, want.x, want.y, want.z);
    for (int c = 0; c < 3; ++c) expect_rel(got[c], want[c], 0.025, "channel " + std::to_string(c));
    // Without glass in the way T = 1: 8.6 %, 27 % and 53 % more — far outside the tolerance.
    // Without the light paths there is nothing at all.
    EXPECT_EQ(image_mean(trace(scene, scene.cameras[0], 4, 4, 1, 0.0)), Rgb(0.0));
}

// (a') A square lamp (Le = 3, 1 x 1 at y = 2, facing down) seen from the patch through the
// slab: eye paths from the patch that refract through the slab and hit the lamp (no
// shadow ray can: glass blocks it). Expected: rho/pi x the integral over the patch's
// hemisphere of Le T_slab(theta) cos theta over the directions whose ray — displaced
// sideways in the slab, parallel after it — lands on the lamp; computed here by quadrature
// over the seen square and the directions. The displacement makes the lamp look ~4 %
// larger, so an eye path that went straight through would be off by that. The slab is wide
// (5 x 5) here: the side walls of a narrow one reflect (totally, from inside) light of the
// lamp onto the patch too, several % near its rim — real light, but not in the formula.
TEST(RenderPathtraceGlass, SlabTransmitsAreaLightToEyePaths) {
    const Scene scene = test::scene_from_json(slab_scene(R"(,
    {"type": "polygon", "material": "lamp",
     "vertices": [[-0.5, 2, -0.5], [0.5, 2, -0.5], [0.5, 2, 0.5], [-0.5, 2, 0.5]]})",
                                                         "", "2.5", "2.5"));
    const Image im = trace(scene, scene.cameras[0], 8, 8, 4096, 0.0);
    // Quadrature: points of the seen square (+-0.0998: 0.4 tan 14 deg), directions on a
    // (cos theta, phi) grid of the cone that can reach the lamp.
    const double half = 0.4 * std::tan(14.0 * kPi / 180.0);
    const int np = 6, nt = 400, nphi = 256;
    const double cos_min = 0.7;  // the lamp's corners are within 30 deg of every point
    Rgb sum(0.0);
    for (int a = 0; a < np; ++a)
        for (int b = 0; b < np; ++b) {
            const double px = (2.0 * (a + 0.5) / np - 1.0) * half;
            const double pz = (2.0 * (b + 0.5) / np - 1.0) * half;
            Rgb E(0.0);
            for (int i = 0; i < nt; ++i) {
                // cos theta uniform in [cos_min, 1]: E = int Le T cos dw, dw = dcos dphi.
                const double c = cos_min + (1.0 - cos_min) * (i + 0.5) / nt;
                const double s = std::sqrt(1.0 - c * c), tan_i = s / c;
                const double sin_t = s / kN, tan_t = sin_t / std::sqrt(1.0 - sin_t * sin_t);
                // Horizontal reach at y = 2: 0.5 and 1.4 of air, 0.1 of glass.
                const double reach = 1.9 * tan_i + 0.1 * tan_t;
                const Rgb T = slab_transmittance(c, 0.1, Rgb(0, 2, 6));
                for (int j = 0; j < nphi; ++j) {
                    const double phi = 2.0 * kPi * (j + 0.5) / nphi;
                    const double x = px + reach * std::cos(phi), z = pz + reach * std::sin(phi);
                    if (std::abs(x) <= 0.5 && std::abs(z) <= 0.5)
                        E += 3.0 * T * c * ((1.0 - cos_min) / nt) * (2.0 * kPi / nphi);
                }
            }
            sum += E / double(np * np);
        }
    const Rgb want = 0.5 / kPi * sum;
    const Rgb got = image_mean(im);
    std::printf("slab, area lamp: radiance got (%.5f %.5f %.5f) want (%.5f %.5f %.5f)\n", got.x,
                got.y, got.z, want.x, want.y, want.z);
    // Noise: ~12 % of the 262k paths' bounces reach the lamp, 0.5 %; quadrature < 0.3 %.
    for (int c = 0; c < 3; ++c) expect_rel(got[c], want[c], 0.02, "channel " + std::to_string(c));
}

// (b) A glass ball (R = 1, n = 1.5, smooth) in a directional light travelling +x focuses it
// at the paraxial focus f = n R / (2 (n - 1)) = 1.5 from its centre. A diffuse wall facing
// the ball at x = X (in the ball's shadow) is seen straight on by a camera 0.15 in front of
// it, the image covering the square |y|, |z| <= 0.1: the image plane is parallel to the
// wall, so the image mean is rho/pi x the wall's mean irradiance over the square. The
// prediction traces the meridional rays exactly (entry at height h, refraction, exit,
// deviation 2 (i - r)) with transmittance (1 - F)^2, and sums E 2 pi h dh (1 - F)^2 times
// the part of the ring of radius |y(h)| inside the square; internal reflections (< 0.3 %
// of the flux, scattered) are left out.
double ball_lens_window_irradiance(double X, double a) {
    const int n = 200000;
    double flux = 0.0;
    for (int k = 0; k < n; ++k) {
        const double h = (k + 0.5) / n;  // R = 1
        const double i = std::asin(h), r = std::asin(h / kN);
        const double F = fresnel_dielectric(std::cos(i), 1.0 / kN);
        const double ex = std::cos(2 * r - i), ey = std::sin(2 * r - i);  // exit point
        const double y = std::abs(ey + (X - ex) * std::tan(-2.0 * (i - r)));
        double inside = 0.0;  // the part of the circle of radius y inside the square
        if (y <= a)
            inside = 1.0;
        else if (y < a * std::sqrt(2.0))
            inside = 1.0 - 4.0 / kPi * std::acos(a / y);
        flux += 2.0 * kPi * h * (1.0 / n) * (1.0 - F) * (1.0 - F) * inside;
    }
    return flux / (4.0 * a * a);  // per unit irradiance of the light
}

Rgb ball_lens_radiance(double X, double particles) {
    const std::string x = std::to_string(X);
    const Scene scene = test::scene_from_json(R"({
  "materials": {"wall": {"diffuse": [0.5, 0.5, 0.5]}, "glass": {"dielectric": {"ior": 1.5}}},
  "objects": [
    {"type": "sphere", "center": [0, 0, 0], "radius": 1, "subdivisions": 4, "material": "glass"},
    {"type": "polygon", "material": "wall",
     "vertices": [[)" + x + R"(, -0.6, -0.6], [)" +
                                              x + R"(, -0.6, 0.6], [)" + x + R"(, 0.6, 0.6], [)" +
                                              x + R"(, 0.6, -0.6]]}],
  "lights": [{"type": "directional", "direction": [1, 0, 0], "irradiance": [1, 1, 1]}]
})");
    Camera cam;
    cam.eye = Vec3(X - 0.15, 0, 0);  // outside the ball for X > 1.15
    cam.look_at = Vec3(X, 0, 0);
    cam.up = Vec3(0, 1, 0);
    cam.fov_y_deg = 2.0 * std::atan(0.1 / 0.15) * 180.0 / kPi;
    return image_mean(trace(scene, cam, 8, 8, 1, particles));
}

TEST(RenderPathtraceGlass, BallLensFocusesAtNROverTwoNMinusOne) {
    const double f = kN / (2.0 * (kN - 1.0));
    ASSERT_DOUBLE_EQ(f, 1.5);
    const double a = 0.1;
    const double at_focus = 0.5 / kPi * ball_lens_window_irradiance(f, a);
    const double beyond = 0.5 / kPi * ball_lens_window_irradiance(f + 1.0, a);
    const double before = 0.5 / kPi * ball_lens_window_irradiance(f - 0.25, a);
    const Rgb got_focus = ball_lens_radiance(f, 6e5);
    const Rgb got_beyond = ball_lens_radiance(f + 1.0, 6e5);
    const Rgb got_before = ball_lens_radiance(f - 0.25, 6e5);
    std::printf(
        "ball lens: radiance at f %.4f (ray optics %.4f), f+1 %.4f (%.4f), f-0.25 %.4f "
        "(%.4f); no lens: %.4f\n",
        got_focus.x, at_focus, got_beyond.x, beyond, got_before.x, before, 0.5 / kPi);
    // The concentration at the paraxial focus (30x the unfocused light) and its fall-off
    // beyond; before it the marginal rays, which cross the axis nearer the ball (spherical
    // aberration), gather into the square too, so it is brighter still there.
    EXPECT_GT(at_focus, 20.0 * 0.5 / kPi);
    EXPECT_GT(at_focus, 4.0 * beyond);
    EXPECT_GT(before, at_focus);
    // Noise: > 1.5e4 particles in the square at the focus (0.8 %), ~2e3 beside it (2.5 %);
    // the facets of a 5120-triangle ball with interpolated normals add ~1 %.
    for (int c = 0; c < 3; ++c) {
        expect_rel(got_focus[c], at_focus, 0.05, "at the focus");
        expect_rel(got_beyond[c], beyond, 0.08, "1 beyond the focus");
        expect_rel(got_before[c], before, 0.06, "0.25 before the focus");
    }
}

// (c) A closed furnace (every face emits Le = 1 and reflects rho = 0.5) with a glass ball and
// a glass block inside: the radiance is Le / (1 - rho) = 2 everywhere, seen directly, in
// the glass's reflection or through it — glass neither adds nor loses light. Absorbing
// glass must darken what is seen through it.
TEST(RenderPathtraceGlass, FurnaceWithGlassInsideStaysLeOverOneMinusRho) {
    auto furnace = [](const std::string& absorption) {
        return test::scene_from_json(R"({
  "materials": {"glow": {"diffuse": [0.5, 0.5, 0.5], "emission": [1, 1, 1]},
                "glass": {"dielectric": {"ior": 1.5, "absorption": )" +
                                     absorption + R"(}}},
  "objects": [
    {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "flip": true, "material": "glow"},
    {"type": "sphere", "center": [0, 0, 0.2], "radius": 0.45, "subdivisions": 3,
     "material": "glass"},
    {"type": "box", "min": [-0.8, -0.9, -0.2], "max": [-0.3, -0.3, 0.4], "rotate_y_deg": 20,
     "material": "glass"}],
  "cameras": [{"name": "in", "eye": [0.1, 0.1, -0.95], "look_at": [0, 0, 0.2], "up": [0, 1, 0],
               "fov_y_deg": 60}]
})");
    };
    const Scene clear = furnace("[0, 0, 0]");
    const Image im = trace(clear, clear.cameras[0], 12, 12, 1024, 0.0);
    double worst = 0.0;
    Rgb mean(0.0);
    for (const Rgb& p : im.pixels) {
        mean += p / double(im.pixels.size());
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(p[c] / 2.0 - 1.0));
    }
    std::printf("furnace with glass: mean (%.4f %.4f %.4f), want 2; worst pixel %.4f\n", mean.x,
                mean.y, mean.z, worst);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], 2.0, 0.01);
    EXPECT_LT(worst, 0.08);  // 1024 paths a pixel: a few % of noise per pixel
    // Absorbing glass (sigma = 3 per unit in blue): the pixels through the ball darken in
    // blue only.
    const Scene tinted = furnace("[0, 0, 3]");
    const Image dark = trace(tinted, tinted.cameras[0], 12, 12, 256, 0.0);
    const Rgb centre = dark.at(6, 6);
    EXPECT_NEAR(centre.x, 2.0, 0.2);
    EXPECT_LT(centre.z, 0.7 * centre.x);
}

// Mirror chains are counted once: a point light between two facing mirrors over a floor.
// The eye's image sources take the chains of up to two mirrors, the light tracer the longer
// ones (it splats none of the shorter). The floor point (1, 0, 0) gets I cos / r^2 from
// the light's images at x = 4k (k mirrors, rho_s^|k|); a vertical mirror never sends the
// floor's light back to it.
TEST(RenderPathtraceGlass, MirrorChainsCountedOnceBetweenImagesAndLightPaths) {
    const Scene scene = test::scene_from_json(R"({
  "materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]}, "mirror": {"specular": [0.9, 0.9, 0.9]}},
  "objects": [
    {"type": "polygon", "material": "floor",
     "vertices": [[-2, 0, -1], [-2, 0, 1], [2, 0, 1], [2, 0, -1]]},
    {"type": "polygon", "material": "mirror",
     "vertices": [[2, 0, -1], [2, 0, 1], [2, 2, 1], [2, 2, -1]]},
    {"type": "polygon", "material": "mirror",
     "vertices": [[-2, 0, -1], [-2, 2, -1], [-2, 2, 1], [-2, 0, 1]]}],
  "lights": [{"type": "point", "position": [0, 1, 0], "intensity": [10, 10, 10]}]
})");
    {
        const RayCaster caster(scene);
        const PathTracer tracer(scene, caster);
        EXPECT_EQ(tracer.image_source_order(), 2);
        EXPECT_TRUE(LightTracer(scene, caster, tracer.image_source_order()).needed());
    }
    // A camera 2.5 above the floor's middle sees it all but 0.1 at the mirrors' feet (so no
    // mirror): 16 x 8 pixels over |x| <= 1.9, |z| <= 0.95.
    Camera cam;
    cam.eye = Vec3(0, 2.5, 0);
    cam.look_at = Vec3(0, 0, 0);
    cam.up = Vec3(0, 0, 1);
    cam.fov_y_deg = 2.0 * std::atan(0.38) * 180.0 / kPi;
    const int w = 16, h = 8;
    const Image eye_only = trace(scene, cam, w, h, 64, 0.0);
    const Image both = trace(scene, cam, w, h, 64, 2e6);
    // The expectation: the image's mean over an 8 x 8 grid of rays per pixel (the eye paths'
    // 8 x 8 strata sample the same pixel areas).
    const PinholeCamera pin(cam, scene.normalisation, w, h);
    double want = 0.0, want_short = 0.0;
    const int g = 8;
    for (int y = 0; y < h * g; ++y)
        for (int x = 0; x < w * g; ++x) {
            const Vec3 d = pin.direction((x + 0.5) / g, (y + 0.5) / g);
            const Vec3 p = cam.eye + (cam.eye.y / -d.y) * d;
            for (int k = -60; k <= 60; ++k) {
                const Vec3 v(4.0 * k, 1.0, 0.0);
                const double r = glm::length(v - p);
                const double e = std::pow(0.9, std::abs(k)) * 10.0 * (v.y / r) / (r * r);
                const double L = 0.5 / kPi * e / (w * h * g * g);
                want += L;
                if (std::abs(k) <= 2) want_short += L;
            }
        }
    const double got_eye = image_mean(eye_only).x, got = image_mean(both).x;
    std::printf(
        "mirror chains: eye only %.6f (orders <= 2: %.6f), with light paths %.6f (all "
        "orders: %.6f; orders >= 3 are %.2f %%)\n",
        got_eye, want_short, got, want, 100.0 * (want / want_short - 1.0));
    EXPECT_NEAR(got_eye / want_short, 1.0, 2e-3);  // image sources: no noise but the jitter
    // The light tracer adds the orders >= 3 (0.38 %) and nothing else: an order-0..2 image
    // counted twice would add >= 0.9^2 x ~1 %, and leaving out the long chains 0.38 %.
    EXPECT_NEAR(got / want, 1.0, 1.5e-3);
    EXPECT_GE(got, got_eye);
}

// One mirror and no glass: every chain is an image source's, the light tracer has nothing
// to do; glass added makes it needed.
TEST(RenderPathtraceGlass, LightTracerOnlyWhereImagesCannotReach) {
    const std::string lights =
        R"(, "lights": [{"type": "point", "position": [0, 1, 0], "intensity": [1, 1, 1]}]})";
    const std::string base = R"({
  "materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]}, "mirror": {"specular": [0.9, 0.9, 0.9]},
                "glass": {"dielectric": {"ior": 1.5}}},
  "objects": [
    {"type": "polygon", "material": "floor",
     "vertices": [[-2, 0, -1], [-2, 0, 1], [2, 0, 1], [2, 0, -1]]},
    {"type": "polygon", "material": "mirror",
     "vertices": [[2, 0, -1], [2, 0, 1], [2, 2, 1], [2, 2, -1]]})";
    const Scene one_mirror = test::scene_from_json(base + "]" + lights);
    const Scene with_glass = test::scene_from_json(
        base +
        R"(, {"type": "box", "min": [-0.5, 0.2, -0.5], "max": [0, 0.4, 0], "material": "glass"}])" +
        lights);
    const RayCaster c1(one_mirror), c2(with_glass);
    EXPECT_FALSE(LightTracer(one_mirror, c1, 2).needed());
    EXPECT_TRUE(LightTracer(with_glass, c2, 2).needed());
}

// A glass ball under a point light, light paths on: the same image on one thread and on two,
// bit for bit, and a caustic in it.
TEST(RenderPathtraceGlass, CausticImageIndependentOfThreadCount) {
    const Scene scene = test::scene_from_json(R"({
  "materials": {"floor": {"diffuse": [0.7, 0.7, 0.7]},
                "glass": {"dielectric": {"ior": 1.5, "absorption": [0.1, 0.2, 0.3]}}},
  "objects": [
    {"type": "polygon", "material": "floor",
     "vertices": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]},
    {"type": "sphere", "center": [0, 1, 0], "radius": 0.4, "subdivisions": 3,
     "material": "glass"}],
  "lights": [{"type": "point", "position": [0, 3, 0], "intensity": [20, 20, 20]}],
  "cameras": [{"name": "c", "eye": [0, 3, -3], "look_at": [0, 0, 0], "up": [0, 1, 0],
               "fov_y_deg": 50}]
})");
    Image one, two;
    {
        ThreadLimit limit(1);
        one = trace(scene, scene.cameras[0], 24, 16, 4, 2e5);
    }
    {
        ThreadLimit limit(2);
        two = trace(scene, scene.cameras[0], 24, 16, 4, 2e5);
    }
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    for (size_t k = 0; k < one.pixels.size(); ++k) EXPECT_EQ(one.pixels[k], two.pixels[k]) << k;
    const Image eye_only = trace(scene, scene.cameras[0], 24, 16, 4, 0.0);
    EXPECT_GT(image_mean(one).x, image_mean(eye_only).x);  // the caustic's light
}

}  // namespace
}  // namespace vlf
