// texel_albedo.cpp — per-texel mean albedo of textured charts (texel_albedo.hpp).
#include "vlf/scene/texel_albedo.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/core/parallel.hpp"

namespace vlf {

namespace {

// At most this many samples along a triangle's side (a million per triangle).
constexpr int kMaxSamplesPerSide = 1024;

void chart_albedo(const Scene& scene, Chart& chart) {
    const Material& m = scene.material_of(chart);
    const TexelFrame& grid = chart.texels;
    std::vector<Rgb> sum(size_t(grid.count()), Rgb(0.0));
    std::vector<double> weight(size_t(grid.count()), 0.0);
    for (int id : chart.faces) {
        const Face& f = scene.faces[size_t(id)];
        if (f.uv.size() != 3) continue;
        const Vec3 &a = f.vertices[0], &b = f.vertices[1], &c = f.vertices[2];
        const double longest =
            std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        // 4 samples per texel side; each sample is the texture's mean over its own share
        // of the triangle (a mip lookup as wide as the texture pixels between samples), so
        // thin features of the texture are neither missed nor aliased.
        const Texture& tex = scene.textures[size_t(m.diffuse_texture)];
        double pixels = 0.0;
        for (int e = 0; e < 3; ++e) {
            const Vec2 d = f.uv[size_t((e + 1) % 3)] - f.uv[size_t(e)];
            pixels = std::max({pixels, std::abs(d.x) * tex.width, std::abs(d.y) * tex.height});
        }
        const int n = std::clamp(int(std::ceil(4.0 * longest / grid.size)), 1, kMaxSamplesPerSide);
        const double footprint = pixels / n;
        const double w = f.area / (double(n) * n);
        // Sub-triangle centres of the n x n subdivision, in barycentric steps of 1/n.
        for (int i = 0; i < n; ++i)
            for (int j = 0; i + j < n; ++j)
                for (int up = 0; up < 2; ++up) {
                    if (up && i + j + 1 >= n) continue;  // the upside-down ones fit inside
                    const double s = (i + (up ? 2.0 : 1.0) / 3.0) / n;
                    const double t = (j + (up ? 2.0 : 1.0) / 3.0) / n;
                    const Vec3 x = a + s * (b - a) + t * (c - a);
                    const Vec2 q = grid.to_texel(x);
                    const int ti = std::clamp(int(std::floor(q.x)), 0, grid.width - 1);
                    const int tj = std::clamp(int(std::floor(q.y)), 0, grid.height - 1);
                    const size_t k = size_t(tj) * size_t(grid.width) + size_t(ti);
                    sum[k] += w * scene.albedo_at(f, x, footprint);
                    weight[k] += w;
                }
    }
    chart.texel_albedo.assign(size_t(grid.count()), m.diffuse);
    for (size_t k = 0; k < sum.size(); ++k)
        if (weight[k] > 0) chart.texel_albedo[k] = sum[k] / weight[k];
}

}  // namespace

void compute_texel_albedo(Scene& scene) {
    parallel_for(0L, long(scene.charts.size()), [&](long c) {
        Chart& chart = scene.charts[size_t(c)];
        chart.texel_albedo.clear();
        if (scene.material_of(chart).diffuse_texture >= 0) chart_albedo(scene, chart);
    });
}

}  // namespace vlf
