// Hot-kernel benchmarks: continuous clipping of one beam against a texel grid, and one
// walkthrough lookup (L_T of a face on a ray of the light field, and a P^T lookup), and the
// SHA-256 that checks every bake file when a bundle is loaded.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <random>

#include "vlf/bake/bake.hpp"
#include "vlf/core/checksum.hpp"
#include "vlf/field/lightmap.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/propagation.hpp"
#include "vlf/transport/texel_clip.hpp"

namespace {

// One beam footprint (a parallelogram of about one texel, at random offsets and
// orientations) clipped against a 64 x 64 texel grid.
void BM_ClipBeamToTexels(benchmark::State& state) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(2.0, 60.0), a(0.0, 6.28318), sz(0.3, 2.0);
    std::vector<std::array<vlf::Vec2, 4>> quads(1024);
    for (auto& q : quads) {
        const vlf::Vec2 c(u(rng), u(rng));
        const double t = a(rng), s = sz(rng);
        const vlf::Vec2 ex = s * vlf::Vec2(std::cos(t), std::sin(t)),
                        ey = s * 0.7 * vlf::Vec2(-std::sin(t + 0.3), std::cos(t + 0.3));
        q = {c - ex - ey, c + ex - ey, c + ex + ey, c - ex + ey};
    }
    std::vector<vlf::TexelOverlap> out;
    size_t k = 0;
    for (auto _ : state) {
        out.clear();
        vlf::clip_quad_to_grid(quads[k++ & 1023].data(), 64, 64, out);
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_ClipBeamToTexels);

struct SmallBake {
    vlf::Scene scene;
    vlf::Bake bake;
    SmallBake() {
        scene = vlf::load_scene(std::string(VLF_SOURCE_DIR) + "/scenes/cornell-mirrors.json");
        vlf::PropagateParams p;
        p.field.directions = 129;
        p.field.resolution = 64;
        p.cycles = 2;
        const vlf::Propagation run = vlf::propagate(scene, p, {});
        bake = vlf::make_bake(scene, p, *run.transport, vlf::propagation_report(scene, p, run, 0));
    }
};
const SmallBake& small_bake() {
    static const SmallBake b;
    return b;
}

// L_T of a stored face on a ray of the light field (the inner step of rays mode, §6.1).
void BM_RayLookup(benchmark::State& state) {
    const vlf::Bake& bake = small_bake().bake;
    const vlf::RayImages& r = bake.rays;
    // Collect (direction, pixel, face) triples that exist.
    std::vector<std::array<int, 4>> probes;
    const int N = r.resolution;
    for (int d = 0; d < r.directions && probes.size() < 4096; d += 7)
        for (int p = 0; p < N * N; p += 13) {
            const uint64_t b = r.pixel_offset[size_t(d) * N * N + p];
            if (b < r.pixel_offset[size_t(d) * N * N + p + 1])
                probes.push_back({d, p % N, p / N, r.face[b]});
        }
    size_t k = 0;
    vlf::RgbF v;
    for (auto _ : state) {
        const auto& q = probes[k++ % probes.size()];
        benchmark::DoNotOptimize(r.lookup(q[0], q[1], q[2], q[3], v));
    }
}
BENCHMARK(BM_RayLookup);

// Bilinear P^T lookup on a wall (texture mode's diffuse step, §6.2).
void BM_LightmapLookup(benchmark::State& state) {
    const SmallBake& sb = small_bake();
    const vlf::Face& f = sb.bake.scene.faces[2];  // back wall
    const vlf::Chart& c = sb.bake.scene.chart_of(f);
    const vlf::Rgb* rad = sb.bake.lightmap_radiance.data() + sb.bake.texel_offset[f.chart];
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    std::vector<vlf::Vec3> pts(1024);
    for (auto& p : pts)
        p = c.texels.to_plane(vlf::Vec2(u(rng) * c.texels.width, u(rng) * c.texels.height));
    size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(vlf::sample_lightmap(c, rad, pts[k++ & 1023]));
}
BENCHMARK(BM_LightmapLookup);

// SHA-256 throughput over a 16 MiB buffer (bytes/s in the output).
void BM_Sha256(benchmark::State& state) {
    const std::string data(16 << 20, 'v');
    for (auto _ : state) benchmark::DoNotOptimize(vlf::sha256_hex(data));
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(data.size()));
}
BENCHMARK(BM_Sha256);

}  // namespace
