// atlas.cpp — shelf packing of the charts' texel grids into the lightmap atlas (atlas.hpp).
#include "vlf/bake/atlas.hpp"

#include <algorithm>
#include <cmath>

namespace vlf {

namespace {

constexpr int kGutter = 1;  // texels between atlas rectangles (and after the last)

}  // namespace

Atlas pack_atlas(const Scene& scene) {
    Atlas a;
    const int nf = static_cast<int>(scene.charts.size());
    a.rects.resize(nf);
    std::vector<int> order(nf);
    double cells = 0.0;
    int widest = 1;
    for (int f = 0; f < nf; ++f) {
        order[f] = f;
        const TexelFrame& t = scene.charts[f].texels;
        cells += double(t.width + kGutter) * double(t.height + kGutter);
        widest = std::max(widest, t.width + kGutter);
    }
    std::sort(order.begin(), order.end(), [&](int p, int q) {
        const TexelFrame &a1 = scene.charts[p].texels, &b1 = scene.charts[q].texels;
        if (a1.height != b1.height) return a1.height > b1.height;
        if (a1.width != b1.width) return a1.width > b1.width;
        return p < q;
    });
    a.width = std::max(widest, static_cast<int>(std::ceil(std::sqrt(cells))));
    int x = 0, y = 0, shelf = 0;
    for (int f : order) {
        const TexelFrame& t = scene.charts[f].texels;
        if (x + t.width + kGutter > a.width) {  // next shelf
            y += shelf;
            x = 0;
            shelf = 0;
        }
        a.rects[f] = {f, x, y, t.width, t.height};
        x += t.width + kGutter;
        shelf = std::max(shelf, t.height + kGutter);
    }
    a.height = std::max(1, y + shelf);
    return a;
}

}  // namespace vlf
