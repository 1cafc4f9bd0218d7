// The whole light field's statistics (field_stats.hpp) add up over the rasterised PSFs, and
// rasterising every direction gives the same field on one and two threads.
#include "vlf/field/field_stats.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/scene_loader.hpp"

namespace vlf {
namespace {

// One PSF per direction, rasterised in parallel.
std::vector<Psf> rasterise_field(const Scene& scene, const FieldParams& p) {
    const DirectionSet dirs(p.directions, p.scheme);
    std::vector<Psf> psfs(dirs.size());
    parallel_for(0, dirs.size(), [&](long d) {
        psfs[d] = rasterise_psf(scene, dirs.direction(int(d)), int(d), p.resolution, p.tile);
    });
    return psfs;
}

bool same_psf(const Psf& a, const Psf& b) {
    if (a.tiles.size() != b.tiles.size() || a.tile_of != b.tile_of) return false;
    for (size_t i = 0; i < a.tiles.size(); ++i) {
        const Tile &x = a.tiles[i], &y = b.tiles[i];
        if (x.fragments.size() != y.fragments.size() || x.spans.size() != y.spans.size())
            return false;
        for (size_t f = 0; f < x.fragments.size(); ++f)
            if (x.fragments[f].face != y.fragments[f].face ||
                x.fragments[f].covered != y.fragments[f].covered)
                return false;
        for (size_t s = 0; s < x.spans.size(); ++s)
            if (x.spans[s].begin != y.spans[s].begin || x.spans[s].end != y.spans[s].end)
                return false;
    }
    return true;
}

TEST(FieldStats, SameFieldOnOneAndTwoThreads) {
    const Scene scene = load_scene(test::source_path("scenes/cornell.json"));
    FieldParams p;
    p.directions = 129;
    p.resolution = 32;
    p.tile = 8;
    std::vector<Psf> one, two;
    {
        ThreadLimit limit(1);
        one = rasterise_field(scene, p);
    }
    {
        ThreadLimit limit(2);
        two = rasterise_field(scene, p);
    }
    ASSERT_EQ(one.size(), 129u);
    for (size_t d = 0; d < one.size(); ++d) EXPECT_TRUE(same_psf(one[d], two[d]));
}

TEST(FieldStats, StatisticsAddUp) {
    const Scene scene = load_scene(test::source_path("scenes/cornell.json"));
    FieldParams p;
    p.directions = 33;
    p.resolution = 64;
    p.tile = 8;
    const FieldStats s = measure_field(scene, p);
    const std::vector<Psf> field = rasterise_field(scene, p);
    int64_t tiles = 0, fragments = 0, covered = 0;
    for (const Psf& psf : field) {
        tiles += static_cast<int64_t>(psf.tiles.size());
        for (const Tile& t : psf.tiles) {
            fragments += static_cast<int64_t>(t.fragments.size());
            covered += t.covered;
        }
    }
    EXPECT_EQ(s.tiles_total, 33 * 64);
    EXPECT_EQ(s.nonempty_tiles, tiles);
    EXPECT_EQ(s.fragments, fragments);
    EXPECT_EQ(s.covered_rays, covered);
    EXPECT_NEAR(s.fragments_per_tile_mean, double(fragments) / tiles, 1e-12);
    EXPECT_GE(s.fragments_per_tile_max, static_cast<int>(s.fragments_per_tile_mean));
    EXPECT_GT(s.memory.total(), 0);
    EXPECT_EQ(s.specular_rays, 0);  // the plain Cornell room has no mirror
}

}  // namespace
}  // namespace vlf
