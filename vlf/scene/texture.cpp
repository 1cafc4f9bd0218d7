// texture.cpp — bilinear, wrapping lookups of sRGB textures in linear RGB, with box-filtered
// mip levels (texture.hpp).
#include "vlf/scene/texture.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace vlf {

namespace {

const std::array<double, 256>& srgb_table() {
    static const std::array<double, 256> table = [] {
        std::array<double, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[size_t(i)] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        }
        return t;
    }();
    return table;
}

int wrap(long i, int n) {
    const long r = i % n;
    return int(r < 0 ? r + n : r);
}

// Bilinear between texel centres of one level, wrapping; row 0 is the top (v = 1).
// Coordinates are wrapped into one period first, so huge ones stay in range of a long.
Rgb bilinear(const Texture::Level& l, const Vec2& uv) {
    const double u = uv.x - std::floor(uv.x), v = uv.y - std::floor(uv.y);
    const double x = u * l.width - 0.5, y = (1.0 - v) * l.height - 0.5;
    if (!std::isfinite(x) || !std::isfinite(y)) return Rgb(0.0);
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    Rgb sum(0.0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const double w = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty);
            const size_t at = (size_t(wrap(long(fy) + dy, l.height)) * size_t(l.width) +
                               size_t(wrap(long(fx) + dx, l.width))) *
                              3;
            sum += w * Rgb(l.rgb[at], l.rgb[at + 1], l.rgb[at + 2]);
        }
    return sum;
}

// The next level: half the size (rounded up), each texel the mean of the up to 2 x 2 it
// covers.
Texture::Level half(const Texture::Level& a) {
    Texture::Level b;
    b.width = std::max(1, (a.width + 1) / 2);
    b.height = std::max(1, (a.height + 1) / 2);
    b.rgb.assign(size_t(b.width) * size_t(b.height) * 3, 0.0f);
    for (int y = 0; y < b.height; ++y)
        for (int x = 0; x < b.width; ++x) {
            const int x1 = std::min(2 * x + 2, a.width), y1 = std::min(2 * y + 2, a.height);
            const double n = double((x1 - 2 * x) * (y1 - 2 * y));
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                for (int sy = 2 * y; sy < y1; ++sy)
                    for (int sx = 2 * x; sx < x1; ++sx)
                        sum += a.rgb[(size_t(sy) * size_t(a.width) + size_t(sx)) * 3 + size_t(c)];
                b.rgb[(size_t(y) * size_t(b.width) + size_t(x)) * 3 + size_t(c)] = float(sum / n);
            }
        }
    return b;
}

}  // namespace

void Texture::finish() {
    levels.clear();
    Level base;
    base.width = width;
    base.height = height;
    base.rgb.resize(srgb.size());
    const auto& lut = srgb_table();
    for (size_t i = 0; i < srgb.size(); ++i) base.rgb[i] = float(lut[srgb[i]]);
    average = Rgb(0.0);
    const size_t n = size_t(width) * size_t(height);
    for (size_t i = 0; i < n; ++i)
        average += Rgb(lut[srgb[3 * i]], lut[srgb[3 * i + 1]], lut[srgb[3 * i + 2]]);
    average = n ? average / double(n) : Rgb(1.0);
    levels.push_back(std::move(base));
    while (levels.back().width > 1 || levels.back().height > 1)
        levels.push_back(half(levels.back()));
}

Rgb Texture::at(const Vec2& uv) const {
    return levels.empty() ? Rgb(1.0) : bilinear(levels[0], uv);
}

Rgb Texture::filtered(const Vec2& uv, double pixels) const {
    if (levels.empty() || !(pixels > 1.0)) return at(uv);
    const double level = std::min(std::log2(pixels), double(levels.size() - 1));
    const size_t lo = size_t(level);
    const size_t hi = std::min(lo + 1, levels.size() - 1);
    const double t = level - double(lo);
    return (1.0 - t) * bilinear(levels[lo], uv) + t * bilinear(levels[hi], uv);
}

}  // namespace vlf
