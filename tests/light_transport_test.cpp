// Delta lights in propagation (issue 14, light_beams.hpp): per-texel irradiance against
// closed forms — a point light's I cos(theta) / r^2 integrated over each texel (its exact
// solid angle), a spot's falloff, a directional light's E cos(theta) with a shadow whose
// edge texels are lit in proportion to their lit area, a mirror's image source — and the
// ledger with every light type.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "test_util.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/light_beams.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

using test::params;

std::unique_ptr<Transport> run(const Scene& scene, const PropagateParams& p) {
    auto t = std::make_unique<Transport>(scene, p);
    for (int c = 1; c <= p.cycles; ++c) t->run_cycle(c == p.cycles);
    return t;
}

Scene from_json(const std::string& text) {
    return load_scene_from_string(text, "test.json", test::source_path("scenes"));
}

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

// The irradiance a floor texel received in cycle 1 (W per square unit): rho_d E A is what
// its P^T holds after one cycle, the floor seeing nothing else.
double texel_irradiance(const Transport& t, const Chart& c, size_t k) {
    const size_t at = t.texture_maps().begin(c.id) + k;
    return t.texture_maps().total[at].x / (0.5 * c.texel_area[k]);
}

const Chart& floor_chart(const Scene& scene) {
    return scene.chart_of(scene.faces[size_t(scene.objects[0].first_face)]);
}

// A point light at height h over the floor: a texel's mean irradiance is I x its solid
// angle / its area (cube_solid_angle: the texel on the plane at distance h, scaled by 1/h).
TEST(LightTransport, PointLightIrradiancePerTexel) {
    const Vec3 light(0.3, 0.7, -0.2);
    const double I = 2.0;
    const Scene scene = from_json(floor_scene(
        "", R"({"type": "point", "position": [0.3, 0.7, -0.2], "intensity": [2, 2, 2]})"));
    const auto t = run(scene, params(33, 64, 8, 1));
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
    std::printf("point light: worst texel error %.2e over %d texels\n", worst, checked);
    // Every watt is booked: 4 pi I emitted.
    const LedgerEntry& e = t->ledger().back();
    EXPECT_NEAR(e.emitted.x, 4.0 * kPi * I, 1e-9 * 4.0 * kPi * I);
    EXPECT_LE(e.relative_error(), 1e-9);
}

}  // namespace
}  // namespace vlf
