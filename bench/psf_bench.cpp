// PSF rasterisation benchmarks: one PSF, and the whole field of the Cornell room.
#include <benchmark/benchmark.h>

#include "vlf/core/parallel.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/exchange.hpp"
#include "vlf/field/field_stats.hpp"
#include "vlf/scene/scene_loader.hpp"

namespace {

const vlf::Scene& cornell() {
    static const vlf::Scene scene =
        vlf::load_scene(std::string(VLF_SOURCE_DIR) + "/scenes/cornell.json");
    return scene;
}

// One PSF of the Cornell room (N = arg0, m = arg1), a direction off the axes.
void BM_RasterisePsf(benchmark::State& state) {
    const vlf::Scene& scene = cornell();
    const vlf::Vec3 omega = glm::normalize(vlf::Vec3(0.3, 0.5, 0.8));
    for (auto _ : state) {
        vlf::Psf psf = vlf::rasterise_psf(scene, omega, 0, static_cast<int>(state.range(0)),
                                          static_cast<int>(state.range(1)));
        benchmark::DoNotOptimize(psf.tiles.data());
    }
}
BENCHMARK(BM_RasterisePsf)->Args({64, 8})->Args({128, 16})->Unit(benchmark::kMicrosecond);

// All 2049 directions of the Cornell room at N = 128, m = 16, on all cores (issue goal:
// under 2 s on 2 cores).
void BM_RasteriseField(benchmark::State& state) {
    const vlf::Scene& scene = cornell();
    vlf::FieldParams p;
    p.directions = static_cast<int>(state.range(0));
    p.resolution = static_cast<int>(state.range(1));
    p.tile = static_cast<int>(state.range(2));
    const vlf::DirectionSet dirs(p.directions, p.scheme);
    for (auto _ : state) {
        std::vector<vlf::Psf> field(dirs.size());
        vlf::parallel_for(0, dirs.size(), [&](long d) {
            field[d] =
                vlf::rasterise_psf(scene, dirs.direction(int(d)), int(d), p.resolution, p.tile);
        });
        benchmark::DoNotOptimize(field.data());
    }
}
BENCHMARK(BM_RasteriseField)
    ->Args({2049, 128, 16})
    ->Args({513, 64, 8})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Exchange buffers of every tile of one PSF.
void BM_ExchangePsf(benchmark::State& state) {
    const vlf::Scene& scene = cornell();
    const vlf::Psf psf =
        vlf::rasterise_psf(scene, glm::normalize(vlf::Vec3(0.3, 0.5, 0.8)), 0,
                           static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    vlf::TileExchange x;
    vlf::ExchangeScratch scratch;
    for (auto _ : state) {
        for (const vlf::Tile& t : psf.tiles) vlf::build_exchange(scene, psf, t, x, scratch);
        benchmark::DoNotOptimize(x.partner.data());
    }
}
BENCHMARK(BM_ExchangePsf)->Args({64, 8})->Args({128, 16})->Unit(benchmark::kMicrosecond);

// One tile's exchange buffer (VLF §4.1: for every fragment and covered ray, the facing
// fragment along the ray): the tile with the most fragments of one PSF of the office scene
// (137 faces), N = 64, m = arg0. Counters: fragments and covered rays of that tile.
void BM_ExchangeTile(benchmark::State& state) {
    static const vlf::Scene office =
        vlf::load_scene(std::string(VLF_SOURCE_DIR) + "/scenes/office.json");
    const int m = static_cast<int>(state.range(0));
    const vlf::Psf psf =
        vlf::rasterise_psf(office, glm::normalize(vlf::Vec3(0.3, 0.5, 0.8)), 0, 64, m);
    const vlf::Tile* busiest = &psf.tiles.front();
    for (const vlf::Tile& t : psf.tiles)
        if (t.fragments.size() > busiest->fragments.size()) busiest = &t;
    vlf::TileExchange x;
    vlf::ExchangeScratch scratch;
    for (auto _ : state) {
        vlf::build_exchange(office, psf, *busiest, x, scratch);
        benchmark::DoNotOptimize(x.partner.data());
    }
    state.counters["fragments"] = static_cast<double>(busiest->fragments.size());
    state.counters["rays"] = static_cast<double>(busiest->covered);
}
BENCHMARK(BM_ExchangeTile)->Arg(8)->Arg(16)->Unit(benchmark::kMicrosecond);

}  // namespace
