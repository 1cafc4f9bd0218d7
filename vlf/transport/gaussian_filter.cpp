#include "vlf/transport/gaussian_filter.hpp"

#include <cmath>
#include <vector>

#include "vlf/core/parallel.hpp"

namespace vlf {

void gaussian_filter_next(const Scene& scene, TextureMaps& maps, double sigma) {
    if (sigma <= 0.0) return;
    const int radius = static_cast<int>(std::ceil(3.0 * sigma));
    std::vector<double> kernel(2 * radius + 1);
    for (int i = -radius; i <= radius; ++i)
        kernel[i + radius] = std::exp(-0.5 * (i * i) / (sigma * sigma));
    double kernel_sum = 0.0;  // over the whole 2D kernel
    for (double a : kernel)
        for (double b : kernel) kernel_sum += a * b;
    parallel_for(0, static_cast<long>(scene.charts.size()), [&](long fi) {
        const Chart& f = scene.charts[fi];
        const int W = f.texels.width, H = f.texels.height;
        const size_t b = maps.begin(f.id);
        const double cell = f.texels.size * f.texels.size;
        std::vector<Rgb> value(size_t(W) * H, Rgb(0.0));  // B = P / A
        for (size_t k = 0; k < value.size(); ++k)
            if (f.texel_area[k] > 0.0) value[k] = maps.next[b + k] / f.texel_area[k];
        std::vector<Rgb> out(value.size());
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const size_t k = size_t(j) * W + i;
                out[k] = maps.next[b + k];
                const double ai = f.texel_area[k];
                if (ai <= 0.0) continue;
                Rgb flow(0.0);
                for (int y = std::max(0, j - radius); y <= std::min(H - 1, j + radius); ++y)
                    for (int x = std::max(0, i - radius); x <= std::min(W - 1, i + radius); ++x) {
                        const size_t q = size_t(y) * W + x;
                        if (q == k || f.texel_area[q] <= 0.0) continue;
                        const double g = kernel[x - i + radius] * kernel[y - j + radius];
                        flow += (value[q] - value[k]) * (f.texel_area[q] * g);
                    }
                out[k] += flow * (ai / (cell * kernel_sum));
            }
        for (size_t k = 0; k < out.size(); ++k) maps.next[b + k] = out[k];
    });
}

}  // namespace vlf
