// Walkthrough rendering of a bake by lookup (render/render.hpp, VLF §6; DESIGN §7–8): the
// emitter mask, pixel super-sampling, mode names, and the accuracy of every render mode
// against the path-traced reference on the Cornell scenes, away from emitters.
#include "vlf/render/render.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <string>
#include <utility>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/render/image_metrics.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/propagation.hpp"

namespace vlf {
namespace {

namespace fs = std::filesystem;

// The eye at the origin looks along +z with a 90 degree field: at depth z, image point
// (px, py) of a 16 x 16 image is x = -(px / 8 - 1) z, y = (1 - py / 8) z (the camera's right
// is -x). Depth 0.5: one pixel is 1/16 wide. A lamp faces the eye with its edges at pixel
// columns 4.3 and 9.1 and rows 2.5 and 5.05; a diffuse strip nearer the eye hides columns
// 5.9 to 7.1; a second lamp turns its back to the eye; a wall closes the view.
constexpr const char* kMaskScene = R"({
  "materials": {"wall": {"diffuse": [0.5, 0.5, 0.5]}, "lamp": {"emission": [5, 5, 5]}},
  "objects": [
    {"name": "wall", "type": "polygon", "material": "wall",
     "vertices": [[-3, -3, 2], [-3, 3, 2], [3, 3, 2], [3, -3, 2]]},
    {"name": "lamp", "type": "polygon", "material": "lamp",
     "vertices": [[-0.06875, 0.184375, 0.5], [-0.06875, 0.34375, 0.5],
                  [0.23125, 0.34375, 0.5], [0.23125, 0.184375, 0.5]]},
    {"name": "strip", "type": "polygon", "material": "wall",
     "vertices": [[0.03375, -1, 0.3], [0.03375, 1, 0.3], [0.07875, 1, 0.3], [0.07875, -1, 0.3]]},
    {"name": "back lamp", "type": "polygon", "material": "lamp",
     "vertices": [[-0.2, -0.3, 0.5], [-0.2, -0.1, 0.5], [-0.4, -0.1, 0.5], [-0.4, -0.3, 0.5]]}],
  "cameras": [{"name": "eye", "eye": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0],
               "fov_y_deg": 90}]
})";

TEST(RenderEmitterMask, MarksPixelsWhoseSubPixelRaysSeeALampsFront) {
    const Scene scene = load_scene_from_string(kMaskScene, "mask.json", ".");
    ASSERT_EQ(scene.faces.size(), 4u);
    int facing_away = 0;  // the back lamp only
    for (const Face& f : scene.faces) {
        ASSERT_NEAR(std::abs(f.normal.z), 1.0, 1e-12) << "face " << f.id;
        facing_away += f.normal.z > 0.0;
    }
    ASSERT_EQ(facing_away, 1);
    const Bake bake = test::scene_only_bake(scene);
    const Renderer r(bake);
    // Columns and rows whose k x k sample grid, at offsets (i + 0.5) / k, hits the lamp:
    // k = 4 misses the 0.1 and 0.05 slivers of column 9 and row 5, k = 16 (first offset
    // 1/32) finds them. Column 6 lies wholly behind the strip; 5 and 7 peek out.
    auto expect_mask = [&](int k, int last_col, int last_row) {
        const PixelMask m = r.emitter_mask(scene.cameras[0], 16, 16, k);
        ASSERT_EQ(m.width, 16);
        ASSERT_EQ(m.height, 16);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const bool want = x >= 4 && x <= last_col && x != 6 && y >= 2 && y <= last_row;
                EXPECT_EQ(m.at(x, y), want) << "k=" << k << " pixel " << x << "," << y;
            }
    };
    expect_mask(4, 8, 4);
    expect_mask(16, 9, 5);
    EXPECT_THROW(r.emitter_mask(scene.cameras[0], 16, 16, 0), ParameterError);
}

// pixel_samples = k renders what a k times finer image averaged over k x k blocks gives.
TEST(RenderPixelSamples, AreABoxFilterOfAFinerImage) {
    const Scene scene = load_scene(test::source_path("scenes/cornell-mirrors.json"));
    Bake bake = test::scene_only_bake(scene);
    for (size_t t = 0; t < bake.lightmap_radiance.size(); ++t)  // any varied light maps
        bake.lightmap_radiance[t] = Rgb(double(t % 7), double(t % 13) * 0.5, 1.0 + (t % 5));
    const Renderer r(bake);
    for (RenderMode mode : {RenderMode::Texture, RenderMode::Raytrace}) {
        const int size = 12, k = 3;
        RenderSettings s;
        s.mode = mode;
        s.width = s.height = size * k;
        const Image fine = r.render(scene.cameras[0], s);
        s.width = s.height = size;
        s.pixel_samples = k;
        const Image im = r.render(scene.cameras[0], s);
        s.pixel_samples = 1;
        const Image centre = r.render(scene.cameras[0], s);
        double total = 0.0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                Rgb want(0.0);
                for (int j = 0; j < k; ++j)
                    for (int i = 0; i < k; ++i) want += fine.at(k * x + i, k * y + j);
                want /= double(k * k);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(im.at(x, y)[c], want[c], 1e-9 * (1.0 + std::abs(want[c])))
                        << to_string(mode) << " pixel " << x << "," << y;
                total += want.x;
            }
        EXPECT_GT(total, 0.0);
        EXPECT_GT(relative_rmse(centre, im), 0.01) << "k = 1 should differ at edges";
    }
    RenderSettings bad;
    bad.pixel_samples = 0;
    EXPECT_THROW(r.render(scene.cameras[0], bad), ParameterError);
}

TEST(RenderModes, NamesRoundTrip) {
    for (RenderMode m :
         {RenderMode::Rays, RenderMode::Texture, RenderMode::Raytrace, RenderMode::Pathtrace})
        EXPECT_EQ(render_mode_from_string(to_string(m)), m);
    EXPECT_THROW(render_mode_from_string("raster"), ParameterError);
}

// ---------------------------------------------------------------------------------------
// Accuracy of the bake against the path-traced reference (DESIGN §8)

// VLF §7's Cornell configuration with mirrors: l = 2049, N = 128, m = 16.
PropagateParams accuracy_params() {
    PropagateParams p;
    p.field.directions = 2049;
    p.field.resolution = 128;
    p.field.tile = 16;
    p.cycles = 8;
    p.resample = true;
    return p;
}

struct Baked {
    Scene scene;
    Bake bake;
    double seconds = 0.0;
};

std::unique_ptr<Baked> bake_scene(const std::string& file) {
    auto b = std::make_unique<Baked>();
    b->scene = load_scene(test::source_path(file));
    const PropagateParams p = accuracy_params();
    const auto t0 = std::chrono::steady_clock::now();
    const Propagation run = propagate(b->scene, p, {});
    b->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    b->bake = make_bake(b->scene, p, *run.transport, propagation_report(b->scene, p, run, 0.0));
    std::printf("%s: propagated l=%d N=%d m=%d, %d cycles in %.1f s\n", file.c_str(),
                p.field.directions, p.field.resolution, p.field.tile, p.cycles, b->seconds);
    return b;
}

// data/README.md: the references and the command that made them.
Image reference(const std::string& name) {
    return read_exr(test::source_path("data/" + name));
}

#if defined(__SANITIZE_ADDRESS__)
#define VLF_SKIP_UNDER_SANITIZER() GTEST_SKIP() << "accuracy tests take hours under ASan"
#else
#define VLF_SKIP_UNDER_SANITIZER() static_cast<void>(0)
#endif

// The reference integrates over each pixel's area (jittered samples); the lookup modes
// render k x k rays per pixel on a grid (RenderSettings::pixel_samples), the same
// footprint, so edges compare like with like. k must be large: the lamp (radiance 17)
// against the ceiling (0.1) makes an edge pixel's coverage error of 1/(2k) worth 17/(2k) —
// at k = 4 that alone gave 7.6 % relative RMSE on cornell.json. The emitter mask uses the
// same k x k rays.
constexpr int kPixelSamples = 16;

// The issue's targets (issue 9): away from emitters, relative RMSE <= 5 % and the mean
// radiance within 2 % of the reference's, per channel, in every lookup mode. The whole
// image (lamp included, so a bake that lost the emission fails) within 5 % too.
constexpr double kMaxRmseAway = 0.05;
constexpr double kMaxRatioOff = 0.02;
constexpr double kMaxRmseWhole = 0.05;

// Propagates the scene, renders its first camera in every lookup mode at the reference's
// size and checks each against the reference.
void expect_accurate(const std::string& scene_file, const std::string& reference_file) {
    const auto b = bake_scene(scene_file);
    const Renderer r(b->bake);
    const Camera& cam = b->scene.cameras.at(0);
    const Image ref = reference(reference_file);
    const PixelMask emitters = r.emitter_mask(cam, ref.width, ref.height, kPixelSamples);
    for (RenderMode mode : {RenderMode::Rays, RenderMode::Texture, RenderMode::Raytrace}) {
        RenderSettings s;
        s.width = ref.width;
        s.height = ref.height;
        s.mode = mode;
        s.pixel_samples = kPixelSamples;
        const auto t0 = std::chrono::steady_clock::now();
        const Image im = r.render(cam, s);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const ImageError e = image_error(im, ref, emitters);
        const std::string name = to_string(mode);
        std::printf(
            "%s %-8s relative RMSE %.4f, away from emitters %.4f (%zu of %zu pixels), "
            "mean ratio there %.4f %.4f %.4f; %dx%d x %d^2 rays in %.2f s\n",
            scene_file.c_str(), name.c_str(), e.rmse, e.rmse_away, e.away_pixels, e.pixels,
            e.ratio_away.x, e.ratio_away.y, e.ratio_away.z, ref.width, ref.height, kPixelSamples,
            seconds);
        EXPECT_LE(e.rmse, kMaxRmseWhole) << name;
        EXPECT_LE(e.rmse_away, kMaxRmseAway) << name;
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(e.ratio_away[c], 1.0, kMaxRatioOff) << name << " channel " << c;
        if (const char* out = std::getenv("VLF_RENDER_TEST_OUT"))
            write_image(
                std::string(out) + "/" + fs::path(scene_file).stem().string() + "-" + name + ".exr",
                im);
    }
}

TEST(RenderAccuracy, CornellAwayFromEmitters) {
    VLF_SKIP_UNDER_SANITIZER();
    expect_accurate("scenes/cornell.json", "cornell-pathtrace-128.exr");
}

TEST(RenderAccuracy, CornellMirrorsAwayFromEmitters) {
    VLF_SKIP_UNDER_SANITIZER();
    expect_accurate("scenes/cornell-mirrors.json", "cornell-mirrors-pathtrace-128.exr");
}

// A finished propagation of `scene`: its ledger closes in every cycle, and its texture-mode
// image of the first camera is within `rmse_away` relative RMSE of the reference away from
// emitters, its mean there within kMaxRatioOff per channel.
void expect_texture_near(const Scene& scene, const PropagateParams& p, const Propagation& run,
                         const std::string& reference_file, const char* what, double rmse_away) {
    for (const LedgerEntry& e : run.transport->ledger()) EXPECT_LE(e.relative_error(), 1e-9);
    const Bake bake = make_bake(scene, p, *run.transport, propagation_report(scene, p, run, 0.0));
    const Renderer r(bake);
    const Camera& cam = scene.cameras.at(0);
    const Image ref = reference(reference_file);
    RenderSettings s;
    s.width = ref.width;
    s.height = ref.height;
    s.mode = RenderMode::Texture;
    s.pixel_samples = kPixelSamples;
    const Image im = r.render(cam, s);
    const ImageError e =
        image_error(im, ref, r.emitter_mask(cam, ref.width, ref.height, kPixelSamples));
    std::printf(
        "%s: texture against the path tracer, RMSE away from emitters %.4f (%zu of %zu "
        "pixels), mean ratio %.4f %.4f %.4f\n",
        what, e.rmse_away, e.away_pixels, e.pixels, e.ratio_away.x, e.ratio_away.y, e.ratio_away.z);
    EXPECT_LE(e.rmse_away, rmse_away);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.ratio_away[c], 1.0, kMaxRatioOff) << "channel " << c;
}

// Issue 14: the glass ball on the Cornell box floor under a point light of the lamp's power
// (the classic focused caustic), baked at the default field with 8 cycles, against the path
// tracer (its light tracer finds the caustic): texture mode within the issue's 10 % relative
// RMSE (every pixel: the scene has no emitter to see) and its mean within 2 % per channel,
// the bound of the other accuracy tests. The reference: 1024 spp at 512 x 512 averaged to
// 128 x 128 (data/README.md).
TEST(RenderAccuracy, CornellGlassBallUnderAPointLight) {
    VLF_SKIP_UNDER_SANITIZER();
    const Scene scene = load_scene(test::source_path("scenes/cornell-glass-point.json"));
    PropagateParams p;
    p.cycles = 8;
    const Propagation run = propagate(scene, p, {});
    expect_texture_near(scene, p, run, "cornell-glass-point-pathtrace-128.exr",
                        "glass ball under a point light", 0.10);
}

// Issue 14: the glass ball on the Cornell box floor under its ceiling lamp. The caustic the
// ball focuses from the lamp is traced on from the lamp in cycle 1 (lamp_caustics.hpp; the
// field alone left its peak 2-3x low). Baked with the final preset's field and texels
// (l = 2049, N = 128, m = 16, 7.5-mm texels, filter 1.5) and 8 cycles, texture mode against
// a 16,384-spp path-traced reference (data/README.md): within the issue's 5 % relative RMSE
// away from the lamp, and its mean within 2 % per channel, the bound of the other accuracy
// tests (8 cycles leave about 1 % of the light in the glass and on the walls).
TEST(RenderAccuracy, CornellGlassBallUnderTheCeilingLamp) {
    VLF_SKIP_UNDER_SANITIZER();
    LoadOptions load;
    load.texel_divisions = 64;
    const Scene scene = load_scene(test::source_path("scenes/cornell-glass.json"), load);
    PropagateParams p;
    p.field = {2049, 128, 16, DirectionScheme::Octahedral};
    p.texel_divisions = load.texel_divisions;
    p.filter_sigma = 1.5;
    p.cycles = 8;
    const Propagation run = propagate(scene, p, {});
    // The rays' estimate of the lamp's light on the glass ball against the power the field
    // handed over: within the field's form-factor bound, 3 % (TransportFormFactor).
    const CausticStats& cs = run.transport->lamp_caustics();
    ASSERT_GT(cs.rays, 0);
    EXPECT_NEAR(cs.estimated.x / cs.handed.x, 1.0, 0.03);
    expect_texture_near(scene, p, run, "cornell-glass-pathtrace-128.exr",
                        "glass ball under the ceiling lamp", 0.05);
}

// Issue 11: however small the lamp, its power enters the field. The empty Cornell box lit
// by a 1 mm square of the big lamp's power (small_emitters.hpp: it owns no ray in most
// directions, so it shoots by ray casting): the ledger closes, and the walls get the path
// tracer's radiance — mean within 5 % per channel away from the lamp (the issue's bound;
// 8 cycles leave about 1 % unshot), relative RMSE within 10 % against a 512-spp reference
// of 64 x 64 pixels (its own noise is about 3 %).
TEST(RenderAccuracy, OneMillimetreLampLightsTheBox) {
    VLF_SKIP_UNDER_SANITIZER();
    std::ifstream in(test::source_path("scenes/cornell-empty.json"));
    std::string text((std::istreambuf_iterator<char>(in)), {});
    auto replace = [&](const std::string& from, const std::string& to) {
        const size_t at = text.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        text.replace(at, from.size(), to);
    };
    // 130 x 105 mm at Le = (17, 12, 4) -> 1 x 1 mm at 13,650 times the radiance.
    replace("\"emission\": [17.0, 12.0, 4.0]", "\"emission\": [232050.0, 163800.0, 54600.0]");
    replace(
        "[[343.0, 548.7, 227.0], [343.0, 548.7, 332.0], [213.0, 548.7, 332.0], [213.0, 548.7, "
        "227.0]]",
        "[[278.5, 548.7, 279.0], [278.5, 548.7, 280.0], [277.5, 548.7, 280.0], [277.5, 548.7, "
        "279.0]]");
    const Scene scene = load_scene_from_string(text, "tiny-lamp.json", test::source_path("scenes"));
    PropagateParams p;
    p.cycles = 8;
    const Propagation run = propagate(scene, p, {});
    for (const LedgerEntry& e : run.transport->ledger()) EXPECT_LE(e.relative_error(), 1e-9);
    EXPECT_LT(run.transport->ledger().back().unshot.x,
              0.02 * run.transport->ledger().back().emitted.x);
    const Bake bake = make_bake(scene, p, *run.transport, propagation_report(scene, p, run, 0.0));
    const Renderer r(bake);
    const Camera& cam = scene.cameras.at(0);
    RenderSettings ref;
    ref.width = ref.height = 64;
    ref.mode = RenderMode::Pathtrace;
    ref.spp = 512;
    const Image pt = r.render(cam, ref);
    RenderSettings tex = ref;
    tex.mode = RenderMode::Texture;
    tex.pixel_samples = kPixelSamples;
    const Image im = r.render(cam, tex);
    // The lamp is far below a pixel: its own pixel and the ones around it (where the
    // path tracer's jittered samples can meet it) are the "emitter" pixels.
    PixelMask mask = r.emitter_mask(cam, 64, 64, kPixelSamples);
    const PinholeCamera pc(cam, scene.normalisation, 64, 64);
    const Vec3 to_lamp =
        glm::normalize(scene.normalisation.to_normalised(Vec3(278.0, 548.7, 279.5)) - pc.origin());
    int lx = 0, ly = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            if (glm::dot(pc.direction(x + 0.5, y + 0.5), to_lamp) >
                glm::dot(pc.direction(lx + 0.5, ly + 0.5), to_lamp))
                lx = x, ly = y;
    for (int y = std::max(0, ly - 1); y <= std::min(63, ly + 1); ++y)
        for (int x = std::max(0, lx - 1); x <= std::min(63, lx + 1); ++x)
            mask.on[size_t(y) * 64 + x] = 1;
    const ImageError e = image_error(im, pt, mask);
    std::printf(
        "1 mm lamp: texture against the path tracer, RMSE away %.4f, mean ratio %.4f %.4f "
        "%.4f\n",
        e.rmse_away, e.ratio_away.x, e.ratio_away.y, e.ratio_away.z);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.ratio_away[c], 1.0, 0.05) << "channel " << c;
    EXPECT_LE(e.rmse_away, 0.10);
}

}  // namespace
}  // namespace vlf
