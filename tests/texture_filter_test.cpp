// The maps' post-processing after each cycle (vlf/transport/rim_pools.hpp,
// vlf/transport/gaussian_filter.hpp): both move power only within a face, conserve it to rounding,
// and keep a uniform field uniform, partial rim texels included.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_util.hpp"
#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/gaussian_filter.hpp"
#include "vlf/transport/rim_pools.hpp"

namespace vlf {
namespace {

// A triangle and a rectangle of 7.3 x 4.6 texels: rim texels of every size.
Scene odd_faces() {
    return load_scene_from_string(R"({
      "materials": {"f": {"diffuse": [0.5, 0.5, 0.5], "emission": [1, 1, 1]}},
      "objects": [
        {"type": "polygon", "material": "f", "vertices": [[0, 0, 0], [0.73, 0, 0], [0.73, 0.46, 0], [0, 0.46, 0]]},
        {"type": "polygon", "material": "f", "vertices": [[0, 0, 0.5], [0.81, 0.1, 0.5], [0.2, 0.67, 0.5]]}
      ],
      "settings": {"texel_size": 0.1}
    })",
                                  "odd.json", ".");
}

// P = B * area: a field of exitance B(texel).
template <class F>
void fill(const Scene& scene, TextureMaps& maps, F&& exitance) {
    for (const Face& f : scene.faces)
        for (size_t k = 0; k < maps.count(f.id); ++k)
            maps.next[maps.begin(f.id) + k] = Rgb(exitance(f, k)) * f.texel_area[k];
}

double face_power(const TextureMaps& maps, const Face& f) {
    return TextureMaps::sum(maps.next, maps.begin(f.id), maps.count(f.id)).x;
}

void expect_uniform(const Scene& scene, const TextureMaps& maps, double value) {
    for (const Face& f : scene.faces)
        for (size_t k = 0; k < maps.count(f.id); ++k) {
            if (f.texel_area[k] <= 0.0) continue;
            EXPECT_NEAR(maps.next[maps.begin(f.id) + k].x / f.texel_area[k], value, 1e-12 * value)
                << "face " << f.id << " texel " << k << " (inside "
                << f.texel_area[k] / (f.texels.size * f.texels.size) << ")";
        }
}

TEST(GaussianFilter, UniformFieldStaysUniformAtEveryRim) {
    const Scene scene = odd_faces();
    for (double sigma : {0.7, 1.0, 2.5}) {
        TextureMaps maps(scene);
        fill(scene, maps, [](const Face&, size_t) { return 3.0; });
        gaussian_filter_next(scene, maps, sigma);
        expect_uniform(scene, maps, 3.0);
    }
}

TEST(GaussianFilter, ConservesPowerAndSmoothsLikeAGaussianInside) {
    const Scene scene = odd_faces();
    TextureMaps maps(scene);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 2.0);
    fill(scene, maps, [&](const Face&, size_t) { return u(rng); });
    const double before0 = face_power(maps, scene.faces[0]),
                 before1 = face_power(maps, scene.faces[1]);
    gaussian_filter_next(scene, maps, 1.0);
    EXPECT_NEAR(face_power(maps, scene.faces[0]), before0, 1e-12 * before0);
    EXPECT_NEAR(face_power(maps, scene.faces[1]), before1, 1e-12 * before1);

    // An impulse in the rectangle: what its neighbours receive follows the Gaussian of
    // their distance (a diagonal neighbour exp(-1 / (2 sigma^2)) of a side neighbour; the
    // impulse itself keeps the weight of the kernel cells beyond the rim as well).
    const Face& f = scene.faces[0];
    const int W = f.texels.width;
    const size_t c = size_t(2) * W + 3;
    ASSERT_GE(f.texel_area[c], 0.999 * f.texels.size * f.texels.size);
    fill(scene, maps, [&](const Face& g, size_t k) { return g.id == 0 && k == c ? 1.0 : 0.0; });
    gaussian_filter_next(scene, maps, 0.7);
    const size_t b = maps.begin(0);
    const double g1 = std::exp(-1.0 / (2 * 0.49));
    EXPECT_NEAR(maps.next[b + c + W + 1].x / maps.next[b + c + 1].x, g1, 1e-9);
    EXPECT_NEAR(maps.next[b + c + 2].x / maps.next[b + c + 1].x, g1 * g1 * g1, 1e-9);
}

TEST(RimPools, SliversShareTheirHostsValueAndPowerIsKept) {
    const Scene scene = odd_faces();
    TextureMaps maps(scene);
    const RimPools pools = build_rim_pools(scene, maps);
    ASSERT_FALSE(pools.empty());
    // A uniform field is unchanged.
    fill(scene, maps, [](const Face&, size_t) { return 2.0; });
    pool_rim_texels(pools, scene, maps, maps.next);
    expect_uniform(scene, maps, 2.0);
    // Any field: power per face kept; a pooled texel shows its host's exitance; hosts are
    // at least half inside, every pooled texel less than wholly inside.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 2.0);
    fill(scene, maps, [&](const Face&, size_t) { return u(rng); });
    const double before = face_power(maps, scene.faces[1]);
    pool_rim_texels(pools, scene, maps, maps.next);
    EXPECT_NEAR(face_power(maps, scene.faces[1]), before, 1e-12 * before);
    int pooled = 0;
    for (const Face& f : scene.faces) {
        const double cell = f.texels.size * f.texels.size;
        for (size_t k = 0; k < maps.count(f.id); ++k) {
            const size_t t = maps.begin(f.id) + k, h = pools.host[t];
            if (h == t) continue;
            ++pooled;
            EXPECT_LT(f.texel_area[k], cell * (1 - 1e-9));
            EXPECT_GE(f.texel_area[h - maps.begin(f.id)], 0.5 * cell);
            EXPECT_NEAR(maps.next[t].x / f.texel_area[k],
                        maps.next[h].x / f.texel_area[h - maps.begin(f.id)], 1e-12);
        }
    }
    EXPECT_GT(pooled, 5);
}

}  // namespace
}  // namespace vlf
