// Rim pools (transport/rim_pools.hpp): sliver texels at a face's rim share their host's
// exitance; power per face is kept and a uniform field stays uniform.
#include "vlf/transport/rim_pools.hpp"

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

TEST(RimPools, SliversShareTheirHostsValueAndPowerIsKept) {
    const Scene scene = odd_faces();
    TextureMaps maps(scene);
    const RimPools pools = build_rim_pools(scene, maps);
    ASSERT_FALSE(pools.empty());
    // A uniform field is unchanged.
    fill(scene, maps, [](const Chart&, size_t) { return 2.0; });
    pool_rim_texels(pools, scene, maps, maps.next);
    expect_uniform(scene, maps, 2.0);
    // Any field: power per face kept; a pooled texel shows its host's exitance; hosts are
    // at least half inside, every pooled texel less than wholly inside.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 2.0);
    fill(scene, maps, [&](const Chart&, size_t) { return u(rng); });
    const double before = face_power(maps, scene.charts[1]);
    pool_rim_texels(pools, scene, maps, maps.next);
    EXPECT_NEAR(face_power(maps, scene.charts[1]), before, 1e-12 * before);
    int pooled = 0;
    for (const Chart& f : scene.charts) {
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
