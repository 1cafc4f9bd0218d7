#include "vlf/field/lightmap.hpp"

#include <algorithm>
#include <cmath>

namespace vlf {

std::vector<Rgb> texel_radiance(const Scene& scene, const TextureMaps& maps) {
    std::vector<Rgb> out(maps.texels(), Rgb(0.0));
    for (const Chart& c : scene.charts) {
        const size_t b = maps.begin(c.id), n = maps.count(c.id);
        for (size_t t = 0; t < n; ++t) out[b + t] = maps.radiance(c, t);
    }
    return out;
}

namespace {

// Bilinear axis: texel-centre coordinate c = texel coordinate - 0.5, clamped to the grid,
// gives the two texels i0, i1 and the weight of i1.
void axis(double x, int size, int& i0, int& i1, double& w1) {
    const double c = std::clamp(x - 0.5, 0.0, double(size - 1));
    if (!std::isfinite(c) || size == 1) {
        i0 = i1 = std::clamp(static_cast<int>(std::floor(std::isfinite(x) ? x : 0.0)), 0, size - 1);
        w1 = 0.0;
        return;
    }
    i0 = std::min(static_cast<int>(std::floor(c)), size - 2);
    i1 = i0 + 1;
    w1 = c - i0;
}

}  // namespace

Rgb sample_lightmap(const Chart& f, const Rgb* radiance, const Vec3& point) {
    const TexelFrame& tf = f.texels;
    const int W = tf.width, H = tf.height;
    if (W <= 0 || H <= 0 || f.texel_area.empty()) return Rgb(0.0);
    const Vec2 uv = tf.to_texel(point);
    int i[2], j[2];
    double wu, wv;
    axis(uv.x, W, i[0], i[1], wu);
    axis(uv.y, H, j[0], j[1], wv);
    const double reliable = kReliableTexelFraction * tf.size * tf.size;

    Rgb sum(0.0);
    double wsum = 0.0;
    // Fallback: the candidate with the largest texel area; ties go to the larger weight,
    // i.e. the nearer texel.
    size_t best = 0;
    double best_area = -1.0, best_w = -1.0;
    for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
            const double w = (a ? wu : 1.0 - wu) * (b ? wv : 1.0 - wv);
            const size_t k = size_t(j[b]) * W + i[a];
            const double area = f.texel_area[k];
            if (area > best_area || (area == best_area && w > best_w)) {
                best = k;
                best_area = area;
                best_w = w;
            }
            if (w <= 0.0 || area < reliable) continue;
            sum += w * radiance[k];
            wsum += w;
        }
    if (wsum > 0.0) return sum / wsum;
    if (best_area > 0.0) return radiance[best];

    // None of the four touches the polygon (a point off the face, or a sliver face):
    // the nearest reliable texel of the grid, else the grid's largest texel.
    double best_d2 = 1e300;
    best_area = 0.0;
    bool found = false;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const size_t k = size_t(y) * W + x;
            const double area = f.texel_area[k];
            if (area <= 0.0) continue;
            const double dx = x + 0.5 - uv.x, dy = y + 0.5 - uv.y;
            const double d2 = std::isfinite(dx * dx + dy * dy) ? dx * dx + dy * dy : 0.0;
            const bool ok = area >= reliable;
            // Prefer reliable texels; among them the nearest. Else the largest area.
            const bool better = ok ? (!found || d2 < best_d2) : (!found && area > best_area);
            if (better) {
                best = k;
                best_d2 = d2;
                best_area = area;
                found = found || ok;
            }
        }
    return best_area > 0.0 ? radiance[best] : Rgb(0.0);
}

}  // namespace vlf
