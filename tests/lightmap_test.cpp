// Bilinear P^T lookup (field/lightmap.hpp, VLF §6.3): linear radiance reproduced inside a
// face, unreliable rim texels without weight, texel radiance = power / (pi area).
#include "vlf/field/lightmap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "test_util.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/scene/texel_frame.hpp"

namespace vlf {
namespace {

// A chart of one face.
Chart textured_face(const std::vector<Vec3>& vertices, double texel) {
    const std::vector<Face> faces{test::make_face(vertices)};
    Chart c;
    c.faces = {0};
    c.normal = faces[0].normal;
    c.area = faces[0].area;
    build_chart_texels(c, faces, texel, 512);
    return c;
}

TEST(Lightmap, LinearRadianceIsReproducedInside) {
    // A tilted rectangle, 10 x 6 full texels.
    const Vec3 a(0.1, -0.2, 0.3), eu = glm::normalize(Vec3(1, 0.2, -0.1));
    const Vec3 ev = glm::normalize(glm::cross(Vec3(0.3, 0.1, 1.0), eu));
    const double texel = 0.05;
    const Chart f = textured_face({a, a + 0.5 * eu, a + 0.5 * eu + 0.3 * ev, a + 0.3 * ev}, texel);
    ASSERT_GE(f.texels.width, 6);
    ASSERT_GE(f.texels.height, 6);
    const Vec3 gx(2.0, -1.0, 0.5), gy(-0.3, 4.0, 1.0), gz(1.0, 1.0, -2.0);
    auto L = [&](const Vec3& p) {
        return Rgb(1.0 + glm::dot(gx, p), 2.0 + glm::dot(gy, p), 3.0 + glm::dot(gz, p));
    };
    std::vector<Rgb> rad(f.texels.count());
    for (int j = 0; j < f.texels.height; ++j)
        for (int i = 0; i < f.texels.width; ++i)
            rad[size_t(j) * f.texels.width + i] = L(f.texels.to_plane({i + 0.5, j + 0.5}));
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int tested = 0;
    for (int k = 0; k < 2000; ++k) {
        // Points between the texel centres of texels wholly inside the face.
        const Vec2 t(0.5 + u(rng) * (f.texels.width - 1.0), 0.5 + u(rng) * (f.texels.height - 1.0));
        const int i0 = std::min(int(t.x - 0.5), f.texels.width - 2);
        const int j0 = std::min(int(t.y - 0.5), f.texels.height - 2);
        const double full = texel * texel * (1 - 1e-9);
        bool inside = true;
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                inside &= f.texel_area[size_t(j0 + b) * f.texels.width + i0 + c] >= full;
        if (!inside) continue;
        const Vec3 p = f.texels.to_plane(t);
        const Rgb got = sample_lightmap(f, rad.data(), p);
        const Rgb want = L(p);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * (1 + std::abs(want[c])));
        ++tested;
    }
    EXPECT_GT(tested, 500);
    // At a texel centre: exactly that texel. Beyond the border: clamped to the border.
    EXPECT_EQ(sample_lightmap(f, rad.data(), f.texels.to_plane({2.5, 3.5})),
              rad[size_t(3) * f.texels.width + 2]);
    const Rgb border = sample_lightmap(f, rad.data(), f.texels.to_plane({0.5, 2.5}));
    const Rgb outside = sample_lightmap(f, rad.data(), f.texels.to_plane({-3.0, 2.5}));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(outside[c], border[c], 1e-12);
}

TEST(Lightmap, UnreliableRimTexelsGetNoWeight) {
    // A right triangle: texels along the hypotenuse are partly outside; those below 25%
    // carry an absurd radiance that must never show.
    const Chart f = textured_face({{0, 0, 0}, {0.4, 0, 0}, {0, 0.3, 0}}, 0.023);
    const double reliable = kReliableTexelFraction * f.texels.size * f.texels.size;
    std::vector<Rgb> rad(f.texels.count());
    int unreliable = 0;
    for (int k = 0; k < f.texels.count(); ++k) {
        const bool ok = f.texel_area[k] >= reliable;
        rad[k] = ok ? Rgb(1.0 + 0.01 * (k % 7), 2.0, 3.0) : Rgb(1e9);
        unreliable += f.texel_area[k] > 0 && !ok;
    }
    ASSERT_GT(unreliable, 3);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 0.4);
    for (int k = 0; k < 3000; ++k) {
        const double x = u(rng), y = u(rng);
        if (x / 0.4 + y / 0.3 > 1.0) continue;  // on the face
        const Rgb v =
            sample_lightmap(f, rad.data(), f.texels.to_plane(f.texels.to_texel({x, y, 0})));
        EXPECT_GE(v.x, 1.0 - 1e-12);
        EXPECT_LE(v.x, 1.06 + 1e-12);
        EXPECT_NEAR(v.y, 2.0, 1e-12);
    }
    // A sliver face with no reliable texel falls back to its largest texel.
    const Chart s = textured_face({{0, 0, 0}, {0.4, 0, 0}, {0.4, 0.004, 0}, {0, 0.004, 0}}, 0.05);
    ASSERT_GT(s.texels.width, 2);
    std::vector<Rgb> srad(s.texels.count());
    for (size_t k = 0; k < srad.size(); ++k) srad[k] = Rgb(double(k) + 1.0);
    const Vec3 at(0.2, 0.002, 0);
    const Rgb v = sample_lightmap(s, srad.data(), at);
    const double k = v.x - 1.0;  // the texel it took: one of the two nearest along u
    EXPECT_EQ(k, std::floor(k));
    EXPECT_LE(std::abs(k + 0.5 - s.texels.to_texel(at).x), 1.0);
    EXPECT_EQ(v, srad[size_t(k)]);
}

TEST(Lightmap, TexelRadianceIsPowerOverPiArea) {
    const Scene s = load_scene(test::source_path("scenes/closed-box.json"));
    TextureMaps maps(s);
    for (size_t k = 0; k < maps.texels(); ++k) maps.total[k] = Rgb(1.0 + k % 5, 2.0, 0.5);
    const std::vector<Rgb> r = texel_radiance(s, maps);
    ASSERT_EQ(r.size(), maps.texels());
    for (const Chart& f : s.charts)
        for (size_t t = 0; t < maps.count(f.id); ++t) {
            const Rgb want = f.texel_area[t] > 0
                                 ? maps.total[maps.begin(f.id) + t] / (kPi * f.texel_area[t])
                                 : Rgb(0.0);
            EXPECT_EQ(r[maps.begin(f.id) + t], want);
        }
}

}  // namespace
}  // namespace vlf
