#include "vlf/gaussian_filter.hpp"

#include <cmath>
#include <vector>

#include "vlf/parallel.hpp"

namespace vlf {

void gaussian_filter_next(const Scene& scene, TextureMaps& maps, double sigma) {
    if (sigma <= 0.0) return;
    const int radius = static_cast<int>(std::ceil(3.0 * sigma));
    std::vector<double> kernel(2 * radius + 1);
    for (int i = -radius; i <= radius; ++i)
        kernel[i + radius] = std::exp(-0.5 * (i * i) / (sigma * sigma));
    parallel_for(0, static_cast<long>(scene.faces.size()), [&](long fi) {
        const Face& f = scene.faces[fi];
        const int W = f.texels.width, H = f.texels.height;
        const size_t b = maps.begin(f.id);
        const double cell = f.texels.size * f.texels.size;
        std::vector<Rgb> out(size_t(W) * H, Rgb(0.0));
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const Rgb p = maps.next[b + size_t(j) * W + i];
                if (p.x == 0 && p.y == 0 && p.z == 0) continue;
                double sum = 0.0;
                for (int y = std::max(0, j - radius); y <= std::min(H - 1, j + radius); ++y)
                    for (int x = std::max(0, i - radius); x <= std::min(W - 1, i + radius); ++x)
                        sum += kernel[x - i + radius] * kernel[y - j + radius] *
                               (f.texel_area[size_t(y) * W + x] / cell);
                if (sum <= 0.0) {  // isolated texel: keep its power
                    out[size_t(j) * W + i] += p;
                    continue;
                }
                for (int y = std::max(0, j - radius); y <= std::min(H - 1, j + radius); ++y)
                    for (int x = std::max(0, i - radius); x <= std::min(W - 1, i + radius); ++x) {
                        const double g = kernel[x - i + radius] * kernel[y - j + radius] *
                                         (f.texel_area[size_t(y) * W + x] / cell);
                        if (g > 0) out[size_t(y) * W + x] += p * (g / sum);
                    }
            }
        for (size_t t = 0; t < out.size(); ++t) maps.next[b + t] = out[t];
    });
}

}  // namespace vlf
