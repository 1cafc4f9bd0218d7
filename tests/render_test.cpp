// Walkthrough rendering (VLF §6; DESIGN §7–8): pinhole camera and camera paths, image I/O,
// the path-traced reference (furnace, determinism) and the accuracy of the bake's render
// modes against that reference on the Cornell scenes.
#include "vlf/render/render.hpp"

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
#include "vlf/bake/bake.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/render/camera.hpp"
#include "vlf/render/image_io.hpp"
#include "vlf/render/image_metrics.hpp"
#include "vlf/render/pathtrace.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/propagation.hpp"

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

// Up between two keyframes rolled 170 degrees apart about the view direction: slerp of the
// orientations keeps it a unit vector orthogonal to the view, turning at constant speed
// through the shorter arc. A normalised linear blend of the up vectors (the blend itself
// shrinks to 9% of unit length mid-way) has turned less than 5 degrees a quarter of the
// way, where slerp has turned 42.5, and keeps a keyframe's up that is not orthogonal to
// a tilted view.
TEST(CameraPath, UpRotatesBySlerpOfTheOrientation) {
    const double roll = glm::radians(170.0);
    CameraPath p;
    p.frames = 21;
    CameraKeyframe a, b;
    a.camera.eye = b.camera.eye = Vec3(1, 2, 3);
    a.camera.look_at = b.camera.look_at = Vec3(1, 2, 13);  // looking along +z
    a.camera.up = Vec3(0, 1, 0);
    b.camera.up = Vec3(-std::sin(roll), std::cos(roll), 0);
    b.time = 1.0;
    p.keyframes = {a, b};
    const Vec3 view(0, 0, 1);
    double previous = -1.0;
    for (int k = 0; k < p.frames; ++k) {
        const double s = double(k) / (p.frames - 1);
        const Camera c = p.frame(k);
        EXPECT_NEAR(glm::length(c.up), 1.0, 1e-12) << "s = " << s;
        EXPECT_NEAR(glm::dot(c.up, view), 0.0, 1e-12) << "s = " << s;
        const double angle =
            std::atan2(glm::dot(glm::cross(a.camera.up, c.up), view), glm::dot(a.camera.up, c.up));
        EXPECT_NEAR(angle, s * roll, 1e-9) << "s = " << s;  // uniform, hence monotonic
        EXPECT_GT(angle, previous) << "s = " << s;
        previous = angle;
    }
    // Keyframes whose up is not orthogonal to their (downward) view: the interpolated up is.
    for (CameraKeyframe* f : {&a, &b}) {
        f->camera.look_at = f->camera.eye + Vec3(0, -1, 1);
        f->camera.up = Vec3(0, 1, 0);
    }
    b.camera.eye.x += 1;
    b.camera.look_at.x += 1;
    p.keyframes = {a, b};
    for (double t : {0.25, 0.5, 0.75}) {
        const Camera c = p.at(t);
        EXPECT_NEAR(glm::length(c.up), 1.0, 1e-12);
        EXPECT_NEAR(glm::dot(c.up, glm::normalize(c.look_at - c.eye)), 0.0, 1e-12);
        EXPECT_GT(c.up.y, 0.7);  // still up, tilted with the view
    }
}

TEST(CameraPath, BadPathsThrowNamingThePlace) {
    auto fails = [](const char* text, const char* needle) -> ::testing::AssertionResult {
        try {
            camera_path_from_json(nlohmann::json::parse(text), "p.json");
        } catch (const Error& e) {
            if (std::string(e.what()).find(needle) != std::string::npos)
                return ::testing::AssertionSuccess();
            return ::testing::AssertionFailure() << "message: " << e.what();
        }
        return ::testing::AssertionFailure() << "no error";
    };
    EXPECT_TRUE(fails(R"({"frames": 3})", "p.json: (top level): missing required key 'keyframes'"));
    EXPECT_TRUE(fails(R"({"keyframes": [{"eye":[0,0,0],"look_at":[0,0,1]}]})",
                      "p.json: (top level): missing required key 'frames'"));
    EXPECT_TRUE(fails(R"({"frames": "3", "keyframes": [{"eye":[0,0,0],"look_at":[0,0,1]}]})",
                      "p.json: frames: expected an integer, got \"3\""));
    EXPECT_TRUE(fails(R"({"frames": 0, "keyframes": [{"eye":[0,0,0],"look_at":[0,0,1]}]})",
                      "p.json: frames: must be in [1, 1000000] (got 0)"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": []})",
                      "p.json: keyframes: expected at least 1 element, got an empty array"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": [{"eye":[0,0],"look_at":[0,0,1]}]})",
                      "p.json: keyframes[0].eye: expected an array of 3 numbers, got an array of "
                      "2 elements"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": [{"eye":[0,0,0],"look_at":[0,0,1],"time":1},
                                                      {"eye":[0,0,0],"look_at":[0,0,1],"time":1}]})",
                      "p.json: keyframes[1].time: times must strictly increase (1 after 1)"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": [{"eye":[0,0,0],"look_at":[0,0,1],"zoom":2}]})",
                      "p.json: keyframes[0].zoom: unknown key (expected one of: eye, look_at, up, "
                      "fov_y_deg, time)"));
    EXPECT_TRUE(fails(R"({"frames": 3, "keyframes": [{"eye":[0,0,0],"look_at":[0,0,0]}]})",
                      "p.json: keyframes[0]: eye and look_at coincide"));
    EXPECT_TRUE(
        fails(R"({"frames": 3, "fps": 30, "keyframes": [{"eye":[0,0,0],"look_at":[0,0,1]}]})",
              "p.json: fps: unknown key (expected one of: keyframes, frames)"));
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

PixelMask mask_of(int w, int h, std::initializer_list<std::pair<int, int>> set) {
    PixelMask m;
    m.width = w;
    m.height = h;
    m.on.assign(size_t(w) * h, 0);
    for (auto [x, y] : set) m.on[size_t(y) * w + x] = 1;
    return m;
}

TEST(ImageMetric, AwayFromIsOutsideTheThreeByThreeNeighbourhoods) {
    // Set pixels at a corner and inside; the cleared blocks are clipped at the border.
    const PixelMask emitters = mask_of(8, 6, {{0, 0}, {5, 3}});
    const PixelMask away = away_from(emitters);
    ASSERT_EQ(away.width, 8);
    ASSERT_EQ(away.height, 6);
    int cleared = 0;
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 8; ++x) {
            const bool near_corner = x <= 1 && y <= 1;
            const bool near_inner = x >= 4 && x <= 6 && y >= 2 && y <= 4;
            EXPECT_EQ(away.at(x, y), !(near_corner || near_inner)) << x << "," << y;
            cleared += !away.at(x, y);
        }
    EXPECT_EQ(cleared, 4 + 9);
    // Radius 0: exactly the complement.
    const PixelMask complement = away_from(emitters, 0);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 8; ++x) EXPECT_EQ(complement.at(x, y), !emitters.at(x, y));
}

TEST(ImageMetric, ErrorAwayFromEmittersIgnoresTheLampAndItsRim) {
    // Reference: a lamp pixel of radiance 17 amid a constant (1, 2, 3). The image gets the
    // lamp and its eight neighbours badly wrong and is off by (+10 %, -5 %, 0) elsewhere:
    // away from the lamp the RMSE is sqrt((0.1^2 1 + 0.05^2 4) / (1 + 4 + 9)) and the
    // mean ratio (1.1, 0.95, 1); the whole-image RMSE is dominated by the lamp.
    const int w = 9, h = 7;
    Image ref, im;
    ref.width = im.width = w;
    ref.height = im.height = h;
    ref.pixels.assign(size_t(w) * h, Rgb(1, 2, 3));
    ref.at(3, 2) = Rgb(17.0);
    im.pixels.assign(size_t(w) * h, Rgb(1.1, 1.9, 3.0));
    for (int y = 1; y <= 3; ++y)
        for (int x = 2; x <= 4; ++x) im.at(x, y) = Rgb(5.0);
    const PixelMask emitters = mask_of(w, h, {{3, 2}});
    const ImageError e = image_error(im, ref, emitters);
    EXPECT_EQ(e.pixels, size_t(w * h));
    EXPECT_EQ(e.away_pixels, size_t(w * h - 9));
    EXPECT_NEAR(e.rmse_away, std::sqrt((0.01 + 0.0025 * 4) / 14.0), 1e-12);
    EXPECT_NEAR(e.ratio_away.x, 1.1, 1e-12);
    EXPECT_NEAR(e.ratio_away.y, 0.95, 1e-12);
    EXPECT_NEAR(e.ratio_away.z, 1.0, 1e-12);
    EXPECT_GT(e.rmse, 0.3);  // the lamp pixel (off by 12) and its rim dominate
    EXPECT_NEAR(e.rmse, relative_rmse(im, ref), 1e-15);
    EXPECT_NEAR(relative_rmse(im, ref, away_from(emitters)), e.rmse_away, 1e-15);
    // Excluding the lamp pixel alone (radius 0), the errors of its rim come back in.
    EXPECT_GT(relative_rmse(im, ref, away_from(emitters, 0)), 0.4);
    EXPECT_THROW(image_error(im, ref, mask_of(w, h + 1, {})), Error);
    EXPECT_THROW(mean_ratio(im, gradient(w, h + 1), away_from(emitters)), Error);
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
    const Bake bake = scene_only_bake(scene);
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
    Bake bake = scene_only_bake(scene);
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

}  // namespace
}  // namespace vlf
