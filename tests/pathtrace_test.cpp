// The path-traced reference (render/pathtrace.hpp, DESIGN §7–8): a furnace converges to
// Le / (1 - rho), and the image does not depend on the thread count; delta lights (point,
// spot, directional, the sun's disc; directly and as image sources in planar mirrors) give
// the analytic radiance rho/pi E of a Lambertian floor.
#include "vlf/render/pathtrace.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/render/image_metrics.hpp"
#include "vlf/render/render.hpp"
#include "vlf/scene/scene_loader.hpp"

namespace vlf {
namespace {

namespace fs = std::filesystem;

// Closed furnace: an inward-facing box plus a tilted block inside, every face emitting
// Le and reflecting rho (different per channel, up to 0.8 so long paths matter).
constexpr const char* kFurnace = R"({
  "materials": {"glow": {"diffuse": [0.3, 0.6, 0.8], "emission": [1.0, 0.5, 2.0]}},
  "objects": [
    {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "flip": true, "material": "glow"},
    {"type": "box", "min": [-0.3, -0.99, -0.3], "max": [0.3, -0.2, 0.3], "rotate_y_deg": 30,
     "material": "glow"}],
  "cameras": [{"name": "in", "eye": [0.1, 0.2, -0.9], "look_at": [0, -0.4, 0.5], "up": [0, 1, 0],
               "fov_y_deg": 90}]
})";

TEST(RenderPathtrace, FurnaceConvergesToLeOverOneMinusRho) {
    const Scene scene = load_scene_from_string(kFurnace, "furnace.json", ".");
    const Bake bake = test::scene_only_bake(scene);
    const Renderer r(bake);
    RenderSettings s;
    s.width = 8;
    s.height = 8;
    s.mode = RenderMode::Pathtrace;
    s.spp = 16384;  // per-pixel noise ~0.5 % in the rho = 0.8 channel
    const Image im = r.render(scene.cameras[0], s);
    const Rgb want = Rgb(1.0, 0.5, 2.0) / (Rgb(1.0) - Rgb(0.3, 0.6, 0.8));
    Rgb mean(0.0), worst(0.0);
    for (const Rgb& p : im.pixels) {
        mean += p / double(im.pixels.size());
        worst = glm::max(worst, glm::abs(p / want - Rgb(1.0)));
    }
    std::printf(
        "furnace: want (%.4f %.4f %.4f) mean (%.4f %.4f %.4f) worst pixel rel. error "
        "(%.4f %.4f %.4f)\n",
        want.x, want.y, want.z, mean.x, mean.y, mean.z, worst.x, worst.y, worst.z);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(mean[c] / want[c], 1.0, 0.005) << "channel " << c;
        EXPECT_LT(worst[c], 0.02) << "channel " << c;
    }
}

TEST(RenderPathtrace, IndependentOfThreadCount) {
    const Scene scene = load_scene(test::source_path("scenes/cornell-mirrors.json"));
    const Bake bake = test::scene_only_bake(scene);
    const Renderer r(bake);
    RenderSettings s;
    s.width = 24;
    s.height = 20;
    s.mode = RenderMode::Pathtrace;
    s.spp = 8;
    Image one, two;
    {
        ThreadLimit limit(1);
        one = r.render(scene.cameras[0], s);
    }
    {
        ThreadLimit limit(2);
        two = r.render(scene.cameras[0], s);
    }
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    double sum = 0.0;
    for (size_t k = 0; k < one.pixels.size(); ++k) {
        EXPECT_EQ(one.pixels[k], two.pixels[k]) << "pixel " << k;
        sum += one.pixels[k].x;
    }
    EXPECT_GT(sum, 0.0);
    s.seed = 2;  // another seed, another image
    EXPECT_GT(relative_rmse(r.render(scene.cameras[0], s), one), 0.0);
}

// ---- delta lights (light.hpp): next-event estimation and image sources ----
//
// In these scenes every surface but the lit floor is black or a mirror perpendicular to the
// floor, and nothing is above the floor: a bounce from the floor escapes (or dies on black,
// or climbs on through a vertical mirror, which keeps its upward component). So the floor's
// radiance is exactly rho/pi E of the delta lights, and the estimate has no noise but the
// sun disc's: the tolerances below are rounding, or stated sampling noise.

constexpr double kRho = 0.5;

// The path-traced radiance of the surface at user point p (unit front normal `normal`),
// seen straight on from just in front of it: the mean of `paths` paths.
Rgb radiance_at(const Scene& scene, const PathTracer& tracer, const Vec3& p, const Vec3& normal,
                int paths = 16) {
    Pcg32 rng(11, 0);
    const Vec3 o = scene.normalisation.to_normalised(p) + 1e-3 * normal;
    Rgb sum(0.0);
    for (int i = 0; i < paths; ++i) sum += tracer.radiance(o, -normal, rng);
    return sum / double(paths);
}

void expect_rgb_near(const Rgb& got, const Rgb& want, double rel, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], rel * std::abs(want[c]) + 1e-300)
            << what << ", channel " << c << ": got " << got[c] << ", want " << want[c];
}

// A one-sided floor facing +y at y = 0, x in [-8, 12], z in [-10, 10] (its centre is not
// the origin and it is 20 units wide: the normalisation's centre and scale both matter),
// then `rest` (more objects, lights, materials' uses).
std::string floor_scene(const std::string& more_objects, const std::string& lights) {
    return R"({
  "materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]}, "black": {},
                "mirror": {"specular": [0.8, 0.6, 0.4]}},
  "objects": [{"type": "polygon", "material": "floor",
               "vertices": [[-8, 0, -10], [-8, 0, 10], [12, 0, 10], [12, 0, -10]]})" +
           more_objects + R"(],
  "lights": [)" +
           lights + "]}";
}

const Vec3 kUp(0, 1, 0);

TEST(RenderPathtraceLights, PointLightOverFloorIsIcosOverR2) {
    const Scene scene = load_scene_from_string(
        floor_scene("", R"({"type": "point", "position": [0, 2, 0], "intensity": [10, 20, 5]})"),
        "point.json", ".");
    ASSERT_NE(scene.normalisation.scale, 1.0);
    const RayCaster caster(scene);
    const PathTracer tracer(scene, caster);
    EXPECT_EQ(tracer.emitter_triangles(), 0);  // lit by the light alone
    const Rgb I(10, 20, 5);
    for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1.5, 0, 0.7), Vec3(3, 0, -2), Vec3(-6, 0, 5)}) {
        const Vec3 to_light = Vec3(0, 2, 0) - p;
        const double r = glm::length(to_light), cos_x = to_light.y / r;
        expect_rgb_near(radiance_at(scene, tracer, p, kUp), kRho / kPi * I * cos_x / (r * r), 1e-9,
                        "floor point (" + std::to_string(p.x) + ", " + std::to_string(p.z) + ")");
    }

    // The light below the floor reaches only its back: nothing (one-sided faces).
    const Scene below = load_scene_from_string(
        floor_scene("", R"({"type": "point", "position": [0, -2, 0], "intensity": [10, 20, 5]})"),
        "below.json", ".");
    const RayCaster below_caster(below);
    const PathTracer below_tracer(below, below_caster);
    EXPECT_EQ(radiance_at(below, below_tracer, Vec3(1, 0, 1), kUp), Rgb(0.0));

    // The whole renderer with no emitting face: a finite, lit image.
    const Bake bake = test::scene_only_bake(scene);
    const Renderer renderer(bake);
    RenderSettings s;
    s.width = 6;
    s.height = 4;
    s.mode = RenderMode::Pathtrace;
    s.spp = 4;
    Camera cam;
    cam.eye = Vec3(0, 8, -4);
    cam.look_at = Vec3(0, 0, 0);
    const Image im = renderer.render(cam, s);
    for (const Rgb& px : im.pixels)
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(px[c]));
            EXPECT_GT(px[c], 0.0);
        }
}

TEST(RenderPathtraceLights, SpotFalloffIsFullNoneAndSmoothstep) {
    const Scene scene = load_scene_from_string(
        floor_scene("", R"({"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0],
                            "inner_deg": 20, "outer_deg": 40, "intensity": [30, 30, 30]})"),
        "spot.json", ".");
    const RayCaster caster(scene);
    const PathTracer tracer(scene, caster);
    const double h = 2.0;
    // The floor point at angle theta off the axis, in the direction phi around it.
    auto at = [&](double theta_deg, double phi_deg) {
        const double d = h * std::tan(theta_deg * kPi / 180.0), phi = phi_deg * kPi / 180.0;
        return Vec3(d * std::cos(phi), 0, d * std::sin(phi));
    };
    auto unlimited = [&](double theta_deg) {  // a point light's radiance there
        const double c = std::cos(theta_deg * kPi / 180.0), r = h / c;
        return kRho / kPi * 30.0 * c / (r * r);
    };
    // Inside the inner cone: full.
    expect_rgb_near(radiance_at(scene, tracer, at(10, 30), kUp), Rgb(unlimited(10)), 1e-9,
                    "10 deg");
    // Beyond the outer cone: none.
    EXPECT_EQ(radiance_at(scene, tracer, at(50, 200), kUp), Rgb(0.0));
    // Between: smoothstep in cos theta, t = (cos 30 - cos 40) / (cos 20 - cos 40) = 0.576,
    // 3t^2 - 2t^3 = 0.613 (a linear falloff would give 0.576).
    const double c20 = std::cos(20 * kPi / 180), c30 = std::cos(30 * kPi / 180),
                 c40 = std::cos(40 * kPi / 180);
    const double t = (c30 - c40) / (c20 - c40), smooth = t * t * (3 - 2 * t);
    expect_rgb_near(radiance_at(scene, tracer, at(30, 120), kUp), Rgb(smooth * unlimited(30)), 1e-9,
                    "30 deg");
}

TEST(RenderPathtraceLights, DirectionalLightIsECosAndShadowed) {
    const Rgb E(2, 3, 4);
    {  // A floor tilted by 25 deg under a light straight down: rho/pi E cos 25.
        const Scene scene = load_scene_from_string(R"({
  "materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]}},
  "objects": [{"type": "polygon", "material": "floor", "rotate_z_deg": 25,
               "vertices": [[-5, 0, -5], [-5, 0, 5], [5, 0, 5], [5, 0, -5]]}],
  "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [2, 3, 4]}]})",
                                                   "tilted.json", ".");
        const RayCaster caster(scene);
        const PathTracer tracer(scene, caster);
        const Vec3 n = scene.faces[0].normal;
        const double cos25 = std::cos(25 * kPi / 180);
        ASSERT_NEAR(n.y, cos25, 1e-12);
        const Vec3 along = glm::normalize(glm::cross(n, Vec3(0, 0, 1)));  // in the plane
        for (const Vec3& p : {Vec3(0.0), 3.0 * along + Vec3(0, 0, 1), -2.0 * along})
            expect_rgb_near(radiance_at(scene, tracer, p, n), kRho / kPi * E * cos25, 1e-9,
                            "tilted floor");
    }
    // A black wall at x = 0, 1 high, under light travelling along (1, -1, 0)/sqrt 2: its
    // shadow on the floor reaches from x = 0 to x = 1.
    const std::string wall = R"(,
  {"type": "polygon", "material": "black",
   "vertices": [[0, 0, -3], [0, 0, 3], [0, 1, 3], [0, 1, -3]]})";
    const Scene scene =
        load_scene_from_string(floor_scene(wall, R"({"type": "directional", "direction": [1, -1, 0],
                              "irradiance": [2, 3, 4]})"),
                               "wall.json", ".");
    const RayCaster caster(scene);
    const PathTracer tracer(scene, caster);
    const Rgb lit = kRho / kPi * E * std::sqrt(0.5);
    expect_rgb_near(radiance_at(scene, tracer, Vec3(2, 0, 0), kUp), lit, 1e-9, "behind, lit");
    expect_rgb_near(radiance_at(scene, tracer, Vec3(-2, 0, 0), kUp), lit, 1e-9, "before, lit");
    EXPECT_EQ(radiance_at(scene, tracer, Vec3(0.5, 0, 0), kUp), Rgb(0.0));
    EXPECT_EQ(radiance_at(scene, tracer, Vec3(0.5, 0, 2.5), kUp), Rgb(0.0));
}

TEST(RenderPathtraceLights, SunDiscGivesEFacingItAndAPenumbra) {
    const Rgb E(2, 3, 4);
    {  // A 30 deg disc straight above: E on the floor facing its centre (by definition of
       // E), not E x the mean cosine over the disc (0.983). Noise: the sampled cosine varies
       // by < 3.5 %, so 4000 paths leave < 0.06 %.
        const Scene scene = load_scene_from_string(
            floor_scene("", R"({"type": "directional", "direction": [0, -1, 0],
                                "irradiance": [2, 3, 4], "angular_diameter_deg": 30})"),
            "sun.json", ".");
        const RayCaster caster(scene);
        const PathTracer tracer(scene, caster);
        expect_rgb_near(radiance_at(scene, tracer, Vec3(1, 0, 2), kUp, 4000), kRho / kPi * E, 0.003,
                        "wide disc, facing");
    }
    // The wall of the previous test under a 4 deg disc: the point on the edge of the
    // centre's shadow sees half the disc. Noise of that half: 0.5/sqrt(20000) = 0.35 %;
    // the lit half is the steeper one, its cosine 1.5 % above cos 45. Without the disc it
    // would be all or nothing.
    const std::string wall = R"(,
  {"type": "polygon", "material": "black",
   "vertices": [[0, 0, -3], [0, 0, 3], [0, 1, 3], [0, 1, -3]]})";
    const Scene scene =
        load_scene_from_string(floor_scene(wall, R"({"type": "directional", "direction": [1, -1, 0],
                              "irradiance": [2, 3, 4], "angular_diameter_deg": 4})"),
                               "penumbra.json", ".");
    const RayCaster caster(scene);
    const PathTracer tracer(scene, caster);
    const Rgb half = 0.5 * kRho / kPi * E * std::sqrt(0.5) * 1.015;
    expect_rgb_near(radiance_at(scene, tracer, Vec3(1, 0, 0), kUp, 20000), half, 0.02, "penumbra");
    EXPECT_EQ(radiance_at(scene, tracer, Vec3(0.5, 0, 0), kUp, 1000), Rgb(0.0));  // umbra
}

// A point light at (0, 1, 0) over the floor, a mirror at x = 2 facing it (y in [0, 2], z in
// [-1, 1]; rho_s = (0.8, 0.6, 0.4)) and two black cards: a floor point x gets I cos_1 / r_1^2
// directly and rho_s I cos_2 / r_2^2 from the light's image at (4, 1, 0), where the line from x to
// the image crosses the mirror's polygon and both legs are clear.
TEST(RenderPathtraceLights, MirrorImageSourceAddsRhoSOverImageDistance) {
    const std::string objects = R"(,
  {"type": "polygon", "material": "mirror",
   "vertices": [[2, 0, -1], [2, 0, 1], [2, 2, 1], [2, 2, -1]]},
  {"type": "polygon", "material": "black",
   "vertices": [[1.5, 0, -1], [1.5, 0, -0.2], [1.5, 0.3, -0.2], [1.5, 0.3, -1]]},
  {"type": "polygon", "material": "black",
   "vertices": [[1.5, 0.4, 0.2], [1.5, 0.4, 0.3], [1.5, 0.6, 0.3], [1.5, 0.6, 0.2]]})";
    const Scene scene = load_scene_from_string(
        floor_scene(objects,
                    R"({"type": "point", "position": [0, 1, 0], "intensity": [10, 10, 10]})"),
        "mirror.json", ".");
    const RayCaster caster(scene);
    const PathTracer tracer(scene, caster);
    ASSERT_EQ(tracer.mirror_faces(), 1);
    const Rgb I(10.0), rho_s(0.8, 0.6, 0.4);
    // I cos / r^2 at floor point p from a source at v, cos = v.y / r.
    auto e = [](const Vec3& p, const Vec3& v) {
        const double r = glm::length(v - p);
        return (v.y - p.y) / (r * r * r);
    };
    const Vec3 light(0, 1, 0), image(4, 1, 0);
    // (1, 0, 0): the image line meets the mirror at (2, 1/3, 0): both paths.
    const Vec3 both(1, 0, 0);
    expect_rgb_near(radiance_at(scene, tracer, both, kUp),
                    kRho / kPi * I * (e(both, light) + rho_s * e(both, image)), 1e-9,
                    "direct and mirrored");
    // (1, 0, -0.5): it would meet the mirror at (2, 1/3, -1/3), but the low black card at
    // x = 1.5 blocks the leg to the mirror (crossed at y = 1/6, z = -0.42; the leg from the
    // mirror to the light passes over it at y = 0.5): direct only.
    const Vec3 blocked(1, 0, -0.5);
    expect_rgb_near(radiance_at(scene, tracer, blocked, kUp), kRho / kPi * I * e(blocked, light),
                    1e-9, "leg to the mirror blocked");
    // (1, 0, 0.5): the mirror point (2, 1/3, 1/3) is clear from x (crossed at y = 1/6), but
    // the leg on to the light meets the floating card (x = 1.5, y = 0.5, z = 0.25).
    const Vec3 blocked2(1, 0, 0.5);
    expect_rgb_near(radiance_at(scene, tracer, blocked2, kUp), kRho / kPi * I * e(blocked2, light),
                    1e-9, "leg from the mirror blocked");
    // (1, 0, 3): the line meets the mirror's plane at z = 2, beside its polygon: direct only.
    const Vec3 beside(1, 0, 3);
    expect_rgb_near(radiance_at(scene, tracer, beside, kUp), kRho / kPi * I * e(beside, light),
                    1e-9, "beside the mirror");
}

// Two facing mirrors at x = +-2: images of the light at (0, 1, 0) in each (x = +-4) and of
// those in the other one (x = +-8, rho_s^2). A directional light through one mirror too.
TEST(RenderPathtraceLights, SecondOrderImagesAndDirectionalThroughMirror) {
    const std::string east = R"(,
  {"type": "polygon", "material": "mirror",
   "vertices": [[2, 0, -1], [2, 0, 1], [2, 2, 1], [2, 2, -1]]})";
    const std::string west = R"(,
  {"type": "polygon", "material": "mirror",
   "vertices": [[-2, 0, -1], [-2, 2, -1], [-2, 2, 1], [-2, 0, 1]]})";
    const Rgb I(10, 5, 1), rho_s(0.8, 0.6, 0.4);
    {
        const Scene scene = load_scene_from_string(
            floor_scene(east + west,
                        R"({"type": "point", "position": [0, 1, 0], "intensity": [10, 5, 1]})"),
            "two-mirrors.json", ".");
        const RayCaster caster(scene);
        const PathTracer tracer(scene, caster);
        ASSERT_EQ(tracer.mirror_faces(), 2);
        EXPECT_EQ(tracer.mirror_pairs(), 2);
        const Vec3 p(1, 0, 0);
        Rgb want(0.0);
        for (const auto& [vx, weight] :
             std::initializer_list<std::pair<double, Rgb>>{{0.0, Rgb(1.0)},
                                                           {4.0, rho_s},
                                                           {-4.0, rho_s},
                                                           {8.0, rho_s * rho_s},
                                                           {-8.0, rho_s * rho_s}}) {
            const double r2 = (vx - 1) * (vx - 1) + 1;  // cos = 1 / r
            want += weight * I / (r2 * std::sqrt(r2));
        }
        Pcg32 rng(1, 2);
        const Rgb got = tracer.delta_irradiance(scene.normalisation.to_normalised(p), kUp, rng);
        expect_rgb_near(got, want, 1e-9, "two mirrors, orders 0-2");
    }
    {  // Light travelling (1, -1, 0)/sqrt 2 into the mirror at x = 2 comes back along
       // (-1, -1, 0)/sqrt 2: at (1, 0, 0) via the mirror point (2, 1, 0); at (1, 0, 3) the
       // mirror point (2, 1, 3) is beside the polygon.
        const Scene scene = load_scene_from_string(
            floor_scene(
                east,
                R"({"type": "directional", "direction": [1, -1, 0], "irradiance": [2, 3, 4]})"),
            "sun-mirror.json", ".");
        const RayCaster caster(scene);
        const PathTracer tracer(scene, caster);
        ASSERT_EQ(tracer.mirror_faces(), 1);
        const Rgb E(2, 3, 4);
        expect_rgb_near(radiance_at(scene, tracer, Vec3(1, 0, 0), kUp),
                        kRho / kPi * E * std::sqrt(0.5) * (Rgb(1.0) + rho_s), 1e-9,
                        "directional, direct and mirrored");
        expect_rgb_near(radiance_at(scene, tracer, Vec3(1, 0, 3), kUp),
                        kRho / kPi * E * std::sqrt(0.5), 1e-9, "directional, beside the mirror");
    }
}

}  // namespace
}  // namespace vlf
