// The path-traced reference (render/pathtrace.hpp, DESIGN §7–8): a furnace converges to
// Le / (1 - rho), and the image does not depend on the thread count.
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

}  // namespace
}  // namespace vlf
