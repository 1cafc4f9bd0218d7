// Walkthrough rendering (VLF §6; DESIGN §7–8): pinhole camera and camera paths, image I/O,
// the path-traced reference (furnace, determinism) and the accuracy of the bake's render
// modes against that reference on the Cornell scenes.
#include "vlf/render.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "test_util.hpp"
#include "vlf/bake.hpp"
#include "vlf/camera.hpp"
#include "vlf/error.hpp"
#include "vlf/image_io.hpp"
#include "vlf/image_metrics.hpp"
#include "vlf/parallel.hpp"
#include "vlf/pathtrace.hpp"
#include "vlf/propagation.hpp"
#include "vlf/scene_loader.hpp"

namespace vlf {
namespace {

namespace fs = std::filesystem;

double angle_deg(const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) *
           180.0 / kPi;
}

// ---------------------------------------------------------------------------------------
// Camera

TEST(CameraRays, CentrePixelPointsAtLookAt) {
    Normalisation norm;
    norm.center = Vec3(10, -3, 7);
    norm.scale = 0.01;
    Camera c;
    c.eye = Vec3(50, 20, -300);
    c.look_at = Vec3(-40, 60, 100);
    c.up = Vec3(0, 1, 0);
    c.fov_y_deg = 40;
    const PinholeCamera cam(c, norm, 64, 48);
    EXPECT_LT(glm::length(cam.origin() - norm.to_normalised(c.eye)), 1e-12);
    const Vec3 centre = cam.direction(32.0, 24.0);
    const Vec3 want = glm::normalize(norm.to_normalised(c.look_at) - norm.to_normalised(c.eye));
    EXPECT_LT(glm::length(centre - want), 1e-12);
    EXPECT_NEAR(glm::length(centre), 1.0, 1e-12);
}

TEST(CameraRays, FieldOfViewAndOrientation) {
    Camera c;
    c.eye = Vec3(0, 0, 0);
    c.look_at = Vec3(0, 0, 1);
    c.up = Vec3(0, 1, 0);
    c.fov_y_deg = 60;
    const int W = 200, H = 100;
    const PinholeCamera cam(c, Normalisation{}, W, H);
    // Top and bottom image edges are fov/2 from the axis; row 0 is the top.
    EXPECT_NEAR(angle_deg(cam.direction(W / 2.0, 0), c.look_at), 30.0, 1e-9);
    EXPECT_NEAR(angle_deg(cam.direction(W / 2.0, H), c.look_at), 30.0, 1e-9);
    EXPECT_GT(cam.direction(W / 2.0, 0).y, 0.0);
    EXPECT_NEAR(angle_deg(cam.direction(W / 2.0, 0), cam.direction(W / 2.0, H)), 60.0, 1e-9);
    // Horizontal: tan(h/2) = aspect * tan(v/2); right = forward x up = -x here.
    const double h = 2.0 * std::atan(2.0 * std::tan(kPi / 6)) * 180.0 / kPi;
    EXPECT_NEAR(angle_deg(cam.direction(0, H / 2.0), cam.direction(W, H / 2.0)), h, 1e-9);
    EXPECT_LT(cam.direction(W, H / 2.0).x, 0.0);
}

TEST(CameraRays, DegenerateCameraThrows) {
    Camera c;
    c.eye = c.look_at = Vec3(1, 2, 3);
    EXPECT_THROW(PinholeCamera(c, Normalisation{}, 8, 8), ParameterError);
    c.look_at = Vec3(1, 5, 3);  // looking along up
    EXPECT_THROW(PinholeCamera(c, Normalisation{}, 8, 8), ParameterError);
    c.look_at = Vec3(1, 2, 4);
    c.fov_y_deg = 180;
    EXPECT_THROW(PinholeCamera(c, Normalisation{}, 8, 8), ParameterError);
}

TEST(CameraPath, InterpolatesThroughKeyframes) {
    const auto j = nlohmann::json::parse(R"({"frames": 5, "keyframes": [
        {"eye": [0,0,0], "look_at": [0,0,1], "fov_y_deg": 40, "time": 0},
        {"eye": [1,0,0], "look_at": [1,0,1], "fov_y_deg": 60, "time": 1},
        {"eye": [2,1,0], "look_at": [2,1,1], "up": [0,1,0], "fov_y_deg": 60, "time": 3}]})");
    const CameraPath p = camera_path_from_json(j, "path.json");
    ASSERT_EQ(p.keyframes.size(), 3u);
    EXPECT_EQ(p.frames, 5);
    EXPECT_LT(glm::length(p.frame(0).eye - Vec3(0, 0, 0)), 1e-12);
    EXPECT_LT(glm::length(p.frame(4).eye - Vec3(2, 1, 0)), 1e-12);
    EXPECT_LT(glm::length(p.at(1.0).eye - Vec3(1, 0, 0)), 1e-12);
    EXPECT_NEAR(p.at(0.5).fov_y_deg, 50.0, 1e-12);  // linear fov
    // Catmull-Rom on collinear, evenly timed points stays on the line.
    EXPECT_NEAR(p.at(0.5).eye.y, 0.0, 0.05);
    EXPECT_GT(p.at(0.5).eye.x, 0.3);
    EXPECT_LT(p.at(0.5).eye.x, 0.7);
}

TEST(CameraPath, BadPathsThrowNamingThePlace) {
    auto fails = [](const char* text, const char* needle) {
        try {
            camera_path_from_json(nlohmann::json::parse(text), "p.json");
        } catch (const Error& e) {
            return std::string(e.what()).find(needle) != std::string::npos;
        }
        return false;
    };
    EXPECT_TRUE(fails(R"({"frames": 3})", "keyframes"));
    EXPECT_TRUE(fails(R"({"keyframes": [{"eye":[0,0,0],"look_at":[0,0,1]}]})", "frames"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": [{"eye":[0,0],"look_at":[0,0,1]}]})",
                      "keyframes[0].eye"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": [{"eye":[0,0,0],"look_at":[0,0,1],"time":1},
                                                      {"eye":[0,0,0],"look_at":[0,0,1],"time":1}]})",
                      "strictly increase"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": [{"eye":[0,0,0],"look_at":[0,0,1],"zoom":2}]})",
                      "unknown key"));
}

TEST(CameraParse, VectorsAndSizes) {
    EXPECT_EQ(parse_vec3("1,-2.5,3e2", "--eye"), Vec3(1, -2.5, 300));
    EXPECT_THROW(parse_vec3("1,2", "--eye"), ParameterError);
    EXPECT_THROW(parse_vec3("1,2,x", "--eye"), ParameterError);
    EXPECT_THROW(parse_vec3("1,2,3,4", "--eye"), ParameterError);
    EXPECT_THROW(parse_vec3("1,nan,3", "--eye"), ParameterError);
    int w = 0, h = 0;
    parse_size("640x480", "--size", w, h);
    EXPECT_EQ(w, 640);
    EXPECT_EQ(h, 480);
    EXPECT_THROW(parse_size("640", "--size", w, h), ParameterError);
    EXPECT_THROW(parse_size("0x480", "--size", w, h), ParameterError);
    EXPECT_THROW(parse_size("-3x4", "--size", w, h), ParameterError);
}

// ---------------------------------------------------------------------------------------
// Image I/O

class ImageIo : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("vlf-image-" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    fs::path m_dir;
};

Image gradient(int w, int h) {
    Image im;
    im.width = w;
    im.height = h;
    im.pixels.resize(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) im.at(x, y) = Rgb(0.01 * x, 0.5 + y, 1000.0 / (1 + x + y));
    return im;
}

TEST_F(ImageIo, ExrRoundTripWithinHalfPrecision) {
    const Image im = gradient(37, 23);
    const std::string p = (m_dir / "a.exr").string();
    write_image(p, im);
    EXPECT_FALSE(fs::exists(p + ".partial"));
    const Image back = read_exr(p);
    ASSERT_EQ(back.width, im.width);
    ASSERT_EQ(back.height, im.height);
    for (size_t k = 0; k < im.pixels.size(); ++k)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(back.pixels[k][c], im.pixels[k][c],
                        1e-3 * std::abs(im.pixels[k][c]) + 1e-7);
    EXPECT_LT(relative_rmse(back, im), 1e-3);
}

TEST_F(ImageIo, PngWrittenAndNonEmpty) {
    const std::string p = (m_dir / "a.png").string();
    write_image(p, gradient(16, 8), 1.0);
    ASSERT_TRUE(fs::exists(p));
    EXPECT_GT(fs::file_size(p), 8u);
    EXPECT_EQ(test::read_text(p).substr(1, 3), "PNG");
    const auto bytes = tone_map_srgb8(gradient(16, 8), 0.0);
    EXPECT_EQ(bytes.size(), 16u * 8u * 3u);
    // Reinhard + sRGB: radiance 1 -> 0.5 -> sRGB 188.
    Image one;
    one.width = one.height = 1;
    one.pixels = {Rgb(1.0, 0.0, 3.0)};
    const auto b = tone_map_srgb8(one, 0.0);
    EXPECT_EQ(b[0], 188);
    EXPECT_EQ(b[1], 0);
    EXPECT_EQ(tone_map_srgb8(one, -1.0)[0], 156);  // 0.5 -> 1/3 -> sRGB 156
}

TEST_F(ImageIo, UnknownExtensionAndBadPathsThrow) {
    EXPECT_THROW(write_image((m_dir / "a.tiff").string(), gradient(4, 4)), Error);
    EXPECT_THROW(write_image((m_dir / "no-such-dir" / "a.exr").string(), gradient(4, 4)), Error);
    EXPECT_THROW(write_image((m_dir / "no-such-dir" / "a.png").string(), gradient(4, 4)), Error);
    EXPECT_THROW(read_exr((m_dir / "missing.exr").string()), Error);
    const std::string junk = (m_dir / "junk.exr").string();
    std::FILE* f = std::fopen(junk.c_str(), "wb");
    std::fputs("not an exr", f);
    std::fclose(f);
    EXPECT_THROW(read_exr(junk), Error);
}

TEST(ImageMetric, RelativeRmse) {
    Image a = gradient(8, 8), b = a;
    EXPECT_EQ(relative_rmse(a, b), 0.0);
    for (Rgb& p : b.pixels) p *= 1.1;
    EXPECT_NEAR(relative_rmse(b, a), 0.1, 1e-12);
    EXPECT_THROW(relative_rmse(gradient(4, 4), gradient(4, 5)), Error);
}

// ---------------------------------------------------------------------------------------
// Path-traced reference

// A bake holding only a scene (zero light maps, no rays): enough for the path tracer.
Bake scene_only_bake(const Scene& scene) {
    Bake b;
    b.scene = scene;
    b.texel_offset.assign(scene.faces.size() + 1, 0);
    for (size_t f = 0; f < scene.faces.size(); ++f)
        b.texel_offset[f + 1] = b.texel_offset[f] + size_t(scene.faces[f].texels.count());
    b.lightmap_radiance.assign(b.texel_offset.back(), Rgb(0.0));
    return b;
}

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
    const Bake bake = scene_only_bake(scene);
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
    const Bake bake = scene_only_bake(scene);
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

// The reference integrates over each pixel's area (jittered samples); the lookup modes
// shoot one ray through the pixel centre. Rendering them `k` times finer and averaging
// k x k blocks gives the same pixel footprint, so edges compare like with like. k must be
// large: the lamp (radiance 17) against the ceiling (0.1) makes an edge pixel's coverage
// error of 1/(2k) worth 17/(2k) — at k = 4 that alone gave 7.6 % relative RMSE on
// cornell.json, at k = 16 the whole image is within 1.5 %.
Image render_box_filtered(const Renderer& r, const Camera& cam, RenderMode mode, int size, int k) {
    RenderSettings s;
    s.width = s.height = size * k;
    s.mode = mode;
    const Image fine = r.render(cam, s);
    Image im;
    im.width = im.height = size;
    im.pixels.assign(size_t(size) * size, Rgb(0.0));
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) im.at(x / k, y / k) += fine.at(x, y) / double(k * k);
    return im;
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

// Relative RMSE of every lookup mode against the reference, printed; also over the pixels
// away from the lamp (reference red < 3), where the lamp's exact Le does not dominate.
struct ModeErrors {
    double all[3] = {0, 0, 0}, without_lamp[3] = {0, 0, 0};
};

ModeErrors measure(const std::string& scene_file, const std::string& reference_file) {
    const auto b = bake_scene(scene_file);
    const Renderer r(b->bake);
    const Camera& cam = b->scene.cameras.at(0);
    const Image ref = reference(reference_file);
    const RenderMode modes[3] = {RenderMode::Rays, RenderMode::Texture, RenderMode::Raytrace};
    ModeErrors e;
    for (int m = 0; m < 3; ++m) {
        const auto t0 = std::chrono::steady_clock::now();
        const Image im = render_box_filtered(r, cam, modes[m], ref.width, 16);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        e.all[m] = relative_rmse(im, ref);
        double num = 0.0, den = 0.0;
        for (size_t k = 0; k < im.pixels.size(); ++k)
            if (ref.pixels[k].x < 3.0) {
                const Rgb d = im.pixels[k] - ref.pixels[k];
                num += glm::dot(d, d);
                den += glm::dot(ref.pixels[k], ref.pixels[k]);
            }
        e.without_lamp[m] = std::sqrt(num / den);
        std::printf("%s %-8s relative RMSE %.4f (without the lamp %.4f); %dx%d in %.2f s\n",
                    scene_file.c_str(), to_string(modes[m]).c_str(), e.all[m], e.without_lamp[m],
                    ref.width * 16, ref.height * 16, seconds);
        if (const char* out = std::getenv("VLF_RENDER_TEST_OUT"))
            write_image(std::string(out) + "/" + fs::path(scene_file).stem().string() + "-" +
                            to_string(modes[m]) + ".exr",
                        im);
    }
    return e;
}

TEST(RenderAccuracy, CornellTextureAndRaytraceWithin5Percent) {
    VLF_SKIP_UNDER_SANITIZER();
    const ModeErrors e = measure("scenes/cornell.json", "cornell-pathtrace-128.exr");
    EXPECT_LE(e.all[1], 0.05) << "texture";
    EXPECT_LE(e.all[2], 0.05) << "raytrace";
}

TEST(RenderAccuracy, CornellMirrorsRaytraceWithin10Percent) {
    VLF_SKIP_UNDER_SANITIZER();
    const ModeErrors e =
        measure("scenes/cornell-mirrors.json", "cornell-mirrors-pathtrace-128.exr");
    EXPECT_LE(e.all[2], 0.10) << "raytrace";
}

}  // namespace
}  // namespace vlf
