#include "vlf/transport/rim_pools.hpp"

#include <algorithm>

#include "vlf/core/parallel.hpp"

namespace vlf {

namespace {
constexpr double kWhole = 1.0 - 1e-9;  // a texel wholly inside its face
constexpr double kHost = 0.5;          // a host is at least half inside
}  // namespace

bool RimPools::empty() const {
    for (size_t t = 0; t < host.size(); ++t)
        if (host[t] != t) return false;
    return true;
}

RimPools build_rim_pools(const Scene& scene, const TextureMaps& maps) {
    RimPools p;
    p.host.resize(maps.texels());
    p.pool_area.assign(maps.texels(), 0.0);
    parallel_for(0, static_cast<long>(scene.charts.size()), [&](long fi) {
        const Chart& f = scene.charts[fi];
        const int W = f.texels.width, H = f.texels.height;
        const size_t b = maps.begin(f.id);
        const double cell = f.texels.size * f.texels.size;
        auto inside = [&](int i, int j) { return f.texel_area[size_t(j) * W + i] / cell; };
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const size_t k = size_t(j) * W + i;
                p.host[b + k] = static_cast<uint32_t>(b + k);
                if (f.texel_area[k] <= 0.0 || inside(i, j) >= kWhole) continue;
                double best = std::max(inside(i, j), kHost - 1e-12);
                for (int y = std::max(0, j - 1); y <= std::min(H - 1, j + 1); ++y)
                    for (int x = std::max(0, i - 1); x <= std::min(W - 1, i + 1); ++x)
                        if (inside(x, y) > best) {
                            best = inside(x, y);
                            p.host[b + k] = static_cast<uint32_t>(b + size_t(y) * W + x);
                        }
            }
        // A host may be a rim texel itself: follow each chain (strictly more inside at every
        // step, so it ends) to its root.
        for (size_t k = 0; k < size_t(W) * H; ++k) {
            uint32_t h = p.host[b + k];
            while (p.host[h] != h) h = p.host[h];
            p.host[b + k] = h;
        }
        for (size_t k = 0; k < size_t(W) * H; ++k) p.pool_area[p.host[b + k]] += f.texel_area[k];
    });
    return p;
}

void pool_rim_texels(const RimPools& pools, const Scene& scene, const TextureMaps& maps,
                     std::vector<Rgb>& power) {
    parallel_for(0, static_cast<long>(scene.charts.size()), [&](long fi) {
        const Chart& f = scene.charts[fi];
        const size_t b = maps.begin(f.id), n = maps.count(f.id);
        bool any = false;
        for (size_t t = b; t < b + n && !any; ++t) any = pools.host[t] != t;
        if (!any) return;
        std::vector<Rgb> pooled(n, Rgb(0.0));
        for (size_t t = b; t < b + n; ++t) pooled[pools.host[t] - b] += power[t];
        for (size_t t = b; t < b + n; ++t) {
            const size_t h = pools.host[t];
            if (pools.pool_area[h] > 0.0)
                power[t] = pooled[h - b] * (f.texel_area[t - b] / pools.pool_area[h]);
        }
    });
}

}  // namespace vlf
