// The walkthrough's pinhole camera and camera paths (render/camera.hpp, VLF §6; DESIGN §7):
// rays through pixels, field of view, bad cameras, keyframe interpolation and bad paths.
#include "vlf/render/camera.hpp"

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
#include "vlf/scene/scene_loader.hpp"

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

}  // namespace
}  // namespace vlf
