// texture_test.cpp — diffuse colour textures (issue 12): the lookup's orientation, the
// per-texel albedo of textured charts, propagation with it (the ledger, and exact ratios to
// an untextured bake under direct light), full-resolution rendering, and the bake round trip.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "test_util.hpp"
#include "vlf/bake/bake.hpp"
#include "vlf/render/render.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/ledger.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {
namespace {

using test::run_transport;
using test::TempDir;

// A binary PPM (stb reads it like any image): row 0 at the top.
std::string ppm(int w, int h, const std::vector<uint8_t>& rgb) {
    std::string s = "P6\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
    s.append(rgb.begin(), rgb.end());
    return s;
}

// A unit floor (y = 0, x and z in [0, 1], u = x, v = z) with the material `floor`, and a
// lamp facing it from y = 0.5. Nothing else: the floor receives only the lamp's light.
std::string floor_obj() {
    return "mtllib m.mtl\n"
           "v 0 0 0\nv 0 0 1\nv 1 0 1\nv 1 0 0\n"
           "vt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\n"
           "usemtl floor\nf 1/1 2/2 3/3 4/4\n"
           "v 0.4 0.5 0.4\nv 0.6 0.5 0.4\nv 0.6 0.5 0.6\nv 0.4 0.5 0.6\n"
           "usemtl lamp\nf 5 6 7 8\n";
}

// Top row red, green; bottom row blue, white.
const std::vector<uint8_t> kChecker = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};

Scene textured_floor(const TempDir& dir, bool textured, double kd = 0.8) {
    dir.write("t.ppm", ppm(2, 2, kChecker));
    const std::string kd_line =
        "Kd " + std::to_string(kd) + " " + std::to_string(kd) + " " + std::to_string(kd) + "\n";
    dir.write("m.mtl", "newmtl floor\n" + kd_line + (textured ? "map_Kd t.ppm\n" : "") +
                           "newmtl lamp\nKd 0 0 0\nKe 5 5 5\n");
    LoadOptions o;
    o.texel_size_user = 1.0 / 16;
    return load_scene(dir.write("floor.obj", floor_obj()), o);
}

const Face& first_face_of(const Scene& s, const std::string& object) {
    for (const SceneObject& o : s.objects)
        if (o.name == object) return s.faces[size_t(o.first_face)];
    ADD_FAILURE() << "no object " << object;
    return s.faces.front();
}

TEST(Texture, CoordinatesRunRightAndUpFromTheImagesBottomLeft) {
    TempDir dir("orient");
    const Scene s = textured_floor(dir, true, 1.0);
    ASSERT_EQ(s.textures.size(), 1u);
    const Face& f = first_face_of(s, "floor/floor");
    ASSERT_EQ(f.uv.size(), 3u);
    auto albedo = [&](double x, double z) {
        // The face holding (x, z): the floor's two triangles.
        for (const SceneObject& o : s.objects) {
            if (o.name != "floor/floor") continue;
            for (int k = 0; k < o.face_count; ++k) {
                const Face& t = s.faces[size_t(o.first_face + k)];
                const Vec3 p = s.normalisation.to_normalised({x, 0.0, z});
                bool inside = true;
                for (size_t e = 0; e < 3; ++e) {
                    const Vec3 a = t.vertices[e], b = t.vertices[(e + 1) % 3];
                    if (glm::dot(glm::cross(b - a, p - a), t.normal) < -1e-12) inside = false;
                }
                if (inside) return s.albedo_at(t, p);
            }
        }
        ADD_FAILURE() << "no face at " << x << ", " << z;
        return Rgb(0.0);
    };
    // Texel centres: (u, v) = (0.25, 0.25) is the bottom-left texel (blue), (0.75, 0.75)
    // the top-right (green). Kd = 1, so the albedo is the texel's linear colour.
    const Rgb bl = albedo(0.25, 0.25), tr = albedo(0.75, 0.75), tl = albedo(0.25, 0.75);
    EXPECT_NEAR(bl.z, 1.0, 1e-9);
    EXPECT_NEAR(bl.x + bl.y, 0.0, 1e-9);
    EXPECT_NEAR(tr.y, 1.0, 1e-9);
    EXPECT_NEAR(tr.x + tr.z, 0.0, 1e-9);
    EXPECT_NEAR(tl.x, 1.0, 1e-9);
    // The material's diffuse is Kd x the texture's mean.
    const Material& m = s.material_of(f);
    EXPECT_NEAR(m.diffuse.x, 0.5, 1e-9);
    EXPECT_NEAR(m.diffuse.y, 0.5, 1e-9);
    EXPECT_NEAR(m.diffuse.z, 0.5, 1e-9);
}

TEST(Texture, TexelAlbedoIsTheTexturesMeanOverEachTexel) {
    TempDir dir("texel");
    const Scene s = textured_floor(dir, true, 0.8);
    const Chart& c = s.chart_of(first_face_of(s, "floor/floor"));
    ASSERT_EQ(c.texel_albedo.size(), size_t(c.texels.count()));
    // Area-weighted mean over the chart = the material's mean albedo (within the sampling).
    Rgb mean(0.0);
    double area = 0.0;
    for (size_t k = 0; k < c.texel_albedo.size(); ++k) {
        mean += c.texel_albedo[k] * c.texel_area[k];
        area += c.texel_area[k];
    }
    mean /= area;
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(mean[ch], 0.4, 0.02) << ch;
    // The texels vary with the texture: somewhere nearly pure red, somewhere nearly white.
    double most_red = 0.0, most_white = 0.0;
    for (const Rgb& a : c.texel_albedo) {
        most_red = std::max(most_red, a.x - a.y - a.z);
        most_white = std::max(most_white, std::min({a.x, a.y, a.z}));
    }
    EXPECT_GT(most_red, 0.6);
    EXPECT_GT(most_white, 0.6);
    // An untextured floor has none.
    TempDir plain("plain");
    const Scene u = textured_floor(plain, false);
    EXPECT_TRUE(u.chart_of(first_face_of(u, "floor/floor")).texel_albedo.empty());
}

// The floor sees only the lamp, so each texel reflects exactly its albedo times what it
// receives: a textured floor's texel radiance over its albedo equals an untextured floor's
// over its albedo, texel by texel, and the ledger closes.
TEST(Texture, PropagationReflectsEachTexelsAlbedo) {
    TempDir a("prop_a"), b("prop_b");
    const Scene tex = textured_floor(a, true, 0.8);
    const Scene plain = textured_floor(b, false, 0.3);
    for (bool perturb : {false, true}) {
        PropagateParams p = test::params(129, 64, 8, 3);
        if (perturb) p.perturbations = 2;
        const auto ta = run_transport(tex, p);
        const auto tb = run_transport(plain, p);
        for (const LedgerEntry& e : ta->ledger()) EXPECT_LE(e.relative_error(), 1e-9);
        const Chart& ca = tex.chart_of(first_face_of(tex, "floor/floor"));
        const Chart& cb = plain.chart_of(first_face_of(plain, "floor/floor"));
        ASSERT_EQ(ca.texels.count(), cb.texels.count());
        const Rgb le(0.0);
        double worst = 0.0;
        int compared = 0;
        for (size_t k = 0; k < size_t(ca.texels.count()); ++k) {
            if (ca.texel_area[k] <= 0.0) continue;
            const Rgb la = ta->texture_maps().radiance(ca, k);
            const Rgb lb = tb->texture_maps().radiance(cb, k);
            for (int ch = 0; ch < 3; ++ch) {
                const double rho = ca.texel_albedo[k][ch];
                if (rho < 0.05 || lb[ch] <= 0.0) continue;
                worst = std::max(worst, std::abs((la[ch] / rho) / (lb[ch] / 0.3) - 1.0));
                ++compared;
            }
        }
        EXPECT_GT(compared, 100);
        EXPECT_LT(worst, 1e-5) << "perturbations " << p.perturbations;
    }
}

// A texture on a material that reflects nothing diffusely (a mirror with map_Kd) is not a
// texture of its albedo: nothing is textured, and the ledger closes.
TEST(Texture, MirrorWithATextureKeepsTheLedger) {
    TempDir dir("mirror");
    dir.write("t.ppm", ppm(2, 2, kChecker));
    dir.write("m.mtl",
              "newmtl floor\nKd 0 0 0\nKs 0.5 0.5 0.5\nillum 3\nmap_Kd t.ppm\n"
              "newmtl lamp\nKd 0 0 0\nKe 5 5 5\n");
    const Scene s = load_scene(dir.write("floor.obj", floor_obj()));
    EXPECT_TRUE(s.chart_of(first_face_of(s, "floor/floor")).texel_albedo.empty());
    const auto t = run_transport(s, test::params(129, 32, 8, 3));
    for (const LedgerEntry& e : t->ledger()) EXPECT_LE(e.relative_error(), 1e-9);
}

// Texture mode shows the texture at full resolution: inside one texel the rendered colour
// follows the texture, and the bake round trip keeps textures and coordinates.
TEST(Texture, BakeKeepsTexturesAndRendersThemAtFullResolution) {
    TempDir dir("bake");
    // An 8 x 8 checker of black and white: finer than the 1/4 texels below.
    std::vector<uint8_t> fine;
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
            const uint8_t v = (i + j) % 2 ? 255 : 0;
            fine.insert(fine.end(), {v, v, v});
        }
    dir.write("t.ppm", ppm(8, 8, fine));
    dir.write("m.mtl",
              "newmtl floor\nKd 0.8 0.8 0.8\nmap_Kd t.ppm\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n");
    LoadOptions o;
    o.texel_size_user = 0.25;
    const Scene scene = load_scene(dir.write("floor.obj", floor_obj()), o);
    const PropagateParams p = test::params(33, 32, 8, 2);
    auto t = run_transport(scene, p);
    const std::string out = (dir.path / "b.vlf").string();
    write_bake(out, make_bake(scene, p, *t, nlohmann::json::object()));
    const Bake bake = read_bake(out);
    ASSERT_EQ(bake.scene.textures.size(), 1u);
    EXPECT_EQ(bake.scene.textures[0].srgb, scene.textures[0].srgb);
    for (size_t f = 0; f < scene.faces.size(); ++f)
        EXPECT_EQ(bake.scene.faces[f].uv, scene.faces[f].uv);
    const Renderer renderer(bake);
    // Rays straight down onto the centres of two neighbouring texture cells near the
    // floor's middle: one black, one white, in the same lightmap texel.
    std::vector<PrimaryRay> rays;
    for (double x : {0.5 + 1.0 / 16, 0.5 + 3.0 / 16}) {
        const Vec3 at = scene.normalisation.to_normalised({x, 0.0, 0.5 + 1.0 / 16});
        rays.push_back({at + Vec3(0, 0.1, 0), Vec3(0, -1, 0)});
    }
    RenderSettings s;
    s.mode = RenderMode::Texture;
    const std::vector<Rgb> c = renderer.shade(rays, s);
    const double dark = std::min(c[0].x, c[1].x), light = std::max(c[0].x, c[1].x);
    EXPECT_GT(light, 0.0);
    EXPECT_LT(dark, 0.02 * light);
}

}  // namespace
}  // namespace vlf
