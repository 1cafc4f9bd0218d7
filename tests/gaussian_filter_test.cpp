// The energy-preserving Gaussian filter of the next texture maps (VLF §5,
// transport/gaussian_filter.hpp): it moves power only within a face, conserves it to
// rounding, keeps a uniform field uniform at every rim, and smooths like a Gaussian inside.
#include "vlf/transport/gaussian_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "texture_test_util.hpp"

namespace vlf {
namespace {

using test::expect_uniform;
using test::face_power;
using test::fill;
using test::odd_faces;

TEST(GaussianFilter, UniformFieldStaysUniformAtEveryRim) {
    const Scene scene = odd_faces();
    for (double sigma : {0.7, 1.0, 2.5}) {
        TextureMaps maps(scene);
        fill(scene, maps, [](const Chart&, size_t) { return 3.0; });
        gaussian_filter_next(scene, maps, sigma);
        expect_uniform(scene, maps, 3.0);
    }
}

TEST(GaussianFilter, ConservesPowerAndSmoothsLikeAGaussianInside) {
    const Scene scene = odd_faces();
    TextureMaps maps(scene);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 2.0);
    fill(scene, maps, [&](const Chart&, size_t) { return u(rng); });
    const double before0 = face_power(maps, scene.charts[0]),
                 before1 = face_power(maps, scene.charts[1]);
    gaussian_filter_next(scene, maps, 1.0);
    EXPECT_NEAR(face_power(maps, scene.charts[0]), before0, 1e-12 * before0);
    EXPECT_NEAR(face_power(maps, scene.charts[1]), before1, 1e-12 * before1);

    // An impulse in the rectangle: what its neighbours receive follows the Gaussian of
    // their distance (a diagonal neighbour exp(-1 / (2 sigma^2)) of a side neighbour; the
    // impulse itself keeps the weight of the kernel cells beyond the rim as well).
    const Chart& f = scene.charts[0];
    const int W = f.texels.width;
    const size_t c = size_t(2) * W + 3;
    ASSERT_GE(f.texel_area[c], 0.999 * f.texels.size * f.texels.size);
    fill(scene, maps, [&](const Chart& g, size_t k) { return g.id == 0 && k == c ? 1.0 : 0.0; });
    gaussian_filter_next(scene, maps, 0.7);
    const size_t b = maps.begin(0);
    const double g1 = std::exp(-1.0 / (2 * 0.49));
    EXPECT_NEAR(maps.next[b + c + W + 1].x / maps.next[b + c + 1].x, g1, 1e-9);
    EXPECT_NEAR(maps.next[b + c + 2].x / maps.next[b + c + 1].x, g1 * g1 * g1, 1e-9);
}

}  // namespace
}  // namespace vlf
