// Image error as a viewer sees it (render/image_metrics.hpp): relative RMSE, the pixels
// away from emitters, and the error there.
#include "vlf/render/image_metrics.hpp"

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

TEST(ImageMetric, RelativeRmse) {
    Image a = test::gradient(8, 8), b = a;
    EXPECT_EQ(relative_rmse(a, b), 0.0);
    for (Rgb& p : b.pixels) p *= 1.1;
    EXPECT_NEAR(relative_rmse(b, a), 0.1, 1e-12);
    EXPECT_THROW(relative_rmse(test::gradient(4, 4), test::gradient(4, 5)), Error);
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
    EXPECT_THROW(mean_ratio(im, test::gradient(w, h + 1), away_from(emitters)), Error);
}

}  // namespace
}  // namespace vlf
